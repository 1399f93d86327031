//! Timing a case: rigidref and the rapier3d mirror stepped in interleaved rounds, medians kept;
//! rigidref's step by phase; the solver-only rows.

use super::*;

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
    /// rigidref's contact order in the 3D scenes (`--contact-order`; the scenes' own is
    /// sequential).
    pub contact_order: crate::solve::ContactOrder,
    /// Threads of rigidref's coloured sweeps in the 3D scenes (`--threads`; rapier runs on one).
    pub threads: u32,
    /// `persistent_manifolds` in the 3D scenes (`--persistent-manifolds`; it acts on the
    /// `collision: complete` ones).
    pub persistent_manifolds: bool,
}

impl BenchSettings {
    /// Shorter rounds for scenes of more than 2 000 bodies (a step there takes tens of
    /// milliseconds; ten steps a round is plenty and keeps the full run to minutes). The warm-up
    /// stays the same at every size: a family's sizes are then timed in the same phase of their
    /// motion (the pyramids still settle after 40 steps, which made detection look dearer per
    /// body at the large sizes when they were warmed up for 40 steps instead of 100), so that
    /// the fitted exponents compare like with like (docs/performance.md §"Issue 49: the 3D warm
    /// store, and the bench's warm-up at every size").
    pub fn for_bodies(&self, bodies: usize) -> BenchSettings {
        if bodies > 2000 {
            BenchSettings {
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
    /// narrow phase), the solver's serial set-up, velocity iterations (with the constraint
    /// generation)
    /// ([`crate::verify::references::rapier::RapierPhases`]).
    pub rapier_phases_ms: Option<[f64; 3]>,
    /// PGS ns per contact per sweep.
    pub ns_per_contact_sweep: f64,
    /// The share of pair visits in the timed rounds that detection served from the kept
    /// candidate lists (docs/contact.md §"Temporal coherence"); `None` when no pair met.
    pub detection_kept: Option<f64>,
    /// 3D: the share of kept candidate vertices' signed-distance queries answered on a kept
    /// nearest triangle, over the timed steps (`None` in 2D).
    pub nearest_kept: Option<f64>,
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

    /// That over rapier's collision detection and serial set-up (its timers give its constraint
    /// generation no timer of its own: [`crate::verify::references::rapier::RapierPhases::setup`]).
    pub fn around_solve_ratio(&self) -> Option<f64> {
        self.rapier_phases_ms
            .map(|r| self.around_solve_ms() / (r[0] + r[1]))
    }
}

pub(super) fn median(v: Vec<f64>) -> f64 {
    crate::common::stats::median(v).unwrap_or(f64::NAN)
}

pub(super) fn phase_delta(after: &PhaseTimes, before: &PhaseTimes) -> [f64; 6] {
    let (a, b) = (after.as_array(), before.as_array());
    [0, 1, 2, 3, 4, 5].map(|k| a[k] - b[k])
}

/// What the timed rounds of one engine collected.
#[derive(Default)]
pub(super) struct Rounds {
    pub(super) step_ms: Vec<f64>,
    pub(super) phases: Vec<[f64; 6]>,
    pub(super) per_contact: Vec<f64>,
}

impl Rounds {
    /// Times `steps` steps of `world`; `phases` reads its phase clocks. Counts the contacts ×
    /// sweeps and PGS seconds of every solve of the steps, for PGS's cost per contact-sweep.
    pub(super) fn round<S: Simulation<D, R>, const D: usize, const R: usize>(
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

    pub(super) fn phases_ms(&self) -> [f64; 6] {
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

pub(super) fn run_3d(
    case: &BenchCase,
    scene: &Scene,
    s: &BenchSettings,
) -> Result<BenchRow, String> {
    let mut scene = scene.clone();
    scene.params.pgs_iterations = s.iterations;
    scene.params.pgs_order = s.contact_order;
    scene.params.threads = s.threads;
    scene.params.persistent_manifolds = s.persistent_manifolds;
    let mut ours = World::new(&scene)?;
    let mut mirror = RapierMirror::new(&scene)?;
    mirror.set_solver_iterations(s.iterations as usize);
    mirror.enable_timers();
    for _ in 0..s.warmup {
        ours.step().map_err(|e| e.to_string())?;
        mirror.step();
    }
    let mut rounds = Rounds::default();
    let kept_before = ours.detection_stats();
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
    let kept = ours.detection_stats().since(&kept_before);
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
        detection_kept: kept.hit_rate(),
        nearest_kept: kept.nearest_rate(),
    })
}

pub(super) fn run_pile(
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
    let kept_before = world.detection_stats();
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
        detection_kept: world.detection_stats().since(&kept_before).hit_rate(),
        nearest_kept: None,
    })
}

/// The process's peak resident memory, bytes (Linux `VmHWM`; `None` elsewhere).
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
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
