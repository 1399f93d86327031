//! `rigidref compare`: another simulator's trace against the reference's, in trajectory or
//! outcome mode. docs/grading.md. (`compare-problem` and `grade` are compare_problem.rs and
//! grade.rs; they share [`Unreadable`].)

use anyhow::bail;
use clap::Args;
use rigidref::rigid3d::trace::Trace;
use rigidref::tools::grading::compare::{
    AnyTrace, Comparison, OutcomeTolerances, OutcomeTolerances2, Trace2, TrajectoryTolerances,
    compare_outcomes, compare_outcomes_2d, compare_trajectories, compare_trajectories_2d,
    outcome_scene, outcome_scene_2d, read_trace_any, read_trace_of, time_text,
};
use std::path::{Path, PathBuf};

/// An input could not be read or an option is unusable: exit status 2 (1 means the inputs
/// differ).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Unreadable(pub String);

/// Arguments of `rigidref compare`.
#[derive(Args)]
#[command(after_long_help = "\
Trajectory mode (the default) aligns the two traces by time: at each of REF's record times in
the span both cover, OTHER is interpolated (positions, velocities, energies and momenta linearly;
orientations by slerp), and per body and quantity the error, its maximum and the first time it
exceeds its tolerance are reported. Bodies are matched by name when both traces name the same
bodies, else by body (the same mass, the nearest first position), so that bodies listed in
another order under other names are found. Outcome mode compares what happened instead: the
time of first contact, when each body comes to rest (at rest below 0.05 m/s and 0.1 rad/s,
moving above twice that, settling in between, which agrees with either; the speeds are shown),
where and how it rests (orientation up to the body's symmetries, which --scene supplies, by
default the scene REF's header names), the energy at the end, and the Dzhanibekov flip times of
a lone spinning body. Impacts make multi-body scenes chaotic: two correct simulators diverge
after a few impacts; compare such scenes in outcome mode (docs/grading.md says which mode fits
which scene).

Both modes also judge every record of OTHER against itself: each body's positions must follow
its velocities, within 4 of REF's steps at REF's top speed per step (a body cannot move without
velocity, or jump and come back); a trace that does not fails (docs/grading.md §\"Positions
follow velocities\").

Before comparing, OTHER is refused (a verdict of its own, exit status 1) when it cannot be
judged fairly: a header value that makes no sense (dt or a mass ≤ 0); no records; other bodies
than REF's (another number, or a body with no partner of its mass); a non-finite number or a
matrix that is not a rotation; a time repeated or going back; a start later or an end earlier
than REF's by more than the gap allowance (\"ends at 0.5 s of 2 s\"); or records further apart
than the gap allowance: REF's own spacing or 10 of REF's steps, whichever is larger.

2D traces (the image-block system; docs/grading.md §\"2D traces\") are compared in the 2D units
(blocks, time units), with the same refusals; bodies are matched by what the image gives (block
count, mass and first centre), whatever order OTHER lists them in. Trajectory mode: positions,
angles, velocities, angular velocities, energies and momenta. Outcome mode: per body, at rest at
the end or not (below 0.05 block/t at its fastest point, moving above 0.1, settling between), the
rest position (0.1 block) and angle modulo the block shape's quarter-turn symmetry (0.1 rad; the
shape from --scene, an image or 2D scene file, by default REF's source), standing or toppled
(turned by more than 45°), and the total energy at the end.

Both files are read as `grade` reads a submission: regular files only (a FIFO or a device is an
error, never opened for reading), counted against --max-input-mb while they are read. A file
that is not a trace says why (a byte-order mark, a second header, a 2D trace where REF is 3D).

Exit status: 0 the traces agree, 1 they differ or OTHER is refused, 2 a trace is unreadable (or
REF itself is malformed).")]
pub struct CompareArgs {
    /// The reference trace (rigidref's run of the scene).
    pub reference: PathBuf,
    /// The trace to check, in the same format (docs/trace-format.md).
    pub other: PathBuf,
    /// Compare outcomes instead of trajectories.
    #[arg(long)]
    pub outcome: bool,
    /// Trajectory mode: tolerance of positions (m; 2D: blocks), orientations (rad), velocities
    /// (m/s; 2D: blocks per time unit) and angular velocities (rad/s; 2D: rad per time unit),
    /// and of energies and momenta relative to the reference's largest.
    #[arg(long, default_value_t = 1e-3, conflicts_with = "outcome")]
    pub tolerance: f64,
    /// Outcome mode: the scene, for the bodies' sizes, symmetries and axes (3D: a scene file;
    /// 2D: the image or 2D scene file) [default: the scene REF's header names as its source,
    /// when that file exists].
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The trace at `path`, as `grade` reads a submission: a regular file only (a FIFO or a device
/// is an error, unread), counted against --max-input-mb while it is read.
fn read(path: &Path) -> Result<AnyTrace, Unreadable> {
    let limit = rigidref::common::input::max_input_bytes();
    read_trace_any(path, limit, "--max-input-mb").map_err(Unreadable)
}

/// OTHER, of the reference's system (`wanted` dimensions).
fn read_other(args: &CompareArgs, wanted: u64) -> Result<AnyTrace, Unreadable> {
    let limit = rigidref::common::input::max_input_bytes();
    let because = format!("the reference is {wanted}D");
    let trace = read_trace_of(&args.other, wanted, &because, limit, "--max-input-mb")
        .map_err(Unreadable)?;
    if let AnyTrace::Three(t) = &trace {
        for note in &t.notes {
            eprintln!("note: {note}");
        }
    }
    Ok(trace)
}

fn print_comparison(c: &Comparison) {
    if let Some(r) = &c.refused {
        println!(
            "mode             {} — the trace is refused, not compared",
            c.mode
        );
        println!("refused          {}: {}", r.kind, r.message);
        return;
    }
    println!(
        "mode             {} (bodies matched by {}; t = {} … {} s)",
        c.mode, c.matched_by, c.span.0, c.span.1
    );
    if !c.matching.is_empty() {
        let moved: Vec<String> = (c.matching.iter().enumerate())
            .filter(|(i, j)| i != *j)
            .map(|(i, j)| format!("{i} = {j}"))
            .collect();
        if moved.is_empty() {
            println!(
                "matching         every reference body is the other trace's body of the same index"
            );
        } else {
            println!(
                "matching         reference body = other trace's body: {} (the rest at their own index)",
                moved.join(", ")
            );
        }
    }
    if !c.errors.is_empty() {
        println!(
            "{:<44} {:>12} {:>10} {:>12} {:>14}",
            "quantity", "max error", "at t (s)", "tolerance", "first exceeds"
        );
        for e in &c.errors {
            println!(
                "{:<44} {:>12.3e} {:>10.4} {:>12.3e} {:>14}  {}",
                e.quantity,
                e.max_error,
                e.at,
                e.tolerance,
                e.first_exceeded
                    .map_or("-".to_string(), |t| format!("{} s", time_text(t))),
                e.unit
            );
        }
    }
    if !c.outcomes.is_empty() || !c.checks.is_empty() {
        println!(
            "{:<48} {:>24} {:>28} {:>14}  result",
            "observable", "reference", "other", "tolerance"
        );
        for o in c.outcomes.iter().chain(&c.checks) {
            println!(
                "{:<48} {:>24} {:>28} {:>14}  {}",
                o.name,
                o.reference,
                o.other,
                o.tolerance,
                if o.passed { "ok" } else { "DIFFERS" }
            );
        }
    }
    println!(
        "verdict          {}",
        if c.agree {
            "agree".to_string()
        } else {
            format!("differ: {}", c.first_failure().unwrap_or_default())
        }
    );
}

/// 2D traces (the image-block system): trajectory or outcome mode, bodies matched by the image.
fn comparison_2d(args: &CompareArgs, reference: Trace2) -> anyhow::Result<Comparison> {
    let AnyTrace::Two(other) = read_other(args, 2)? else {
        unreachable!("read_other checked the dimension")
    };
    if args.outcome {
        let scene = outcome_scene_2d(&reference, &args.reference, args.scene.as_deref())
            .map_err(|e| Unreadable(format!("--scene: {e}")))?;
        match &scene {
            Some((_, path)) => eprintln!(
                "scene            {} (shapes: symmetries, reach)",
                path.display()
            ),
            None => eprintln!(
                "scene            none found (--scene, or the reference's source {:?}): angles without the shapes' symmetries, reach 1 block",
                reference.header.source
            ),
        }
        return compare_outcomes_2d(
            &reference,
            &other,
            scene.as_ref().map(|(b, _)| b.as_slice()),
            &OutcomeTolerances2::default(),
        )
        .map_err(|e| against(args, e).into());
    }
    compare_trajectories_2d(
        &reference,
        &other,
        &TrajectoryTolerances::uniform(args.tolerance),
    )
    .map_err(|e| against(args, e).into())
}

/// An error of a comparison that could not be made, naming both files (exit status 2).
fn against(args: &CompareArgs, e: String) -> Unreadable {
    Unreadable(format!(
        "{} against {}: {e}",
        args.other.display(),
        args.reference.display()
    ))
}

/// Runs `rigidref compare`.
pub fn compare(args: CompareArgs) -> anyhow::Result<()> {
    if args.tolerance.is_nan() || args.tolerance <= 0.0 {
        let message = format!("--tolerance must be positive, got {}", args.tolerance);
        return Err(Unreadable(message).into());
    }
    let comparison = match read(&args.reference)? {
        AnyTrace::Two(reference) => comparison_2d(&args, reference)?,
        AnyTrace::Three(reference) => {
            for note in &reference.notes {
                eprintln!("note: {note}");
            }
            comparison_3d(&args, reference)?
        }
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&comparison)?);
    } else {
        print_comparison(&comparison);
    }
    if !comparison.agree {
        bail!(
            "{} differs from {}: {}",
            args.other.display(),
            args.reference.display(),
            comparison.first_failure().unwrap_or_default()
        );
    }
    Ok(())
}

/// 3D traces: trajectory or outcome mode.
fn comparison_3d(args: &CompareArgs, reference: Trace) -> anyhow::Result<Comparison> {
    let AnyTrace::Three(other) = read_other(args, 3)? else {
        unreachable!("read_other checked the dimension")
    };
    let comparison = if args.outcome {
        let scene = outcome_scene(&reference, &args.reference, args.scene.as_deref())
            .map_err(|e| Unreadable(format!("--scene: {e}")))?;
        match &scene {
            Some((_, path)) => eprintln!(
                "scene            {} (sizes, symmetries, flip axis)",
                path.display()
            ),
            None => eprintln!(
                "scene            none found (--scene, or the reference's source {:?}): positions to 0.05 m, orientations without symmetries, no flips",
                reference.header.source
            ),
        }
        compare_outcomes(
            &reference,
            &other,
            scene.as_ref().map(|(s, _)| s),
            &OutcomeTolerances::default(),
        )
    } else {
        compare_trajectories(
            &reference,
            &other,
            &TrajectoryTolerances::uniform(args.tolerance),
        )
    }
    .map_err(|e| against(args, e))?;
    Ok(comparison)
}
