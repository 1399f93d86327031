//! `rigidref compare-problem`: two contact-problem files (3D or 2D) for the same state, up to
//! the tangent basis. docs/grading.md.

use super::compare::Unreadable;
use anyhow::bail;
use clap::Args;
use rigidref::problem::json::ProblemFile;
use rigidref::tools::grading::compare_problem::{ProblemTolerance, compare_problems};
use std::path::PathBuf;

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
