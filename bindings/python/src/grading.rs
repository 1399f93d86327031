//! `compare_traces` and `grade`: the library's `tools::grading::compare` and `tools::grading::grade`, the same
//! verdicts and numbers as `rigidref compare` and `rigidref grade`, as Python dicts.

use crate::errors;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rigidref::common::scene_json::Overrides;
use rigidref::tools::grading::compare::{
    AnyTrace, OutcomeTolerances, OutcomeTolerances2, TrajectoryTolerances, compare_outcomes,
    compare_outcomes_2d, compare_trajectories, compare_trajectories_2d, outcome_scene,
    outcome_scene_2d, read_trace_any, read_trace_of,
};
use rigidref::tools::grading::grade::{
    GradeMode, Limits, grade_all, load_references, submission_name, submissions, verdict,
};
use std::path::PathBuf;

/// A serialisable value as Python objects (dicts, lists, floats, str), through JSON.
fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| errors::trace(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Compares a candidate trace with the reference trace, as `rigidref compare` does: mode
/// "trajectory" (every quantity over time, to `tolerance`: m, rad, m/s, rad/s and relative for
/// energies and momenta; a 2D trace in blocks and time units, bodies matched by the image) or
/// "outcome" (what happened; `scene` gives the bodies' sizes and symmetries: a 3D scene
/// file, or for 2D traces the image or 2D scene file; by default the scene the reference
/// names). Returns the report as a dict: "agree"
/// (bool), "mode", "refused" (None, or {"kind", "message"} when the candidate cannot be judged:
/// too short, degenerate, other bodies, non-finite), "errors" (trajectory mode) and "outcomes"
/// (outcome mode). Raises TraceError when a trace cannot be read.
#[pyfunction]
#[pyo3(signature = (reference, candidate, mode = "trajectory", tolerance = 1e-3, scene = None))]
pub fn compare_traces<'py>(
    py: Python<'py>,
    reference: PathBuf,
    candidate: PathBuf,
    mode: &str,
    tolerance: f64,
    scene: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(errors::trace(format!(
            "--tolerance must be positive, got {tolerance}"
        )));
    }
    let against = |e: String| {
        errors::trace(format!(
            "{} against {}: {e}",
            candidate.display(),
            reference.display()
        ))
    };
    // Read as `rigidref compare` reads them: regular files within the input limit, the other
    // of the reference's system.
    let limit = rigidref::common::input::max_input_bytes();
    let reference_trace =
        read_trace_any(&reference, limit, "--max-input-mb").map_err(errors::trace)?;
    let wanted = reference_trace.dimension();
    let because = format!("the reference is {wanted}D");
    let other = read_trace_of(&candidate, wanted, &because, limit, "--max-input-mb")
        .map_err(errors::trace)?;
    // 2D traces (the image-block system): bodies matched by the image, as `rigidref compare`
    // does.
    if let (AnyTrace::Two(reference_trace), AnyTrace::Two(other)) = (&reference_trace, &other) {
        let (reference_trace, other) = (reference_trace.clone(), other.clone());
        let comparison = match mode {
            "trajectory" => {
                let tol = TrajectoryTolerances::uniform(tolerance);
                py.detach(|| compare_trajectories_2d(&reference_trace, &other, &tol))
                    .map_err(against)?
            }
            "outcome" => {
                let shapes = outcome_scene_2d(&reference_trace, &reference, scene.as_deref())
                    .map_err(|e| errors::trace(format!("--scene: {e}")))?;
                py.detach(|| {
                    compare_outcomes_2d(
                        &reference_trace,
                        &other,
                        shapes.as_ref().map(|(b, _)| b.as_slice()),
                        &OutcomeTolerances2::default(),
                    )
                })
                .map_err(against)?
            }
            m => {
                return Err(errors::trace(format!(
                    "mode {m:?}: expected \"trajectory\" or \"outcome\""
                )));
            }
        };
        let d = to_python(py, &comparison)?;
        d.set_item("notes", Vec::<String>::new())?;
        d.set_item("first_failure", comparison.first_failure())?;
        return Ok(d);
    }
    let (AnyTrace::Three(reference_trace), AnyTrace::Three(other)) = (reference_trace, other)
    else {
        unreachable!("read_trace_of checked the dimension")
    };
    let comparison = match mode {
        "trajectory" => {
            let tol = TrajectoryTolerances::uniform(tolerance);
            py.detach(|| compare_trajectories(&reference_trace, &other, &tol))
                .map_err(against)?
        }
        "outcome" => {
            let scene = outcome_scene(&reference_trace, &reference, scene.as_deref())
                .map_err(|e| errors::trace(format!("--scene: {e}")))?;
            py.detach(|| {
                compare_outcomes(
                    &reference_trace,
                    &other,
                    scene.as_ref().map(|(s, _)| s),
                    &OutcomeTolerances::default(),
                )
            })
            .map_err(against)?
        }
        m => {
            return Err(errors::trace(format!(
                "mode {m:?}: expected \"trajectory\" or \"outcome\""
            )));
        }
    };
    let d = to_python(py, &comparison)?;
    let notes: Vec<String> = reference_trace
        .notes
        .iter()
        .chain(&other.notes)
        .cloned()
        .collect();
    d.set_item("notes", notes)?;
    if let Some(first) = comparison.first_failure() {
        d.set_item("first_failure", first)?;
    } else {
        d.set_item("first_failure", py.None())?;
    }
    Ok(d)
}

/// Grades a folder of submission folders against reference runs of `scenes` (3D scene files, 2D
/// images or 2D scene files, mixed as needed, each naming the submissions' files SCENE.jsonl by
/// its stem), as `rigidref grade` does: `time` of simulation per reference (s in 3D, time units
/// in 2D), mode "trajectory" or "outcome", `overrides` (the
/// `--set` pairs) applied to every scene, `max_file_mb` the largest file opened, `jobs` threads.
/// Returns {"rows": [{"submission", "scene", "observable", "result", "figure"}, ...],
/// "verdicts": {submission: {scene: "pass" | "fail" | "refused" | "missing" | "unreadable"}}}.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (submissions_dir, scenes, time = 5.0, mode = "trajectory", overrides = None, max_file_mb = 512, jobs = None))]
pub fn grade<'py>(
    py: Python<'py>,
    submissions_dir: PathBuf,
    scenes: Vec<PathBuf>,
    time: f64,
    mode: &str,
    overrides: Option<&Bound<'_, PyDict>>,
    max_file_mb: u64,
    jobs: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = match mode {
        "trajectory" => GradeMode::Trajectory,
        "outcome" => GradeMode::Outcome,
        m => {
            return Err(errors::trace(format!(
                "mode {m:?}: expected \"trajectory\" or \"outcome\""
            )));
        }
    };
    let folders = submissions(&submissions_dir).map_err(errors::trace)?;
    if folders.is_empty() {
        return Err(errors::trace(format!(
            "{}: no submission folders",
            submissions_dir.display()
        )));
    }
    let overrides =
        Overrides::parse(&crate::world::override_texts(overrides)?).map_err(errors::scene)?;
    let references = py
        .detach(|| load_references(&scenes, &overrides, time))
        .map_err(errors::scene)?;
    let threads =
        jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let limits = Limits {
        max_file_bytes: max_file_mb.saturating_mul(1 << 20),
    };
    let rows = py.detach(|| grade_all(&folders, &references, mode, threads, &limits));
    let out = PyDict::new(py);
    out.set_item("rows", to_python(py, &rows)?)?;
    let verdicts = PyDict::new(py);
    for folder in &folders {
        // The name as the rows give it: byte for byte (a byte that is not UTF-8 as \xNN).
        let name = submission_name(folder);
        let per_scene = PyDict::new(py);
        for r in &references {
            per_scene.set_item(&r.name, verdict(&rows, &name, &r.name))?;
        }
        verdicts.set_item(name, per_scene)?;
    }
    out.set_item("verdicts", verdicts)?;
    Ok(out)
}
