//! Assembling the 3D contact problem from the contacts that collision detection found.
//! docs/contact.md §"Contact Jacobian", §"The right-hand side b", §"Stabilisation".

use crate::problem::{ContactProblem3, FrictionModel, ProblemBody, ProblemContact, RowBounds};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::collide::Contact;
use crate::rigid3d::contact::{generalized_velocity, inverse_mass_matrix, jacobian_block};
use crate::rigid3d::warm_start::{WarmCursor, WarmStart};
use nalgebra::SMatrix;

/// The scene parameters that shape the problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProblemSettings {
    /// Integration step h, s.
    pub h: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Friction model.
    pub friction: FrictionModel,
    /// Compliance c on each normal row, kg⁻¹.
    pub compliance: f64,
    /// Baumgarte factor β ∈ [0, 1]: the fraction of the penetration beyond the slop removed per
    /// step.
    pub stabilization: f64,
    /// Penetration left alone by stabilisation, m.
    pub slop: f64,
    /// The largest push-out velocity β e / h of one contact, m/s.
    pub max_push_speed: f64,
}

/// The contact problem of the current substep: every body (its world M⁻¹ and velocity after the
/// velocity step), and per contact J₁ = [dᵀ (r₁×d)ᵀ] and J₂ = −[dᵀ (r₂×d)ᵀ] for d = n, t1, t2,
/// rᵢ = p − xᵢ, b = J₁u₁ + J₂u₂ − min((β/h) max(depth − slop, 0), v_max) e_n + (gap/h) e_n with
/// gap = max(−depth, 0) (a speculative contact), and λ₀ from `warm`.
pub fn assemble_problem(
    bodies: &[RigidBody],
    contacts: &[Contact],
    settings: &ProblemSettings,
    warm: &WarmStart,
) -> ContactProblem3 {
    let mut problem = ContactProblem3 {
        friction: settings.friction,
        bodies: Vec::new(),
        contacts: Vec::new(),
    };
    assemble_problem_into(bodies, contacts, settings, warm, &mut problem);
    problem
}

/// [`assemble_problem`] into `problem`, its buffers reused (a substep allocates nothing once
/// they have grown to the scene's size).
pub fn assemble_problem_into(
    bodies: &[RigidBody],
    contacts: &[Contact],
    settings: &ProblemSettings,
    warm: &WarmStart,
    problem: &mut ContactProblem3,
) {
    problem.friction = settings.friction;
    problem.bodies.clear();
    problem.bodies.extend(bodies.iter().map(|b| ProblemBody {
        inverse_mass: inverse_mass_matrix(b),
        velocity: generalized_velocity(b),
    }));
    let problem_bodies = &problem.bodies;
    problem.contacts.clear();
    // The contacts come in detection's order, which the warm start's cursor walks forward.
    let mut cursor = WarmCursor::default();
    problem.contacts.extend(contacts.iter().map(|c| {
        let body1 = &bodies[c.body1];
        let mut j1 = jacobian_block(&c.frame, &(c.point - body1.x));
        if crate::common::faults::fault!(jacobian_sign_flip) {
            j1.column_mut(3).neg_mut();
        }
        let j2 = match c.body2 {
            Some(b) => -jacobian_block(&c.frame, &(c.point - bodies[b].x)),
            None => SMatrix::zeros(),
        };
        let mut b = j1 * problem_bodies[c.body1].velocity;
        if let Some(body2) = c.body2 {
            b += j2 * problem_bodies[body2].velocity;
        }
        let push = settings.stabilization / settings.h * (c.depth - settings.slop).max(0.0);
        b[0] -= push.min(settings.max_push_speed);
        // A speculative contact (`collision: complete`, a gap of −depth): the bodies may
        // close the gap within the step, no more (docs/contact.md §"Speculative contacts").
        if c.depth < 0.0 {
            b[0] -= c.depth / settings.h;
        }
        ProblemContact {
            bodies: [Some(c.body1), c.body2],
            jacobian: [j1, j2],
            b,
            mu: settings.mu,
            compliance: settings.compliance,
            lambda0: warm.initial_impulse(c, &mut cursor),
            bounds: RowBounds::Contact,
        }
    }));
}
