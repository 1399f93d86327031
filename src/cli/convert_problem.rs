//! `rigidref convert-problem`: a contact problem from one file format to another, in local
//! form. docs/problem-library.md §"Converting problems".

use clap::Args;
use rigidref::tools::experiments::problem_library::{load, write};
use std::path::PathBuf;

/// Arguments of `rigidref convert-problem`.
#[derive(Args)]
#[command(after_long_help = "\
Reads a problem as `rigidref solve-problems` does (Siconos .dat, rigidref .json of either form,
FCLIB .hdf5 when built with --features fclib) and writes its local form (W, q, μ) in the format
the output's extension names: .json (rigidref's local-form problem file), .dat (Siconos' text,
sparse-block storage, every number to the bit) or .hdf5 (FCLIB local, with --features fclib), so
that Siconos and other FCLIB readers can solve rigidref's problems. A body-form problem becomes
W = J M⁻¹ Jᵀ + C, q = b. Siconos' and FCLIB's formats hold contacts under the Coulomb cone only:
a problem with joint rows is refused for them, box friction is written with a warning (another
solver answers for the cone), and .dat keeps no warm start (a warning says so).")]
pub struct ConvertProblemArgs {
    /// The problem file to read.
    pub input: PathBuf,
    /// The file to write (.json, .dat or .hdf5).
    pub output: PathBuf,
}

/// Converts one file.
pub fn convert_problem(args: ConvertProblemArgs) -> anyhow::Result<()> {
    let problem = load(&args.input).map_err(anyhow::Error::msg)?;
    let source = format!("rigidref convert-problem {}", args.input.display());
    for warning in write(&problem, &source, &args.output).map_err(anyhow::Error::msg)? {
        eprintln!("warning: {warning}");
    }
    eprintln!(
        "wrote {} ({} contacts)",
        args.output.display(),
        problem.contacts()
    );
    Ok(())
}
