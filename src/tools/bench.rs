//! `rigidref bench`: the same scenes in rigidref and in the rapier3d mirror, timed side by side in
//! one process, interleaved, medians of rounds. docs/performance.md.
//!
//! Matched settings: the same scene (bodies, masses, inertias, meshes as the mirror's convex
//! pieces), dt, gravity and μ; one thread; rapier's solver iterations set to the scene's PGS
//! sweeps; sleeping off in the mirror. What is measured per scene: the whole step in each, the
//! ratio, rigidref's step by phase (detection, assembly, PGS, the rest), and PGS's cost per
//! contact per sweep. Sizes grow so that the report fits how the cost grows with the bodies.

use crate::blocks2d::world::World2;
use crate::rigid3d::collide::CollisionMethod;
use crate::rigid3d::scene::{BodyDescription, Scene};
use crate::rigid3d::world::{PhaseTimes, World};
use crate::sim::Simulation;
use crate::tools::factory::{Pieces, packed_pile};
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
    pub scene: BenchScene,
}

/// What a case runs.
#[derive(Clone, Debug)]
pub enum BenchScene {
    /// A 3D scene, in rigidref and in the rapier3d mirror.
    Rigid3d(Box<Scene>),
    /// The 2D factory's pile of this many bodies ([`packed_pile`]), in rigidref alone (rapier3d
    /// has no 2D mirror here).
    FactoryPile {
        /// Bodies dropped (the container is one more).
        bodies: usize,
        /// What they are.
        pieces: Pieces,
    },
}

impl BenchScene {
    /// Bodies in the scene (a factory pile's container counts as one).
    pub fn bodies(&self) -> usize {
        match self {
            BenchScene::Rigid3d(scene) => scene.bodies.len(),
            BenchScene::FactoryPile { bodies, .. } => bodies + 1,
        }
    }
}

/// The 2D factory's step at `bodies` bodies of `pieces` (the factory's default is random
/// polyominoes) with the factory's settings: a pile made at once by [`packed_pile`], settled by
/// at least [`PILE_WARMUP`] steps.
pub fn factory_pile(bodies: usize, pieces: Pieces) -> BenchCase {
    let (name, family) = match pieces {
        Pieces::Random => (format!("2D factory {bodies}"), "2D factory"),
        Pieces::Bricks => (format!("2D factory bricks {bodies}"), "2D factory bricks"),
        Pieces::Tetris => (
            format!("2D factory tetrominoes {bodies}"),
            "2D factory tetrominoes",
        ),
    };
    BenchCase {
        name,
        family,
        scene: BenchScene::FactoryPile { bodies, pieces },
    }
}

/// Warm-up steps of a factory pile at least (5 time units): the pile is in contact and its
/// pieces have fallen into the holes of the packing, but it is not settled (1.3 to 2.7 contacts
/// per body, against about 3 in a factory run's pile). Longer does not help: a pile of 10 000
/// made at once is crushed by its own weight under 10 sweeps from a cold start (discs overlap by
/// their whole diameter after 200–400 steps, 11 contacts per body), where the factory's pile,
/// grown ten bodies a time unit, holds. The factory target is therefore judged on a factory run
/// (docs/performance.md); these rows are the step's cost at the size.
pub const PILE_WARMUP: u64 = 100;

/// `k × k` copies of the `levels`-row pyramid of [`cube_pyramid`], 2 m apart row to row.
pub fn pyramid_grid(cube: &Scene, levels: usize, k: usize) -> BenchCase {
    let one = cube_pyramid(cube, levels);
    let BenchScene::Rigid3d(pyramid) = one.scene else {
        unreachable!("cube_pyramid makes a 3D scene")
    };
    let pyramid = *pyramid;
    let width = pyramid.bodies.iter().map(|b| b.x0.x).fold(0.0, f64::max) + 2.0;
    let mut scene = pyramid.clone();
    scene.bodies.clear();
    for i in 0..k {
        for j in 0..k {
            for b in &pyramid.bodies {
                let mut copy = b.clone();
                copy.x0 += Vector3::new(i as f64 * width, 0.0, j as f64 * 2.0);
                copy.name = format!("{} [{i},{j}]", b.name);
                scene.bodies.push(copy);
            }
        }
    }
    scene.params.name = format!("{k}×{k} grid of {}", pyramid.params.name);
    BenchCase {
        name: format!("pyramid grid {k}×{k}"),
        family: "pyramid grid",
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}

/// `n × n` copies of `stack` (a scene of one stack at the origin) on a grid `spacing` m apart:
/// the tapered five-cube stack of scenes/box_stack.json (family "stack grid").
pub fn stack_grid(stack: &Scene, n: usize, spacing: f64) -> BenchCase {
    grid_of(stack, n, spacing, "stack grid")
}

/// `n × n` copies of the four equal cubes of scenes/cube_stack.json (`collision: complete`, as
/// the scene says), 1 m apart (family "cube stack grid").
pub fn cube_stack_grid(cubes: &Scene, n: usize) -> BenchCase {
    grid_of(cubes, n, 1.0, "cube stack grid")
}

fn grid_of(stack: &Scene, n: usize, spacing: f64, family: &'static str) -> BenchCase {
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
        name: format!("{family} {n}×{n}"),
        family,
        scene: BenchScene::Rigid3d(Box::new(scene)),
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
        scene: BenchScene::Rigid3d(Box::new(scene)),
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
        scene: BenchScene::Rigid3d(Box::new(scene)),
    }
}

/// One of the assignment's scenes as it is (its own parameters).
pub fn assignment_scene(name: &str, scene: Scene) -> BenchCase {
    BenchCase {
        name: format!("assignment {name}"),
        family: "assignment",
        scene: BenchScene::Rigid3d(Box::new(scene)),
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
    /// PGS sweeps, and rapier's solver iterations (3D scenes; the 2D factory keeps its own 10).
    pub iterations: u32,
}

impl BenchSettings {
    /// Shorter warm-up and rounds for scenes of more than 2 000 bodies (a step there takes tens
    /// of milliseconds; ten steps a round is plenty and keeps the full run to minutes).
    pub fn for_bodies(&self, bodies: usize) -> BenchSettings {
        if bodies > 2000 {
            BenchSettings {
                warmup: self.warmup.min(40),
                steps: self.steps.min(10),
                ..*self
            }
        } else {
            *self
        }
    }
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
    /// PGS sweeps per solve.
    pub iterations: u32,
    /// rigidref, ms per step (median round).
    pub ours_ms: f64,
    /// rapier, ms per step (median round); `None` for the 2D scenes.
    pub rapier_ms: Option<f64>,
    /// rigidref's phases, ms per step, from the same rounds: detect, assemble, solve, apply,
    /// integrate, measure (3D: the penetration measure; 2D: post-stabilisation) ([`PhaseTimes`]).
    pub phases_ms: [f64; 6],
    /// rapier's own phase timers, ms per step (median round): collision detection (broad and
    /// narrow phase), constraint setup, velocity iterations
    /// ([`crate::verify::references::rapier::RapierPhases`]).
    pub rapier_phases_ms: Option<[f64; 3]>,
    /// PGS ns per contact per sweep.
    pub ns_per_contact_sweep: f64,
}

impl BenchRow {
    /// rigidref's step over rapier's.
    pub fn ratio(&self) -> Option<f64> {
        self.rapier_ms.map(|r| self.ours_ms / r)
    }

    /// rigidref's detection, assembly and applying/recording, ms per step (the work around the
    /// solve that rapier's collision detection and constraint setup do).
    pub fn around_solve_ms(&self) -> f64 {
        self.phases_ms[0] + self.phases_ms[1] + self.phases_ms[3]
    }

    /// That over rapier's collision detection and constraint setup.
    pub fn around_solve_ratio(&self) -> Option<f64> {
        self.rapier_phases_ms
            .map(|r| self.around_solve_ms() / (r[0] + r[1]))
    }
}

fn median(v: Vec<f64>) -> f64 {
    crate::common::stats::median(v).unwrap_or(f64::NAN)
}

fn phase_delta(after: &PhaseTimes, before: &PhaseTimes) -> [f64; 6] {
    let (a, b) = (after.as_array(), before.as_array());
    [0, 1, 2, 3, 4, 5].map(|k| a[k] - b[k])
}

/// What the timed rounds of one engine collected.
#[derive(Default)]
struct Rounds {
    step_ms: Vec<f64>,
    phases: Vec<[f64; 6]>,
    per_contact: Vec<f64>,
}

impl Rounds {
    /// Times `steps` steps of `world`; `phases` reads its phase clocks. Counts the contacts ×
    /// sweeps and PGS seconds of every solve of the steps, for PGS's cost per contact-sweep.
    fn round<S: Simulation<D, R>, const D: usize, const R: usize>(
        &mut self,
        steps: u64,
        world: &mut S,
        phases: impl Fn(&S) -> PhaseTimes,
    ) -> Result<(), String> {
        let before = phases(world);
        let (mut contact_sweeps, mut solve_seconds) = (0.0, 0.0);
        let clock = Instant::now();
        for _ in 0..steps {
            world.step().map_err(|e| e.to_string())?;
            for solve in world.solves() {
                contact_sweeps += solve.contacts.len() as f64 * f64::from(solve.report.iterations);
                solve_seconds += solve.solve_seconds;
            }
        }
        self.step_ms
            .push(clock.elapsed().as_secs_f64() * 1e3 / steps as f64);
        let p = phase_delta(&phases(world), &before);
        self.phases.push(p.map(|x| x * 1e3 / steps as f64));
        self.per_contact.push(if contact_sweeps > 0.0 {
            solve_seconds * 1e9 / contact_sweeps
        } else {
            0.0
        });
        Ok(())
    }

    fn phases_ms(&self) -> [f64; 6] {
        [0, 1, 2, 3, 4, 5].map(|k| median(self.phases.iter().map(|p| p[k]).collect()))
    }
}

/// Runs one case (in both engines for a 3D scene) and returns its row.
pub fn run_case(case: &BenchCase, s: &BenchSettings) -> Result<BenchRow, String> {
    let s = &s.for_bodies(case.scene.bodies());
    match &case.scene {
        BenchScene::Rigid3d(scene) => run_3d(case, scene, s),
        BenchScene::FactoryPile { bodies, pieces } => run_pile(case, *bodies, *pieces, s),
    }
}

fn run_3d(case: &BenchCase, scene: &Scene, s: &BenchSettings) -> Result<BenchRow, String> {
    let mut scene = scene.clone();
    scene.params.pgs_iterations = s.iterations;
    let mut ours = World::new(&scene)?;
    let mut mirror = RapierMirror::new(&scene)?;
    mirror.set_solver_iterations(s.iterations as usize);
    mirror.enable_timers();
    for _ in 0..s.warmup {
        ours.step().map_err(|e| e.to_string())?;
        mirror.step();
    }
    let mut rounds = Rounds::default();
    let (mut rapier_ms, mut rapier_phases) = (Vec::new(), Vec::new());
    for _ in 0..s.rounds {
        rounds.round(s.steps, &mut ours, |w: &World| w.phase_times)?;
        let mut phases = [0.0; 3];
        let clock = Instant::now();
        for _ in 0..s.steps {
            mirror.step();
            let p = mirror.last_step_phases();
            phases[0] += p.collision;
            phases[1] += p.setup;
            phases[2] += p.iterations;
        }
        rapier_ms.push(clock.elapsed().as_secs_f64() * 1e3 / s.steps as f64);
        rapier_phases.push(phases.map(|x| x / s.steps as f64));
    }
    Ok(BenchRow {
        name: case.name.clone(),
        family: case.family,
        bodies: scene.bodies.len(),
        contacts: ours.solves.iter().map(|s| s.contacts.len()).sum(),
        iterations: s.iterations,
        ours_ms: median(rounds.step_ms.clone()),
        rapier_ms: Some(median(rapier_ms)),
        phases_ms: rounds.phases_ms(),
        rapier_phases_ms: Some(
            [0, 1, 2].map(|k| median(rapier_phases.iter().map(|p: &[f64; 3]| p[k]).collect())),
        ),
        ns_per_contact_sweep: median(rounds.per_contact),
    })
}

fn run_pile(
    case: &BenchCase,
    bodies: usize,
    pieces: Pieces,
    s: &BenchSettings,
) -> Result<BenchRow, String> {
    let mut world: World2 = packed_pile(bodies, pieces, 1);
    for _ in 0..s.warmup.max(PILE_WARMUP) {
        world.step().map_err(|e| e.to_string())?;
    }
    let mut rounds = Rounds::default();
    for _ in 0..s.rounds {
        rounds.round(s.steps, &mut world, |w: &World2| w.phase_times)?;
    }
    Ok(BenchRow {
        name: case.name.clone(),
        family: case.family,
        bodies: world.bodies.len(),
        contacts: world.contacts_in_step,
        iterations: world.params.iterations,
        ours_ms: median(rounds.step_ms.clone()),
        rapier_ms: None,
        phases_ms: rounds.phases_ms(),
        rapier_phases_ms: None,
        ns_per_contact_sweep: median(rounds.per_contact),
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
    crate::tools::scaling::linear_fit(&logs).map(|fit| fit.slope)
}

/// Bodies from which a family's exponent is fitted: the range starts at 100 (below it a
/// step is dominated by fixed costs); families with fewer than two such sizes use every size.
pub const EXPONENT_FROM_BODIES: usize = 100;

/// The rows of `family` the exponents are fitted over, and the smallest size used.
fn fitted_rows<'a>(rows: &'a [BenchRow], family: &str) -> Vec<&'a BenchRow> {
    let all: Vec<&BenchRow> = rows.iter().filter(|r| r.family == family).collect();
    let large: Vec<&BenchRow> = all
        .iter()
        .copied()
        .filter(|r| r.bodies >= EXPONENT_FROM_BODIES)
        .collect();
    if large.len() >= 2 { large } else { all }
}

/// The fitted exponent of `g` against the bodies over `rows` (`None` where `g` has no value).
fn exponent_of(rows: &[&BenchRow], g: impl Fn(&BenchRow) -> Option<f64>) -> Option<f64> {
    let points: Option<Vec<(f64, f64)>> = rows
        .iter()
        .map(|r| g(r).map(|y| (r.bodies as f64, y)))
        .collect();
    fitted_exponent(&points?)
}

fn cell(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".to_string(), |x| format!("{x:.digits$}"))
}

/// The families of `rows` in order of first appearance, the assignment's scenes left out (they
/// are not sizes of one scene).
fn families(rows: &[BenchRow]) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for r in rows {
        if r.family != "assignment" && !out.contains(&r.family) {
            out.push(r.family);
        }
    }
    out
}

/// The report as Markdown: one table row per case, the fitted exponents per family, and the
/// issue's targets read off the rows.
pub fn markdown(rows: &[BenchRow], s: &BenchSettings) -> String {
    let mut out = format!(
        "{} PGS sweeps in 3D (rapier: {} solver iterations; the 2D factory keeps its 10 sweeps), medians of {} rounds of {} steps after {} warm-up steps ({} and {} above 2 000 bodies). Times in ms per step; \"measure\" is the 3D penetration measure and 2D post-stabilisation; rapier's columns are its own timers.\n\n",
        s.iterations,
        s.iterations,
        s.rounds,
        s.steps,
        s.warmup,
        s.for_bodies(usize::MAX).steps,
        s.for_bodies(usize::MAX).warmup,
    );
    out.push_str("| scene | bodies | contacts | rigidref ms/step | rapier ms/step | ratio | detect | assemble | PGS | apply | integrate | measure | PGS ns/contact/sweep | rapier collision | rapier setup | rapier iterations | detect+assemble+apply / rapier collision+setup |\n");
    out.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let rp = |k: usize| cell(r.rapier_phases_ms.map(|p| p[k]), 3);
        out.push_str(&format!(
            "| {} | {} | {} | {:.3} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.1} | {} | {} | {} | {} |\n",
            r.name,
            r.bodies,
            r.contacts,
            r.ours_ms,
            cell(r.rapier_ms, 3),
            cell(r.ratio(), 2),
            r.phases_ms[0],
            r.phases_ms[1],
            r.phases_ms[2],
            r.phases_ms[3],
            r.phases_ms[4],
            r.phases_ms[5],
            r.ns_per_contact_sweep,
            rp(0),
            rp(1),
            rp(2),
            cell(r.around_solve_ratio(), 2),
        ));
    }
    out.push_str(&format!(
        "\nFitted exponents p of cost ∝ bodiesᵖ (least squares in log–log, over the sizes from {EXPONENT_FROM_BODIES} bodies up where a family has two, else over all):\n\n"
    ));
    out.push_str("| family | sizes (bodies) | rigidref step | rapier step | detection | contacts | PGS per contact-sweep |\n|---|---|---|---|---|---|---|\n");
    for f in families(rows) {
        let used = fitted_rows(rows, f);
        out.push_str(&format!(
            "| {f} | {}–{} | {} | {} | {} | {} | {} |\n",
            used.first().map_or(0, |r| r.bodies),
            used.last().map_or(0, |r| r.bodies),
            cell(exponent_of(&used, |r| Some(r.ours_ms)), 2),
            cell(exponent_of(&used, |r| r.rapier_ms), 2),
            cell(exponent_of(&used, |r| Some(r.phases_ms[0])), 2),
            cell(exponent_of(&used, |r| Some(r.contacts as f64)), 2),
            cell(exponent_of(&used, |r| Some(r.ns_per_contact_sweep)), 2),
        ));
    }
    out.push_str(&targets(rows));
    out
}

/// The targets (issue 20, item 3) as read off `rows`: each with what was measured and
/// whether it holds. Only the families the run had.
pub fn targets(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "\nTargets, from the rows above:\n\n| target | measured | met |\n|---|---|---|\n",
    );
    let yes = |b: bool| if b { "yes" } else { "no" };
    // The grid and equal-cube scenes from 20 bodies (smaller ones are fixed costs).
    let structures: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| {
            matches!(
                r.family,
                "stack grid" | "cube stack grid" | "cube pyramid" | "pyramid grid"
            ) && r.bodies >= 20
        })
        .collect();
    fn worst(g: &dyn Fn(&BenchRow) -> Option<f64>, of: &[&BenchRow]) -> Option<(f64, String)> {
        of.iter()
            .filter_map(|r| g(r).map(|x| (x, r.name.clone())))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
    if let Some((ratio, name)) = worst(&|r| r.ratio(), &structures) {
        let best = structures
            .iter()
            .filter_map(|r| r.ratio())
            .fold(f64::INFINITY, f64::min);
        out.push_str(&format!(
            "| whole step ≤ 1.0× rapier's (grids and pyramids, ≥ 20 bodies) | {best:.2}–{ratio:.2}× (worst: {name}) | {} |\n",
            yes(ratio <= 1.0)
        ));
    }
    let per_iteration = |r: &BenchRow| {
        r.rapier_phases_ms
            .filter(|_| r.contacts > 0)
            .map(|p| p[2] * 1e6 / (r.contacts as f64 * f64::from(r.iterations)))
    };
    let pgs: Vec<(f64, f64)> = structures
        .iter()
        .filter_map(|r| per_iteration(r).map(|theirs| (r.ns_per_contact_sweep, theirs)))
        .collect();
    if !pgs.is_empty() {
        let ours = pgs.iter().map(|p| p.0).fold(0.0, f64::max);
        let theirs = pgs.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let below = pgs.iter().all(|(a, b)| a < b);
        out.push_str(&format!(
            "| PGS per contact per sweep below rapier's per contact per iteration | ours up to {ours:.1} ns; rapier's iterations from {theirs:.1} ns (its timer over our contact count) | {} |\n",
            yes(below)
        ));
    }
    let rigid: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| r.family != "assignment" && r.bodies >= 20)
        .collect();
    if let Some((ratio, name)) = worst(&|r| r.around_solve_ratio(), &rigid) {
        out.push_str(&format!(
            "| detection, assembly and recording per body ≤ 1.5× rapier's collision detection and constraint setup | up to {ratio:.2}× (worst: {name}) | {} |\n",
            yes(ratio <= 1.5)
        ));
    }
    if let Some(r) = rows
        .iter()
        .filter(|r| r.family == "2D factory")
        .min_by_key(|r| r.bodies.abs_diff(10_001))
    {
        let rate = 1e3 / r.ours_ms;
        out.push_str(&format!(
            "| 2D factory at 10 000 bodies ≥ 30 steps/s | {rate:.1} steps/s at {} bodies | {} |\n",
            r.bodies,
            if r.bodies >= 10_000 {
                yes(rate >= 30.0)
            } else {
                "not measured at 10 000"
            }
        ));
    }
    // Linear cost: the families measured across the range, 100 to 10 000 bodies (the
    // single pyramids and the rain stop short of it, and their contacts per body grow with size:
    // their exponents are in the table above, not judged here).
    let mut linear = Vec::new();
    for f in families(rows) {
        let used = fitted_rows(rows, f);
        let (low, top) = (
            used.first().map_or(0, |r| r.bodies),
            used.last().map_or(0, |r| r.bodies),
        );
        if low < EXPONENT_FROM_BODIES || top < 10_000 {
            continue;
        }
        let by_bodies = exponent_of(&used, |r| Some(r.ours_ms));
        // Against contacts: the same fit with contacts in place of bodies.
        let by_contacts = fitted_exponent(
            &used
                .iter()
                .map(|r| (r.contacts as f64, r.ours_ms))
                .collect::<Vec<_>>(),
        );
        if let (Some(b), Some(c)) = (by_bodies, by_contacts) {
            linear.push((f, b, c, low, top));
        }
    }
    if linear.is_empty() {
        out.push_str("| cost linear from 100 to 10 000 bodies: exponent ≤ 1.1 | no family measured from 100 to 10 000 bodies in this run | – |\n");
    } else {
        let listed: Vec<String> = linear
            .iter()
            .map(|(f, b, c, low, top)| {
                format!("{f} ({low}–{top}): {b:.2} in bodies, {c:.2} in contacts")
            })
            .collect();
        out.push_str(&format!(
            "| cost linear from 100 to 10 000 bodies and contacts: exponent ≤ 1.1 | {} | {} |\n",
            listed.join("; "),
            yes(linear.iter().all(|e| e.1 <= 1.1 && e.2 <= 1.1))
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

/// Draws ms per step against bodies, log–log, one colour per family: rigidref solid with filled
/// dots, rapier dashed with open circles (DIR/bench.svg of `rigidref bench --out DIR`).
pub fn svg(rows: &[BenchRow], path: &std::path::Path, title: &str) -> Result<(), String> {
    use plotters::prelude::*;
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", path.display());
    let plotted: Vec<&BenchRow> = rows.iter().filter(|r| r.family != "assignment").collect();
    let (mut x_max, mut y_min, mut y_max) = (10.0_f64, f64::INFINITY, 0.0_f64);
    for r in &plotted {
        x_max = x_max.max(r.bodies as f64);
        for y in [Some(r.ours_ms), r.rapier_ms].into_iter().flatten() {
            y_min = y_min.min(y);
            y_max = y_max.max(y);
        }
    }
    if !y_min.is_finite() {
        (y_min, y_max) = (0.01, 1.0);
    }
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(20)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(
            (1.0..x_max * 1.5).log_scale(),
            (y_min * 0.7..y_max * 1.5).log_scale(),
        )
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("bodies")
        .y_desc("ms per step")
        .draw()
        .map_err(|e| err(&e))?;
    let palette = crate::tools::plot::COLOURS;
    for (k, family) in families(rows).into_iter().enumerate() {
        let colour = palette[k % palette.len()];
        let of = |g: &dyn Fn(&BenchRow) -> Option<f64>| -> Vec<(f64, f64)> {
            plotted
                .iter()
                .filter(|r| r.family == family)
                .filter_map(|r| g(r).map(|y| (r.bodies as f64, y)))
                .collect()
        };
        let ours = of(&|r| Some(r.ours_ms));
        chart
            .draw_series(LineSeries::new(ours.clone(), colour.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(format!("rigidref: {family}"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(ours.iter().map(|p| Circle::new(*p, 4, colour.filled())))
            .map_err(|e| err(&e))?;
        let theirs = of(&|r| r.rapier_ms);
        if !theirs.is_empty() {
            chart
                .draw_series(DashedLineSeries::new(
                    theirs.clone(),
                    6,
                    4,
                    colour.stroke_width(1),
                ))
                .map_err(|e| err(&e))?
                .label(format!("rapier3d: {family}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(1))
                });
            chart
                .draw_series(
                    theirs
                        .iter()
                        .map(|p| Circle::new(*p, 4, colour.stroke_width(1))),
                )
                .map_err(|e| err(&e))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// One scene stepped with PGS and with the exact Newton solver, each with the scene's own
/// parameters (docs/performance.md §"The exact solver's cost").
#[derive(Clone, Debug, PartialEq)]
pub struct SolverRow {
    /// The scene's name.
    pub name: String,
    /// Median ms per step with PGS (the scene's `pgs_iterations`).
    pub pgs_ms: f64,
    /// Median ms per step with `solver: newton`.
    pub newton_ms: f64,
    /// Newton iterations per solve, mean over the timed steps (the fallback's included).
    pub newton_iterations: f64,
    /// Timed solves the Newton solver did not converge on.
    pub unconverged: usize,
}

impl SolverRow {
    /// Newton's step time over PGS's.
    pub fn ratio(&self) -> f64 {
        self.newton_ms / self.pgs_ms.max(1e-12)
    }
}

/// Steps `scene` with PGS and with the Newton solver side by side: `s.warmup` steps each, then
/// `s.rounds` rounds of `s.steps` steps, PGS then Newton in each round; medians.
pub fn solver_row(name: &str, scene: &Scene, s: &BenchSettings) -> Result<SolverRow, String> {
    use crate::solve::Solver;
    let with = |solver| {
        let mut scene = scene.clone();
        scene.params.solver = solver;
        World::new(&scene)
    };
    let (mut pgs, mut newton) = (with(Solver::Pgs)?, with(Solver::Newton)?);
    for _ in 0..s.warmup {
        pgs.step().map_err(|e| e.to_string())?;
        newton.step().map_err(|e| e.to_string())?;
    }
    let (mut pgs_ms, mut newton_ms) = (Vec::new(), Vec::new());
    let (mut iterations, mut solves, mut unconverged) = (0u64, 0u64, 0usize);
    for _ in 0..s.rounds {
        let clock = Instant::now();
        for _ in 0..s.steps {
            pgs.step().map_err(|e| e.to_string())?;
        }
        pgs_ms.push(clock.elapsed().as_secs_f64() * 1e3 / s.steps as f64);
        let mut elapsed = 0.0;
        for _ in 0..s.steps {
            let clock = Instant::now();
            newton.step().map_err(|e| e.to_string())?;
            elapsed += clock.elapsed().as_secs_f64();
            for solve in &newton.solves {
                iterations += u64::from(solve.report.iterations);
                solves += 1;
                unconverged += usize::from(!solve.report.converged);
            }
        }
        newton_ms.push(elapsed * 1e3 / s.steps as f64);
    }
    Ok(SolverRow {
        name: name.to_string(),
        pgs_ms: median(pgs_ms),
        newton_ms: median(newton_ms),
        newton_iterations: iterations as f64 / solves.max(1) as f64,
        unconverged,
    })
}

/// The solver rows as a Markdown table.
pub fn solver_markdown(rows: &[SolverRow]) -> String {
    let mut out = String::from(
        "\nThe exact solver's cost: each scene with its own parameters, PGS and `solver: newton` \
         side by side (interleaved rounds, medians).\n\n\
         | scene | PGS ms/step | Newton ms/step | Newton / PGS | Newton iterations per solve | unconverged solves |\n\
         |---|---|---|---|---|---|\n",
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {:.4} | {:.4} | {:.2} | {:.2} | {} |\n",
            r.name,
            r.pgs_ms,
            r.newton_ms,
            r.ratio(),
            r.newton_iterations,
            r.unconverged
        ));
    }
    out
}
