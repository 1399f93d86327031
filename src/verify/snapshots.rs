//! The compact, rounded run summaries that the insta snapshot tests keep, for the 3D and the 2D
//! system: round-off never shows in them and behaviour always does.

use crate::rigid3d::scene::Scene;
use crate::rigid3d::world::World;
use crate::sim::{Flow, drive};

/// The compact, rounded summary of a run that the insta snapshot tests keep
/// (tests/suite/verify/snapshots.rs): the state of every body at whole seconds, contact counts, energies and
/// the deepest penetration, rounded so that round-off never shows and behaviour always does.
pub fn summary(scene: &Scene, seconds: u32) -> Result<String, String> {
    use std::fmt::Write;
    let mut world = World::new(scene)?;
    let per_second = (1.0 / scene.params.dt).round() as u64;
    let mut out = String::new();
    let p = &scene.params;
    let _ = writeln!(
        out,
        "scene {:?}: {} bodies, dt {} s, {} substeps, μ {}, gravity [{}, {}, {}], collisions {}",
        p.name,
        world.bodies.len(),
        p.dt,
        p.substeps,
        p.mu,
        p.gravity.x,
        p.gravity.y,
        p.gravity.z,
        p.check_collisions
    );
    let mut deepest: f64 = 0.0;
    let mut contact_frames = 0u64;
    let r = |x: f64| {
        // Four decimals, with −0 shown as 0.
        let v = (x * 1e4).round() / 1e4;
        if v == 0.0 { 0.0 } else { v }
    };
    for second in 0..=seconds {
        if second > 0 {
            drive(&mut world, per_second, |w, _| {
                if !w.solves.is_empty() {
                    contact_frames += 1;
                }
                for s in &w.solves {
                    for c in &s.contacts {
                        deepest = deepest.max(c.depth);
                    }
                }
                Ok::<_, String>(Flow::Continue)
            })?;
        }
        let e = world.energy();
        let contacts = world.solves.last().map_or(0, |s| s.contacts.len());
        let _ = writeln!(
            out,
            "t = {second} s: E = {} J (kinetic {} + {}, potential {}), {contacts} contacts",
            r(e.total),
            r(e.kinetic_linear),
            r(e.kinetic_angular),
            r(e.potential)
        );
        for (i, b) in world.bodies.iter().enumerate() {
            let _ = writeln!(
                out,
                "  body {i}: x [{}, {}, {}]  v [{}, {}, {}]  ω [{}, {}, {}]",
                r(b.x.x),
                r(b.x.y),
                r(b.x.z),
                r(b.v.x),
                r(b.v.y),
                r(b.v.z),
                r(b.omega.x),
                r(b.omega.y),
                r(b.omega.z)
            );
        }
    }
    let _ = writeln!(
        out,
        "frames with contacts: {contact_frames}; deepest penetration: {} m",
        r(deepest)
    );
    Ok(out)
}

/// The 2D counterpart of [`summary`]: every `every` time units up to `until`, a 2D world's
/// energies, contact count and each body's x, θ, v, ω to four decimals; then the deepest disc
/// overlap seen. For insta snapshots of the project's 2D scenes.
pub fn summary2(
    mut world: crate::blocks2d::world::World2,
    every: f64,
    until: f64,
) -> Result<String, String> {
    use std::fmt::Write;
    let r = |x: f64| {
        // Four decimals, with −0 shown as 0.
        let v = (x * 1e4).round() / 1e4;
        if v == 0.0 { 0.0 } else { v }
    };
    let p = &world.params;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} bodies ({} pinned), step {}, {} substeps, {} iterations {:?}, μ {}",
        world.bodies.len(),
        world.bodies.iter().filter(|b| b.pinned).count(),
        p.dt,
        p.substeps,
        p.iterations,
        p.order,
        p.mu
    );
    let steps_per_report = (every / p.dt).round().max(1.0) as u64;
    let reports = (until / every).round() as u64;
    let mut deepest: f64 = 0.0;
    for report in 0..=reports {
        if report > 0 {
            drive(&mut world, steps_per_report, |w, _| {
                deepest = deepest.max(w.deepest_overlap());
                Ok::<_, String>(Flow::Continue)
            })?;
        }
        let e = world.energy();
        let _ = writeln!(
            out,
            "t = {}: kinetic {}, potential {}, {} contacts",
            r(world.time()),
            r(e.kinetic),
            r(e.potential),
            world.contacts.len()
        );
        for (i, b) in world.bodies.iter().enumerate().filter(|(_, b)| !b.pinned) {
            let _ = writeln!(
                out,
                "  body {i}: x [{}, {}]  θ {}  v [{}, {}]  ω {}",
                r(b.x.x),
                r(b.x.y),
                r(b.theta),
                r(b.v.x),
                r(b.v.y),
                r(b.omega)
            );
        }
    }
    let _ = writeln!(out, "deepest disc overlap: {} blocks", r(deepest));
    Ok(out)
}
