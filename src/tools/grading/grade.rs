//! Grading a batch of submissions: each submission folder holds a trace per scene (`NAME.jsonl`
//! for scene `NAME.json`, or for a 2D scene `NAME.png` or `NAME.json`) and optionally the first
//! contact's problem (`NAME.problem.json`); each is compared with the reference's run of the
//! scene, in the scene's system. One table of submission × scene ×
//! observable. docs/grading.md §"Grading a batch".

use super::compare::{
    Comparison, OutcomeTolerances, OutcomeTolerances2, Trace2, TrajectoryTolerances,
    compare_outcomes, compare_outcomes_2d, compare_trajectories, compare_trajectories_2d,
    read_trace2_file, time_text,
};
use super::compare_problem::{ProblemTolerance, compare_problems};
use crate::blocks2d::body::Body2;
use crate::blocks2d::scene::Scene2;
use crate::blocks2d::trace::{Record2, TraceHeader2};
use crate::common::scene_json::Overrides;
use crate::problem::json::ProblemFile;
use crate::rigid3d::scene::Scene;
use crate::rigid3d::trace::{Trace, TraceHeader, TraceRecord, read_trace};
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

/// Runs the 3D `scene` (named `name`) for `time` seconds, recording every frame and keeping the
/// first contact problem.
pub fn reference(name: &str, scene: Scene, time: f64) -> Result<Reference, String> {
    let mut world = World::new(&scene)?;
    let steps = steps_in(time, scene.params.dt, "").map_err(|e| format!("{name}: {e}"))?;
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
    let steps = steps_in(time, world.params.dt, "").map_err(|e| format!("{name}: {e}"))?;
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

/// One row of the grade table.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GradeRow {
    /// The submission folder's name.
    pub submission: String,
    /// The scene's name.
    pub scene: String,
    /// The observable or quantity (`trace` for the file as a whole).
    pub observable: String,
    /// `pass`, `fail`, `refused` (the trace is too short, degenerate or for other bodies:
    /// [`crate::tools::grading::compare::Refusal`]), `missing` or `unreadable`.
    pub result: String,
    /// The figure: the error, the observable's values, or what is wrong with the file.
    pub figure: String,
}

fn row(submission: &str, scene: &str, observable: &str, result: &str, figure: String) -> GradeRow {
    GradeRow {
        submission: submission.into(),
        scene: scene.into(),
        observable: observable.into(),
        result: result.into(),
        figure,
    }
}

fn comparison_rows(submission: &str, scene: &str, c: &Comparison) -> Vec<GradeRow> {
    if let Some(r) = &c.refused {
        return vec![row(
            submission,
            scene,
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
            submission,
            scene,
            "bodies matched by the image",
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
        rows.push(row(submission, scene, &e.quantity, result, figure));
    }
    for o in &c.outcomes {
        let figure = format!(
            "reference {}, submission {} (tolerance {})",
            o.reference, o.other, o.tolerance
        );
        rows.push(row(
            submission,
            scene,
            &o.name,
            if o.passed { "pass" } else { "fail" },
            figure,
        ));
    }
    rows
}

/// Grades one submission folder against every reference. Never fails: a missing or unreadable
/// file becomes its row.
pub fn grade_submission(
    dir: &Path,
    references: &[Reference],
    mode: GradeMode,
    limits: &Limits,
) -> Vec<GradeRow> {
    let submission = dir.file_name().map_or_else(
        || dir.display().to_string(),
        |n| n.to_string_lossy().to_string(),
    );
    let mut rows = Vec::new();
    for r in references {
        let path = dir.join(format!("{}.jsonl", r.name));
        if let Err((result, why)) = admissible(dir, &path, limits) {
            rows.push(row(&submission, &r.name, "trace", result, why));
        } else {
            let compared = match &r.run {
                ReferenceRun::Three { scene, trace } => {
                    let read = std::fs::File::open(&path)
                        .map_err(|e| format!("{}: cannot open: {e}", path.display()))
                        .and_then(|f| {
                            read_trace(std::io::BufReader::new(f), &path.display().to_string())
                        });
                    if let Ok(candidate) = &read {
                        for note in &candidate.notes {
                            rows.push(row(
                                &submission,
                                &r.name,
                                "trace header",
                                "note",
                                note.clone(),
                            ));
                        }
                    }
                    read.and_then(|candidate| match mode {
                        GradeMode::Trajectory => compare_trajectories(
                            trace,
                            &candidate,
                            &TrajectoryTolerances::default(),
                        ),
                        GradeMode::Outcome => compare_outcomes(
                            trace,
                            &candidate,
                            Some(scene),
                            &OutcomeTolerances::default(),
                        ),
                    })
                }
                ReferenceRun::Two { bodies, trace } => {
                    read_trace2_file(&path).and_then(|candidate| match mode {
                        GradeMode::Trajectory => compare_trajectories_2d(
                            trace,
                            &candidate,
                            &TrajectoryTolerances::default(),
                        ),
                        GradeMode::Outcome => compare_outcomes_2d(
                            trace,
                            &candidate,
                            Some(bodies),
                            &OutcomeTolerances2::default(),
                        ),
                    })
                }
            };
            match compared {
                Ok(c) => rows.extend(comparison_rows(&submission, &r.name, &c)),
                Err(e) => rows.push(row(&submission, &r.name, "trace", "unreadable", e)),
            }
        }
        let problem_path = dir.join(format!("{}.problem.json", r.name));
        let problem_given = std::fs::symlink_metadata(&problem_path).is_ok();
        if let (true, Some(_)) = (problem_given, &r.first_problem)
            && let Err((result, why)) = admissible(dir, &problem_path, limits)
        {
            rows.push(row(
                &submission,
                &r.name,
                "first contact problem",
                result,
                why,
            ));
        } else if let (true, Some(reference_problem)) = (problem_given, &r.first_problem) {
            let result = ProblemFile::read(&problem_path)
                .and_then(|p| compare_problems(reference_problem, &p, ProblemTolerance::default()));
            rows.push(match result {
                Ok((diffs, n)) if diffs.is_empty() => row(
                    &submission,
                    &r.name,
                    "first contact problem",
                    "pass",
                    format!("{n} values agree"),
                ),
                Ok((diffs, n)) => row(
                    &submission,
                    &r.name,
                    "first contact problem",
                    "fail",
                    format!(
                        "{} of {n} values differ; first: {} (reference {}, submission {})",
                        diffs.len(),
                        diffs[0].quantity,
                        diffs[0].reference,
                        diffs[0].other
                    ),
                ),
                Err(e) => row(
                    &submission,
                    &r.name,
                    "first contact problem",
                    "unreadable",
                    e,
                ),
            });
        }
    }
    rows
}

/// The submission folders of `dir`, sorted by name.
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

/// A submission's verdict for a scene: `pass` when every row passes, else the worst result
/// (`missing`, `unreadable`, `refused`, `fail`).
pub fn verdict(rows: &[GradeRow], submission: &str, scene: &str) -> &'static str {
    let mine = rows
        .iter()
        .filter(|r| r.submission == submission && r.scene == scene);
    let mut verdict = "pass";
    for r in mine {
        verdict = match (verdict, r.result.as_str()) {
            (_, "missing") => "missing",
            ("missing", _) => "missing",
            (_, "unreadable") => "unreadable",
            ("unreadable", _) => "unreadable",
            (_, "refused") => "refused",
            ("refused", _) => "refused",
            (_, "fail") => "fail",
            (v, _) => v,
        };
    }
    verdict
}

/// The table as CSV (one row per observable).
pub fn to_csv(rows: &[GradeRow]) -> Result<String, String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["submission", "scene", "observable", "result", "figure"])
        .map_err(|e| e.to_string())?;
    for r in rows {
        w.write_record([&r.submission, &r.scene, &r.observable, &r.result, &r.figure])
            .map_err(|e| e.to_string())?;
    }
    String::from_utf8(w.into_inner().map_err(|e| e.to_string())?).map_err(|e| e.to_string())
}

/// The table as Markdown: the verdict of each submission for each scene, then every row that
/// did not pass.
pub fn to_markdown(rows: &[GradeRow], scenes: &[String]) -> String {
    let mut names: Vec<&str> = rows.iter().map(|r| r.submission.as_str()).collect();
    names.dedup();
    let mut out = String::from("| submission |");
    for s in scenes {
        out.push_str(&format!(" {s} |"));
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(scenes.len()));
    out.push('\n');
    for n in &names {
        out.push_str(&format!("| {n} |"));
        for s in scenes {
            out.push_str(&format!(" {} |", verdict(rows, n, s)));
        }
        out.push('\n');
    }
    let problems: Vec<&GradeRow> = rows.iter().filter(|r| r.result != "pass").collect();
    if !problems.is_empty() {
        out.push_str(
            "\n| submission | scene | observable | result | figure |\n|---|---|---|---|---|\n",
        );
        for r in problems {
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} |\n",
                r.submission,
                r.scene,
                r.observable,
                r.result,
                r.figure.replace('|', "\\|")
            ));
        }
    }
    out
}
