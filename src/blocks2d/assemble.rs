//! The 2D contact problem: 3 degrees of freedom per body (vx, vy, ω), 2 rows per contact (n, t),
//! assembled into the shared [`crate::problem::ContactProblem`]. docs/blocks2d.md §"Contact
//! problem".

use super::body::{Body2, cross};
use super::collide::{Contact2, tangent};
use super::params::Params2;
use super::warm_start::{WarmCursor, WarmStore2};
use crate::problem::{ContactProblem, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};

/// The 2D problem: 3 degrees of freedom per body (vx, vy, ω), 2 rows per contact (n, t).
pub type ContactProblem2 = ContactProblem<3, 2>;

/// A problem with no bodies and no contacts: a buffer to assemble into.
pub fn empty_problem2() -> ContactProblem2 {
    ContactProblem {
        friction: FrictionModel::Box,
        bodies: Vec::new(),
        contacts: Vec::new(),
    }
}

/// The Jacobian block of a body at lever arm r for direction rows (n, t): [d_x, d_y, r × d].
fn jacobian_block2(n: &Vector2<f64>, t: &Vector2<f64>, r: &Vector2<f64>) -> SMatrix<f64, 2, 3> {
    SMatrix::<f64, 2, 3>::new(n.x, n.y, cross(r, n), t.x, t.y, cross(r, t))
}

/// The 2D contact problem of `contacts`, assembled into `problem` (its buffers reused, so that a
/// substep does not allocate once they have grown): M⁻¹ = diag(1/m, 1/m, 1/I) (zero for pinned
/// bodies), u = (vx, vy, ω), J₁ = [nᵀ, r₁×n; tᵀ, r₁×t], J₂ = −[… r₂ …], b = J u with restitution
/// on approaching normal rows (b_n = (J u)_n + e (J u⁰)_n where (J u⁰)_n < 0, u⁰ = `before_kick`,
/// each body's (vx, vy, ω) before this substep's forces), λ₀ from `warm`. docs/blocks2d.md
/// §"Contact problem".
pub fn assemble_problem2(
    bodies: &[Body2],
    before_kick: &[Vector3<f64>],
    contacts: &[Contact2],
    params: &Params2,
    warm: Option<&WarmStore2>,
    problem: &mut ContactProblem2,
) {
    let mut cursor = WarmCursor::default();
    problem.friction = FrictionModel::Box;
    problem.bodies.clear();
    problem.bodies.extend(bodies.iter().map(|b| ProblemBody {
        inverse_mass: Matrix3::from_diagonal(&Vector3::new(b.inv_mass, b.inv_mass, b.inv_inertia)),
        velocity: Vector3::new(b.v.x, b.v.y, b.omega),
    }));
    let problem_bodies = &problem.bodies;
    problem.contacts.clear();
    problem.contacts.extend(contacts.iter().map(|c| {
        let t = tangent(&c.normal);
        let j1 = jacobian_block2(&c.normal, &t, &(c.point - bodies[c.body1].x));
        let j2 = -jacobian_block2(&c.normal, &t, &(c.point - bodies[c.body2].x));
        let mut b = j1 * problem_bodies[c.body1].velocity + j2 * problem_bodies[c.body2].velocity;
        // The bounce is e times the approach speed the body arrived with, not the speed after
        // this substep's gravity kick: that would add e g h per bounce (e = 1 gained 0.1 block
        // of height per bounce) and make resting contacts hop.
        let approach = (j1 * before_kick[c.body1] + j2 * before_kick[c.body2])[0];
        if approach < 0.0 {
            b[0] += params.restitution * approach;
        }
        let lambda0 = warm
            .and_then(|w| w.find(&(c.body1, c.body2, c.block1, c.block2), &mut cursor))
            .map_or(SVector::<f64, 2>::zeros(), |p| {
                SVector::<f64, 2>::new(p.dot(&c.normal), p.dot(&t))
            });
        ProblemContact {
            bodies: [Some(c.body1), Some(c.body2)],
            jacobian: [j1, j2],
            b,
            mu: params.mu,
            compliance: 0.0,
            lambda0,
            bounds: RowBounds::Contact,
        }
    }));
}
