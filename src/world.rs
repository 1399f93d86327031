//! One step of the simulation, in the order it runs. docs/dynamics.md §"The step".
//!
//! Per frame of length `dt`, `substeps` substeps of length h = dt / substeps, each:
//!
//! 1. zero the force accumulators and add gravity, f = m g;
//! 2. step velocities (symplectic Euler, velocity half): [`RigidBody::step_velocity`];
//! 3. contact processing: detect → assemble the contact problem → solve → apply impulses
//!    (issue #3; until then bodies pass through each other and the ground);
//! 4. step positions with the new velocities: [`RigidBody::step_position`];
//! 5. check that every state component is finite.

use crate::body::RigidBody;
use crate::diagnostics::{Energy, Momentum, system_energy, system_momentum};
use crate::scene::{Scene, SimParameters};

/// A simulation in progress.
#[derive(Clone, Debug)]
pub struct World {
    /// Parameters from the scene.
    pub params: SimParameters,
    /// The bodies, in scene order.
    pub bodies: Vec<RigidBody>,
    /// Frames completed.
    pub step: u64,
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
    /// Sets up the bodies at their initial state.
    pub fn new(scene: &Scene) -> World {
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
        World {
            params: scene.params.clone(),
            bodies,
            step: 0,
        }
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
        for substep in 0..self.params.substeps {
            for body in &mut self.bodies {
                body.zero_forces();
                body.force += gravity * body.mass;
            }
            for body in &mut self.bodies {
                body.step_velocity(h, integrator);
            }
            // Contact processing goes here (issue #3): it changes velocities only.
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
