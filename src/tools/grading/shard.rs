//! Grading on a cluster without links or home-made lists (docs/grading.md §"More submissions
//! than one machine handles"): `grade --shard K/N` grades the K-th of N shares of a submissions
//! folder, and `grade --merge DIR…` joins the shares' reports into one, refusing a submission
//! graded twice and naming every submission no share graded.
//!
//! The share of a submission is its place in the folder's listing, sorted by the names' bytes:
//! the i-th (from 0) belongs to shard i mod N + 1. Every run writes `grade.json` beside its
//! tables: the rows, and what the merge checks (the shard, the scenes, the mode, the time, and
//! the listing it saw, as a count and a digest of the names).

use super::grade::{GradeMode, GradeRow};
use super::table::submission_name;
use std::path::{Path, PathBuf};

/// The `format` of `grade.json`.
pub const GRADE_FORMAT: &str = "rigidref-grade";

/// Which share of the submissions a run grades: shard `index` (1-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// 1 to `count`.
    pub index: usize,
    /// How many shards the submissions are cut into.
    pub count: usize,
}

impl Shard {
    /// The whole folder: shard 1 of 1.
    pub const ALL: Shard = Shard { index: 1, count: 1 };
}

impl std::str::FromStr for Shard {
    type Err = String;
    /// `K/N` with 1 ≤ K ≤ N, e.g. `3/20` (in a Slurm array task:
    /// `$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`).
    fn from_str(text: &str) -> Result<Shard, String> {
        let bad = || format!("{text:?}: expected K/N with 1 ≤ K ≤ N, e.g. 3/20");
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// The submissions of `shard`: of `all` (sorted, as `grade::submissions` lists them), the i-th
/// for every i with i mod N = K − 1.
pub fn share(all: &[PathBuf], shard: Shard) -> Vec<PathBuf> {
    all.iter()
        .enumerate()
        .filter(|(i, _)| i % shard.count == shard.index - 1)
        .map(|(_, p)| p.clone())
        .collect()
}

/// A digest of a listing (the names, in order): FNV-1a, 64 bits, as hex. Two runs that saw the
/// same folder have the same digest.
pub fn listing_digest(names: &[String]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for name in names {
        for b in name.bytes().chain([0u8]) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// What a run of `grade` writes as `grade.json`: its rows and what `--merge` checks.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GradeRun {
    /// [`GRADE_FORMAT`].
    pub format: String,
    /// 1.
    pub version: u32,
    /// The shard this run graded.
    pub shard: Shard,
    /// `trajectory` or `outcome`.
    pub mode: String,
    /// The reference runs' `--time`.
    pub time: f64,
    /// The scenes' names, in order.
    pub scenes: Vec<String>,
    /// How many submissions the folder held when this run listed it.
    pub submissions_seen: usize,
    /// [`listing_digest`] of that listing.
    pub listing: String,
    /// The submissions this run graded (their names as the tables show them).
    pub graded: Vec<String>,
    /// The rows.
    pub rows: Vec<GradeRow>,
}

impl GradeRun {
    /// A run's record: `all` the folder's listing, `graded` this shard's share of it.
    pub fn new(
        shard: Shard,
        mode: GradeMode,
        time: f64,
        scenes: Vec<String>,
        all: &[PathBuf],
        graded: &[PathBuf],
        rows: Vec<GradeRow>,
    ) -> GradeRun {
        let names: Vec<String> = all.iter().map(|p| submission_name(p)).collect();
        GradeRun {
            format: GRADE_FORMAT.into(),
            version: 1,
            shard,
            mode: match mode {
                GradeMode::Trajectory => "trajectory".into(),
                GradeMode::Outcome => "outcome".into(),
            },
            time,
            scenes,
            submissions_seen: names.len(),
            listing: listing_digest(&names),
            graded: graded.iter().map(|p| submission_name(p)).collect(),
            rows,
        }
    }

    /// Reads `dir/grade.json`; errors name the file.
    pub fn read(dir: &Path) -> Result<GradeRun, String> {
        let path = dir.join("grade.json");
        let limit = crate::common::input::max_input_bytes();
        let text = crate::common::input::read_regular_text(&path, limit, "--max-input-mb")
            .map_err(|e| {
                format!(
                    "{}: {e} (a report of `rigidref grade` has one)",
                    path.display()
                )
            })?;
        let run: GradeRun = serde_json::from_str(&text).map_err(|e| {
            format!(
                "{}: not a grade report: {}",
                path.display(),
                crate::common::trace::json_problem(&e)
            )
        })?;
        if run.format != GRADE_FORMAT || run.version != 1 {
            return Err(format!(
                "{}: not a grade report of version 1 (format {:?}, version {})",
                path.display(),
                run.format,
                run.version
            ));
        }
        Ok(run)
    }
}

/// The shards' reports in `dirs` joined into one run, against the submissions folder as it is
/// now (`all`, as `grade::submissions` lists it): an error when the reports are not the shards
/// of one run (another count, mode, time or scenes; a shard twice; listings that differ, as when
/// the folder changed while the array ran), when a submission was graded twice, or when a
/// submission of the folder was graded by no shard (every one named). Also returns the
/// submissions graded that the folder no longer holds (their rows are kept, after the others).
pub fn merge(dirs: &[PathBuf], all: &[PathBuf]) -> Result<(GradeRun, Vec<String>), String> {
    let runs: Vec<(PathBuf, GradeRun)> = dirs
        .iter()
        .map(|d| GradeRun::read(d).map(|r| (d.clone(), r)))
        .collect::<Result<_, _>>()?;
    let Some((first_dir, first)) = runs.first() else {
        return Err("--merge: no report folders given".into());
    };
    let describe = |r: &GradeRun| {
        format!(
            "shard {} of {}, {} mode, --time {}, scenes {}",
            r.shard.index,
            r.shard.count,
            r.mode,
            r.time,
            r.scenes.join(" ")
        )
    };
    for (dir, r) in &runs {
        if r.shard.count != first.shard.count
            || r.mode != first.mode
            || r.time != first.time
            || r.scenes != first.scenes
        {
            return Err(format!(
                "{} is {}, but {} is {}: not shards of one run (a report left from an earlier \
                 run? remove it, or run the array again)",
                dir.display(),
                describe(r),
                first_dir.display(),
                describe(first)
            ));
        }
    }
    for (k, (dir, r)) in runs.iter().enumerate() {
        if let Some((other, _)) = runs[..k].iter().find(|(_, o)| o.shard == r.shard) {
            return Err(format!(
                "shard {} of {} is in both {} and {}",
                r.shard.index,
                r.shard.count,
                other.display(),
                dir.display()
            ));
        }
    }
    for (dir, r) in &runs {
        if r.listing != first.listing {
            return Err(format!(
                "{} saw {} submissions and {} saw {}, or other names: the submissions folder \
                 changed while the shards ran; run them all again",
                dir.display(),
                r.submissions_seen,
                first_dir.display(),
                first.submissions_seen
            ));
        }
    }
    let mut graded_by: std::collections::BTreeMap<&str, &Path> = Default::default();
    let mut twice = Vec::new();
    for (dir, r) in &runs {
        for name in &r.graded {
            if let Some(before) = graded_by.insert(name, dir) {
                twice.push(format!(
                    "{name:?} ({} and {})",
                    before.display(),
                    dir.display()
                ));
            }
        }
    }
    if !twice.is_empty() {
        return Err(format!(
            "graded in two shards: {}; merge each submission's report once",
            twice.join(", ")
        ));
    }
    let names: Vec<String> = all.iter().map(|p| submission_name(p)).collect();
    let missing: Vec<String> = names
        .iter()
        .filter(|n| !graded_by.contains_key(n.as_str()))
        .map(|n| format!("{n:?}"))
        .collect();
    if !missing.is_empty() {
        let absent: Vec<String> = (1..=first.shard.count)
            .filter(|k| !runs.iter().any(|(_, r)| r.shard.index == *k))
            .map(|k| k.to_string())
            .collect();
        let shards = if absent.is_empty() {
            String::new()
        } else {
            format!(
                " (no report of shard {} of {})",
                absent.join(", "),
                first.shard.count
            )
        };
        return Err(format!(
            "{} of {} submissions graded by no shard{shards}: {}; grade them (run their shards \
             again) and merge again",
            missing.len(),
            names.len(),
            missing.join(", ")
        ));
    }
    // The rows in the folder's order, as one run of the whole folder writes them; then those
    // of submissions the folder no longer holds.
    let gone: Vec<String> = (runs.iter())
        .flat_map(|(_, r)| r.graded.iter())
        .filter(|n| !names.contains(n))
        .cloned()
        .collect();
    let mut rows: Vec<GradeRow> = Vec::new();
    for name in names.iter().chain(&gone) {
        for (_, r) in &runs {
            rows.extend(r.rows.iter().filter(|row| &row.submission == name).cloned());
        }
    }
    let graded: Vec<String> = names.iter().chain(&gone).cloned().collect();
    let run = GradeRun {
        format: GRADE_FORMAT.into(),
        version: 1,
        shard: Shard::ALL,
        mode: first.mode.clone(),
        time: first.time,
        scenes: first.scenes.clone(),
        submissions_seen: names.len(),
        listing: listing_digest(&names),
        graded,
        rows,
    };
    Ok((run, gone))
}
