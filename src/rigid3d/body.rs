//! A 3D rigid body: its mass properties, its state in the world (spatial) frame, its force
//! accumulators, and the two halves of the symplectic Euler step (velocities, then positions).
//!
//! Sign and frame conventions (docs/dynamics.md §"State and conventions"): `x` is the centre of
//! mass in the world frame; `R` maps body-frame vectors to world-frame vectors (x_world = x + R p);
//! `v` and `ω` are world-frame vectors; the body frame's origin is the centre of mass.

use crate::rigid3d::mesh::TriMesh;
use crate::rigid3d::rotation::{exp_so3, reorthonormalize, skew};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// How the angular velocity is advanced; chosen per scene with the key `integrator`.
/// docs/dynamics.md §"Equations of motion" and §"Implicit gyroscopic term".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngularIntegrator {
    /// The assignment's scheme: ω += h J⁻¹(τ − ω × Jω) with the world inertia J = R J₀ Rᵀ.
    #[default]
    Spatial,
    /// The same equation written in the body frame: ω_b += h J₀⁻¹(τ_b − ω_b × J₀ω_b), ω = R ω_b.
    /// Algebraically identical to `Spatial`; kept as an independent evaluation of the same step.
    Body,
    /// Implicit Euler on the gyroscopic term in the body frame, solved by Newton's method;
    /// the torque is applied explicitly. Dissipates a little energy instead of gaining it.
    ImplicitGyroscopic,
}

impl AngularIntegrator {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            AngularIntegrator::Spatial => "spatial",
            AngularIntegrator::Body => "body",
            AngularIntegrator::ImplicitGyroscopic => "implicit_gyroscopic",
        }
    }
}

/// A rigid body with a triangle-mesh shape.
#[derive(Clone, Debug)]
pub struct RigidBody {
    /// Name from the scene file.
    pub name: String,
    /// Mass m, kg.
    pub mass: f64,
    /// 1/m, 1/kg.
    pub inv_mass: f64,
    /// Inertia about the centre of mass in the body frame J₀, kg·m².
    pub inertia_body: Matrix3<f64>,
    /// J₀⁻¹, 1/(kg·m²).
    pub inertia_body_inv: Matrix3<f64>,
    /// Centre of mass position in the world frame, m.
    pub x: Vector3<f64>,
    /// Rotation from body to world frame.
    pub rotation: Matrix3<f64>,
    /// Linear velocity of the centre of mass, m/s.
    pub v: Vector3<f64>,
    /// Angular velocity in the world frame, rad/s.
    pub omega: Vector3<f64>,
    /// Accumulated force in the world frame, N.
    pub force: Vector3<f64>,
    /// Accumulated torque about the centre of mass in the world frame, N·m.
    pub torque: Vector3<f64>,
    /// World-frame inertia J = R J₀ Rᵀ, kg·m²; kept current by [`RigidBody::update_world_inertia`].
    pub inertia_world: Matrix3<f64>,
    /// World-frame inverse inertia J⁻¹ = R J₀⁻¹ Rᵀ, 1/(kg·m²).
    pub inertia_world_inv: Matrix3<f64>,
    /// The shape in the body frame (centre of mass at the origin), m.
    pub mesh: Arc<TriMesh>,
}

impl RigidBody {
    /// A body at rest at the origin. `inertia_body` must be symmetric positive definite and
    /// `mass` positive; the scene loader checks both before calling this.
    pub fn new(name: &str, mass: f64, inertia_body: Matrix3<f64>, mesh: Arc<TriMesh>) -> RigidBody {
        let inertia_body_inv = inertia_body.try_inverse().unwrap_or_else(Matrix3::zeros);
        let mut body = RigidBody {
            name: name.to_string(),
            mass,
            inv_mass: 1.0 / mass,
            inertia_body,
            inertia_body_inv: (inertia_body_inv + inertia_body_inv.transpose()) * 0.5,
            x: Vector3::zeros(),
            rotation: Matrix3::identity(),
            v: Vector3::zeros(),
            omega: Vector3::zeros(),
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            inertia_world: inertia_body,
            inertia_world_inv: inertia_body_inv,
            mesh,
        };
        body.update_world_inertia();
        body
    }

    /// Sets the force and torque accumulators to zero.
    pub fn zero_forces(&mut self) {
        self.force = Vector3::zeros();
        self.torque = Vector3::zeros();
    }

    /// Adds a force (N) applied at the world point `point` (m): it contributes the torque
    /// (point − x) × f about the centre of mass.
    pub fn add_force_at(&mut self, force: &Vector3<f64>, point: &Vector3<f64>) {
        self.force += force;
        self.torque += (point - self.x).cross(force);
    }

    /// Velocity half of the symplectic Euler step: v += h f/m and the angular update chosen by
    /// `integrator`. docs/dynamics.md §"Equations of motion".
    pub fn step_velocity(&mut self, h: f64, integrator: AngularIntegrator) {
        self.v += self.force * (h * self.inv_mass);
        self.omega = match integrator {
            AngularIntegrator::Spatial => {
                let mut gyroscopic = self.omega.cross(&(self.inertia_world * self.omega));
                if crate::common::faults::fault!(no_gyroscopic_term) {
                    gyroscopic = Vector3::zeros();
                }
                self.omega + self.inertia_world_inv * (self.torque - gyroscopic) * h
            }
            AngularIntegrator::Body => {
                let r = self.rotation;
                let omega_body = r.transpose() * self.omega;
                let torque_body = r.transpose() * self.torque;
                let gyroscopic = omega_body.cross(&(self.inertia_body * omega_body));
                r * (omega_body + self.inertia_body_inv * (torque_body - gyroscopic) * h)
            }
            AngularIntegrator::ImplicitGyroscopic => {
                let r = self.rotation;
                let omega_body =
                    implicit_gyroscopic_step(&self.inertia_body, &(r.transpose() * self.omega), h);
                r * (omega_body + self.inertia_body_inv * (r.transpose() * self.torque) * h)
            }
        };
    }

    /// Position half of the symplectic Euler step, with the new velocities: x += h v,
    /// R ← exp(h \[ω\]×) R (re-orthonormalised), then the world inertia follows R.
    /// docs/dynamics.md §"Rotation update".
    pub fn step_position(&mut self, h: f64) {
        self.x += self.v * h;
        self.rotation = reorthonormalize(&(exp_so3(&(self.omega * h)) * self.rotation));
        self.update_world_inertia();
    }

    /// J = R J₀ Rᵀ and J⁻¹ = R J₀⁻¹ Rᵀ. docs/dynamics.md §"World inertia".
    pub fn update_world_inertia(&mut self) {
        let r = if crate::common::faults::fault!(transposed_world_inertia) {
            self.rotation.transpose()
        } else {
            self.rotation
        };
        self.inertia_world = r * self.inertia_body * r.transpose();
        self.inertia_world_inv = r * self.inertia_body_inv * r.transpose();
    }

    /// Angular velocity in the body frame, ω_b = Rᵀω, rad/s.
    pub fn omega_body(&self) -> Vector3<f64> {
        self.rotation.transpose() * self.omega
    }

    /// The first state component that is not finite, by name, if any. Velocities are checked
    /// first because a step updates them first: a blow-up shows there before it reaches x and R.
    pub fn first_non_finite(&self) -> Option<&'static str> {
        let finite = |v: &Vector3<f64>| v.iter().all(|c| c.is_finite());
        if !finite(&self.v) {
            Some("velocity v")
        } else if !finite(&self.omega) {
            Some("angular velocity omega")
        } else if !finite(&self.x) {
            Some("position x")
        } else if !self.rotation.iter().all(|c| c.is_finite()) {
            Some("rotation R")
        } else {
            None
        }
    }
}

/// Implicit Euler on the torque-free gyroscopic equation in the body frame.
///
/// Solves f(ω) = J₀(ω − ω₀) + h ω × J₀ω = 0 by Newton's method from ω₀ with the Jacobian
/// ∂f/∂ω = J₀ + h(\[ω\]× J₀ − \[J₀ω\]×), iterated until the update is below 1e-15 |ω| (two to four
/// iterations at h|ω| ≤ 0.1; at most [`IMPLICIT_GYROSCOPIC_MAX_NEWTON`]). Solving to convergence
/// matters: the exact solution never gains energy or |L|, a single Newton step can (by ~1e-10
/// per step on a thin rod). If the Jacobian is singular (only for absurd h|ω|) the result is NaN,
/// which stops the run with the body and quantity named. docs/dynamics.md §"Implicit gyroscopic
/// term".
pub fn implicit_gyroscopic_step(
    inertia_body: &Matrix3<f64>,
    omega_body: &Vector3<f64>,
    h: f64,
) -> Vector3<f64> {
    let mut omega = *omega_body;
    for _ in 0..IMPLICIT_GYROSCOPIC_MAX_NEWTON {
        let momentum = inertia_body * omega;
        let residual = inertia_body * (omega - omega_body) + omega.cross(&momentum) * h;
        let jacobian = inertia_body + (skew(&omega) * inertia_body - skew(&momentum)) * h;
        let Some(delta) = jacobian.lu().solve(&residual) else {
            return Vector3::repeat(f64::NAN);
        };
        omega -= delta;
        if delta.norm() <= 1e-15 * omega.norm() {
            break;
        }
    }
    omega
}

/// Newton iterations allowed per implicit gyroscopic step. Convergence is quadratic from ω₀,
/// so this is reached only when h|ω| is far beyond any useful step.
pub const IMPLICIT_GYROSCOPIC_MAX_NEWTON: u32 = 20;
