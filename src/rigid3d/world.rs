//! One step of the simulation, in the order it runs. docs/dynamics.md §"The step".
//!
//! Per frame of length `dt`, `substeps` substeps of length h = dt / substeps, each:
//!
//! 1. zero the force accumulators and add gravity and the applied loads,
//!    f = m g + F + Ḟ t (scene keys `force`, `force_rate`; t the substep's start);
//! 2. step velocities (symplectic Euler, velocity half): [`RigidBody::step_velocity`];
//! 3. contact processing, when `check_collisions` is on: detect ([`crate::rigid3d::collide`];
//!    with `tangents: starter`, each contact's tangents remade by the starter's rule) →
//!    assemble the contact problem ([`crate::rigid3d::assemble`]) → solve ([`crate::solve::solve`]:
//!    PGS, or the exact Newton solver with `solver: newton`) →
//!    apply the velocity changes u⁺ = u + M⁻¹Jᵀλ;
//! 4. step positions with the new velocities: [`RigidBody::step_position`];
//! 5. check that every state component is finite.
//!
//! After the frame, the penetration measure ([`crate::rigid3d::collide::penetration`]) records
//! how deep bodies interpenetrate, whatever contacts were found.

use crate::rigid3d::assemble::{ProblemSettings, assemble_problem_into};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::collide::audit::DetectionAudit;
use crate::rigid3d::collide::detect::Detector;
use crate::rigid3d::collide::penetration::Penetration;
use crate::rigid3d::collide::pieces::ConvexPieces;
use crate::rigid3d::collide::sphere_tree::{self, SphereTree};
use crate::rigid3d::collide::{Contact, Culling, MeshCollider};
use crate::rigid3d::diagnostics::{Energy, Momentum, system_energy, system_momentum};
use crate::rigid3d::frame::Tangents;
use crate::rigid3d::scene::{Scene, SimParameters};
use crate::rigid3d::warm_start::WarmStart;
pub use crate::sim::PhaseTimes;
use crate::sim::{BodyId, ContactGeometry, NonFinite, Simulation, SubstepSolve};
use crate::solve::{PgsSettings, SolverSettings, SolverWorkspace, solve};
use std::sync::Arc;
use std::time::Instant;

/// The contact solve of one substep (the shared record, with 3D contacts and 6 × 3 problems).
pub type Solve3 = SubstepSolve<Contact, 6, 3>;

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
    pub solves: Vec<Solve3>,
    /// Solve records of earlier frames, kept for their buffers so that a frame does not
    /// allocate once they have grown.
    spare_solves: Vec<Solve3>,
    /// The interpenetrating pairs after the last frame (the penetration measure).
    pub penetrations: Vec<Penetration>,
    colliders: Vec<MeshCollider>,
    detector: Detector,
    warm_start: WarmStart,
    workspace: SolverWorkspace<6, 3>,
    contact_buffer: Vec<Contact>,
    /// Wall time spent in each phase of the step since the world was made (`rigidref bench`).
    pub phase_times: PhaseTimes,
    /// Detection held against the oracle on every substep, when switched on
    /// ([`World::audit_detection`]; `rigidref crosscheck`).
    audit: Option<Box<DetectionAudit>>,
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
                b.ellipsoid = d.ellipsoid;
                b.load = d.force;
                b.load_rate = d.force_rate;
                b.update_world_inertia();
                b
            })
            .collect();
        // Bodies that share a mesh share its convex pieces (decomposing one takes a while).
        let mut pieces: Vec<(Arc<crate::rigid3d::mesh::TriMesh>, Arc<ConvexPieces>)> = Vec::new();
        let mut colliders = Vec::with_capacity(scene.bodies.len());
        for d in &scene.bodies {
            let known = pieces
                .iter()
                .find(|(mesh, _)| Arc::ptr_eq(mesh, &d.mesh) || **mesh == *d.mesh)
                .map(|(_, p)| p.clone());
            let shared = match known {
                Some(p) => p,
                None => {
                    let p = Arc::new(
                        ConvexPieces::of_mesh(&d.mesh)
                            .map_err(|e| format!("{}: body {:?}: {e}", d.source, d.name))?,
                    );
                    pieces.push((d.mesh.clone(), p.clone()));
                    p
                }
            };
            colliders.push(
                MeshCollider::with_pieces(d.mesh.clone(), shared)
                    .map_err(|e| format!("{}: body {:?}: {e}", d.source, d.name))?,
            );
        }
        if scene.params.culling == Culling::SphereTree {
            // One tree per distinct mesh, shared by the bodies that use it.
            let mut trees: Vec<(Arc<crate::rigid3d::mesh::TriMesh>, Arc<SphereTree>)> = Vec::new();
            for (d, collider) in scene.bodies.iter().zip(colliders.iter_mut()) {
                let known = trees
                    .iter()
                    .find(|(mesh, _)| Arc::ptr_eq(mesh, &d.mesh) || **mesh == *d.mesh)
                    .map(|(_, t)| t.clone());
                let tree = known.unwrap_or_else(|| {
                    let t = Arc::new(collider.build_sphere_tree(sphere_tree::DEFAULT_DEPTH));
                    trees.push((d.mesh.clone(), t.clone()));
                    t
                });
                collider.sphere_tree = Some(tree);
            }
        }
        let mut world = World {
            params: scene.params.clone(),
            bodies,
            step: 0,
            solves: Vec::new(),
            spare_solves: Vec::new(),
            penetrations: Vec::new(),
            colliders,
            detector: if scene.params.detection_cache {
                Detector::cached(scene.params.check_detection)
                    .with_persistent_manifolds(scene.params.persistent_manifolds)
            } else {
                Detector::default()
            },
            warm_start: WarmStart::new(scene.params.warm_start),
            workspace: SolverWorkspace::with_threads(scene.params.pgs_seed, scene.params.threads),
            contact_buffer: Vec::new(),
            phase_times: PhaseTimes::default(),
            audit: None,
        };
        world.measure_penetration();
        Ok(world)
    }

    /// The body colliders (mesh queries and convex pieces), in body order.
    pub fn colliders(&self) -> &[MeshCollider] {
        &self.colliders
    }

    /// How often detection kept a pair's candidates, and what its debug check found
    /// (`check_detection`). docs/contact.md §"Temporal coherence".
    pub fn detection_stats(&self) -> crate::common::pair_cache::CacheStats {
        self.detector.stats()
    }

    /// The debug check's first difference from fresh detection that is not allowed, said
    /// (`None` when there was none). docs/contact.md §"Persistent manifolds".
    pub fn detection_check_example(&self) -> Option<&str> {
        self.detector.check_example()
    }

    /// From now on, hold detection against the separating-axis oracle on every substep
    /// (docs/contact.md §"The oracle campaign"); the totals are [`World::detection_audit`].
    pub fn audit_detection(&mut self) {
        self.audit.get_or_insert_with(Default::default);
    }

    /// The detection audit's totals, when switched on.
    pub fn detection_audit(&self) -> Option<&DetectionAudit> {
        self.audit.as_deref()
    }

    /// Re-measures [`World::penetrations`] for the current state.
    pub fn measure_penetration(&mut self) {
        self.detector
            .penetrations(&self.bodies, &self.colliders, &mut self.penetrations);
    }

    /// The deepest interpenetration of any pair now, m (0 when none).
    pub fn deepest_penetration(&self) -> f64 {
        self.penetrations
            .iter()
            .map(|p| p.depth)
            .fold(0.0, f64::max)
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
            max_push_speed: p.stabilization_max_speed,
        }
    }

    /// The PGS settings, from the scene parameters.
    pub fn pgs_settings(&self) -> PgsSettings {
        PgsSettings {
            max_iterations: self.params.pgs_iterations,
            tolerance: self.params.pgs_tolerance,
            order: self.params.pgs_order,
            local: self.params.pgs_local_solve,
        }
    }

    /// The solver settings: the scene's `solver` and each solver's settings (Newton's are its
    /// defaults, docs/contact.md §"Newton solver").
    pub fn solver_settings(&self) -> SolverSettings {
        SolverSettings {
            solver: self.params.solver,
            pgs: self.pgs_settings(),
            newton: Default::default(),
        }
    }

    /// Contact processing of one substep: detect → assemble → solve → apply. Changes velocities
    /// only. Records the solve in `solves` when there were contacts.
    fn process_contacts(&mut self, substep: u32) {
        let mut contacts = std::mem::take(&mut self.contact_buffer);
        let clock = Instant::now();
        self.detector.detect(
            &self.bodies,
            &self.colliders,
            self.params.collision,
            &mut contacts,
        );
        if self.params.tangents != Tangents::Orthonormal {
            for c in &mut contacts {
                c.frame = self.params.tangents.frame(&c.frame.n);
            }
        }
        self.phase_times.detect += clock.elapsed().as_secs_f64();
        if let Some(audit) = &mut self.audit {
            audit.check(
                &self.bodies,
                &self.colliders,
                &contacts,
                self.params.collision == crate::rigid3d::collide::CollisionMethod::Complete,
                (self.step + 1, substep),
            );
        }
        if contacts.is_empty() {
            self.warm_start.clear();
            self.contact_buffer = contacts;
            return;
        }
        let clock = Instant::now();
        let mut record = self.spare_solves.pop().unwrap_or_else(|| SubstepSolve {
            substep,
            contacts: Vec::new(),
            problem: crate::problem::ContactProblem {
                friction: Default::default(),
                bodies: Vec::new(),
                contacts: Vec::new(),
            },
            lambda: Vec::new(),
            report: Default::default(),
            solve_seconds: 0.0,
            solve_cpu_seconds: 0.0,
        });
        assemble_problem_into(
            &self.bodies,
            &contacts,
            &self.problem_settings(),
            &self.warm_start,
            &mut record.problem,
        );
        self.phase_times.assemble += clock.elapsed().as_secs_f64();
        record.lambda.clear();
        let settings = self.solver_settings();
        let (report, solve_seconds, cpu) = crate::common::timing::timed(|| {
            solve(
                &record.problem,
                &settings,
                &mut self.workspace,
                &mut record.lambda,
            )
        });
        self.phase_times.solve += solve_seconds;
        let clock = Instant::now();
        for (i, body) in self.bodies.iter_mut().enumerate() {
            let du = self.workspace.delta_velocity(i);
            body.v += du.fixed_rows::<3>(0);
            body.omega += du.fixed_rows::<3>(3);
        }
        self.warm_start.store(&contacts, &record.lambda);
        record.substep = substep;
        // The record keeps this substep's contacts by taking their buffer, not a copy; detection
        // writes the next substep's into the record's old one (it clears what it is given).
        std::mem::swap(&mut record.contacts, &mut contacts);
        record.report = report;
        record.solve_seconds = solve_seconds;
        record.solve_cpu_seconds = cpu.unwrap_or(0.0);
        self.solves.push(record);
        self.contact_buffer = contacts;
        self.phase_times.apply += clock.elapsed().as_secs_f64();
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
        self.spare_solves.append(&mut self.solves);
        for substep in 0..self.params.substeps {
            let clock = Instant::now();
            // Applied loads at the substep's start time (explicit, like gravity).
            let t = self.time() + f64::from(substep) * h;
            for body in &mut self.bodies {
                body.zero_forces();
                body.force += gravity * body.mass + body.load + body.load_rate * t;
            }
            for body in &mut self.bodies {
                body.step_velocity(h, integrator);
            }
            self.phase_times.integrate += clock.elapsed().as_secs_f64();
            if self.params.check_collisions {
                self.process_contacts(substep);
            }
            let clock = Instant::now();
            for body in &mut self.bodies {
                body.step_position(h, integrator);
            }
            self.phase_times.integrate += clock.elapsed().as_secs_f64();
            self.check_finite_at(Some(substep))?;
        }
        self.step += 1;
        let clock = Instant::now();
        self.measure_penetration();
        self.phase_times.measure += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// The first non-finite state component, at `substep` of the step being computed (or, with
    /// `None`, in the state as it stands).
    fn check_finite_at(&self, substep: Option<u32>) -> Result<(), NonFinite> {
        for (index, body) in self.bodies.iter().enumerate() {
            if let Some(quantity) = body.first_non_finite() {
                return Err(NonFinite {
                    quantity: quantity.to_string(),
                    body: Some(BodyId {
                        index,
                        name: Some(body.name.clone()),
                    }),
                    step: self.step + u64::from(substep.is_some()),
                    substep,
                    time: self.time(),
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

impl Simulation<6, 3> for World {
    type Contact = Contact;
    type Energy = Energy;
    type Momentum = Momentum;

    fn step(&mut self) -> Result<(), NonFinite> {
        World::step(self)
    }
    fn steps_done(&self) -> u64 {
        self.step
    }
    fn time(&self) -> f64 {
        World::time(self)
    }
    fn dt(&self) -> f64 {
        self.params.dt
    }
    fn h(&self) -> f64 {
        self.params.h()
    }
    fn solves(&self) -> &[Solve3] {
        &self.solves
    }
    fn energy(&self) -> Energy {
        World::energy(self)
    }
    fn momentum(&self) -> Momentum {
        World::momentum(self)
    }
    fn check_finite(&self) -> Result<(), NonFinite> {
        self.check_finite_at(None)
    }
}

impl ContactGeometry for Contact {
    fn point(&self) -> Vec<f64> {
        self.point.iter().copied().collect()
    }
    fn normal(&self) -> Vec<f64> {
        self.frame.n.iter().copied().collect()
    }
    fn depth(&self) -> f64 {
        self.depth
    }
}
