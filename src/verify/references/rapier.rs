//! A rapier3d mirror of a scene: the behavioural reference. docs/verification.md §"rapier3d".
//!
//! The same bodies (mass and inertia from the body files, set explicitly; colliders from the same
//! OBJ as the same convex pieces `collision: complete` uses: the mesh's hull when it is convex,
//! else a compound of the pieces of its convex decomposition), the ground as a
//! half-space y ≥ 0... below, gravity, frame step dt, friction μ (combined as the minimum, so
//! body–ground and body–body pairs both get μ), restitution 0 and no damping. rapier integrates
//! with its own substepped soft (TGS) solver and its own contact generation, so trajectories are
//! compared through observables with documented tolerances, never state by state.

use crate::rigid3d::collide::pieces::{ConvexPieces, rotation};
use crate::rigid3d::mesh::TriMesh;
use crate::rigid3d::scene::Scene;
use nalgebra::{Matrix3, Vector3};
use rapier3d_f64::geometry::PairContacts;
use rapier3d_f64::math::{Rotation, Vector};
use rapier3d_f64::prelude::*;

/// One body's state, world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Snapshot {
    /// Centre of mass, m.
    pub x: Vector3<f64>,
    /// Rotation.
    pub rotation: Matrix3<f64>,
    /// Velocity, m/s.
    pub v: Vector3<f64>,
    /// Angular velocity, rad/s.
    pub omega: Vector3<f64>,
}

/// rapier's own timers for one step, ms (its `profiler` feature; [`RapierMirror::enable_timers`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RapierPhases {
    /// Collision detection: broad and narrow phase (contact manifolds).
    pub collision: f64,
    /// Of which the narrow phase.
    pub narrow_phase: f64,
    /// The solver's serial set-up before its workers start (its "velocity assembly" timer). In
    /// rapier 0.36's staged island solver this is not the constraint set-up: the workers
    /// generate the contact constraints (and write the impulses back) inside the iterations'
    /// timer, 5–9 % of it on the pyramids (docs/performance.md §"Issue 49: what rapier's set-up
    /// timer holds").
    pub setup: f64,
    /// The velocity iterations (its substepped solve), with the workers' constraint generation,
    /// impulse write-back and position integration.
    pub iterations: f64,
    /// The whole step.
    pub step: f64,
}

/// The rapier world built from a scene.
pub struct RapierMirror {
    world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
}

fn vector(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn from_vector(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

fn from_rotation(q: &Rotation) -> Matrix3<f64> {
    let m = rapier3d_f64::math::Matrix::from_quat(*q);
    Matrix3::from_columns(&[
        from_vector(m.x_axis),
        from_vector(m.y_axis),
        from_vector(m.z_axis),
    ])
}

/// A collider for `mesh`: its convex pieces (docs/contact.md §"Convex pieces"), as one convex
/// polyhedron when the mesh is convex and as a compound of them otherwise.
fn collider(mesh: &TriMesh) -> Result<ColliderBuilder, String> {
    let pieces = ConvexPieces::of_mesh(mesh)?;
    let mut shapes: Vec<SharedShape> = pieces
        .pieces
        .iter()
        .map(|p| {
            let points: Vec<_> = p
                .vertices
                .iter()
                .map(|v| rapier3d_f64::math::Vector::new(v.x, v.y, v.z))
                .collect();
            SharedShape::convex_hull(&points)
                .ok_or_else(|| "a convex piece spans no volume".to_string())
        })
        .collect::<Result<_, _>>()?;
    if shapes.len() == 1 {
        Ok(ColliderBuilder::new(shapes.remove(0)))
    } else {
        let parts = shapes
            .into_iter()
            .map(|s| (rapier3d_f64::math::Pose::IDENTITY, s))
            .collect();
        Ok(ColliderBuilder::compound(parts))
    }
}

impl RapierMirror {
    /// Builds the mirror of `scene`.
    pub fn new(scene: &Scene) -> Result<RapierMirror, String> {
        let p = &scene.params;
        let mut world = PhysicsWorld::new();
        world.gravity = vector(&p.gravity);
        world.integration_parameters.dt = p.dt;
        let mut handles = Vec::new();
        for body in &scene.bodies {
            let eigen = body.inertia.symmetric_eigen();
            let mut frame = eigen.eigenvectors;
            if frame.determinant() < 0.0 {
                frame.column_mut(2).neg_mut();
            }
            let mass = MassProperties::with_principal_inertia_frame(
                Vector::ZERO,
                body.mass,
                vector(&eigen.eigenvalues),
                rotation(&frame),
            );
            let rb = RigidBodyBuilder::dynamic()
                .translation(vector(&body.x0))
                .rotation(rotation(&body.r0).to_scaled_axis())
                .linvel(vector(&body.v0))
                .angvel(vector(&body.omega0))
                .additional_mass_properties(mass)
                .linear_damping(0.0)
                .angular_damping(0.0)
                .can_sleep(false)
                .build();
            let handle = world.bodies.insert(rb);
            if p.check_collisions {
                let c = collider(&body.mesh)
                    .map_err(|e| format!("{}: {e}", body.source))?
                    .density(0.0)
                    .friction(p.mu)
                    .friction_combine_rule(CoefficientCombineRule::Min)
                    .restitution(0.0)
                    .build();
                world
                    .colliders
                    .insert_with_parent(c, handle, &mut world.bodies);
            }
            handles.push(handle);
        }
        if p.check_collisions {
            let ground =
                ColliderBuilder::halfspace(rapier3d_f64::na::Unit::new_unchecked(Vector::Y))
                    .friction(p.mu)
                    .friction_combine_rule(CoefficientCombineRule::Min)
                    .restitution(0.0)
                    .build();
            world.colliders.insert(ground);
        }
        Ok(RapierMirror { world, handles })
    }

    /// Sets rapier's solver iterations (matched to PGS sweeps by `rigidref bench`).
    pub fn set_solver_iterations(&mut self, n: usize) {
        self.world.integration_parameters.num_solver_iterations = n.max(1);
    }

    /// Sets rapier's step, s (the mirror steps at the scene's frame step unless told otherwise:
    /// `rigidref validate` steps at dt / substeps).
    pub fn set_step(&mut self, h: f64) {
        self.world.integration_parameters.dt = h;
    }

    /// What rapier's documentation recommends for accuracy (docs/validation.md §"rapier"):
    /// `num_solver_iterations` 12 ("8-12: Use for demanding scenarios (stacks of objects, complex
    /// machinery)"), the Coulomb friction model (one friction constraint per contact point; the
    /// default `Simplified` is "significantly faster [...] but less accurate") and no contact
    /// recycling (whose stale contacts are a documented trade-off).
    pub fn set_accurate(&mut self) {
        let p = &mut self.world.integration_parameters;
        p.num_solver_iterations = 12;
        p.friction_model = rapier3d_f64::dynamics::FrictionModel::Coulomb;
        p.contact_recycling = false;
    }

    /// rapier's settings that `rigidref validate` reports.
    pub fn settings_report(&self) -> serde_json::Value {
        let p = &self.world.integration_parameters;
        serde_json::json!({
            "dt": p.dt,
            "num_solver_iterations": p.num_solver_iterations,
            "num_internal_pgs_iterations": p.num_internal_pgs_iterations,
            "num_internal_stabilization_iterations": p.num_internal_stabilization_iterations,
            "friction_model": format!("{:?}", p.friction_model),
            "contact_recycling": p.contact_recycling,
            "contact_clustering": p.contact_clustering,
            "contact_softness_natural_frequency": p.contact_softness.natural_frequency,
            "contact_softness_damping_ratio": p.contact_softness.damping_ratio,
            "allowed_linear_error": p.allowed_linear_error(),
            "prediction_distance": p.prediction_distance(),
        })
    }

    /// rapier's model read back for `rigidref validate`: the step (s), gravity (m/s²), each body's
    /// mass (kg), inertia about its centre of mass in the body frame (kg·m², rows, rebuilt from
    /// rapier's principal moments and frame) and its colliders' friction, the ground's friction,
    /// and the rule rapier combines them by (every collider here asks for `Min`).
    pub fn readback(&self) -> serde_json::Value {
        let bodies: Vec<serde_json::Value> = self
            .handles
            .iter()
            .map(|h| {
                let body = &self.world.bodies[*h];
                let m = body
                    .mass_properties()
                    .local_mprops
                    .reconstruct_inertia_matrix();
                let cols = [m.x_axis, m.y_axis, m.z_axis];
                let rows: Vec<[f64; 3]> = (0..3)
                    .map(|i| [cols[0][i], cols[1][i], cols[2][i]])
                    .collect();
                let mu: Vec<f64> = body
                    .colliders()
                    .iter()
                    .map(|c| self.world.colliders[*c].friction())
                    .collect();
                serde_json::json!({"mass": body.mass(), "inertia": rows, "mu": mu})
            })
            .collect();
        let ground: Vec<f64> = self
            .world
            .colliders
            .iter()
            .filter(|(_, c)| c.parent().is_none())
            .map(|(_, c)| c.friction())
            .collect();
        let g = from_vector(self.world.gravity);
        serde_json::json!({
            "h": self.world.integration_parameters.dt,
            "gravity": [g.x, g.y, g.z],
            "bodies": bodies,
            "ground_mu": ground,
            "pair_mu_rule": "min of the two colliders' friction",
        })
    }

    /// Sets each body's applied force to the scene's load at time `t` (s): force + force_rate t.
    pub fn apply_loads(&mut self, scene: &Scene, t: f64) {
        for (h, d) in self.handles.iter().zip(&scene.bodies) {
            let f = d.force + d.force_rate * t;
            let body = &mut self.world.bodies[*h];
            body.reset_forces(false);
            if f != Vector3::zeros() {
                body.add_force(vector(&f), true);
            }
        }
    }

    /// The contact points of the last step as trace contacts: point (on the body), the normal
    /// from the other body (or the ground) into it, depth, and the normal impulse rapier applied
    /// (N·s). rapier's friction impulses are per manifold (its default `Simplified` model) or in
    /// a basis of its own, so the tangential entries are left zero (docs/validation.md §"rapier").
    pub fn contact_records(&self) -> Vec<crate::rigid3d::trace::ContactRecord> {
        let index = |c: ColliderHandle| -> i64 {
            self.world.colliders[c]
                .parent()
                .and_then(|b| self.handles.iter().position(|h| *h == b))
                .map_or(-1, |k| k as i64)
        };
        let mut out = Vec::new();
        for pair in self.world.contact_pairs() {
            let PairContacts::Rigid(rigid) = &pair.contacts else {
                continue;
            };
            let (b1, b2) = (index(pair.collider1), index(pair.collider2));
            let pose1 = *self.world.colliders[pair.collider1].position();
            for manifold in rigid.solver_manifolds() {
                let n = from_vector(manifold.data.normal);
                for point in &manifold.points {
                    if point.data.impulse == 0.0 && point.dist > 0.0 {
                        continue;
                    }
                    let p = from_vector(pose1 * point.local_p1);
                    // rapier's normal points out of collider 1; the trace's from the other body
                    // into the body named first.
                    let (bodies, normal) = if b1 >= 0 {
                        ([b1, b2], -n)
                    } else {
                        ([b2, b1], n)
                    };
                    out.push(crate::rigid3d::trace::ContactRecord {
                        bodies,
                        p: p.into(),
                        n: normal.into(),
                        depth: -point.dist,
                        lambda: [point.data.impulse, 0.0, 0.0],
                    });
                }
            }
        }
        out
    }

    /// Advances one frame of dt.
    pub fn step(&mut self) {
        self.world.step();
    }

    /// Turns on rapier's phase timers, read by [`RapierMirror::last_step_phases`] (they cost a
    /// clock read per phase).
    pub fn enable_timers(&mut self) {
        self.world.physics_pipeline.counters.enable();
    }

    /// rapier's phase times of the last step, ms (zero unless [`RapierMirror::enable_timers`]).
    pub fn last_step_phases(&self) -> RapierPhases {
        let c = &self.world.physics_pipeline.counters;
        RapierPhases {
            collision: c.stages.collision_detection_time.time_ms(),
            narrow_phase: c.cd.narrow_phase_time.time_ms(),
            setup: c.solver.velocity_assembly_time.time_ms(),
            iterations: c.solver.velocity_resolution_time.time_ms(),
            step: c.step_time.time_ms(),
        }
    }

    /// Every body's state.
    pub fn snapshots(&self) -> Vec<Snapshot> {
        self.handles
            .iter()
            .map(|h| {
                let b = &self.world.bodies[*h];
                Snapshot {
                    x: from_vector(b.translation()),
                    rotation: from_rotation(b.rotation()),
                    v: from_vector(b.linvel()),
                    omega: from_vector(b.angvel()),
                }
            })
            .collect()
    }

    /// Whether any pair of colliders is touching (has an active contact).
    pub fn has_contacts(&self) -> bool {
        self.world
            .contact_pairs()
            .any(|p| p.has_any_active_contact())
    }
}
