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
    /// The implicit midpoint rule on the body-frame Euler equations L' = L × J₀⁻¹L with the
    /// matching Cayley rotation update (not a Lie–Poisson map; docs/dynamics.md §"Conservative
    /// rotation"): a torque-free body keeps
    /// its kinetic energy, |L| and its world angular momentum to round-off at any step. Torques
    /// and contact impulses act as a kick before the free rotation (a splitting).
    /// docs/dynamics.md §"Conservative rotation".
    Conservative,
}

impl AngularIntegrator {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            AngularIntegrator::Spatial => "spatial",
            AngularIntegrator::Body => "body",
            AngularIntegrator::ImplicitGyroscopic => "implicit_gyroscopic",
            AngularIntegrator::Conservative => "conservative",
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
    /// An analytic ellipsoid contact shape, when the scene gives one (`ellipsoid`): it replaces
    /// the mesh in collision (ground contact at its lowest point; other meshes' vertices against
    /// its implicit surface). The mesh is then for drawing only.
    pub ellipsoid: Option<crate::rigid3d::shape::Ellipsoid>,
    /// A constant applied force at the centre of mass, world frame, N (scene key `force`).
    pub load: Vector3<f64>,
    /// The rate of an applied force growing from zero, F(t) = load_rate · t at the centre of
    /// mass, world frame, N/s (scene key `force_rate`).
    pub load_rate: Vector3<f64>,
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
            ellipsoid: None,
            load: Vector3::zeros(),
            load_rate: Vector3::zeros(),
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
            AngularIntegrator::Conservative => {
                // Only the torque's kick here: the gyroscopic motion is the free rotation that
                // step_position makes, moving R and ω together.
                self.omega + self.inertia_world_inv * self.torque * h
            }
        };
    }

    /// Position half of the symplectic Euler step, with the new velocities: x += h v,
    /// R ← exp(h \[ω\]×) R (re-orthonormalised), then the world inertia follows R.
    /// docs/dynamics.md §"Rotation update". With [`AngularIntegrator::Conservative`] the rotation
    /// is instead the free rotation of [`conservative_rotation_step`], which also moves ω
    /// (docs/dynamics.md §"Conservative rotation").
    pub fn step_position(&mut self, h: f64, integrator: AngularIntegrator) {
        self.x += self.v * h;
        if integrator == AngularIntegrator::Conservative {
            let momentum_body = self.inertia_body * (self.rotation.transpose() * self.omega);
            let (momentum_body, q) =
                conservative_rotation_step(&self.inertia_body_inv, &momentum_body, h);
            self.rotation = reorthonormalize(&(self.rotation * q));
            self.omega = self.rotation * (self.inertia_body_inv * momentum_body);
        } else {
            self.rotation = reorthonormalize(&(exp_so3(&(self.omega * h)) * self.rotation));
        }
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

/// One step of the torque-free body by the implicit midpoint rule on the body-frame Euler
/// equations L' = L × J₀⁻¹L, with the rotation that matches it.
///
/// Solves F(L₁) = L₁ − L₀ − h m × J₀⁻¹m = 0, m = (L₀ + L₁)/2, by Newton's method from L₀
/// (∂F/∂L₁ = I − (h/2)(\[m\]× J₀⁻¹ − \[J₀⁻¹m\]×)) until the update is below 1e-15 |L₁|. With
/// ω = J₀⁻¹m and Q = cay(hω) = (I − (h/2)\[ω\]×)⁻¹(I + (h/2)\[ω\]×), the solution is exactly
/// L₁ = Qᵀ L₀, so R₁ = R₀ Q keeps the world angular momentum R L (and |L|) to round-off, and the
/// midpoint rule keeps the quadratic invariant ½ Lᵀ J₀⁻¹ L, the kinetic energy. If Newton has
/// not converged in [`CONSERVATIVE_MAX_NEWTON`] iterations (only at large h|ω| on a very
/// unequal body) the step is made as two half steps, recursively, at most
/// [`CONSERVATIVE_MAX_HALVINGS`] deep: each half step conserves the same quantities.
/// Returns (L₁, Q) with L₁ = Qᵀ L₀, body frame, kg·m²/s. docs/dynamics.md §"Conservative rotation".
pub fn conservative_rotation_step(
    inertia_body_inv: &Matrix3<f64>,
    momentum_body: &Vector3<f64>,
    h: f64,
) -> (Vector3<f64>, Matrix3<f64>) {
    midpoint_rotation(inertia_body_inv, momentum_body, h, 0)
}

/// [`conservative_rotation_step`] at halving depth `depth`.
fn midpoint_rotation(
    inertia_body_inv: &Matrix3<f64>,
    l0: &Vector3<f64>,
    h: f64,
    depth: u32,
) -> (Vector3<f64>, Matrix3<f64>) {
    let mut l1 = *l0;
    let mut converged = false;
    for _ in 0..CONSERVATIVE_MAX_NEWTON {
        let m = (l0 + l1) * 0.5;
        let omega = inertia_body_inv * m;
        let residual = l1 - l0 - m.cross(&omega) * h;
        let jacobian =
            Matrix3::identity() - (skew(&m) * inertia_body_inv - skew(&omega)) * (0.5 * h);
        let Some(delta) = jacobian.lu().solve(&residual) else {
            break;
        };
        l1 -= delta;
        if delta.norm() <= 1e-15 * l1.norm() {
            converged = true;
            break;
        }
    }
    if !converged && depth < CONSERVATIVE_MAX_HALVINGS {
        // Two half steps: R₀ Q_a Q_b, and L goes to Q_bᵀ Q_aᵀ L₀.
        let (la, qa) = midpoint_rotation(inertia_body_inv, l0, 0.5 * h, depth + 1);
        let (lb, qb) = midpoint_rotation(inertia_body_inv, &la, 0.5 * h, depth + 1);
        return (lb, qa * qb);
    }
    if !converged {
        // Not silently an unconverged midpoint: NaN stops the run naming the body and quantity,
        // as the implicit gyroscopic step does.
        return (Vector3::repeat(f64::NAN), Matrix3::repeat(f64::NAN));
    }
    let w = skew(&(inertia_body_inv * ((l0 + l1) * 0.5))) * (0.5 * h);
    let q = (Matrix3::identity() - w)
        .lu()
        .solve(&(Matrix3::identity() + w))
        .unwrap_or(Matrix3::repeat(f64::NAN));
    (q.transpose() * l0, q)
}

/// Newton iterations allowed per conservative step before it is halved (from L₀ Newton
/// converges in 3 to 6 at h|ω| ≤ 1).
pub const CONSERVATIVE_MAX_NEWTON: u32 = 30;

/// How many times a conservative step may be halved (2²⁰ pieces at most; never reached in
/// the tests, up to h|ω| ≈ 35).
pub const CONSERVATIVE_MAX_HALVINGS: u32 = 20;

/// Implicit Euler on the torque-free gyroscopic equation in the body frame.
///
/// Solves f(ω) = J₀(ω − ω₀) + h ω × J₀ω = 0 by Newton's method from ω₀ with the Jacobian
/// ∂f/∂ω = J₀ + h(\[ω\]× J₀ − \[J₀ω\]×), iterated until the update is below 1e-15 |ω| (two to four
/// iterations at h|ω| ≤ 0.1). Solving to convergence matters: the exact solution never gains
/// energy or |L|, an unconverged iterate can. Where Newton does not converge in
/// [`IMPLICIT_GYROSCOPIC_MAX_NEWTON`] iterations (large h|ω|) the step is taken as two implicit
/// Euler steps of h/2, recursively, at most [`IMPLICIT_GYROSCOPIC_MAX_HALVINGS`] times; if that
/// still does not converge the result is NaN, which stops the run with the body and quantity
/// named, rather than an answer that may gain energy. docs/dynamics.md §"Implicit gyroscopic
/// term".
pub fn implicit_gyroscopic_step(
    inertia_body: &Matrix3<f64>,
    omega_body: &Vector3<f64>,
    h: f64,
) -> Vector3<f64> {
    implicit_gyroscopic_halving(inertia_body, omega_body, h, 0)
}

/// [`implicit_gyroscopic_step`] at halving depth `depth`.
fn implicit_gyroscopic_halving(
    inertia_body: &Matrix3<f64>,
    omega_body: &Vector3<f64>,
    h: f64,
    depth: u32,
) -> Vector3<f64> {
    let mut omega = *omega_body;
    for _ in 0..IMPLICIT_GYROSCOPIC_MAX_NEWTON {
        let momentum = inertia_body * omega;
        let residual = inertia_body * (omega - omega_body) + omega.cross(&momentum) * h;
        let jacobian = inertia_body + (skew(&omega) * inertia_body - skew(&momentum)) * h;
        let Some(delta) = jacobian.lu().solve(&residual) else {
            break;
        };
        omega -= delta;
        if delta.norm() <= 1e-15 * omega.norm() || omega == *omega_body {
            return omega;
        }
    }
    if depth < IMPLICIT_GYROSCOPIC_MAX_HALVINGS {
        let half = implicit_gyroscopic_halving(inertia_body, omega_body, 0.5 * h, depth + 1);
        return implicit_gyroscopic_halving(inertia_body, &half, 0.5 * h, depth + 1);
    }
    Vector3::repeat(f64::NAN)
}

/// Newton iterations allowed per implicit gyroscopic step. Convergence is quadratic from ω₀,
/// so this is reached only when h|ω| is far beyond any useful step.
pub const IMPLICIT_GYROSCOPIC_MAX_NEWTON: u32 = 20;

/// How many times an implicit gyroscopic step may be halved (2²⁰ pieces at most).
pub const IMPLICIT_GYROSCOPIC_MAX_HALVINGS: u32 = 20;
