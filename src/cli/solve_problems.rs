//! `rigidref solve-problems`: a library of contact problems (Siconos' `.dat`, rigidref's
//! problem files) solved by several solvers, a Markdown table and a performance profile.
//! docs/problem-library.md.

use super::progress::Progress;
use anyhow::{Context, bail};
use clap::Args;
use rigidref::tools::experiments::problem_library::{
    LibraryEntry, LibrarySettings, LibrarySolver, Profile, load, markdown_table, solve_entry,
};
use std::path::{Path, PathBuf};

/// Arguments of `rigidref solve-problems`.
#[derive(Args)]
#[command(after_long_help = "\
Each problem is read into local form (W, q, μ: docs/contact.md §\"The local form\") and solved
by every solver named, each stopped as soon as Siconos' error measure of its answer is at or
below the tolerance (checked after every PGS sweep, at every Newton iterate and at each centre
of the proximal fallback; not inside a proximal subproblem, which stops on its own law norm):

  error = √(Σ_k ‖λ_k − proj_K(λ_k − ŵ_k)‖²) / max(‖q‖, ‖λ‖, ‖w‖),

w = W λ + q and ŵ De Saxcé's velocity (docs/problem-library.md §\"Siconos' error measure\"):
Siconos ≥ 4.4's denominator; Siconos 4.1–4.3 divide by ‖q‖ alone (--json gives that one as
q_normalised_error, and the undivided absolute_error). A box-friction problem (a rigidref problem of the
assignment's friction model) is judged by its own law instead: rigidref's residual divided by
max(‖q‖, ‖w‖). The table gives per problem and solver: converged or
not, iterations (PGS sweeps, Newton iterations with its fallbacks), wall time of the solve, the
final error, and the largest of the answer's physical criteria (Signorini, cone boundary,
maximum dissipation, J; docs/contact.md §\"Physical criteria\"); --json adds rigidref's
residual, the exact Coulomb residual and every criterion. --profile writes a Dolan–Moré performance profile: for each solver, the
fraction of problems it solved within τ times the fastest solver's time.

Files: Siconos' .dat text (dense, sparse-block and sparse storage; a global problem is skipped
with a note), rigidref's .json problem files (local form, or body form converted), and FCLIB's
.hdf5 files when rigidref is built with --features fclib (local problems, and global ones of
rigid bodies through the body form). A folder is read for its .dat, .json and .hdf5 files. Files that cannot be read are skipped with a one-line note;
the exit status is 1 only when none could be read. Solvers: pgs (row visits, the assignment's),
pgs-exact (exact local solves: Siconos' NSGS), newton (the exact solver), newton-regularised
(the same with its plain runs' Newton matrix regularised by ε = (‖F‖∞ / max|b|)^1.5: fewer
iterations on problems with redundant contacts, more on some others; docs/contact.md §\"Newton
solver\", **Regularisation following ‖F‖**), auto (NSGS while its
rate promises the tolerance within 1 000 sweeps, then Newton warm-started from its λ; the iter
column says which path answered: nsgs, nsgs+newton or nsgs+proximal, with sweeps + Newton
iterations; docs/contact.md §\"Automatic choice: NSGS, then Newton\"), newton-twins (Newton,
restarted once from its own answer; where it still stalls, the problem without one contact of
each near-duplicate pair that carries the error (normal rows of W with cosine above 1 − 1e-8),
solved by Newton and judged on the whole problem: exact where the contacts left out end with
w_n ≥ 0; the iter column names them; docs/contact.md §\"Near-duplicate contacts left out\",
the method for RockPile_tob1).")]
pub struct SolveProblemsArgs {
    /// Problem files, or folders of them.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Solvers, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "pgs,pgs-exact,newton"
    )]
    pub solver: Vec<LibrarySolver>,
    /// Converged where Siconos' error is at or below this (relative).
    #[arg(long, default_value_t = 1e-8)]
    pub tolerance: f64,
    /// PGS sweeps at most.
    #[arg(long, default_value_t = 20_000)]
    pub sweeps: u32,
    /// Newton iterations at most per run (before and within its fallbacks).
    #[arg(long, default_value_t = 200)]
    pub newton_iterations: u32,
    /// Write the performance profile to this SVG file.
    #[arg(long, value_name = "SVG")]
    pub profile: Option<PathBuf>,
    /// Print every result as JSON instead of the Markdown table.
    #[arg(long)]
    pub json: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The problem files named: files as given, folders' .dat and .json files sorted by name.
fn files(inputs: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .with_context(|| format!("{}: cannot read folder", input.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension()
                        .is_some_and(|e| e == "dat" || e == "json" || e == "hdf5" || e == "h5")
                })
                .collect();
            found.sort();
            if found.is_empty() {
                bail!(
                    "{}: no problem files (.dat, .json, .hdf5) in the folder",
                    input.display()
                );
            }
            out.extend(found);
        } else if input.exists() {
            out.push(input.clone());
        } else {
            bail!("{}: no such file or folder", input.display());
        }
    }
    Ok(out)
}

fn name_of(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Runs the comparison.
pub fn solve_problems(args: SolveProblemsArgs) -> anyhow::Result<()> {
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        bail!(
            "--tolerance must be a positive number, got {}",
            args.tolerance
        );
    }
    let mut solvers = args.solver.clone();
    solvers.dedup();
    let settings = LibrarySettings {
        tolerance: args.tolerance,
        sweeps: args.sweeps,
        newton_iterations: args.newton_iterations,
    };
    let paths = files(&args.inputs)?;
    let mut progress = Progress::new(
        paths.len() as u64,
        "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} problems (eta {eta}) {msg}",
        args.quiet,
    );
    let mut entries: Vec<LibraryEntry> = Vec::new();
    let mut skipped = 0;
    for (i, path) in paths.iter().enumerate() {
        progress.bar().set_message(name_of(path));
        match load(path) {
            Ok(problem) => entries.push(solve_entry(&name_of(path), &problem, &solvers, &settings)),
            Err(e) => {
                skipped += 1;
                progress.println(&format!("skipped: {e}"));
            }
        }
        progress.tick(i as u64 + 1);
    }
    progress.finish();
    if entries.is_empty() {
        bail!(
            "none of the {} files could be read as a problem",
            paths.len()
        );
    }
    let profile = Profile::of(&entries, &solvers);
    if let Some(path) = &args.profile {
        let title = format!(
            "Performance profile, {} problems, error ≤ {:.0e} (docs/problem-library.md)",
            entries.len(),
            args.tolerance
        );
        let svg = profile.svg(&title).map_err(anyhow::Error::msg)?;
        std::fs::write(path, svg).with_context(|| format!("{}: cannot write", path.display()))?;
    }
    if args.json {
        let value = serde_json::json!({
            "tolerance": args.tolerance,
            "skipped": skipped,
            "problems": entries,
            "profile": profile,
        });
        println!("{}", serde_json::to_string_pretty(&value)?);
    } else {
        print!("{}", markdown_table(&entries, &solvers));
        if skipped > 0 {
            println!("\n{skipped} file(s) skipped (see the notes above).");
        }
    }
    Ok(())
}
