//! `rigidref validate`: rigidref as the yardstick for other simulators (docs/validation.md).
//!
//! Each known-answer scene ([`scenes`]) is converted once into a mirror description
//! ([`mirror`]) and run in every engine asked for ([`engines`]: rapier in-process, MuJoCo,
//! PyBullet and Drake through the Python mirrors), each with its documented defaults and with the
//! settings its documentation recommends for accuracy, and in rigidref with the exact (Newton)
//! solver ([`runs`]). Every run writes a rigidref trace; every trace is measured by the same code
//! ([`observe`]) and judged against the closed forms ([`judge`]) and against rigidref's run; the
//! report ([`report`]) is Markdown, JSON and SVG plots. Engines that are not installed are
//! reported as such, never dropped.

pub mod engines;
pub mod judge;
pub mod mirror;
pub mod observe;
pub mod report;
pub mod runs;
pub mod scenes;
pub mod two_d;

use engines::{Engine, EngineStatus, Job, Settings};
use judge::Expected;
use mirror::MirrorScene;
use observe::Measured;
use scenes::{KnownScene, SCENES_3D};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What `rigidref validate` is asked to do.
#[derive(Clone, Debug)]
pub struct ValidateOptions {
    /// The engines besides rigidref (which always runs: it is the reference).
    pub engines: Vec<Engine>,
    /// Scene names of the known-answer set (`sliding_cube`, …); empty: all of them.
    pub scenes: Vec<String>,
    /// The folder holding the scenes (the repository's `scenes/`).
    pub scene_dir: PathBuf,
    /// Where the report, traces and mirrors go (created).
    pub out: PathBuf,
    /// The Python interpreter that has the engines.
    pub python: PathBuf,
}

/// How a run went.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "status", content = "why", rename_all = "snake_case")]
pub enum RunStatus {
    /// It ran; its trace is measured.
    Ran,
    /// The engine is not installed (why, in one line).
    NotInstalled(String),
    /// It failed (one line).
    Failed(String),
    /// Not run yet: a report written while the validation runs (or left by one that stopped
    /// midway) lists the runs still to come so.
    Pending,
}

/// One engine × settings on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct RunResult {
    /// The engine.
    pub engine: Engine,
    /// Its settings (`None` for rigidref's reference run).
    pub settings: Option<Settings>,
    /// How it went.
    pub status: RunStatus,
    /// Its trace, relative to the output folder.
    pub trace: Option<String>,
    /// The engine's settings as applied and its model read back (the Python mirrors' model file;
    /// rapier's settings).
    pub model: Option<serde_json::Value>,
    /// The observables.
    pub measured: Vec<MeasuredJudged>,
    /// Its plotted series (each observable against time), drawn into the scene's SVG (not in
    /// the JSON).
    #[serde(skip)]
    pub plotted: Option<crate::tools::viewing::plot::PlottedRun>,
}

/// A measured value with its judgement.
#[derive(Clone, Debug, Serialize)]
pub struct MeasuredJudged {
    /// The observable's key.
    pub key: &'static str,
    /// The value.
    pub value: Option<f64>,
    /// value − the closed form's value.
    pub error: Option<f64>,
    /// value − rigidref's value.
    pub versus_rigidref: Option<f64>,
    /// Within the tolerance of the closed form (`None`: reported only).
    pub passed: Option<bool>,
}

impl RunResult {
    /// The label of the run in tables and legends: `mujoco (default)`, `rigidref (Newton)`.
    pub fn label(&self) -> String {
        match self.settings {
            Some(s) => format!("{} ({})", self.engine.name(), s.name()),
            None => format!("{} (Newton)", self.engine.name()),
        }
    }

    /// (passed, judged) over the observables with a tolerance.
    pub fn score(&self) -> (usize, usize) {
        let judged: Vec<bool> = self.measured.iter().filter_map(|m| m.passed).collect();
        (judged.iter().filter(|p| **p).count(), judged.len())
    }
}

/// One scene's results.
#[derive(Clone, Debug, Serialize)]
pub struct SceneResult {
    /// The scene file's name.
    pub file: String,
    /// The scene's own name.
    pub name: String,
    /// The scene file as read.
    pub source: String,
    /// 3 (a mesh scene) or 2 (a 2D block scene).
    pub dimension: u32,
    /// Frames run, and the frame step (s).
    pub frames: u64,
    /// Frame step, s.
    pub dt: f64,
    /// The observables' expectations.
    pub expected: Vec<Expected>,
    /// rigidref's run first, then each engine × settings.
    pub runs: Vec<RunResult>,
}

/// The whole validation.
#[derive(Clone, Debug, Serialize)]
pub struct Validation {
    /// Each engine asked for: its version or why it is missing.
    pub engines: Vec<EngineStatus>,
    /// Each scene.
    pub scenes: Vec<SceneResult>,
}

/// The scenes to run: those named, else the 3D set when a 3D engine (or none) is asked for and
/// the 2D set when pymunk is.
fn scene_list(
    names: &[String],
    engines: &[Engine],
) -> Result<(Vec<KnownScene>, Vec<two_d::KnownScene2>), String> {
    if names.is_empty() {
        let three = engines.is_empty() || engines.iter().any(|e| !e.is_2d());
        let two = engines.iter().any(|e| e.is_2d());
        return Ok((
            if three {
                SCENES_3D.to_vec()
            } else {
                Vec::new()
            },
            if two {
                two_d::SCENES_2D.to_vec()
            } else {
                Vec::new()
            },
        ));
    }
    let (mut three, mut two) = (Vec::new(), Vec::new());
    for n in names {
        if let Some(k) = scenes::known_scene(n) {
            three.push(k);
        } else if let Some(k) = two_d::known_scene2(n) {
            two.push(k);
        } else {
            let known: Vec<&str> = SCENES_3D
                .iter()
                .map(|s| s.file.trim_end_matches(".json"))
                .chain(two_d::SCENES_2D.iter().map(|s| two_d::stem(s.file)))
                .collect();
            return Err(format!(
                "--scenes: {n:?} is not a known-answer scene (known: {})",
                known.join(", ")
            ));
        }
    }
    Ok((three, two))
}

/// A Python mirror's model file: its content, or the error it records.
fn read_model(model_path: &Path) -> Result<Option<serde_json::Value>, String> {
    std::fs::read_to_string(model_path)
        .map_err(|e| format!("{}: not written: {e}", model_path.display()))
        .and_then(|t| {
            serde_json::from_str::<serde_json::Value>(&t)
                .map_err(|e| format!("{}: {e}", model_path.display()))
        })
        .and_then(|v| match v["error"].as_str() {
            Some(err) => Err(err.to_string()),
            None => Ok(Some(v)),
        })
}

fn create(dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create: {e}", dir.display()))
}

fn relative(out: &Path, path: &Path) -> String {
    path.strip_prefix(out).unwrap_or(path).display().to_string()
}

/// Reads a trace and measures it.
fn measure(
    scene: &crate::rigid3d::scene::Scene,
    known: &KnownScene,
    path: &Path,
) -> Result<(Vec<Measured>, crate::rigid3d::trace::Trace), String> {
    let trace = crate::rigid3d::trace::read_trace_file(path)?;
    let measured = observe::observe(scene, known, &trace)?;
    Ok((measured, trace))
}

fn judged(
    expected: &[Expected],
    measured: &[Measured],
    reference: &[Measured],
) -> Vec<MeasuredJudged> {
    measured
        .iter()
        .map(|m| {
            let exp = expected.iter().find(|e| e.key == m.key);
            let exact = exp.and_then(|e| e.exact);
            let error = m.value.zip(exact).map(|(v, x)| v - x);
            let passed = exp
                .and_then(|e| e.tolerance)
                .map(|tol| error.is_some_and(|e| e.abs() <= tol));
            let theirs = reference
                .iter()
                .find(|r| r.key == m.key)
                .and_then(|r| r.value);
            MeasuredJudged {
                key: m.key,
                value: m.value,
                error,
                versus_rigidref: m.value.zip(theirs).map(|(a, b)| a - b),
                passed,
            }
        })
        .collect()
}

/// A run not yet done: rigidref's reference run is done first, then each engine in turn, so a
/// report written midway lists the rest as pending.
fn pending(engine: Engine, settings: Settings, status: &EngineStatus) -> RunResult {
    let status = match &status.missing {
        Some(why) => RunStatus::NotInstalled(why.clone()),
        None => RunStatus::Pending,
    };
    RunResult {
        engine,
        settings: Some(settings),
        status,
        trace: None,
        model: None,
        measured: Vec::new(),
        plotted: None,
    }
}

/// The measured values of a scene's reference run (its first), as measured.
fn reference_of(scene: &SceneResult) -> Vec<Measured> {
    scene.runs[0]
        .measured
        .iter()
        .map(|m| Measured {
            key: m.key,
            value: m.value,
        })
        .collect()
}

/// Puts `run` in its row of `scene` (the engine × settings row written pending).
fn place(scene: &mut SceneResult, run: RunResult) {
    if let Some(slot) = scene
        .runs
        .iter_mut()
        .find(|r| r.engine == run.engine && r.settings == run.settings)
    {
        *slot = run;
    }
}

/// Runs the validation and writes its report (report.md, report.json, plots/) into
/// `options.out`. The report is rewritten after every run (rigidref's reference run of each scene
/// first, then each engine's runs scene by scene, each Python engine after its one process), so a
/// validation that stops midway leaves every run finished so far, the rest marked pending
/// (docs/validation.md §"The report").
pub fn validate(options: &ValidateOptions) -> Result<Validation, String> {
    let (known, known_2d) = scene_list(&options.scenes, &options.engines)?;
    let out = &options.out;
    create(out)?;
    let python_engines: Vec<Engine> = options
        .engines
        .iter()
        .copied()
        .filter(|e| e.is_python())
        .collect();
    let mut statuses: Vec<EngineStatus> = Vec::new();
    let run_py = engines::write_mirrors(&out.join("mirrors"))?;
    let probed = if python_engines.is_empty() {
        Vec::new()
    } else {
        engines::probe(&options.python, &run_py, &python_engines)
    };
    let mut asked: Vec<Engine> = Vec::new();
    for &engine in &options.engines {
        if !asked.contains(&engine) {
            asked.push(engine);
        }
    }
    for &engine in &asked {
        if engine == Engine::Rapier {
            statuses.push(EngineStatus {
                engine,
                version: Some("rapier3d-f64 0.36.1 (built in)".into()),
                missing: None,
            });
        } else if let Some(s) = probed.iter().find(|s| s.engine == engine) {
            statuses.push(s.clone());
        }
    }
    // Load every scene and write its description.
    create(&out.join("descriptions"))?;
    let mut loaded = Vec::new();
    for k in &known {
        let path = options.scene_dir.join(k.file);
        if !path.is_file() {
            return Err(format!(
                "{}: not found (give the folder of rigidref's scenes with --scene-dir)",
                path.display()
            ));
        }
        let scene = crate::rigid3d::scene::load_scene(&path).map_err(|e| e.to_string())?;
        let frames = crate::sim::steps_in(k.seconds, scene.params.dt, " s")?;
        let stem = k.file.trim_end_matches(".json");
        let description = MirrorScene::of_scene(&scene, stem, frames)?;
        let dpath = out.join("descriptions").join(format!("{stem}.mirror.json"));
        let text = serde_json::to_string_pretty(&description).map_err(|e| e.to_string())?;
        std::fs::write(&dpath, text + "\n")
            .map_err(|e| format!("{}: cannot write: {e}", dpath.display()))?;
        loaded.push((*k, scene, frames, dpath));
    }
    let loaded_2d = known_2d
        .iter()
        .map(|k| two_d::load(*k, &options.scene_dir, &out.join("descriptions")))
        .collect::<Result<Vec<_>, String>>()?;
    let mut v = Validation {
        engines: statuses.clone(),
        scenes: Vec::new(),
    };
    // rigidref's reference runs, every other row pending.
    for (k, scene, frames, _) in &loaded {
        let stem = k.file.trim_end_matches(".json");
        let expected = judge::expectations(scene, k);
        let dir = out.join("traces").join("rigidref");
        create(&dir)?;
        let path = dir.join(format!("{stem}.jsonl"));
        runs::run_rigidref(scene, *frames, &path)?;
        let (reference, trace) = measure(scene, k, &path)?;
        let mut runs: Vec<RunResult> = vec![RunResult {
            engine: Engine::Rigidref,
            settings: None,
            status: RunStatus::Ran,
            trace: Some(relative(out, &path)),
            model: None,
            measured: judged(&expected, &reference, &reference),
            plotted: Some(report::plotted_3d(
                format!("{} (Newton)", Engine::Rigidref.name()),
                &trace,
                scene,
            )),
        }];
        for status in statuses.iter().filter(|s| !s.engine.is_2d()) {
            runs.extend(Settings::BOTH.map(|settings| pending(status.engine, settings, status)));
        }
        v.scenes.push(SceneResult {
            file: k.file.to_string(),
            name: scene.params.name.clone(),
            source: options.scene_dir.join(k.file).display().to_string(),
            dimension: 3,
            frames: *frames,
            dt: scene.params.dt,
            expected,
            runs,
        });
        report::write_progress(&v, v.scenes.len() - 1, out)?;
    }
    let statuses_2d: Vec<EngineStatus> = statuses
        .iter()
        .filter(|s| s.engine.is_2d())
        .cloned()
        .collect();
    for l in &loaded_2d {
        let mut scene = two_d::reference(l, out)?;
        for status in &statuses_2d {
            scene
                .runs
                .extend(Settings::BOTH.map(|settings| pending(status.engine, settings, status)));
        }
        v.scenes.push(scene);
        report::write_progress(&v, v.scenes.len() - 1, out)?;
    }
    let first_2d = loaded.len();
    // Each engine in turn: its runs measured and written one by one.
    for status in statuses.iter().filter(|s| s.missing.is_none()) {
        let engine = status.engine;
        let mut failure: Option<String> = None;
        if engine.is_python() {
            let mut jobs = Vec::new();
            for settings in Settings::BOTH {
                let dir = out
                    .join("traces")
                    .join(format!("{}-{}", engine.name(), settings.name()));
                create(&dir)?;
                let described: Vec<(&str, &PathBuf)> = if engine.is_2d() {
                    loaded_2d
                        .iter()
                        .map(|l| (two_d::stem(l.known.file), &l.description))
                        .collect()
                } else {
                    loaded
                        .iter()
                        .map(|(k, _, _, d)| (k.file.trim_end_matches(".json"), d))
                        .collect()
                };
                for (stem, dpath) in described {
                    jobs.push(Job {
                        description: std::fs::canonicalize(dpath).unwrap_or(dpath.clone()),
                        settings: settings.name(),
                        trace: dir.join(format!("{stem}.jsonl")),
                        model: dir.join(format!("{stem}.model.json")),
                    });
                }
            }
            if jobs.is_empty() {
                continue;
            }
            let jobs_file = out
                .join("traces")
                .join(format!("{}-jobs.json", engine.name()));
            failure =
                engines::run_python_jobs(&options.python, &run_py, engine, &jobs, &jobs_file).err();
        }
        if engine.is_2d() {
            for (i, l) in loaded_2d.iter().enumerate() {
                for settings in Settings::BOTH {
                    let scene = &mut v.scenes[first_2d + i];
                    let run =
                        two_d::engine_run(l, scene, engine, settings, failure.as_deref(), out);
                    place(scene, run);
                    report::write_progress(&v, first_2d + i, out)?;
                }
            }
            continue;
        }
        for (i, (k, scene, frames, _)) in loaded.iter().enumerate() {
            let stem = k.file.trim_end_matches(".json");
            for settings in Settings::BOTH {
                let mut run = RunResult {
                    engine,
                    settings: Some(settings),
                    status: RunStatus::Ran,
                    trace: None,
                    model: None,
                    measured: Vec::new(),
                    plotted: None,
                };
                let dir = out
                    .join("traces")
                    .join(format!("{}-{}", engine.name(), settings.name()));
                create(&dir)?;
                let path = dir.join(format!("{stem}.jsonl"));
                let outcome: Result<Option<serde_json::Value>, String> = if engine == Engine::Rapier
                {
                    runs::run_rapier(scene, settings, *frames, &path).map(Some)
                } else if let Some(e) = &failure {
                    Err(e.clone())
                } else {
                    read_model(&dir.join(format!("{stem}.model.json")))
                };
                let result = &mut v.scenes[i];
                match outcome.and_then(|model| measure(scene, k, &path).map(|m| (model, m))) {
                    Ok((model, (measured, trace))) => {
                        run.model = model;
                        run.trace = Some(relative(out, &path));
                        run.measured = judged(&result.expected, &measured, &reference_of(result));
                        run.plotted = Some(report::plotted_3d(run.label(), &trace, scene));
                    }
                    Err(e) => run.status = RunStatus::Failed(e),
                }
                place(result, run);
                report::write_progress(&v, i, out)?;
            }
        }
    }
    report::write_report(&v, out)?;
    Ok(v)
}
