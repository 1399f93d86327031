//! The report of `rigidref validate`: report.md (the headline table, then each scene's
//! observables per run, the engines' settings), report.json (everything, machine-readable) and one
//! SVG per scene with each observable against time, the runs overlaid (docs/validation.md
//! §"The report").

use super::{RunStatus, SceneResult, Validation};
use crate::rigid3d::trace::Trace;
use crate::tools::viewing::plot::{PlottedRun, TIME_UNIT_3D, plot_runs};
use crate::tools::viewing::series::{Plot, Series};
use std::fmt::Write as _;
use std::path::Path;

fn number(v: Option<f64>) -> String {
    match v {
        None => "–".into(),
        Some(v) if v == 0.0 => "0".into(),
        Some(v) if v.abs() >= 1e-3 && v.abs() < 1e4 => format!("{v:.4}"),
        Some(v) => format!("{v:.3e}"),
    }
}

fn cell(run: &super::RunResult) -> String {
    match &run.status {
        RunStatus::NotInstalled(_) => "not installed".into(),
        RunStatus::Failed(_) => "failed".into(),
        RunStatus::Pending => "pending".into(),
        RunStatus::Ran => {
            let (passed, judged) = run.score();
            format!(
                "{passed}/{judged}{}",
                if passed == judged { " ✓" } else { " ✗" }
            )
        }
    }
}

/// The Markdown report.
pub fn markdown(v: &Validation) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# rigidref validate\n");
    let _ = writeln!(
        s,
        "Every scene of the known-answer set run in each engine (with its documented defaults and with the settings its documentation recommends for accuracy) and in rigidref (the exact Newton solver), each run measured on its trace by the same code and judged against the closed forms (docs/validation.md).\n"
    );
    let _ = writeln!(
        s,
        "## Engines\n\n| engine | version or why not |\n|---|---|"
    );
    let _ = writeln!(s, "| rigidref | this build (solver: newton) |");
    for e in &v.engines {
        let what = match (&e.version, &e.missing) {
            (Some(ver), None) => ver.clone(),
            (_, Some(why)) => format!("**not installed**: {why}"),
            _ => String::new(),
        };
        let _ = writeln!(s, "| {} | {what} |", e.engine.name());
    }
    for dimension in [3, 2] {
        let scenes: Vec<&super::SceneResult> = v
            .scenes
            .iter()
            .filter(|s| s.dimension == dimension)
            .collect();
        let Some(first) = scenes.first() else {
            continue;
        };
        let what = if dimension == 3 {
            "3D scenes"
        } else {
            "2D scenes (docs/validation.md §\"2D: pymunk\"; judged against the closed form where the disc model has one, else rigidref's exact run)"
        };
        let _ = writeln!(
            s,
            "\n## Headline, {what}: observables within tolerance (passed/judged)\n"
        );
        let labels: Vec<String> = first.runs.iter().map(|r| r.label()).collect();
        let _ = writeln!(s, "| scene | {} |", labels.join(" | "));
        let _ = writeln!(s, "|---|{}", "---|".repeat(labels.len()));
        for scene in &scenes {
            let cells: Vec<String> = scene.runs.iter().map(cell).collect();
            let _ = writeln!(
                s,
                "| {} | {} |",
                scene.file.trim_end_matches(".json"),
                cells.join(" | ")
            );
        }
    }
    for scene in &v.scenes {
        let _ = writeln!(
            s,
            "\n## {} — {}\n",
            scene.file.trim_end_matches(".json"),
            scene.name
        );
        let stem = scene.file.trim_end_matches(".json");
        let unit = if scene.dimension == 2 {
            "time units"
        } else {
            "s"
        };
        let _ = writeln!(
            s,
            "{} steps of {} {unit}. Plots: [`plots/{stem}.svg`](plots/{stem}.svg).\n",
            scene.frames, scene.dt
        );
        let labels: Vec<String> = scene.runs.iter().map(|r| r.label()).collect();
        let _ = writeln!(
            s,
            "| observable | closed form | tolerance | {} |",
            labels.join(" | ")
        );
        let _ = writeln!(s, "|---|---|---|{}", "---|".repeat(labels.len()));
        for e in &scene.expected {
            let unit = if e.unit.is_empty() {
                String::new()
            } else {
                format!(" ({})", e.unit)
            };
            let values: Vec<String> = scene
                .runs
                .iter()
                .map(|r| match &r.status {
                    RunStatus::Ran => r
                        .measured
                        .iter()
                        .find(|m| m.key == e.key)
                        .map(|m| {
                            let mark = match m.passed {
                                Some(true) => " ✓",
                                Some(false) => " ✗",
                                None => "",
                            };
                            format!("{}{mark}", number(m.value))
                        })
                        .unwrap_or_else(|| "–".into()),
                    _ => "–".into(),
                })
                .collect();
            let _ = writeln!(
                s,
                "| {}{unit} | {} | {} | {} |",
                e.name,
                number(e.exact),
                number(e.tolerance),
                values.join(" | ")
            );
        }
        let _ = writeln!(s);
        for e in &scene.expected {
            let _ = writeln!(s, "- {}: {}", e.name, e.note);
        }
        for r in &scene.runs {
            match &r.status {
                RunStatus::Failed(why) | RunStatus::NotInstalled(why) => {
                    let _ = writeln!(s, "- {}: {why}", r.label());
                }
                RunStatus::Pending => {
                    let _ = writeln!(
                        s,
                        "- {}: pending (not run yet: the validation is running, or stopped before it)",
                        r.label()
                    );
                }
                RunStatus::Ran => {}
            }
        }
    }
    let _ = writeln!(s, "\n## Settings as applied\n");
    let _ = writeln!(
        s,
        "Each engine's settings read back from its model after building it (the Python mirrors' `*.model.json`, rapier's integration parameters), for the first scene of each dimension.\n"
    );
    for scene in [
        v.scenes.iter().find(|s| s.dimension == 3),
        v.scenes.iter().find(|s| s.dimension == 2),
    ]
    .into_iter()
    .flatten()
    {
        for r in scene.runs.iter().filter(|r| r.model.is_some()) {
            let model = r.model.as_ref().unwrap();
            let settings = if model.get("settings").is_some() {
                &model["settings"]
            } else {
                model
            };
            let _ = writeln!(s, "- {}: `{}`", r.label(), settings);
        }
    }
    s
}

const PANELS: [(&str, &str, &str); 4] = [
    (
        "position",
        "body displacement from its start (the last body)",
        "m",
    ),
    ("speed", "speed of the last body", "m/s"),
    (
        "penetration",
        "deepest penetration (rigidref's measure)",
        "m",
    ),
    ("energy", "total energy", "J"),
];

/// A 3D run's series for the scene's plot ([`PANELS`]; the penetration only where the scene
/// checks collisions), each against time. docs/validation.md §"The report".
pub fn plotted_3d(
    label: String,
    trace: &Trace,
    scene: &crate::rigid3d::scene::Scene,
) -> PlottedRun {
    let records = &trace.records;
    let last = records
        .first()
        .map_or(0, |r| r.bodies.len().saturating_sub(1));
    let start = records
        .first()
        .map(|r| r.bodies[last].x)
        .unwrap_or([0.0; 3]);
    let series = |f: &dyn Fn(&crate::rigid3d::trace::TraceRecord) -> f64| Series {
        name: String::new(),
        values: records.iter().map(|r| Some(f(r))).collect(),
    };
    let penetration = super::observe::penetrations(scene, records).unwrap_or_default();
    let mut plots = vec![
        Plot {
            key: PANELS[0].0,
            title: PANELS[0].1.into(),
            unit: PANELS[0].2.into(),
            log: false,
            series: vec![series(&|r| {
                let x = r.bodies[last].x;
                ((x[0] - start[0]).powi(2) + (x[1] - start[1]).powi(2) + (x[2] - start[2]).powi(2))
                    .sqrt()
            })],
        },
        Plot {
            key: PANELS[1].0,
            title: PANELS[1].1.into(),
            unit: PANELS[1].2.into(),
            log: false,
            series: vec![series(&|r| {
                let v = r.bodies[last].v;
                (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
            })],
        },
        Plot {
            key: PANELS[2].0,
            title: PANELS[2].1.into(),
            unit: PANELS[2].2.into(),
            log: false,
            series: vec![Series {
                name: String::new(),
                values: penetration.into_iter().map(Some).collect(),
            }],
        },
        Plot {
            key: PANELS[3].0,
            title: PANELS[3].1.into(),
            unit: PANELS[3].2.into(),
            log: false,
            series: vec![series(&|r| r.energy.total)],
        },
    ];
    if !scene.params.check_collisions {
        plots.retain(|p| p.key != "penetration");
    }
    PlottedRun {
        label,
        t: records.iter().map(|r| r.t).collect(),
        time_unit: TIME_UNIT_3D,
        plots,
    }
}

/// Writes report.md and report.json into `out`.
pub fn write_tables(v: &Validation, out: &Path) -> Result<(), String> {
    let write = |name: &str, text: String| {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
    };
    write("report.md", markdown(v))?;
    let json = serde_json::to_string_pretty(v).map_err(|e| e.to_string())?;
    write("report.json", json + "\n")
}

/// Draws plots/SCENE.svg of `scene` into `out`: each observable's series against time, the
/// runs that have finished overlaid (rigidref's first).
pub fn write_plot(scene: &SceneResult, out: &Path) -> Result<(), String> {
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots)
        .map_err(|e| format!("{}: cannot create: {e}", plots.display()))?;
    let runs: Vec<PlottedRun> = scene
        .runs
        .iter()
        .filter_map(|r| r.plotted.clone())
        .filter(|p| !p.t.is_empty())
        .collect();
    if runs.is_empty() {
        return Ok(());
    }
    plot_runs(
        &runs,
        &[],
        &plots.join(format!("{}.svg", scene.file.trim_end_matches(".json"))),
        &scene.name,
    )
}

/// Writes the report as it stands after a run of scene `index` finished: report.md, report.json
/// and that scene's plot. docs/validation.md §"The report".
pub fn write_progress(v: &Validation, index: usize, out: &Path) -> Result<(), String> {
    write_tables(v, out)?;
    write_plot(&v.scenes[index], out)
}

/// Writes report.md, report.json and plots/SCENE.svg of every scene into `out`.
pub fn write_report(v: &Validation, out: &Path) -> Result<(), String> {
    write_tables(v, out)?;
    for scene in &v.scenes {
        write_plot(scene, out)?;
    }
    Ok(())
}
