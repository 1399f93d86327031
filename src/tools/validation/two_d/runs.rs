//! A 2D scene's runs, measured and judged: rigidref's reference run, each engine's run, and the
//! series of the scene's plot. docs/validation.md §"2D: pymunk" and §"The report".

use super::*;
use crate::blocks2d::trace::Record2;
use crate::tools::validation::engines::{Engine, Settings};
use crate::tools::validation::{RunResult, RunStatus, SceneResult};
use crate::tools::viewing::plot::{PlottedRun, TIME_UNIT_2D};
use crate::tools::viewing::series::{Plot, Series};
use std::path::Path;

/// rigidref's exact run of a 2D scene, measured and judged: the scene's result with that one run
/// (the engines' rows are added to it by [`engine_run`]).
pub fn reference(l: &Loaded2, out: &Path) -> Result<SceneResult, String> {
    let name = stem(l.known.file);
    let dir = out.join("traces").join("rigidref");
    crate::tools::validation::create(&dir)?;
    let path = dir.join(format!("{name}.jsonl"));
    run_rigidref_2d(l, &path)?;
    let records = read_trace_2d(&path, l.world.bodies.len())?;
    let reference = observe_2d(l, &records);
    let expected = expectations_2d(l, &reference);
    let run = RunResult {
        engine: Engine::Rigidref,
        settings: None,
        status: RunStatus::Ran,
        trace: Some(crate::tools::validation::relative(out, &path)),
        model: None,
        measured: crate::tools::validation::judged(&expected, &reference, &reference),
        plotted: Some(plotted_2d(
            format!("{} (Newton)", Engine::Rigidref.name()),
            &records,
            l,
        )),
    };
    Ok(SceneResult {
        file: format!("{name}.json"),
        name: name.to_string(),
        source: l.path.display().to_string(),
        dimension: 2,
        frames: l.frames,
        dt: l.world.params.dt,
        expected,
        runs: vec![run],
    })
}

/// A 2D engine's run of `settings` on `l` (its trace already written by the Python mirror under
/// `out/traces/ENGINE-SETTINGS/`), measured and judged against `scene`'s expectations and
/// rigidref's run; `failure`: the engine's process failed as a whole.
pub fn engine_run(
    l: &Loaded2,
    scene: &SceneResult,
    engine: Engine,
    settings: Settings,
    failure: Option<&str>,
    out: &Path,
) -> RunResult {
    let name = stem(l.known.file);
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
    let path = dir.join(format!("{name}.jsonl"));
    let model_path = dir.join(format!("{name}.model.json"));
    let outcome = match failure {
        Some(e) => Err(e.to_string()),
        None => crate::tools::validation::read_model(&model_path),
    };
    match outcome.and_then(|model| read_trace_2d(&path, l.world.bodies.len()).map(|r| (model, r))) {
        Ok((model, records)) => {
            run.model = model;
            run.trace = Some(crate::tools::validation::relative(out, &path));
            run.measured = crate::tools::validation::judged(
                &scene.expected,
                &observe_2d(l, &records),
                &crate::tools::validation::reference_of(scene),
            );
            run.plotted = Some(plotted_2d(run.label(), &records, l));
        }
        Err(e) => run.status = RunStatus::Failed(e),
    }
    run
}

/// The panels of a 2D scene's plot: what its observables are measured from.
pub const PANELS_2D: [(&str, &str, &str); 5] = [
    (
        "position",
        "largest displacement of a body from its start",
        "blocks",
    ),
    ("speed", "largest speed of a body", "blocks/time"),
    ("angle", "largest |θ| of a body", "rad"),
    (
        "penetration",
        "deepest disc overlap (rigidref's detection)",
        "blocks",
    ),
    ("energy", "total energy", "mass·block²/time²"),
];

/// A 2D run's series for the scene's plot ([`PANELS_2D`], bodies that are not pinned), each
/// against time: the quantities its observables are measured from. docs/validation.md
/// §"The report".
pub fn plotted_2d(label: String, records: &[Record2], l: &Loaded2) -> PlottedRun {
    let moving: Vec<usize> = (0..l.world.bodies.len())
        .filter(|&i| !l.world.bodies[i].pinned)
        .collect();
    let Some(first) = records.first() else {
        return PlottedRun {
            label,
            t: Vec::new(),
            time_unit: TIME_UNIT_2D,
            plots: Vec::new(),
        };
    };
    let largest = |r: &Record2, f: &dyn Fn(&Record2, usize) -> f64| {
        moving.iter().map(|&i| f(r, i)).fold(0.0, f64::max)
    };
    let mut world = l.world.clone();
    let mut contacts = Vec::new();
    let values: [Vec<Option<f64>>; 5] = [
        records
            .iter()
            .map(|r| {
                Some(largest(r, &|r, i| {
                    let (a, b) = (r.bodies[i].x, first.bodies[i].x);
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
                }))
            })
            .collect(),
        records
            .iter()
            .map(|r| {
                Some(largest(r, &|r, i| {
                    (r.bodies[i].v[0].powi(2) + r.bodies[i].v[1].powi(2)).sqrt()
                }))
            })
            .collect(),
        records
            .iter()
            .map(|r| Some(largest(r, &|r, i| r.bodies[i].theta.abs())))
            .collect(),
        records
            .iter()
            .map(|r| Some(overlap_at(&mut world, r, &mut contacts)))
            .collect(),
        records.iter().map(|r| Some(r.energy.total)).collect(),
    ];
    let plots = PANELS_2D
        .iter()
        .zip(values)
        .map(|(&(key, title, unit), values)| Plot {
            key,
            title: title.into(),
            unit: unit.into(),
            log: false,
            series: vec![Series {
                name: String::new(),
                values,
            }],
        })
        .collect();
    PlottedRun {
        label,
        t: records.iter().map(|r| r.t).collect(),
        time_unit: TIME_UNIT_2D,
        plots,
    }
}
