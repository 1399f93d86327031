//! `rigidref.validate`: other engines on the known-answer scenes, judged against the closed forms
//! and rigidref's exact run, as `rigidref validate` does (docs/validation.md).

use crate::errors;
use pyo3::prelude::*;
use rigidref::tools::validation::engines::{ENGINES_3D, Engine};
use rigidref::tools::validation::{ValidateOptions, validate as run_validation};
use std::path::PathBuf;

/// Runs the mirrors and judges them, as `rigidref validate` does: `out` (a folder, created) gets
/// report.md, report.json, plots/ and every run's trace; `engines` are names ("rapier",
/// "mujoco", "pybullet", "drake" for the 3D scenes, "pymunk" for the 2D ones; default the four
/// 3D engines), `scenes` names of the known-answer set (default: every scene of the engines'
/// set), `scene_dir` the folder holding rigidref's scenes, `python` the interpreter that has the
/// engines (default: this one, `sys.executable`). Returns report.json's content as a dict; an
/// engine that is not installed is reported in it, never dropped. Raises `SceneError` for an
/// unknown engine or scene.
#[pyfunction]
#[pyo3(signature = (out, engines = None, scenes = None, scene_dir = PathBuf::from("scenes"), python = None))]
pub fn validate<'py>(
    py: Python<'py>,
    out: PathBuf,
    engines: Option<Vec<String>>,
    scenes: Option<Vec<String>>,
    scene_dir: PathBuf,
    python: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let engines = match engines {
        None => ENGINES_3D.to_vec(),
        Some(names) => names
            .iter()
            .map(|n| Engine::parse(n.trim()))
            .collect::<Result<Vec<_>, String>>()
            .map_err(errors::scene)?,
    };
    let python = match python {
        Some(p) => p,
        None => py
            .import("sys")?
            .getattr("executable")?
            .extract::<PathBuf>()?,
    };
    let options = ValidateOptions {
        engines,
        scenes: scenes.unwrap_or_default(),
        scene_dir,
        out,
        python,
    };
    let report = py
        .detach(|| run_validation(&options))
        .map_err(errors::scene)?;
    let text = serde_json::to_string(&report).map_err(errors::scene)?;
    py.import("json")?.call_method1("loads", (text,))
}
