//! Grading a batch of submissions: each submission folder holds a trace per scene (`NAME.jsonl`
//! for scene `NAME.json`, or for a 2D scene `NAME.png` or `NAME.json`) and optionally the first
//! contact's problem (`NAME.problem.json`); each is compared with the reference's run of the
//! scene, in the scene's system. One table of submission × scene ×
//! observable. docs/grading.md §"Grading a batch".

use super::compare::{
    AnyTrace, Comparison, OutcomeTolerances, OutcomeTolerances2, Trace2, TrajectoryTolerances,
    compare_outcomes, compare_outcomes_2d, compare_trajectories, compare_trajectories_2d,
    read_trace_of, time_text,
};
use super::compare_problem::{ProblemTolerance, compare_problems_matched};
use super::table::row;
pub use super::table::{GradeRow, display_name, submission_name, to_csv, to_markdown, verdict};
use crate::blocks2d::body::Body2;
use crate::blocks2d::scene::Scene2;
use crate::blocks2d::trace::{Record2, TraceHeader2};
use crate::common::scene_json::Overrides;
use crate::problem::json::ProblemFile;
use crate::rigid3d::scene::Scene;
use crate::rigid3d::trace::{Trace, TraceHeader, TraceRecord};
use crate::rigid3d::world::World;
use crate::sim::{Flow, drive, steps_in};
use std::path::{Path, PathBuf};

/// Which comparison grading applies (docs/grading.md says which fits which scene).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GradeMode {
    /// Every quantity over time, aligned by time (compare_trajectories, or
    /// compare_trajectories_2d for 2D scenes).
    Trajectory,
    /// What happened: contacts, rest, where and how bodies rest (compare_outcomes, or
    /// compare_outcomes_2d for 2D scenes).
    Outcome,
}

/// The reference for one scene: its run and its first contact's problem.
pub struct Reference {
    /// The scene's file stem, which names the submissions' files.
    pub name: String,
    /// The run, of a 3D scene or of a 2D one (an image or a 2D scene file).
    pub run: ReferenceRun,
    /// The first contact problem of the run, if it had contacts.
    pub first_problem: Option<ProblemFile>,
}

/// A reference run of one of the two systems.
pub enum ReferenceRun {
    /// A 3D scene and its trace (every frame).
    Three {
        /// The scene.
        scene: Box<Scene>,
        /// The trace.
        trace: Trace,
    },
    /// A 2D scene's bodies as loaded (their shapes: outcome mode's symmetries) and its trace
    /// (every step).
    Two {
        /// The bodies at the start.
        bodies: Vec<Body2>,
        /// The trace.
        trace: Trace2,
    },
}

/// The most steps a reference run of `grade` takes: it keeps every step in memory (about
/// 0.3 kB a step, plus 0.15 kB a body (3D; 0.05 kB in 2D) and 0.1 kB a contact), so
/// `--time` is bounded; 200 000 steps are 2 000 s of a 3D scene at 0.01 s, 10 000 time units
/// of a 2D one at 0.05, about 0.6 GB for 10 bodies with 10 contacts.
pub const MAX_GRADE_STEPS: u64 = 200_000;

/// The steps of a reference run of `time` at step `dt`, within [`MAX_GRADE_STEPS`].
fn grade_steps(name: &str, time: f64, dt: f64) -> Result<u64, String> {
    let steps = steps_in(time, dt, "").map_err(|e| format!("{name}: {e}"))?;
    if steps > MAX_GRADE_STEPS {
        return Err(format!(
            "{name}: --time {time} is {steps} steps of {dt}; grade runs a scene for at most \
             {MAX_GRADE_STEPS} steps, since it keeps every step of the reference in memory \
             (docs/grading.md §\"Grading a batch\")"
        ));
    }
    Ok(steps)
}

/// Runs the 3D `scene` (named `name`) for `time` seconds, recording every frame and keeping the
/// first contact problem.
pub fn reference(name: &str, scene: Scene, time: f64) -> Result<Reference, String> {
    let steps = grade_steps(name, time, scene.params.dt)?;
    let mut world = World::new(&scene)?;
    let header = TraceHeader::for_world(&world, &scene.source);
    let mut records = vec![TraceRecord::of_world(&world)];
    let mut first_problem = None;
    drive(&mut world, steps, |w, k| {
        records.push(TraceRecord::of_world(w));
        if first_problem.is_none()
            && let Some(solve) = w.solves.first()
        {
            first_problem = Some(solve.problem_file(&w.params.name, k, w.params.h()));
        }
        Ok::<_, String>(Flow::Continue)
    })
    .map_err(|e| format!("{name}: {e}"))?;
    Ok(Reference {
        name: name.to_string(),
        run: ReferenceRun::Three {
            scene: Box::new(scene),
            trace: Trace {
                header,
                records,
                notes: Vec::new(),
            },
        },
        first_problem,
    })
}

/// Runs the 2D `scene` (named `name`) for `time` time units, recording every step and keeping
/// the first contact problem.
pub fn reference_2d(name: &str, scene: Scene2, time: f64) -> Result<Reference, String> {
    let mut world = scene.world;
    let bodies = world.bodies.clone();
    let steps = grade_steps(name, time, world.params.dt)?;
    let mut header = TraceHeader2::for_world(&world, name, &scene.image.display().to_string());
    header.overrides = scene.overrides;
    let mut records = vec![Record2::of_world(&world, false)];
    let mut first_problem = None;
    drive(&mut world, steps, |w, k| {
        records.push(Record2::of_world(w, false));
        if first_problem.is_none()
            && let Some(solve) = w.solves.iter().find(|s| !s.contacts.is_empty())
        {
            first_problem = Some(solve.problem_file(name, k, w.params.h()));
        }
        Ok::<_, String>(Flow::Continue)
    })
    .map_err(|e| format!("{name}: {e}"))?;
    Ok(Reference {
        name: name.to_string(),
        run: ReferenceRun::Two {
            bodies,
            trace: Trace2 { header, records },
        },
        first_problem,
    })
}

/// The reference of the scene at `path`, named by its file stem: a 2D scene (a .png image or a
/// JSON file with an `image` key) or a 3D scene file, with `overrides` (`--set`) applied, run for
/// `time` (seconds in 3D, time units in 2D).
pub fn load_reference(path: &Path, overrides: &Overrides, time: f64) -> Result<Reference, String> {
    let name = path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().to_string(),
    );
    if crate::blocks2d::scene::is_2d_scene(path) {
        let options = crate::blocks2d::scene::LoadOptions2 {
            overrides: overrides.clone(),
            ..Default::default()
        };
        let shown = path.display().to_string();
        let scene = crate::blocks2d::scene::load_2d(path, &options).map_err(|e| {
            // Name the scene: in a batch, an option's error would not say which one it met.
            if e.0.starts_with(&shown) {
                e.0
            } else {
                format!("{shown}: {}", e.0)
            }
        })?;
        reference_2d(&name, scene, time)
    } else {
        let shown = path.display().to_string();
        let scene = crate::rigid3d::scene::load_scene_with(path, overrides).map_err(|e| {
            if e.0.starts_with(&shown) {
                e.0
            } else {
                format!("{shown}: {}", e.0)
            }
        })?;
        reference(&name, scene, time)
    }
}

/// The references of `paths` ([`load_reference`]); two scenes with one file stem (which names
/// the submissions' files) are an error.
pub fn load_references(
    paths: &[PathBuf],
    overrides: &Overrides,
    time: f64,
) -> Result<Vec<Reference>, String> {
    let mut out: Vec<Reference> = Vec::new();
    for path in paths {
        let r = load_reference(path, overrides, time)?;
        if let Some(same) = out.iter().position(|o| o.name == r.name) {
            return Err(format!(
                "{}: its name {:?} is also scene {}'s, and a scene's file stem names the \
                 submissions' files; rename one",
                path.display(),
                r.name,
                paths[same].display()
            ));
        }
        out.push(r);
    }
    Ok(out)
}

/// What `grade` opens of a submission (docs/grading.md §"Untrusted submissions").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The largest file opened, bytes (`--max-file-mb`).
    pub max_file_bytes: u64,
}

impl Default for Limits {
    /// 512 MB: a 3D trace of 20 bodies recorded every step for 10 minutes at 1 ms is ~300 MB.
    fn default() -> Limits {
        Limits {
            max_file_bytes: 512 << 20,
        }
    }
}

/// Whether `path` may be opened, judged from its metadata alone (never opening it): it must be a
/// regular file (a symbolic link only if it resolves to a regular file inside `dir`) of at most
/// `limits.max_file_bytes`. Err((result, why)): `missing` when there is nothing at `path`,
/// `refused` otherwise.
pub fn admissible(dir: &Path, path: &Path, limits: &Limits) -> Result<(), (&'static str, String)> {
    let shown = path.display();
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Err(("missing", format!("no {shown}")));
    };
    let meta = if meta.file_type().is_symlink() {
        let (Ok(target), Ok(inside)) = (std::fs::canonicalize(path), std::fs::canonicalize(dir))
        else {
            return Err((
                "refused",
                format!("{shown}: a symbolic link to nothing readable; not opened"),
            ));
        };
        if !target.starts_with(&inside) {
            return Err((
                "refused",
                format!(
                    "{shown}: a symbolic link leaving the submission folder (to {}); not opened",
                    target.display()
                ),
            ));
        }
        match std::fs::metadata(&target) {
            Ok(m) => m,
            Err(e) => return Err(("refused", format!("{shown}: {e}; not opened"))),
        }
    } else {
        meta
    };
    if !meta.is_file() {
        return Err((
            "refused",
            format!("{shown}: not a regular file (a folder, FIFO or device); not opened"),
        ));
    }
    if meta.len() > limits.max_file_bytes {
        return Err((
            "refused",
            format!(
                "{shown}: {:.1} MB is more than the limit of {} MB (raise it with --max-file-mb); not opened",
                meta.len() as f64 / (1u64 << 20) as f64,
                limits.max_file_bytes >> 20
            ),
        ));
    }
    Ok(())
}

/// The rows of a comparison (`row(observable, result, figure)` makes one).
fn comparison_rows(c: &Comparison, row: &dyn Fn(&str, &str, String) -> GradeRow) -> Vec<GradeRow> {
    if let Some(r) = &c.refused {
        return vec![row(
            "trace",
            "refused",
            format!("{}: {}", r.kind, r.message),
        )];
    }
    let mut rows = Vec::new();
    let moved: Vec<String> = (c.matching.iter().enumerate())
        .filter(|(i, j)| i != *j)
        .map(|(i, j)| format!("{i} = {j}"))
        .collect();
    if !moved.is_empty() {
        rows.push(row(
            &format!("bodies matched by {}", c.matched_by),
            "note",
            format!("reference body = submission's body: {}", moved.join(", ")),
        ));
    }
    for e in &c.errors {
        let result = if e.first_exceeded.is_none() {
            "pass"
        } else {
            "fail"
        };
        let figure = match e.first_exceeded {
            Some(t) => format!(
                "max {:.3e} {} at t = {} s; exceeds {:.3e} from t = {} s",
                e.max_error,
                e.unit,
                time_text(e.at),
                e.tolerance,
                time_text(t)
            ),
            None => format!(
                "max {:.3e} {} (tolerance {:.3e})",
                e.max_error, e.unit, e.tolerance
            ),
        };
        rows.push(row(&e.quantity, result, figure));
    }
    for o in c.outcomes.iter().chain(&c.checks) {
        let figure = format!(
            "reference {}, submission {} (tolerance {})",
            o.reference, o.other, o.tolerance
        );
        rows.push(row(&o.name, if o.passed { "pass" } else { "fail" }, figure));
    }
    rows
}

/// Whether the submission folder `dir` may be read, judged like its files: a folder, or a
/// symbolic link to a folder inside the submissions folder (`dir`'s parent). Err(why) names the
/// link's target when it leaves.
pub fn admissible_folder(dir: &Path) -> Result<(), String> {
    let shown = dir.display();
    let meta = std::fs::symlink_metadata(dir).map_err(|e| format!("{shown}: {e}"))?;
    if !meta.file_type().is_symlink() {
        return Ok(());
    }
    let root = dir.parent().unwrap_or(Path::new("."));
    let (Ok(target), Ok(inside)) = (std::fs::canonicalize(dir), std::fs::canonicalize(root)) else {
        return Err(format!(
            "{shown}: a symbolic link to nothing readable; not opened"
        ));
    };
    if !target.starts_with(&inside) || target == inside {
        return Err(format!(
            "{shown}: the submission folder is a symbolic link leaving the submissions folder \
             (to {}); not opened",
            target.display()
        ));
    }
    Ok(())
}

/// A submission's trace for reference `r`, compared in `mode` (its rows), and the matching of
/// its bodies onto the reference's when it was compared.
fn grade_trace(
    path: &Path,
    r: &Reference,
    mode: GradeMode,
    limits: &Limits,
    row: &dyn Fn(&str, &str, String) -> GradeRow,
) -> (Vec<GradeRow>, Option<Vec<usize>>) {
    let (wanted, because) = match &r.run {
        ReferenceRun::Three { .. } => (3, "the scene is 3D"),
        ReferenceRun::Two { .. } => (2, "the scene is 2D"),
    };
    let read = read_trace_of(
        path,
        wanted,
        because,
        limits.max_file_bytes,
        "--max-file-mb",
    );
    let mut rows = Vec::new();
    let compared = read.and_then(|candidate| match (&r.run, candidate) {
        (ReferenceRun::Three { scene, trace }, AnyTrace::Three(candidate)) => {
            for note in &candidate.notes {
                rows.push(row("trace header", "note", note.clone()));
            }
            match mode {
                GradeMode::Trajectory => {
                    compare_trajectories(trace, &candidate, &TrajectoryTolerances::default())
                }
                GradeMode::Outcome => compare_outcomes(
                    trace,
                    &candidate,
                    Some(scene),
                    &OutcomeTolerances::default(),
                ),
            }
        }
        (ReferenceRun::Two { bodies, trace }, AnyTrace::Two(candidate)) => match mode {
            GradeMode::Trajectory => {
                compare_trajectories_2d(trace, &candidate, &TrajectoryTolerances::default())
            }
            GradeMode::Outcome => compare_outcomes_2d(
                trace,
                &candidate,
                Some(bodies),
                &OutcomeTolerances2::default(),
            ),
        },
        _ => unreachable!("read_trace_of checked the dimension"),
    });
    match compared {
        Ok(c) => {
            let matching = (c.refused.is_none()).then(|| c.matching.clone());
            rows.extend(comparison_rows(&c, row));
            (rows, matching)
        }
        Err(e) => {
            rows.push(row("trace", "unreadable", e));
            (rows, None)
        }
    }
}

/// A submission's first contact problem against the reference's: its rows. `matching`, the
/// traces' (other body of each reference body), matches the problems' bodies when both
/// problems have the traces' bodies; else they are matched from the problems' contacts.
fn grade_problem(
    path: &Path,
    reference_problem: &ProblemFile,
    matching: Option<&[usize]>,
    limits: &Limits,
    row: &dyn Fn(&str, &str, String) -> GradeRow,
) -> Vec<GradeRow> {
    const WHAT: &str = "first contact problem";
    let text =
        crate::common::input::read_regular_text(path, limits.max_file_bytes, "--max-file-mb")
            .map_err(|e| format!("{}: {e}", path.display()));
    let problem = text.and_then(|t| ProblemFile::parse(&t, &path.display().to_string()));
    let result = problem.and_then(|p| {
        let fits = |map: &[usize]| {
            map.len() == reference_problem.bodies.len()
                && map.iter().all(|&j| j < p.bodies.len())
                && p.bodies.len() == reference_problem.bodies.len()
        };
        let given = matching.filter(|m| fits(m));
        compare_problems_matched(reference_problem, &p, given, ProblemTolerance::default())
    });
    let mut rows = Vec::new();
    match result {
        Ok(report) => {
            for note in &report.notes {
                rows.push(row(WHAT, "note", note.clone()));
            }
            let (diffs, n) = (report.differences, report.compared);
            rows.push(match diffs.first() {
                None => row(WHAT, "pass", format!("{n} values agree")),
                Some(first) => row(
                    WHAT,
                    "fail",
                    format!(
                        "{} of {n} values differ; first: {} (reference {}, submission {})",
                        diffs.len(),
                        first.quantity,
                        first.reference,
                        first.other
                    ),
                ),
            });
        }
        Err(e) => rows.push(row(WHAT, "unreadable", e)),
    }
    rows
}

/// Grades one submission folder against every reference. Never fails: a missing or unreadable
/// file becomes its row, and so does a submission folder that is a link leaving the
/// submissions folder (every scene `refused`, nothing in it opened).
pub fn grade_submission(
    dir: &Path,
    references: &[Reference],
    mode: GradeMode,
    limits: &Limits,
) -> Vec<GradeRow> {
    let submission = submission_name(dir);
    let mut rows = Vec::new();
    if let Err(why) = admissible_folder(dir) {
        for r in references {
            rows.push(row(&submission, &r.name, "trace", "refused", why.clone()));
        }
        return rows;
    }
    for r in references {
        let mine = |observable: &str, result: &str, figure: String| {
            row(&submission, &r.name, observable, result, figure)
        };
        let path = dir.join(format!("{}.jsonl", r.name));
        let matching = match admissible(dir, &path, limits) {
            Err((result, why)) => {
                rows.push(mine("trace", result, why));
                None
            }
            Ok(()) => {
                let (trace_rows, matching) = grade_trace(&path, r, mode, limits, &mine);
                rows.extend(trace_rows);
                matching
            }
        };
        let problem_path = dir.join(format!("{}.problem.json", r.name));
        let problem_given = std::fs::symlink_metadata(&problem_path).is_ok();
        let Some(reference_problem) = r.first_problem.as_ref().filter(|_| problem_given) else {
            continue;
        };
        match admissible(dir, &problem_path, limits) {
            Err((result, why)) => rows.push(mine("first contact problem", result, why)),
            Ok(()) => rows.extend(grade_problem(
                &problem_path,
                reference_problem,
                matching.as_deref(),
                limits,
                &mine,
            )),
        }
    }
    rows
}

/// The submission folders of `dir` (folders and symbolic links to folders, which
/// [`grade_submission`] judges), sorted by their names' bytes.
pub fn submissions(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: cannot read the submissions folder: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    out.sort();
    Ok(out)
}

/// Grades every submission, `threads` at a time; rows in submission order, then scene order.
pub fn grade_all(
    submissions: &[PathBuf],
    references: &[Reference],
    mode: GradeMode,
    threads: usize,
    limits: &Limits,
) -> Vec<GradeRow> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Vec<GradeRow>>> =
        submissions.iter().map(|_| Default::default()).collect();
    std::thread::scope(|s| {
        for _ in 0..threads.max(1).min(submissions.len().max(1)) {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(dir) = submissions.get(k) else { break };
                    let rows = grade_submission(dir, references, mode, limits);
                    *results[k].lock().unwrap_or_else(|e| e.into_inner()) = rows;
                }
            });
        }
    });
    results
        .into_iter()
        .flat_map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
        .collect()
}
