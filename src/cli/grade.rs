//! `rigidref grade`: a batch of submissions against reference runs of the scenes. docs/grading.md.

use anyhow::{Context, bail};
use clap::Args;
use rigidref::tools::grading::grade::{
    GradeMode, grade_all, load_references, submissions, to_csv, to_markdown,
};
use std::path::PathBuf;

/// Arguments of `rigidref grade`.
#[derive(Args)]
#[command(after_long_help = "\
SUBMISSIONS holds one folder per submission. For scene NAME.json (a 3D scene file) or a 2D scene
(an image NAME.png, or a 2D scene file NAME.json) a submission provides its trace as NAME.jsonl
(in the scene's system: a 3D or a 2D trace) and, optionally, its first contact's problem as
NAME.problem.json. One batch may mix 3D and 2D scenes; their file stems must differ. The
reference runs each scene once (for --time, recording every frame; seconds in 3D, time units in
2D); every submission is compared with it
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
    /// The scenes: 3D scene files, 2D images (.png) or 2D scene files; each names the
    /// submissions' files by its stem.
    #[arg(long, required = true, num_args = 1..)]
    pub scenes: Vec<PathBuf>,
    /// Simulated time of the reference runs: seconds for 3D scenes, time units for 2D ones.
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
    /// solves), applied to every scene (a key must be one of each scene's system).
    #[command(flatten)]
    pub sets: super::args::SceneSets,
}

/// Runs `rigidref grade`.
pub fn grade(args: GradeArgs) -> anyhow::Result<()> {
    let folders = submissions(&args.submissions).map_err(anyhow::Error::msg)?;
    if folders.is_empty() {
        bail!("{}: no submission folders", args.submissions.display());
    }
    let overrides = args.sets.overrides()?;
    let references =
        load_references(&args.scenes, &overrides, args.time).map_err(anyhow::Error::msg)?;
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let limits = rigidref::tools::grading::grade::Limits {
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
                .all(|s| rigidref::tools::grading::grade::verdict(&rows, &n, s) == "pass")
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
