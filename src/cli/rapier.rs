//! `rigidref crosscheck --rapier`: the scene in rigidref and in a rapier3d mirror, compared
//! through observables. docs/verification.md §"rapier3d".

use anyhow::{Context, bail};
use rigidref::verify::references::compare::{compare, record_rapier, record_rigidref};

/// Runs the scene at `input` (or the built-in default) for `time` seconds in both and prints the
/// observables side by side (as JSON with `json`).
pub fn rapier(
    input: Option<&std::path::Path>,
    sets: &super::args::SceneSets,
    time: f64,
    json: bool,
) -> anyhow::Result<()> {
    let scene = super::common::load_scene_or_default(input, sets)?;
    let steps = rigidref::sim::steps_in(time, scene.params.dt, " of seconds")
        .map_err(anyhow::Error::msg)
        .with_context(|| scene.source.clone())?;
    let ours =
        record_rigidref(&scene, steps).map_err(|e| anyhow::anyhow!("{}: {e}", scene.source))?;
    let theirs =
        record_rapier(&scene, steps).map_err(|e| anyhow::anyhow!("{}: {e}", scene.source))?;
    let observables = compare(&scene, &ours, &theirs);
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "scene": scene.source, "time": steps as f64 * scene.params.dt, "observables": observables
            }))?
        );
    } else {
        println!(
            "scene {} ({} s, {} frames), rigidref vs rapier3d",
            scene.source,
            steps as f64 * scene.params.dt,
            steps
        );
        println!(
            "{:<40} {:>13} {:>13} {:>13} {:>11}  result",
            "observable", "rigidref", "rapier3d", "reference", "tolerance"
        );
        for o in &observables {
            let reference = o.reference.map_or("-".to_string(), |r| format!("{r:.5}"));
            let tolerance = o
                .tolerance
                .map_or("reported".to_string(), |t| format!("{t:.2e}"));
            println!(
                "{:<40} {:>13.5} {:>13.5} {:>13} {:>11}  {} {}",
                o.name,
                o.rigidref,
                o.rapier,
                reference,
                tolerance,
                if o.passed { "ok" } else { "DIFFERS" },
                o.unit
            );
        }
        println!();
        for o in &observables {
            println!("{}: {}", o.name, o.note);
        }
    }
    let failed: Vec<&str> = observables
        .iter()
        .filter(|o| !o.passed)
        .map(|o| o.name)
        .collect();
    if !failed.is_empty() {
        bail!(
            "{}: rigidref and rapier3d differ beyond tolerance in: {}",
            scene.source,
            failed.join(", ")
        );
    }
    Ok(())
}
