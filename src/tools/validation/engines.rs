//! The engines `rigidref validate` runs, and the Python side of it: the mirrors
//! (python/mirrors/, compiled into the binary and written next to the report so that the run is
//! reproducible by hand), asked which engines are installed and then run one process per engine.
//! docs/validation.md §"Engines".

use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;

/// An engine a scene can be run in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Engine {
    /// rigidref itself, with the exact (Newton) contact solver: the reference run.
    Rigidref,
    /// The rapier3d mirror (src/verify/references/rapier.rs), in-process.
    Rapier,
    /// MuJoCo, through its Python package.
    Mujoco,
    /// PyBullet (Bullet 3).
    Pybullet,
    /// Drake's MultibodyPlant.
    Drake,
    /// pymunk (Chipmunk2D), for the 2D scenes.
    Pymunk,
}

/// The 3D engines, in report order (rigidref is always run: it is the reference).
pub const ENGINES_3D: [Engine; 4] = [
    Engine::Rapier,
    Engine::Mujoco,
    Engine::Pybullet,
    Engine::Drake,
];

impl Engine {
    /// Its name on the command line and in the report.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Rigidref => "rigidref",
            Engine::Rapier => "rapier",
            Engine::Mujoco => "mujoco",
            Engine::Pybullet => "pybullet",
            Engine::Drake => "drake",
            Engine::Pymunk => "pymunk",
        }
    }

    /// The engine named `name` on the command line (rigidref is not one: it always runs).
    pub fn parse(name: &str) -> Result<Engine, String> {
        [
            Engine::Rapier,
            Engine::Mujoco,
            Engine::Pybullet,
            Engine::Drake,
            Engine::Pymunk,
        ]
        .into_iter()
        .find(|e| e.name() == name)
        .ok_or_else(|| {
            format!("--engines: unknown engine {name:?} (known: rapier, mujoco, pybullet, drake, pymunk)")
        })
    }

    /// Whether it mirrors the 2D block scenes (pymunk) rather than the 3D ones.
    pub fn is_2d(self) -> bool {
        self == Engine::Pymunk
    }

    /// Whether it runs through the Python mirrors.
    pub fn is_python(self) -> bool {
        matches!(
            self,
            Engine::Mujoco | Engine::Pybullet | Engine::Drake | Engine::Pymunk
        )
    }
}

/// Which settings an engine runs with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Settings {
    /// Its documented defaults (only the step, gravity and the scene's model set).
    Default,
    /// What its own documentation recommends for accuracy (docs/validation.md, per engine).
    Accurate,
}

impl Settings {
    /// Both, in report order.
    pub const BOTH: [Settings; 2] = [Settings::Default, Settings::Accurate];

    /// Its name in file names and the report.
    pub fn name(self) -> &'static str {
        match self {
            Settings::Default => "default",
            Settings::Accurate => "accurate",
        }
    }
}

/// Whether an engine can be run here.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EngineStatus {
    /// The engine.
    pub engine: Engine,
    /// Its version when installed.
    pub version: Option<String>,
    /// Why it cannot be run, when it cannot (one line).
    pub missing: Option<String>,
}

/// The mirror files, compiled in: (file name, text).
pub const MIRROR_FILES: [(&str, &str); 7] = [
    ("run.py", include_str!("../../../python/mirrors/run.py")),
    (
        "common.py",
        include_str!("../../../python/mirrors/common.py"),
    ),
    (
        "mujoco_mirror.py",
        include_str!("../../../python/mirrors/mujoco_mirror.py"),
    ),
    (
        "pybullet_mirror.py",
        include_str!("../../../python/mirrors/pybullet_mirror.py"),
    ),
    (
        "drake_mirror.py",
        include_str!("../../../python/mirrors/drake_mirror.py"),
    ),
    (
        "pymunk_mirror.py",
        include_str!("../../../python/mirrors/pymunk_mirror.py"),
    ),
    (
        "rigidref_trace.py",
        include_str!("../../../python/rigidref_trace.py"),
    ),
];

/// Writes the mirror files into `dir` (created), returning the path of `run.py`.
pub fn write_mirrors(dir: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create: {e}", dir.display()))?;
    for (name, text) in MIRROR_FILES {
        let path = dir.join(name);
        std::fs::write(&path, text)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    Ok(dir.join("run.py"))
}

/// Asks `python` which of `engines` (Python ones) are installed, through `run.py probe`. An
/// interpreter that cannot be started makes every engine missing, saying why.
pub fn probe(python: &Path, run_py: &Path, engines: &[Engine]) -> Vec<EngineStatus> {
    let names: Vec<&str> = engines.iter().map(|e| e.name()).collect();
    let missing_all = |why: String| {
        engines
            .iter()
            .map(|&engine| EngineStatus {
                engine,
                version: None,
                missing: Some(why.clone()),
            })
            .collect()
    };
    let output = match Command::new(python)
        .arg(run_py)
        .arg("probe")
        .arg(names.join(","))
        .output()
    {
        Ok(o) => o,
        Err(e) => {
            return missing_all(format!(
                "cannot run the Python interpreter {}: {e}",
                python.display()
            ));
        }
    };
    let stdout = String::from_utf8_lossy(&output.stdout);
    let Some(answer) = stdout
        .lines()
        .rev()
        .find_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
    else {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return missing_all(format!(
            "{} {}: no answer ({})",
            python.display(),
            run_py.display(),
            stderr.lines().last().unwrap_or("no output")
        ));
    };
    engines
        .iter()
        .map(|&engine| {
            let entry = &answer[engine.name()];
            if entry["installed"].as_bool() == Some(true) {
                EngineStatus {
                    engine,
                    version: entry["version"].as_str().map(str::to_string),
                    missing: None,
                }
            } else {
                EngineStatus {
                    engine,
                    version: None,
                    missing: Some(
                        entry["reason"]
                            .as_str()
                            .unwrap_or("not installed")
                            .to_string(),
                    ),
                }
            }
        })
        .collect()
}

/// One mirror run for an engine's jobs file.
#[derive(Clone, Debug, Serialize)]
pub struct Job {
    /// The mirror description.
    pub description: PathBuf,
    /// `default` or `accurate`.
    pub settings: &'static str,
    /// The trace to write.
    pub trace: PathBuf,
    /// The model file to write (settings used, read-back model, or the error).
    pub model: PathBuf,
}

/// Runs `jobs` of `engine` in one Python process (`run.py run JOBS.json`). A job that failed
/// says so in its model file; a process that failed as a whole is an error naming its last line.
pub fn run_python_jobs(
    python: &Path,
    run_py: &Path,
    engine: Engine,
    jobs: &[Job],
    jobs_file: &Path,
) -> Result<(), String> {
    let text = serde_json::json!({"engine": engine.name(), "jobs": jobs});
    std::fs::write(jobs_file, format!("{text:#}\n"))
        .map_err(|e| format!("{}: cannot write: {e}", jobs_file.display()))?;
    let output = Command::new(python)
        .arg(run_py)
        .arg("run")
        .arg(jobs_file)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(format!(
            "{}: the {} mirror failed: {}",
            jobs_file.display(),
            engine.name(),
            stderr.lines().last().unwrap_or("no message")
        ));
    }
    Ok(())
}
