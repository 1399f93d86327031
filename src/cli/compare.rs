//! `rigidref compare`, `rigidref compare-problem` and `rigidref grade`: another simulator's
//! output against the reference. docs/grading.md.

use anyhow::{Context, bail};
use clap::Args;
use rigidref::problem::json::ProblemFile;
use rigidref::rigid3d::trace::{Trace, read_trace_file};
use rigidref::tools::compare::{
    Comparison, OutcomeTolerances, TrajectoryTolerances, compare_outcomes, compare_trajectories,
    outcome_scene,
};
use rigidref::tools::compare_problem::{ProblemTolerance, compare_problems};
use rigidref::tools::grade::{GradeMode, grade_all, reference, submissions, to_csv, to_markdown};
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
bodies, else by index. Outcome mode compares what happened instead: the time of first contact,
when each body comes to rest, where and how it rests (orientation up to the body's symmetries,
which --scene supplies, by default the scene REF's header names), the energy at the end, and the
Dzhanibekov flip times of a lone spinning body. Impacts make multi-body scenes chaotic: two
correct simulators diverge after a few impacts; compare such scenes in outcome mode
(docs/grading.md says which mode fits which scene).

Before comparing, OTHER is refused (a verdict of its own, exit status 1) when it cannot be
judged fairly: no records; other bodies than REF's; a non-finite number or a matrix that is not a
rotation; a time repeated or going back; a start later or an end earlier than REF's by more than
one of REF's steps (\"ends at 0.5 s of 2 s\"); or records further apart than REF's own spacing
or 10 of REF's steps, whichever is larger.

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
    /// Trajectory mode: tolerance of positions (m), orientations (rad), velocities (m/s) and
    /// angular velocities (rad/s), and of energies and momenta relative to the reference's
    /// largest.
    #[arg(long, default_value_t = 1e-3, conflicts_with = "outcome")]
    pub tolerance: f64,
    /// Outcome mode: the scene, for the bodies' sizes, symmetries and axes [default: the scene
    /// REF's header names as its source, when that file exists].
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

fn read(path: &Path) -> Result<Trace, Unreadable> {
    let trace = read_trace_file(path).map_err(Unreadable)?;
    for note in &trace.notes {
        eprintln!("note: {note}");
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
                    .map_or("-".to_string(), |t| format!("{t} s")),
                e.unit
            );
        }
    }
    if !c.outcomes.is_empty() {
        println!(
            "{:<48} {:>24} {:>28} {:>14}  result",
            "observable", "reference", "other", "tolerance"
        );
        for o in &c.outcomes {
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

/// The scene for outcome mode and where it came from: --scene, else the reference header's
/// source, looked up as written and then beside the reference trace, when it is a file.
/// Runs `rigidref compare`.
pub fn compare(args: CompareArgs) -> anyhow::Result<()> {
    if args.tolerance.is_nan() || args.tolerance <= 0.0 {
        let message = format!("--tolerance must be positive, got {}", args.tolerance);
        return Err(Unreadable(message).into());
    }
    let reference = read(&args.reference)?;
    let other = read(&args.other)?;
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
        let t = args.tolerance;
        let tol = TrajectoryTolerances {
            position: t,
            angle: t,
            velocity: t,
            omega: t,
            energy: t,
            momentum: t,
        };
        compare_trajectories(&reference, &other, &tol)
    }
    .map_err(|e| {
        Unreadable(format!(
            "{} against {}: {e}",
            args.other.display(),
            args.reference.display()
        ))
    })?;
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

/// Arguments of `rigidref compare-problem`.
#[derive(Args)]
#[command(after_long_help = "\
Compares two 3D contact-problem files for the same state (docs/contact-problem-format.md), up to
each contact's choice of tangent basis: bodies' velocities and inverse masses, and per contact
(matched in order) the bodies, point and normal, μ, compliance, the normal Jacobian row, the
friction rows through TᵀT (invariant under a rotation of t1, t2 about n), the Delassus block's
normal entry, normal-tangent coupling norm, and tangent block's trace and determinant, b_n and
|b_t|, and, when both files hold a solution, λn and |λ_t|. Each value must agree within
tolerance · max(|a|, |b|, scale) + 1e-9 (docs/grading.md §\"Comparing contact problems\").

Exit status: 0 the problems agree, 1 they differ, 2 a file is unreadable.")]
pub struct CompareProblemArgs {
    /// The reference problem file.
    pub reference: PathBuf,
    /// The problem file to check.
    pub other: PathBuf,
    /// Relative tolerance.
    #[arg(long, default_value_t = 1e-6)]
    pub tolerance: f64,
}

/// Runs `rigidref compare-problem`.
pub fn compare_problem(args: CompareProblemArgs) -> anyhow::Result<()> {
    if args.tolerance.is_nan() || args.tolerance <= 0.0 {
        let message = format!("--tolerance must be positive, got {}", args.tolerance);
        return Err(Unreadable(message).into());
    }
    for path in [&args.reference, &args.other] {
        rigidref::common::input::check_size(path)
            .map_err(|e| Unreadable(format!("{}: {e}", path.display())))?;
    }
    let reference = ProblemFile::read(&args.reference).map_err(Unreadable)?;
    let other = ProblemFile::read(&args.other).map_err(Unreadable)?;
    let tol = ProblemTolerance {
        relative: args.tolerance,
        ..Default::default()
    };
    let (diffs, compared) = compare_problems(&reference, &other, tol).map_err(|e| {
        Unreadable(format!(
            "{} against {}: {e}",
            args.other.display(),
            args.reference.display()
        ))
    })?;
    println!(
        "compared         {compared} values, {} contacts",
        reference.contacts.len()
    );
    for d in &diffs {
        println!(
            "differs          {}: reference {}, other {}",
            d.quantity, d.reference, d.other
        );
    }
    if let Some(first) = diffs.first() {
        bail!(
            "{} differs from {} in {} of {compared} values; first: {} (reference {}, other {})",
            args.other.display(),
            args.reference.display(),
            diffs.len(),
            first.quantity,
            first.reference,
            first.other
        );
    }
    println!("verdict          agree");
    Ok(())
}

/// Arguments of `rigidref grade`.
#[derive(Args)]
#[command(after_long_help = "\
SUBMISSIONS holds one folder per submission. For scene NAME.json a submission provides its trace
as NAME.jsonl and, optionally, its first contact's problem as NAME.problem.json. The reference
runs each scene once (for --time, recording every frame); every submission is compared with it
(in parallel over --jobs threads). A missing or malformed file is reported in its row and never
stops the batch. A submission's files are judged before they are opened: a symbolic link leaving
the submission folder, a FIFO, a device or a folder, and a file larger than --max-file-mb are
refused unopened. A trace that stops early, repeats or reorders its times, is too sparse, or has
other bodies or non-finite numbers is refused with its reason (`rigidref compare --help`). A
header without the descriptive keys scene, source, integrator or substeps is noted, not
refused. Writes grade.csv (submission, scene, observable, result, figure) and grade.md
(a verdict per submission and scene, then every row that did not pass) to --out, and prints the
Markdown. For more submissions than one machine handles, run one `rigidref grade` per submission
folder as a job array (docs/grading.md §\"Grading a batch\").")]
pub struct GradeArgs {
    /// The folder of submission folders.
    pub submissions: PathBuf,
    /// The scenes (3D scene files); each names the submissions' files by its stem.
    #[arg(long, required = true, num_args = 1..)]
    pub scenes: Vec<PathBuf>,
    /// Simulated time of the reference runs, s.
    #[arg(long, default_value_t = 5.0)]
    pub time: f64,
    /// How to compare.
    #[arg(long, value_enum, default_value_t = GradeMode::Trajectory)]
    pub mode: GradeMode,
    /// Where to write grade.csv and grade.md.
    #[arg(long, default_value = ".")]
    pub out: PathBuf,
    /// Threads [default: the machine's cores].
    #[arg(long)]
    pub jobs: Option<usize>,
    /// The largest submission file opened, MB; a larger one is refused unopened.
    #[arg(long, default_value_t = 512)]
    pub max_file_mb: u64,
    /// Scene parameters for the reference runs (e.g. `--set solver=newton` for exact contact
    /// solves), applied to every scene.
    #[command(flatten)]
    pub sets: super::args::SceneSets,
}

/// Runs `rigidref grade`.
pub fn grade(args: GradeArgs) -> anyhow::Result<()> {
    let folders = submissions(&args.submissions).map_err(anyhow::Error::msg)?;
    if folders.is_empty() {
        bail!("{}: no submission folders", args.submissions.display());
    }
    let mut references = Vec::new();
    for path in &args.scenes {
        let overrides = args.sets.overrides()?;
        let scene = rigidref::rigid3d::scene::load_scene_with(path, &overrides)
            .map_err(|e| anyhow::anyhow!("{}", e.0))?;
        let name = path.file_stem().map_or_else(
            || path.display().to_string(),
            |s| s.to_string_lossy().to_string(),
        );
        references.push(reference(&name, scene, args.time).map_err(anyhow::Error::msg)?);
    }
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let limits = rigidref::tools::grade::Limits {
        max_file_bytes: args.max_file_mb.saturating_mul(1 << 20),
    };
    let rows = grade_all(&folders, &references, args.mode, threads, &limits);
    let names: Vec<String> = references.iter().map(|r| r.name.clone()).collect();
    let markdown = to_markdown(&rows, &names);
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create", args.out.display()))?;
    let csv_path = args.out.join("grade.csv");
    std::fs::write(&csv_path, to_csv(&rows).map_err(anyhow::Error::msg)?)
        .with_context(|| format!("{}: cannot write", csv_path.display()))?;
    let md_path = args.out.join("grade.md");
    std::fs::write(&md_path, &markdown)
        .with_context(|| format!("{}: cannot write", md_path.display()))?;
    print!("{markdown}");
    let passed = folders
        .iter()
        .filter(|f| {
            let n = f.file_name().unwrap_or_default().to_string_lossy();
            names
                .iter()
                .all(|s| rigidref::tools::grade::verdict(&rows, &n, s) == "pass")
        })
        .count();
    eprintln!(
        "graded {} submissions × {} scenes: {passed} pass every scene; table in {} and {}",
        folders.len(),
        names.len(),
        csv_path.display(),
        md_path.display()
    );
    Ok(())
}
