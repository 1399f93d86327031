//! `rigidref crosscheck --rapier`: the scene in rigidref and in a rapier3d mirror, compared
//! through observables. docs/verification.md §"rapier3d".

use super::crosscheck::CrosscheckArgs;
use anyhow::bail;
use rigidref::reference::compare::{compare, record_rapier, record_rigidref};

/// Runs both and prints the observables side by side.
pub fn rapier(args: &CrosscheckArgs) -> anyhow::Result<()> {
    let scene = super::load_scene_or_default(args.input.as_deref())?;
    if !(args.time.is_finite() && args.time > 0.0) {
        bail!(
            "--time must be a positive number of seconds, got {}",
            args.time
        );
    }
    let steps = (args.time / scene.params.dt + 1e-9).floor().max(1.0) as u64;
    let ours = record_rigidref(&scene, steps, rigidref::faults::Faults::NONE)
        .map_err(|e| anyhow::anyhow!("{}: {e}", scene.source))?;
    let theirs =
        record_rapier(&scene, steps).map_err(|e| anyhow::anyhow!("{}: {e}", scene.source))?;
    let observables = compare(&scene, &ours, &theirs);
    if args.json {
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
