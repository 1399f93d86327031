//! The in-process runs of `rigidref validate`: rigidref itself with the exact (Newton) solver, and
//! the rapier3d mirror, each written as a trace like the Python mirrors' (docs/validation.md
//! §"rigidref and rapier").

use super::engines::Settings;
use crate::rigid3d::scene::Scene;
use crate::rigid3d::trace::{ContactRecord, TraceFormat, TraceHeader, TraceRecord, TraceWriter};
use crate::rigid3d::world::World;
use crate::sim::{Flow, drive};
use crate::solve::Solver;
use crate::verify::references::rapier::{RapierMirror, Snapshot};
use std::path::Path;

fn writer(path: &Path, header: &TraceHeader) -> Result<TraceWriter, String> {
    let file = std::fs::File::create(path)
        .map_err(|e| format!("{}: cannot create: {e}", path.display()))?;
    TraceWriter::new(Box::new(file), TraceFormat::Jsonl, header)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// The scene as rigidref's reference run has it: the scene's own settings with the exact
/// (Newton) contact solver and Coulomb's friction cone (the law the closed forms and the criteria
/// speak of; a scene's `friction_model: box` is the assignment's pyramid).
pub fn reference_scene(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    scene.params.solver = Solver::Newton;
    scene.params.friction_model = crate::problem::FrictionModel::Cone;
    scene
}

/// Runs rigidref (Newton) on `scene` for `frames` frames, writing every frame to `path`.
pub fn run_rigidref(scene: &Scene, frames: u64, path: &Path) -> Result<(), String> {
    let scene = reference_scene(scene);
    let mut world = World::new(&scene)?;
    let mut header = TraceHeader::for_world(&world, &scene.source);
    header.overrides = vec!["solver=newton".into(), "friction_model=cone".into()];
    let mut out = writer(path, &header)?;
    let io = |e: std::io::Error| format!("{}: cannot write: {e}", path.display());
    out.write(TraceRecord::of_world(&world)).map_err(io)?;
    drive(&mut world, frames, |w, _| {
        out.write(TraceRecord::of_world(w)).map_err(io)?;
        Ok::<_, String>(Flow::Continue)
    })?;
    out.flush().map_err(io)
}

/// A record of `world` (the scene's bodies) placed in `states`, at frame `step`, with `contacts`:
/// energies, momenta and the penetration measure computed by rigidref's own code, so that every
/// engine's trace is measured alike.
pub fn record_of_states(
    world: &mut World,
    step: u64,
    states: &[Snapshot],
    contacts: Vec<ContactRecord>,
) -> TraceRecord {
    for (b, s) in world.bodies.iter_mut().zip(states) {
        b.x = s.x;
        b.rotation = s.rotation;
        b.v = s.v;
        b.omega = s.omega;
        b.update_world_inertia();
    }
    world.step = step;
    world.solves.clear();
    world.measure_penetration();
    let mut record = TraceRecord::of_world(world);
    record.contacts = contacts;
    record
}

/// Runs the rapier3d mirror of `scene` with `settings` for `frames` frames, writing `path`; its
/// settings (as applied) are returned for the report.
pub fn run_rapier(
    scene: &Scene,
    settings: Settings,
    frames: u64,
    path: &Path,
) -> Result<serde_json::Value, String> {
    let mut mirror = RapierMirror::new(scene)?;
    mirror.set_step(scene.params.h());
    if settings == Settings::Accurate {
        mirror.set_accurate();
    }
    let mut world = World::new(scene)?;
    let mut header = TraceHeader::for_world(&world, &format!("rapier mirror of {}", scene.source));
    header.integrator = "rapier".into();
    header.collision = "rapier".into();
    let mut out = writer(path, &header)?;
    let io = |e: std::io::Error| format!("{}: cannot write: {e}", path.display());
    out.write(record_of_states(
        &mut world,
        0,
        &mirror.snapshots(),
        Vec::new(),
    ))
    .map_err(io)?;
    let h = scene.params.h();
    let mut k = 0u64;
    for frame in 1..=frames {
        let mut contacts = Vec::new();
        for _ in 0..scene.params.substeps {
            mirror.apply_loads(scene, k as f64 * h);
            mirror.step();
            k += 1;
            let found = mirror.contact_records();
            if !found.is_empty() {
                contacts = found;
            }
        }
        let states = mirror.snapshots();
        if states
            .iter()
            .any(|s| !(s.x.iter().chain(s.v.iter()).all(|v| v.is_finite())))
        {
            return Err(format!(
                "{}: rapier's state is not finite at frame {frame}",
                path.display()
            ));
        }
        out.write(record_of_states(&mut world, frame, &states, contacts))
            .map_err(io)?;
    }
    out.flush().map_err(io)?;
    Ok(serde_json::json!({"settings": mirror.settings_report(), "readback": mirror.readback()}))
}
