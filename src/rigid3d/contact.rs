//! One 3D contact's kinematics: a body's 3×6 Jacobian block from the contact's frame
//! ([`crate::rigid3d::frame::ContactFrame`]), and a body's 6×6 inverse mass matrix and
//! generalised velocity. docs/contact.md §"Contact Jacobian". The Delassus block A = J M⁻¹ Jᵀ is
//! computed from the assembled problem ([`crate::problem::ContactProblem::delassus_block`]) and b
//! by assembly ([`crate::rigid3d::assemble::assemble_problem`]).
//!
//! Sign convention: a contact is between body 1 and body 2 (body 2 may be the ground). The normal
//! n points from body 2 into body 1: it is the direction along which body 1 must move to separate.
//! The relative velocity at the contact point is u_rel = (v1 + ω1 × r1) − (v2 + ω2 × r2) with
//! rᵢ = p − xᵢ, and w_n = n·u_rel > 0 means separating. A normal impulse λn ≥ 0 pushes body 1
//! along +n and body 2 along −n.

use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use nalgebra::{SMatrix, SVector, Vector3};

/// Degrees of freedom of a 3D body: (v, ω).
pub const DOF_3D: usize = 6;
/// Constraint rows of a 3D contact: normal, tangent 1, tangent 2.
pub const ROWS_3D: usize = 3;

/// The 3×6 Jacobian block of one body in one contact: rows n, t1, t2; columns v (3), ω (3).
pub type JacobianBlock3 = SMatrix<f64, ROWS_3D, DOF_3D>;

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
