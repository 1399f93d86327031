//! One step of the simulation, in the order it runs. docs/dynamics.md §"The step".
//!
//! Per frame of length `dt`, `substeps` substeps of length h = dt / substeps, each:
//!
//! 1. zero the force accumulators and add gravity, f = m g;
//! 2. step velocities (symplectic Euler, velocity half): [`RigidBody::step_velocity`];
//! 3. contact processing, when `check_collisions` is on: detect ([`crate::collide`]) →
//!    assemble the contact problem ([`crate::assemble`]) → solve ([`crate::solve::pgs`]) →
//!    apply the velocity changes u⁺ = u + M⁻¹Jᵀλ;
//! 4. step positions with the new velocities: [`RigidBody::step_position`];
//! 5. check that every state component is finite.

use crate::assemble::{ProblemSettings, assemble_problem};
use crate::body::RigidBody;
use crate::collide::{Contact, MeshCollider, detect_contacts};
use crate::diagnostics::{Energy, Momentum, system_energy, system_momentum};
use crate::problem::ContactProblem3;
use crate::problem::json::{GeometryJson, ProblemFile, RunOrigin};
use crate::scene::{Scene, SimParameters};
use crate::solve::{PgsSettings, PgsWorkspace, SolveReport, solve_pgs};
use crate::warm_start::WarmStart;
use nalgebra::SVector;

/// The contact solve of one substep, kept for the trace, `--dump-problems` and `rigidref
/// contacts`.
#[derive(Clone, Debug)]
pub struct SubstepContacts {
    /// The substep within its frame (0-based).
    pub substep: u32,
    /// The contacts collision detection found.
    pub contacts: Vec<Contact>,
    /// The problem assembled from them.
    pub problem: ContactProblem3,
    /// The impulses PGS returned, one per contact (n, t1, t2), N·s.
    pub lambda: Vec<SVector<f64, 3>>,
    /// What the solve did.
    pub report: SolveReport,
}

/// A simulation in progress.
#[derive(Clone, Debug)]
pub struct World {
    /// Parameters from the scene.
    pub params: SimParameters,
    /// The bodies, in scene order.
    pub bodies: Vec<RigidBody>,
    /// Frames completed.
    pub step: u64,
    /// The contact solves of the last frame, one per substep that had contacts.
    pub frame_contacts: Vec<SubstepContacts>,
    /// Deliberate bugs (tests only; [`crate::faults`]); set with [`World::inject_faults`].
    pub faults: crate::faults::Faults,
    colliders: Vec<MeshCollider>,
    warm_start: WarmStart,
    workspace: PgsWorkspace<6, 3>,
    contact_buffer: Vec<Contact>,
}

impl SubstepContacts {
    /// The problem as a contact-problem file (docs/contact-problem-format.md), with the contacts'
    /// geometry, where it came from (`scene`, frame `step`, step size `h`) and the PGS solution.
    pub fn problem_file(&self, scene: &str, step: u64, h: f64) -> ProblemFile {
        let origin = RunOrigin {
            scene,
            step,
            substep: self.substep,
            h,
        };
        let geometry = self.contacts.iter().map(|c| GeometryJson {
            p: c.point.iter().copied().collect(),
            n: c.frame.n.iter().copied().collect(),
            depth: c.depth,
        });
        ProblemFile::of_run(&self.problem, origin, geometry, &self.lambda, &self.report)
    }
}

/// A state component became NaN or infinite; the run must stop.
#[derive(Debug, thiserror::Error)]
#[error(
    "non-finite {quantity} in body {body_index} ({body_name:?}) at step {step}, substep {substep} (t = {time} s)"
)]
pub struct NonFinite {
    /// The frame in which it happened (1-based: the frame being computed).
    pub step: u64,
    /// The substep within the frame (0-based).
    pub substep: u32,
    /// Time at the start of that frame, s.
    pub time: f64,
    /// Index of the body in the scene.
    pub body_index: usize,
    /// Its name.
    pub body_name: String,
    /// Which state component.
    pub quantity: &'static str,
}

impl World {
    /// Sets up the bodies at their initial state. Fails only when a mesh cannot be prepared for
    /// collision queries (scene loading has already checked that it bounds a solid).
    pub fn new(scene: &Scene) -> Result<World, String> {
        let bodies = scene
            .bodies
            .iter()
            .map(|d| {
                let mut b = RigidBody::new(&d.name, d.mass, d.inertia, d.mesh.clone());
                b.x = d.x0;
                b.rotation = d.r0;
                b.v = d.v0;
                b.omega = d.omega0;
                b.update_world_inertia();
                b
            })
            .collect();
        let colliders = scene
            .bodies
            .iter()
            .map(|d| {
                MeshCollider::new(d.mesh.clone())
                    .map_err(|e| format!("{}: body {:?}: {e}", d.source, d.name))
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(World {
            params: scene.params.clone(),
            bodies,
            step: 0,
            frame_contacts: Vec::new(),
            faults: crate::faults::Faults::NONE,
            colliders,
            warm_start: WarmStart::new(scene.params.warm_start),
            workspace: PgsWorkspace::new(scene.params.pgs_seed),
            contact_buffer: Vec::new(),
        })
    }

    /// Switches on deliberate bugs (tests only: docs/verification.md §"Teeth").
    pub fn inject_faults(&mut self, faults: crate::faults::Faults) {
        self.faults = faults;
        for body in &mut self.bodies {
            body.faults = faults;
            body.update_world_inertia();
        }
    }

    /// The settings the problem is assembled with, from the scene parameters.
    pub fn problem_settings(&self) -> ProblemSettings {
        let p = &self.params;
        ProblemSettings {
            h: p.h(),
            mu: p.mu,
            friction: p.friction_model,
            compliance: p.compliance,
            stabilization: p.stabilization,
            slop: p.stabilization_slop,
            faults: self.faults,
        }
    }

    /// The PGS settings, from the scene parameters.
    pub fn pgs_settings(&self) -> PgsSettings {
        PgsSettings {
            max_iterations: self.params.pgs_iterations,
            tolerance: self.params.pgs_tolerance,
            order: self.params.pgs_order,
            faults: self.faults,
        }
    }

    /// Contact processing of one substep: detect → assemble → solve → apply. Changes velocities
    /// only. Records the solve in `frame_contacts` when there were contacts.
    fn process_contacts(&mut self, substep: u32) {
        let mut contacts = std::mem::take(&mut self.contact_buffer);
        detect_contacts(&self.bodies, &self.colliders, &mut contacts);
        if contacts.is_empty() {
            self.warm_start.clear();
            self.contact_buffer = contacts;
            return;
        }
        let problem = assemble_problem(
            &self.bodies,
            &contacts,
            &self.problem_settings(),
            &self.warm_start,
        );
        let mut lambda = Vec::with_capacity(contacts.len());
        let report = solve_pgs(
            &problem,
            &self.pgs_settings(),
            &mut self.workspace,
            &mut lambda,
        );
        for (i, body) in self.bodies.iter_mut().enumerate() {
            let du = self.workspace.delta_velocity(i);
            body.v += du.fixed_rows::<3>(0);
            body.omega += du.fixed_rows::<3>(3);
        }
        self.warm_start.store(&contacts, &lambda);
        self.frame_contacts.push(SubstepContacts {
            substep,
            contacts: contacts.clone(),
            problem,
            lambda,
            report,
        });
        self.contact_buffer = contacts;
    }

    /// Simulated time, s: `step · dt` (not a running sum, so it has no round-off drift).
    pub fn time(&self) -> f64 {
        self.step as f64 * self.params.dt
    }

    /// Advances one frame of `dt`. On error the world holds the non-finite state, for inspection.
    pub fn step(&mut self) -> Result<(), NonFinite> {
        let h = self.params.h();
        let gravity = self.params.gravity;
        let integrator = self.params.integrator;
        self.frame_contacts.clear();
        for substep in 0..self.params.substeps {
            for body in &mut self.bodies {
                body.zero_forces();
                body.force += gravity * body.mass;
            }
            for body in &mut self.bodies {
                body.step_velocity(h, integrator);
            }
            if self.params.check_collisions {
                self.process_contacts(substep);
            }
            for body in &mut self.bodies {
                body.step_position(h);
            }
            self.check_finite(substep)?;
        }
        self.step += 1;
        Ok(())
    }

    fn check_finite(&self, substep: u32) -> Result<(), NonFinite> {
        for (index, body) in self.bodies.iter().enumerate() {
            if let Some(quantity) = body.first_non_finite() {
                return Err(NonFinite {
                    step: self.step + 1,
                    substep,
                    time: self.time(),
                    body_index: index,
                    body_name: body.name.clone(),
                    quantity,
                });
            }
        }
        Ok(())
    }

    /// Total energy, J.
    pub fn energy(&self) -> Energy {
        system_energy(&self.bodies, &self.params.gravity)
    }

    /// Total momentum.
    pub fn momentum(&self) -> Momentum {
        system_momentum(&self.bodies)
    }
}
