//! One 3D contact's geometry and kinematics: its frame (n, t1, t2), a body's 3×6 Jacobian block,
//! and a body's 6×6 inverse mass matrix and generalised velocity. docs/contact.md §"Contact
//! frame", §"Contact Jacobian". The Delassus block A = J M⁻¹ Jᵀ is computed from the assembled
//! problem ([`crate::problem::ContactProblem::delassus_block`]) and b by assembly
//! ([`crate::rigid3d::assemble::assemble_problem`]).
//!
//! Sign convention: a contact is between body 1 and body 2 (body 2 may be the ground). The normal
//! n points from body 2 into body 1: it is the direction along which body 1 must move to separate.
//! The relative velocity at the contact point is u_rel = (v1 + ω1 × r1) − (v2 + ω2 × r2) with
//! rᵢ = p − xᵢ, and w_n = n·u_rel > 0 means separating. A normal impulse λn ≥ 0 pushes body 1
//! along +n and body 2 along −n.

use crate::rigid3d::body::RigidBody;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Degrees of freedom of a 3D body: (v, ω).
pub const DOF_3D: usize = 6;
/// Constraint rows of a 3D contact: normal, tangent 1, tangent 2.
pub const ROWS_3D: usize = 3;

/// The 3×6 Jacobian block of one body in one contact: rows n, t1, t2; columns v (3), ω (3).
pub type JacobianBlock3 = SMatrix<f64, ROWS_3D, DOF_3D>;

/// An orthonormal, right-handed contact frame: t2 = n × t1, so det[n t1 t2] = +1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFrame {
    /// Unit normal, from body 2 into body 1.
    pub n: Vector3<f64>,
    /// First unit tangent.
    pub t1: Vector3<f64>,
    /// Second unit tangent, n × t1.
    pub t2: Vector3<f64>,
}

impl ContactFrame {
    /// The frame for a unit normal `n`. t1 is n crossed with the world axis least aligned with n,
    /// normalised, so |n × e| ≥ √(2/3) and the construction never divides by a small number; for
    /// the ground normal +y this gives t1 = −z, t2 = −x. docs/contact.md §"Contact frame".
    /// (The starter's version has an operator-precedence slip in its axis choice; this one picks
    /// the axis by comparing absolute components explicitly.)
    pub fn from_normal(n: &Vector3<f64>) -> ContactFrame {
        let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
        let axis = if ax <= ay && ax <= az {
            Vector3::x()
        } else if ay <= az {
            Vector3::y()
        } else {
            Vector3::z()
        };
        let t1 = n.cross(&axis).normalize();
        let t2 = n.cross(&t1);
        ContactFrame { n: *n, t1, t2 }
    }

    /// The rows n, t1, t2 as a matrix.
    pub fn rows(&self) -> Matrix3<f64> {
        Matrix3::from_rows(&[self.n.transpose(), self.t1.transpose(), self.t2.transpose()])
    }
}

/// The Jacobian block of a body at lever arm `r` = p − x (m): rows dᵀ \[I | \[r\]×ᵀ\] for d in
/// (n, t1, t2), i.e. [dᵀ, (r × d)ᵀ], so that block · (v, ω) = d · (v + ω × r).
/// Body 2's block is the negative of this with its own r. docs/contact.md §"Contact Jacobian".
pub fn jacobian_block(frame: &ContactFrame, r: &Vector3<f64>) -> JacobianBlock3 {
    let mut j = JacobianBlock3::zeros();
    for (row, d) in [frame.n, frame.t1, frame.t2].iter().enumerate() {
        let angular = r.cross(d);
        for k in 0..3 {
            j[(row, k)] = d[k];
            j[(row, 3 + k)] = angular[k];
        }
    }
    j
}

/// A body's generalised inverse mass M⁻¹ = diag(m⁻¹ I, J⁻¹) (world frame), 6×6.
pub fn inverse_mass_matrix(body: &RigidBody) -> SMatrix<f64, DOF_3D, DOF_3D> {
    let mut m = SMatrix::<f64, DOF_3D, DOF_3D>::zeros();
    for k in 0..3 {
        m[(k, k)] = body.inv_mass;
    }
    m.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&body.inertia_world_inv);
    m
}

/// A body's generalised velocity u = (v, ω).
pub fn generalized_velocity(body: &RigidBody) -> SVector<f64, DOF_3D> {
    SVector::<f64, DOF_3D>::from_fn(|k, _| if k < 3 { body.v[k] } else { body.omega[k - 3] })
}
