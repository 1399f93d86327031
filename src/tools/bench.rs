//! `rigidref bench`: the same scenes in rigidref and in the rapier3d mirror, timed side by side in
//! one process, interleaved, medians of rounds. docs/performance.md.
//!
//! Matched settings: the same scene (bodies, masses, inertias, meshes as the mirror's convex
//! pieces), dt, gravity and μ; one thread; rapier's solver iterations set to the scene's PGS
//! sweeps; sleeping off in the mirror. What is measured per scene: the whole step in each, the
//! ratio, rigidref's step by phase (detection, assembly, PGS, the rest), and PGS's cost per
//! contact per sweep. Sizes grow so that the report fits how the cost grows with the bodies.

use crate::rigid3d::collide::CollisionMethod;
use crate::rigid3d::scene::{BodyDescription, Scene};
use crate::rigid3d::world::{PhaseTimes, World};
use crate::verify::references::rapier::RapierMirror;
use nalgebra::Vector3;
use std::time::Instant;

/// One scene of the benchmark.
#[derive(Clone, Debug)]
pub struct BenchCase {
    /// Family and size, e.g. `stack grid 4×4`.
    pub name: String,
    /// The family, for the fitted exponents.
    pub family: &'static str,
    /// The scene.
    pub scene: Scene,
}

/// `n × n` copies of `stack` (a scene of one stack at the origin) on a grid `spacing` m apart.
pub fn stack_grid(stack: &Scene, n: usize, spacing: f64) -> BenchCase {
    let mut scene = stack.clone();
    scene.bodies.clear();
    let half = (n as f64 - 1.0) / 2.0;
    for i in 0..n {
        for k in 0..n {
            let offset = Vector3::new(
                (i as f64 - half) * spacing,
                0.0,
                (k as f64 - half) * spacing,
            );
            for b in &stack.bodies {
                let mut copy: BodyDescription = b.clone();
                copy.x0 += offset;
                copy.name = format!("{} [{i},{k}]", b.name);
                scene.bodies.push(copy);
            }
        }
    }
    scene.params.name = format!("{n}×{n} grid of {}", stack.params.name);
    BenchCase {
        name: format!("stack grid {n}×{n}"),
        family: "stack grid",
        scene,
    }
}

/// A wall-like pyramid of `levels` rows of equal cubes (`cube`, a scene holding one cube at the
/// origin): row k has `levels − k` cubes 1% of a side apart, each resting across two below,
/// with `collision: complete` (equal boxes need it).
pub fn cube_pyramid(cube: &Scene, levels: usize) -> BenchCase {
    let mut scene = cube.clone();
    let template = cube.bodies[0].clone();
    let side = 2.0
        * template
            .mesh
            .vertices
            .iter()
            .map(|v| v.y)
            .fold(0.0, f64::max);
    scene.bodies.clear();
    for row in 0..levels {
        for i in 0..levels - row {
            let mut b = template.clone();
            b.x0 = Vector3::new(
                (i as f64 + 0.5 * row as f64) * side * 1.01,
                side * (0.5 + row as f64) - 0.001,
                0.0,
            );
            b.name = format!("cube {row}.{i}");
            scene.bodies.push(b);
        }
    }
    scene.params.collision = CollisionMethod::Complete;
    scene.params.name = format!("pyramid of {levels} rows");
    BenchCase {
        name: format!("cube pyramid {levels} rows"),
        family: "cube pyramid",
        scene,
    }
}

/// Spheres raining: an `n × n × layers` lattice of copies of `ball` (a scene of one ball),
/// `spacing` m apart, the lowest layer 1.5 radii above the ground, falling onto it and each
/// other (the vertex rule).
pub fn sphere_rain(ball: &Scene, n: usize, layers: usize, spacing: f64) -> BenchCase {
    let mut scene = ball.clone();
    let template = ball.bodies[0].clone();
    let radius = template.mesh.bounding_radius();
    scene.bodies.clear();
    let half = (n as f64 - 1.0) / 2.0;
    for layer in 0..layers {
        for i in 0..n {
            for k in 0..n {
                let mut b = template.clone();
                // Alternate layers shifted by a quarter spacing, so that the balls do not
                // land exactly on top of each other.
                let shift = if layer % 2 == 1 { 0.25 * spacing } else { 0.0 };
                b.x0 = Vector3::new(
                    (i as f64 - half) * spacing + shift,
                    1.5 * radius + layer as f64 * spacing,
                    (k as f64 - half) * spacing + shift,
                );
                b.name = format!("ball {layer}.{i}.{k}");
                scene.bodies.push(b);
            }
        }
    }
    scene.params.name = format!("{} balls raining", scene.bodies.len());
    BenchCase {
        name: format!("sphere rain {n}×{n}×{layers}"),
        family: "sphere rain",
        scene,
    }
}

/// One of the assignment's scenes as it is (its own parameters).
pub fn assignment_scene(name: &str, scene: Scene) -> BenchCase {
    BenchCase {
        name: format!("assignment {name}"),
        family: "assignment",
        scene,
    }
}

/// How long to measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BenchSettings {
    /// Steps run before timing (the scene settles into its contacts).
    pub warmup: u64,
    /// Steps per timed round.
    pub steps: u64,
    /// Rounds, each timing rigidref then rapier; the median round counts.
    pub rounds: usize,
    /// PGS sweeps, and rapier's solver iterations.
    pub iterations: u32,
}

/// One measured row.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// The case's name.
    pub name: String,
    /// Its family.
    pub family: &'static str,
    /// Bodies.
    pub bodies: usize,
    /// rigidref's contacts in the last step (summed over substeps).
    pub contacts: usize,
    /// rigidref, ms per step (median round).
    pub ours_ms: f64,
    /// rapier, ms per step (median round).
    pub rapier_ms: f64,
    /// rigidref's phases, ms per step, from the same rounds: detect, assemble, solve, apply,
    /// integrate, measure ([`PhaseTimes`]).
    pub phases_ms: [f64; 6],
    /// PGS ns per contact per sweep.
    pub ns_per_contact_sweep: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn phase_delta(after: &PhaseTimes, before: &PhaseTimes) -> [f64; 6] {
    [
        after.detect - before.detect,
        after.assemble - before.assemble,
        after.solve - before.solve,
        after.apply - before.apply,
        after.integrate - before.integrate,
        after.measure - before.measure,
    ]
}

/// Runs one case in both engines and returns its row.
pub fn run_case(case: &BenchCase, s: &BenchSettings) -> Result<BenchRow, String> {
    let mut scene = case.scene.clone();
    scene.params.pgs_iterations = s.iterations;
    let mut ours = World::new(&scene)?;
    let mut mirror = RapierMirror::new(&scene)?;
    mirror.set_solver_iterations(s.iterations as usize);
    for _ in 0..s.warmup {
        ours.step().map_err(|e| e.to_string())?;
        mirror.step();
    }
    let (mut ours_ms, mut rapier_ms, mut phases, mut per_contact) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..s.rounds {
        let before = ours.phase_times;
        let (mut contact_sweeps, mut solve_seconds) = (0.0, 0.0);
        let clock = Instant::now();
        for _ in 0..s.steps {
            ours.step().map_err(|e| e.to_string())?;
            for solve in &ours.solves {
                contact_sweeps +=
                    (solve.contacts.len() as f64) * f64::from(solve.report.iterations);
                solve_seconds += solve.solve_seconds;
            }
        }
        ours_ms.push(clock.elapsed().as_secs_f64() * 1e3 / s.steps as f64);
        let p = phase_delta(&ours.phase_times, &before);
        phases.push(p.map(|x| x * 1e3 / s.steps as f64));
        per_contact.push(if contact_sweeps > 0.0 {
            solve_seconds * 1e9 / contact_sweeps
        } else {
            0.0
        });
        let clock = Instant::now();
        for _ in 0..s.steps {
            mirror.step();
        }
        rapier_ms.push(clock.elapsed().as_secs_f64() * 1e3 / s.steps as f64);
    }
    let phases_ms = [0, 1, 2, 3, 4, 5].map(|k| median(phases.iter().map(|p| p[k]).collect()));
    Ok(BenchRow {
        name: case.name.clone(),
        family: case.family,
        bodies: scene.bodies.len(),
        contacts: ours.solves.iter().map(|s| s.contacts.len()).sum(),
        ours_ms: median(ours_ms),
        rapier_ms: median(rapier_ms),
        phases_ms,
        ns_per_contact_sweep: median(per_contact),
    })
}

/// The least-squares slope of log y against log x: the exponent p of y ∝ xᵖ (`None` for fewer
/// than two distinct points).
pub fn fitted_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / n,
        logs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The report as Markdown: one table row per case, then the fitted exponents per family.
pub fn markdown(rows: &[BenchRow], s: &BenchSettings) -> String {
    let mut out = format!(
        "{} PGS sweeps (rapier: {} solver iterations), medians of {} rounds of {} steps after {} warm-up steps.\n\n",
        s.iterations, s.iterations, s.rounds, s.steps, s.warmup
    );
    out.push_str("| scene | bodies | contacts | rigidref ms/step | rapier ms/step | ratio | detect | assemble | PGS | apply | integrate | measure | PGS ns/contact/sweep |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.1} |\n",
            r.name,
            r.bodies,
            r.contacts,
            r.ours_ms,
            r.rapier_ms,
            r.ours_ms / r.rapier_ms,
            r.phases_ms[0],
            r.phases_ms[1],
            r.phases_ms[2],
            r.phases_ms[3],
            r.phases_ms[4],
            r.phases_ms[5],
            r.ns_per_contact_sweep
        ));
    }
    // The assignment's scenes are not sizes of one scene: no exponent for them.
    let mut families: Vec<&str> = rows
        .iter()
        .map(|r| r.family)
        .filter(|f| *f != "assignment")
        .collect();
    families.dedup();
    out.push_str("\nFitted exponents p of cost ∝ bodiesᵖ (least squares in log–log):\n\n");
    out.push_str("| family | rigidref step | rapier step | detection | PGS per contact-sweep |\n|---|---|---|---|---|\n");
    for f in families {
        let of = |g: &dyn Fn(&BenchRow) -> f64| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.family == f)
                .map(|r| (r.bodies as f64, g(r)))
                .collect();
            fitted_exponent(&points).map_or("–".to_string(), |p| format!("{p:.2}"))
        };
        out.push_str(&format!(
            "| {f} | {} | {} | {} | {} |\n",
            of(&|r| r.ours_ms),
            of(&|r| r.rapier_ms),
            of(&|r| r.phases_ms[0]),
            of(&|r| r.ns_per_contact_sweep)
        ));
    }
    out
}

/// The process's peak resident memory, bytes (Linux `VmHWM`; `None` elsewhere).
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
