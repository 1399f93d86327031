//! One step of the 2D system, in the order it runs. docs/blocks2d.md §"The step".
//!
//! Per step of length `dt`, after the scripted impulses due, `substeps` substeps of
//! h = dt / substeps, each:
//!
//! 1. prescribed motions (shakes) set their bodies' velocities;
//! 2. detect contacts ([`super::collide`]), at the positions the substep starts from;
//! 3. forces: gravity m g (nothing on pinned bodies), the scene's springs and dampers, and with
//!    the penalty model its contact springs;
//! 4. velocities: v += h f/m, ω += h τ/I;
//! 5. contacts and pins: assemble the shared contact problem with 3 degrees of freedom per body
//!    ([`assemble_problem2`], the pins' free rows after the contacts) → solve with the same
//!    solver as 3D ([`crate::solve::solve`]: PGS, or Newton with `solver: newton`) → apply u⁺ = u + M⁻¹Jᵀλ (with the penalty model, the
//!    pins alone);
//!    With shock propagation on, a layer-by-layer pass follows the solve
//!    ([`crate::solve::shock::propagate_shock`]);
//! 6. post-stabilisation (Cline and Pai): a second solve of the same problem shape for a
//!    position-only velocity that removes the penetration beyond the slop;
//! 7. positions: x += h (v + δv), θ += h (ω + δω);
//!
//! and at the end of the step, a check that the state and energy are finite.

mod solve;

use super::assemble::{ContactProblem2, assemble_problem2, empty_problem2};
use super::body::{Body2, cross};
use super::coherence::CachedDetector;
use super::collide::{Contact2, detect_contacts};
use super::diagnostics::{Energy2, Momentum2};
use super::image::BlockGroup;
use super::joints::{Pin2, Spring2};
use super::params::{ContactModel, MAX_ADAPTIVE_SUBSTEPS, Params2};
use super::warm_start::WarmStore2;
use crate::problem::ContactProblem;
use crate::sim::{
    BodyId, ContactGeometry, NonFinite, PhaseTimes, Simulation, SubstepSolve, readable,
};
use crate::solve::shock::propagate_shock;
use crate::solve::{LocalSolve, PgsSettings, SolveReport, Solver, SolverSettings, SolverWorkspace};
use nalgebra::{SVector, Vector2, Vector3};
use std::time::Instant;

/// The contact solve of one substep (the shared record, with 2D contacts and 3 × 2 problems).
pub type Solve2 = SubstepSolve<Contact2, 3, 2>;

/// An impulse applied to a body at a given time (the scripted perturbation that shows a settled
/// stack is not glued).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScriptedImpulse {
    /// Applied at the start of the first step at or after this time, time units.
    pub time: f64,
    /// The body.
    pub body: usize,
    /// The impulse (mass × length / time), world frame.
    pub impulse: Vector2<f64>,
    /// Where, world frame, blocks; `None` is the body's centre of mass.
    pub point: Option<Vector2<f64>>,
}

/// Prescribed motion of a (pinned) body: v(t) = velocity · cos(2π f t), ω(t) = angular ·
/// cos(2π f t) — the shaken container of the nut-bag challenge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shake {
    /// The body (usually the pinned container).
    pub body: usize,
    /// Velocity amplitude, blocks per time unit.
    pub velocity: Vector2<f64>,
    /// Angular velocity amplitude, rad per time unit.
    pub angular: f64,
    /// Frequency, per unit time.
    pub frequency: f64,
}

/// A 2D simulation.
#[derive(Clone, Debug)]
pub struct World2 {
    /// Parameters.
    pub params: Params2,
    /// Bodies.
    pub bodies: Vec<Body2>,
    /// Steps completed.
    pub step: u64,
    /// The last substep's contacts (collision detection's result, with the penalty model too).
    pub contacts: Vec<Contact2>,
    /// The last step's contact solves, one per substep that solved a contact problem.
    pub solves: Vec<Solve2>,
    /// Contacts detected in the last step, summed over its substeps (with the penalty model
    /// too, which solves no problem).
    pub contacts_in_step: usize,
    /// The most contacts detected in one substep of the last step.
    pub most_contacts_in_step: usize,
    /// Substeps the last step took: `params.substeps`, or more with adaptive substeps.
    pub substeps_in_step: u32,
    /// With shock propagation: the most layers a pass has met so far.
    pub shock_layers: u32,
    /// The largest residual of the post-stabilisation solves so far, blocks per time unit
    /// (docs/contact.md §"Residual" on the position problem, μ = 0): how far the last position
    /// correction was from removing the overlap beyond the slop. Reported in the run summary.
    pub post_stabilization_residual: f64,
    /// The most substeps any step took so far.
    pub most_substeps: u32,
    /// Steps whose adaptive substep count hit [`MAX_ADAPTIVE_SUBSTEPS`] (a body moved further
    /// than `max_travel` per substep in them).
    pub capped_steps: u64,
    /// Scripted impulses not yet applied.
    pub impulses: Vec<ScriptedImpulse>,
    /// Prescribed motions.
    pub shakes: Vec<Shake>,
    /// Springs and dampers.
    pub springs: Vec<Spring2>,
    /// Pin joints.
    pub pins: Vec<Pin2>,
    /// The pins' impulses of the last solve (warm start), one (x, y) per pin.
    pin_warm: Vec<SVector<f64, 2>>,
    /// Solve records of earlier steps, kept for their buffers so that a step does not allocate.
    spare_solves: Vec<Solve2>,
    workspace: SolverWorkspace<3, 2>,
    /// Post-stabilisation's problem, impulses and workspace, reused from substep to substep.
    position_problem: ContactProblem2,
    position_lambda: Vec<SVector<f64, 2>>,
    position_workspace: SolverWorkspace<3, 2>,
    /// Post-stabilisation's normal rows alone, their impulses and workspace: the solve it runs
    /// where no pin adds its rows (docs/blocks2d.md §"Post-stabilisation", "Normal rows only").
    normal_problem: ContactProblem<3, 1>,
    normal_lambda: Vec<SVector<f64, 1>>,
    normal_workspace: SolverWorkspace<3, 1>,
    /// Whether the last post-stabilisation solved the normal rows alone (its δu is then in
    /// `normal_workspace`, else in `position_workspace`).
    stabilised_normal_rows: bool,
    /// Whether post-stabilisation may solve the normal rows alone where it can (the default);
    /// off, it always solves both rows of every contact, as before: the same bits, slower
    /// ([`World2::set_normal_rows_post_stabilization`]).
    normal_rows_post_stabilization: bool,
    /// Each body's (vx, vy, ω) before the current substep's forces: restitution's approach speed.
    before_kick: Vec<Vector3<f64>>,
    warm: WarmStore2,
    /// Shock propagation's impulses, a scratch copy of the solve's.
    shock_lambda: Vec<SVector<f64, 2>>,
    /// Wall time spent in each phase of the step since the world was made (`rigidref bench`;
    /// `measure` is post-stabilisation here).
    pub phase_times: PhaseTimes,
    detector: CachedDetector,
}

impl World2 {
    /// A world of the bodies of `groups`, at rest, their inertia and disc trees as `params` say.
    pub fn new(groups: &[BlockGroup], params: Params2) -> World2 {
        World2 {
            bodies: groups
                .iter()
                .map(|g| Body2::from_group_with(g, params.inertia, params.disc_tree))
                .collect(),
            step: 0,
            contacts: Vec::new(),
            solves: Vec::new(),
            contacts_in_step: 0,
            most_contacts_in_step: 0,
            substeps_in_step: params.substeps,
            most_substeps: params.substeps,
            shock_layers: 0,
            post_stabilization_residual: 0.0,
            capped_steps: 0,
            impulses: Vec::new(),
            shakes: Vec::new(),
            springs: Vec::new(),
            pins: Vec::new(),
            pin_warm: Vec::new(),
            spare_solves: Vec::new(),
            workspace: SolverWorkspace::with_threads(params.seed, params.threads),
            position_problem: empty_problem2(),
            position_lambda: Vec::new(),
            position_workspace: SolverWorkspace::with_threads(params.seed, params.threads),
            normal_problem: ContactProblem {
                friction: crate::problem::FrictionModel::Box,
                bodies: Vec::new(),
                contacts: Vec::new(),
            },
            normal_lambda: Vec::new(),
            normal_workspace: SolverWorkspace::with_threads(params.seed, params.threads),
            stabilised_normal_rows: false,
            normal_rows_post_stabilization: true,
            before_kick: Vec::new(),
            warm: WarmStore2::default(),
            shock_lambda: Vec::new(),
            phase_times: PhaseTimes::default(),
            detector: CachedDetector::default(),
            params,
        }
    }

    /// Adds a body (the factory's), keeping every existing index.
    pub fn add_body(&mut self, body: Body2) {
        self.bodies.push(body);
    }

    /// Time, step · step size.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.params.dt
    }

    /// The PGS settings of the velocity solve (and of post-stabilisation): the parameters'
    /// iterations, tolerance and order.
    pub fn pgs_settings(&self) -> PgsSettings {
        PgsSettings {
            max_iterations: self.params.iterations,
            tolerance: self.params.tolerance,
            order: self.params.order,
            local: self.params.local_solve,
        }
    }

    /// The solver settings of the velocity solve and of post-stabilisation: the parameters'
    /// `solver` and each solver's settings (Newton's are its defaults).
    pub fn solver_settings(&self) -> SolverSettings {
        SolverSettings {
            solver: self.params.solver,
            pgs: self.pgs_settings(),
            newton: Default::default(),
        }
    }

    /// Advances one step; fails at the end of a step whose state (or energy) is not finite.
    /// The stages, in order: the step's scripted impulses, then per substep of length h the
    /// shakes, detect, forces (gravity, springs, penalty), the velocity kick, assemble and solve
    /// (with post-stabilisation), and the positions. docs/blocks2d.md §"The step".
    pub fn step(&mut self) -> Result<(), NonFinite> {
        let now = self.time();
        self.begin_step();
        self.apply_due_impulses(now);
        let substeps = self.substeps_for_step();
        self.substeps_in_step = substeps;
        self.most_substeps = self.most_substeps.max(substeps);
        let h = self.params.dt / f64::from(substeps);
        for substep in 0..substeps {
            self.shake(now + f64::from(substep) * h);
            let contacts = self.detect();
            let clock = Instant::now();
            self.apply_forces(&contacts);
            self.kick(h);
            self.phase_times.integrate += clock.elapsed().as_secs_f64();
            let stabilised = self.assemble_and_solve(substep, &contacts, h);
            self.move_positions(h, stabilised);
            self.contacts = contacts;
        }
        self.step += 1;
        self.check_finite()
    }

    /// Before a step: last step's solve records go back to the pool (their buffers are reused),
    /// and the step's contact counters start at zero.
    fn begin_step(&mut self) {
        self.spare_solves.append(&mut self.solves);
        self.contacts_in_step = 0;
        self.most_contacts_in_step = 0;
    }

    /// Applies the scripted impulses due by time `now` (`--impulse`), each once.
    fn apply_due_impulses(&mut self, now: f64) {
        let due: Vec<ScriptedImpulse> = self
            .impulses
            .iter()
            .filter(|i| i.time <= now + 1e-12)
            .copied()
            .collect();
        self.impulses.retain(|i| i.time > now + 1e-12);
        for i in due {
            if let Some(b) = self.bodies.get_mut(i.body) {
                let point = i.point.unwrap_or(b.x);
                b.apply_impulse_at(&i.impulse, &point);
            }
        }
    }

    /// Sets the shaken bodies' velocities for time `t` (`--shake`).
    fn shake(&mut self, t: f64) {
        for s in &self.shakes {
            if let Some(b) = self.bodies.get_mut(s.body) {
                let phase = (2.0 * std::f64::consts::PI * s.frequency * t).cos();
                b.v = s.velocity * phase;
                b.omega = s.angular * phase;
            }
        }
    }

    /// How often detection kept a pair's candidates, and what its debug check found
    /// (`check_detection`). docs/blocks2d.md §"Temporal coherence".
    pub fn detection_stats(&self) -> crate::common::pair_cache::CacheStats {
        self.detector.stats()
    }

    /// Detect: the substep's contacts (in last substep's buffer), counted for the step.
    fn detect(&mut self) -> Vec<Contact2> {
        let mut contacts = std::mem::take(&mut self.contacts);
        let clock = Instant::now();
        if self.params.detection_cache {
            self.detector
                .detect(&self.bodies, self.params.check_detection, &mut contacts);
        } else {
            detect_contacts(&self.bodies, &mut contacts);
        }
        self.phase_times.detect += clock.elapsed().as_secs_f64();
        self.contacts_in_step += contacts.len();
        self.most_contacts_in_step = self.most_contacts_in_step.max(contacts.len());
        contacts
    }

    /// Forces: gravity on every body that is not pinned, the springs, and with the penalty
    /// contact model the contacts' penalty forces.
    fn apply_forces(&mut self, contacts: &[Contact2]) {
        let g = self.params.gravity_vector();
        for b in &mut self.bodies {
            b.force = if b.pinned {
                Vector2::zeros()
            } else {
                g * b.mass
            };
            b.torque = 0.0;
        }
        for spring in &self.springs {
            spring.apply(&mut self.bodies);
        }
        if self.params.contact_model == ContactModel::Penalty {
            self.add_penalty_forces(contacts);
        }
    }

    /// The velocity kick v += h f/m, ω += h τ/I, remembering the velocities before it (for the
    /// contact restitution targets).
    fn kick(&mut self, h: f64) {
        self.before_kick.clear();
        self.before_kick.extend(
            self.bodies
                .iter()
                .map(|b| Vector3::new(b.v.x, b.v.y, b.omega)),
        );
        for b in &mut self.bodies {
            b.step_velocity(h);
        }
    }

    /// Assemble and solve the substep's contact problem (the contacts, or with the penalty model
    /// only the pins), recording the solve; returns whether post-stabilisation ran (its velocity
    /// changes then move the positions). With no contact the warm-start store is emptied.
    fn assemble_and_solve(&mut self, substep: u32, contacts: &[Contact2], h: f64) -> bool {
        // The penalty model's contacts are forces: only the pins enter the problem.
        let solved: &[Contact2] = match self.params.contact_model {
            ContactModel::Pgs => contacts,
            ContactModel::Penalty => &[],
        };
        if !solved.is_empty() || !self.pins.is_empty() {
            let solve = self.solve_contacts(substep, solved, h);
            self.solves.push(solve);
            return self.params.post_stabilization;
        }
        if contacts.is_empty() {
            self.warm.clear();
        }
        false
    }

    /// Positions: x += h v, θ += h ω, plus post-stabilisation's velocity changes when it ran.
    fn move_positions(&mut self, h: f64, stabilised: bool) {
        let clock = Instant::now();
        for (i, b) in self.bodies.iter_mut().enumerate() {
            if stabilised {
                let du = match self.stabilised_normal_rows {
                    true => self.normal_workspace.delta_velocity(i),
                    false => self.position_workspace.delta_velocity(i),
                };
                b.step_position(h, &Vector2::new(du[0], du[1]), du[2]);
            } else {
                b.step_position(h, &Vector2::zeros(), 0.0);
            }
        }
        self.phase_times.integrate += clock.elapsed().as_secs_f64();
    }

    /// The substeps of the step about to run: `params.substeps`, or with adaptive substeps
    /// (`max_travel` set) enough that the fastest body's fastest point, moving at the speed it
    /// starts the step with, travels at most `max_travel` per substep:
    /// n = max(substeps, ⌈s_max · dt / max_travel⌉), at most [`MAX_ADAPTIVE_SUBSTEPS`].
    /// docs/blocks2d.md §"Adaptive substeps".
    pub fn substeps_for_step(&mut self) -> u32 {
        let fixed = self.params.substeps;
        let Some(travel) = self.params.max_travel else {
            return fixed;
        };
        let fastest = self
            .bodies
            .iter()
            .filter(|b| !b.pinned)
            .map(Body2::fastest_point_speed)
            .fold(0.0, f64::max);
        let wanted = (fastest * self.params.dt / travel).ceil();
        if wanted > f64::from(MAX_ADAPTIVE_SUBSTEPS) {
            self.capped_steps += 1;
            return MAX_ADAPTIVE_SUBSTEPS.max(fixed);
        }
        // Here 0 ≤ wanted ≤ the cap (a NaN speed compares false above and gives 0 here).
        (wanted as u32).max(fixed)
    }

    /// Checks every body's state (x, θ, v, ω) and the energies are finite; otherwise says which
    /// body and which quantity, at which step. A run must stop there: contacts of a non-finite
    /// body are meaningless, and JSON has no NaN (an absurd gravity can overflow the potential
    /// energy −m g·x before any state does).
    pub fn check_finite(&self) -> Result<(), NonFinite> {
        let at = |quantity: String, body: Option<BodyId>| NonFinite {
            quantity,
            body,
            step: self.step,
            substep: None,
            time: self.time(),
        };
        for (i, b) in self.bodies.iter().enumerate() {
            let quantities = [
                ("position x", b.x.iter().all(|c| c.is_finite())),
                ("angle θ", b.theta.is_finite()),
                ("velocity v", b.v.iter().all(|c| c.is_finite())),
                ("angular velocity ω", b.omega.is_finite()),
            ];
            if let Some((quantity, _)) = quantities.iter().find(|(_, ok)| !ok) {
                let body = BodyId {
                    index: i,
                    name: None,
                };
                return Err(at(quantity.to_string(), Some(body)));
            }
        }
        let e = self.energy();
        if !(e.kinetic.is_finite() && e.potential.is_finite()) {
            let quantity = format!(
                "energy (kinetic {}, potential {})",
                readable(e.kinetic),
                readable(e.potential)
            );
            return Err(at(quantity, None));
        }
        Ok(())
    }

    /// The deepest disc overlap among the last substep's contacts, blocks (0 without contacts).
    pub fn deepest_overlap(&self) -> f64 {
        self.contacts.iter().map(|c| c.depth).fold(0.0, f64::max)
    }

    /// Kinetic energy, and potential energy: gravitational −Σ m g·x of the non-pinned bodies
    /// plus the springs' elastic energy.
    pub fn energy(&self) -> Energy2 {
        let g = self.params.gravity_vector();
        let kinetic: f64 = self.bodies.iter().map(Body2::kinetic_energy).sum();
        let potential: f64 = self
            .bodies
            .iter()
            .filter(|b| !b.pinned)
            .map(|b| -b.mass * g.dot(&b.x))
            .sum::<f64>()
            + self
                .springs
                .iter()
                .map(|s| s.energy(&self.bodies))
                .sum::<f64>();
        Energy2 {
            kinetic,
            potential,
            total: kinetic + potential,
        }
    }

    /// Linear momentum Σ m v and angular momentum about the origin Σ (x × m v + I ω) of the
    /// non-pinned bodies.
    pub fn momentum(&self) -> Momentum2 {
        let moving = self.bodies.iter().filter(|b| !b.pinned);
        let linear: Vector2<f64> = moving.clone().map(|b| b.v * b.mass).sum();
        let angular = moving
            .map(|b| cross(&b.x, &(b.v * b.mass)) + b.inertia * b.omega)
            .sum();
        Momentum2 {
            linear: linear.into(),
            angular,
        }
    }
}

impl Simulation<3, 2> for World2 {
    type Contact = Contact2;
    type Energy = Energy2;
    type Momentum = Momentum2;

    fn step(&mut self) -> Result<(), NonFinite> {
        World2::step(self)
    }
    fn steps_done(&self) -> u64 {
        self.step
    }
    fn time(&self) -> f64 {
        World2::time(self)
    }
    fn dt(&self) -> f64 {
        self.params.dt
    }
    fn h(&self) -> f64 {
        self.params.dt / f64::from(self.substeps_in_step)
    }
    fn solves(&self) -> &[Solve2] {
        &self.solves
    }
    fn energy(&self) -> Energy2 {
        World2::energy(self)
    }
    fn momentum(&self) -> Momentum2 {
        World2::momentum(self)
    }
    fn check_finite(&self) -> Result<(), NonFinite> {
        World2::check_finite(self)
    }
}

impl ContactGeometry for Contact2 {
    fn point(&self) -> Vec<f64> {
        vec![self.point.x, self.point.y]
    }
    fn normal(&self) -> Vec<f64> {
        vec![self.normal.x, self.normal.y]
    }
    fn depth(&self) -> f64 {
        self.depth
    }
}
