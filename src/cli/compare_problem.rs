//! `rigidref compare-problem`: two contact-problem files (3D or 2D) for the same state, up to
//! the tangent basis. docs/grading.md.

use super::compare::Unreadable;
use anyhow::bail;
use clap::Args;
use rigidref::problem::json::ProblemFile;
use rigidref::tools::grading::compare::{match_traces, read_trace_any};
use rigidref::tools::grading::compare_problem::{ProblemTolerance, compare_problems_matched};
use std::path::{Path, PathBuf};

/// Arguments of `rigidref compare-problem`.
#[derive(Args)]
#[command(after_long_help = "\
Compares two contact-problem files for the same state (docs/contact-problem-format.md), 3D or
2D (both the same), up to each contact's choice of tangent basis: bodies' velocities and inverse
masses, and per contact (matched within the same pair of bodies by the nearest point, or normal
row: two simulators may list contacts in different orders) the bodies, point and normal, μ,
compliance, the normal Jacobian row, the friction rows through TᵀT (invariant under a rotation
of t1, t2 about n in 3D, under the tangent's sign in 2D), the Delassus block's normal entry,
normal-tangent coupling norm, the tangent block's trace (and in 3D determinant), b_n and |b_t|,
and, when both files hold a solution, λn and |λ_t| (unless OTHER's λ solves OTHER's problem:
with friction a problem can have several solutions). Each value must agree within
tolerance · max(|a|, |b|, scale) + 1e-9 (docs/grading.md §\"Comparing contact problems\").

Bodies are matched first, since two simulators may number a scene's bodies differently (the 2D
starter scans its image column by column, rigidref row by row): with --traces, as `compare`
matches the two traces' bodies (by the image in 2D, by name or by mass and first position in
3D); else by the contacts' points (each pair of contacts at one point votes for its bodies),
then by inverse mass and velocity. A contact listed with its bodies the other way round
([ground, bar] against [bar, ground]) is the same contact with its normal flipped and its
Jacobian blocks swapped, and is compared as such. The matching is printed.

Both files are read as `compare` reads traces: regular files only, within --max-input-mb. A
body's inverse mass that is not symmetric positive semidefinite (a mass or an inertia ≤ 0) is
an error.

Exit status: 0 the problems agree, 1 they differ, 2 a file is unreadable.")]
pub struct CompareProblemArgs {
    /// The reference problem file.
    pub reference: PathBuf,
    /// The problem file to check.
    pub other: PathBuf,
    /// Relative tolerance.
    #[arg(long, default_value_t = 1e-6)]
    pub tolerance: f64,
    /// The two traces the problems belong to (REF's and OTHER's, in that order): match the
    /// problems' bodies as `compare` matches the traces' [default: from the problems' contacts].
    #[arg(long, num_args = 2, value_names = ["REF_TRACE", "OTHER_TRACE"])]
    pub traces: Vec<PathBuf>,
}

/// A problem file, read as an untrusted file: a regular file within --max-input-mb.
fn read_problem(path: &Path) -> Result<ProblemFile, Unreadable> {
    let limit = rigidref::common::input::max_input_bytes();
    let text = rigidref::common::input::read_regular_text(path, limit, "--max-input-mb")
        .map_err(|e| Unreadable(format!("{}: {e}", path.display())))?;
    ProblemFile::parse(&text, &path.display().to_string()).map_err(Unreadable)
}

/// Runs `rigidref compare-problem`.
pub fn compare_problem(args: CompareProblemArgs) -> anyhow::Result<()> {
    if args.tolerance.is_nan() || args.tolerance <= 0.0 {
        let message = format!("--tolerance must be positive, got {}", args.tolerance);
        return Err(Unreadable(message).into());
    }
    let reference = read_problem(&args.reference)?;
    let other = read_problem(&args.other)?;
    let tol = ProblemTolerance {
        relative: args.tolerance,
        ..Default::default()
    };
    let bodies = match args.traces.as_slice() {
        [a, b] => {
            let limit = rigidref::common::input::max_input_bytes();
            let a = read_trace_any(a, limit, "--max-input-mb").map_err(Unreadable)?;
            let b = read_trace_any(b, limit, "--max-input-mb").map_err(Unreadable)?;
            let (map, by) = match_traces(&a, &b)
                .map_err(|e| Unreadable(format!("--traces: the bodies cannot be matched: {e}")))?;
            println!("bodies           matched by the traces (by {by})");
            Some(map)
        }
        _ => None,
    };
    let report =
        compare_problems_matched(&reference, &other, bodies.as_deref(), tol).map_err(|e| {
            Unreadable(format!(
                "{} against {}: {e}",
                args.other.display(),
                args.reference.display()
            ))
        })?;
    for note in &report.notes {
        println!("note             {note}");
    }
    let (diffs, compared) = (report.differences, report.compared);
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
