//! `rigidref grade`: a batch of submissions against reference runs of the scenes, or a share of
//! it (`--shard`), or the shares' reports merged (`--merge`). docs/grading.md.

use anyhow::{Context, bail};
use clap::Args;
use rigidref::tools::grading::grade::{
    GradeMode, grade_all, load_references, submissions, to_csv, to_markdown, verdict,
};
use rigidref::tools::grading::shard::{GradeRun, Shard, merge, share};
use std::path::{Path, PathBuf};

/// Arguments of `rigidref grade`.
#[derive(Args)]
#[command(after_long_help = "\
SUBMISSIONS holds one folder per submission. For scene NAME.json (a 3D scene file) or a 2D scene
(an image NAME.png, or a 2D scene file NAME.json) a submission provides its trace as NAME.jsonl
(in the scene's system: a 3D or a 2D trace) and, optionally, its first contact's problem as
NAME.problem.json. One batch may mix 3D and 2D scenes; their file stems must differ. The
reference runs each scene once (for --time, recording every frame; seconds in 3D, time units in
2D; at most 200 000 steps, since every step is kept in memory); every submission is compared
with it (in parallel over --jobs threads). A missing or malformed file is reported in its row
and never stops the batch.

Submissions are untrusted: a submission folder or file that is a symbolic link leaving the
submissions folder (a file's link: leaving its submission folder), a FIFO, a device, and a file
larger than --max-file-mb (judged from its metadata and counted while it is read) are refused
unopened. A trace that stops early, repeats or reorders its times, is too sparse, has other
bodies, non-finite numbers or a header that makes no sense (dt or a mass ≤ 0) is refused with
its reason (`rigidref compare --help`); one whose positions do not follow its velocities fails.
A header without the descriptive keys scene, source, integrator or substeps is noted, not
refused. A submission is its folder's name, byte for byte: a name that is not UTF-8 is shown
with \\xNN for its other bytes (a backslash doubled), escaped in the Markdown (|) and kept from
running as a formula in the CSV (a cell starting with =, +, -, @ gets a leading ').

Writes grade.csv (submission, scene, observable, result, figure), grade.md (a verdict per
submission and scene, then every row that did not pass) and grade.json (the rows and what
--merge checks) to --out, and prints the Markdown.

More submissions than one machine handles: run `grade --shard K/N` as task K of a job array of
N tasks (each grades every N-th submission of the sorted folder; a shard with none writes empty
tables), then `grade SUBMISSIONS --merge REPORT_DIR...` joins the reports: it refuses reports
that are not the shards of one run or that grade a submission twice, and names every
submission no shard graded (docs/grading.md §\"More submissions than one machine handles\").")]
pub struct GradeArgs {
    /// The folder of submission folders.
    pub submissions: PathBuf,
    /// The scenes: 3D scene files, 2D images (.png) or 2D scene files; each names the
    /// submissions' files by its stem.
    #[arg(long, num_args = 1.., required_unless_present = "merge")]
    pub scenes: Vec<PathBuf>,
    /// Simulated time of the reference runs: seconds for 3D scenes, time units for 2D ones (at
    /// most 200 000 steps of each scene).
    #[arg(long, default_value_t = 5.0, allow_negative_numbers = true)]
    pub time: f64,
    /// How to compare.
    #[arg(long, value_enum, default_value_t = GradeMode::Trajectory)]
    pub mode: GradeMode,
    /// Where to write grade.csv, grade.md and grade.json.
    #[arg(long, default_value = ".")]
    pub out: PathBuf,
    /// Threads, at least 1 [default: the machine's cores].
    #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub jobs: Option<usize>,
    /// The largest submission file opened, MB; a larger one is refused unopened.
    #[arg(long, default_value_t = 512)]
    pub max_file_mb: u64,
    /// Grade only shard K of N (1 ≤ K ≤ N): the submissions whose place in the sorted folder,
    /// counted from 0, is K − 1 modulo N. In a Slurm array task:
    /// `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`.
    #[arg(long, value_name = "K/N", conflicts_with = "merge")]
    pub shard: Option<Shard>,
    /// Merge the reports (folders holding grade.json) of `grade --shard` runs into one, checked
    /// against SUBMISSIONS: no submission twice, none missing.
    #[arg(long, num_args = 1.., value_name = "REPORT_DIR", conflicts_with_all = ["scenes", "shard"])]
    pub merge: Vec<PathBuf>,
    /// Scene parameters for the reference runs (e.g. `--set solver=newton` for exact contact
    /// solves), applied to every scene (a key must be one of each scene's system).
    #[command(flatten)]
    pub sets: super::args::SceneSets,
}

/// Writes a run's grade.csv, grade.md and grade.json to `out` and prints the Markdown.
fn write_report(run: &GradeRun, out: &Path) -> anyhow::Result<(PathBuf, PathBuf)> {
    let markdown = to_markdown(&run.rows, &run.scenes);
    std::fs::create_dir_all(out).with_context(|| format!("{}: cannot create", out.display()))?;
    let csv_path = out.join("grade.csv");
    std::fs::write(&csv_path, to_csv(&run.rows).map_err(anyhow::Error::msg)?)
        .with_context(|| format!("{}: cannot write", csv_path.display()))?;
    let md_path = out.join("grade.md");
    std::fs::write(&md_path, &markdown)
        .with_context(|| format!("{}: cannot write", md_path.display()))?;
    let json_path = out.join("grade.json");
    std::fs::write(&json_path, serde_json::to_string(run)?)
        .with_context(|| format!("{}: cannot write", json_path.display()))?;
    print!("{markdown}");
    Ok((csv_path, md_path))
}

/// How many of `run`'s submissions pass every scene.
fn passing(run: &GradeRun) -> usize {
    (run.graded.iter())
        .filter(|n| {
            run.scenes
                .iter()
                .all(|s| verdict(&run.rows, n, s) == "pass")
        })
        .count()
}

/// Runs `rigidref grade`.
pub fn grade(args: GradeArgs) -> anyhow::Result<()> {
    let all = submissions(&args.submissions).map_err(anyhow::Error::msg)?;
    if all.is_empty() {
        bail!("{}: no submission folders", args.submissions.display());
    }
    if !args.merge.is_empty() {
        let (run, gone) = merge(&args.merge, &all).map_err(anyhow::Error::msg)?;
        let (csv_path, md_path) = write_report(&run, &args.out)?;
        if !gone.is_empty() {
            eprintln!(
                "warning: graded but no longer in {}: {}",
                args.submissions.display(),
                gone.join(", ")
            );
        }
        eprintln!(
            "merged {} reports: {} submissions × {} scenes, {} pass every scene; table in {} and {}",
            args.merge.len(),
            run.graded.len(),
            run.scenes.len(),
            passing(&run),
            csv_path.display(),
            md_path.display()
        );
        return Ok(());
    }
    let shard = args.shard.unwrap_or(Shard::ALL);
    let folders = share(&all, shard);
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
    let run = GradeRun::new(shard, args.mode, args.time, names, &all, &folders, rows);
    let (csv_path, md_path) = write_report(&run, &args.out)?;
    let of = if shard == Shard::ALL {
        String::new()
    } else {
        format!(" (shard {}/{} of {})", shard.index, shard.count, all.len())
    };
    eprintln!(
        "graded {} submissions{of} × {} scenes: {} pass every scene; table in {} and {}",
        folders.len(),
        run.scenes.len(),
        passing(&run),
        csv_path.display(),
        md_path.display()
    );
    Ok(())
}
