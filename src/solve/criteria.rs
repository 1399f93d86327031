//! Physical criteria of a contact's answer against Coulomb's law, per contact. ContactBench (Le
//! Lidec et al., "Contact models in robotics: a comparative analysis", IEEE T-RO 2024) defines
//! Signorini, contact complementarity, conic complementarity and the primal and dual
//! feasibilities; the feasibilities, Signorini and the conic complementarity are its, the split of
//! the rest into `cone_boundary` and `max_dissipation` is rigidref's own.
//! docs/contact.md §"Physical criteria".
//!
//! With c = (A + C) λ + b the contact velocity after the impulses (m/s), K = {‖λ_T‖ ≤ μ λn} the
//! friction cone, K* = {c_n ≥ μ ‖c_T‖} its dual and ĉ = c + μ ‖c_T‖ e_n De Saxcé's modified
//! velocity, Coulomb's law is K ∋ λ ⊥ ĉ ∈ K* (§"The exact Coulomb residual"). The criteria are
//!
//!   primal            ε_p = dist_K(λ)                       N·s
//!   dual              ε_d = dist_K*(ĉ)                      m/s
//!   complementarity   ε_c = |λ·ĉ|                           J (N·s · m/s)
//!
//! and, since λ·ĉ = λn c_n + ‖c_T‖ (μλn − ‖λ_T‖) + (‖λ_T‖ ‖c_T‖ + λ_T·c_T), its three parts
//!
//!   signorini         |λn c_n|                              J
//!   cone_boundary     |‖c_T‖ (μλn − ‖λ_T‖)|                 J
//!   max_dissipation   ‖λ_T‖ ‖c_T‖ + λ_T·c_T                 J
//!
//! each zero exactly when its part of the law holds (for λ in K and c_n ≥ 0): no impulse on a separating
//! contact, friction on the cone's rim when sliding, friction opposite to the slip. They are
//! measured against Coulomb's cone whatever the problem's friction model, so that a box-friction
//! answer is judged by the same physics (it violates the cone's parts where it slides off the
//! tangent axes). Per impulse and per step: divided by h, λ is a force (N) and the J are W.

use super::residual::project_cone;
pub use crate::problem::ContactCriteria;
use crate::problem::{ProblemView, RowBounds};
use nalgebra::SVector;

/// Friction coefficients below which the dual criterion is computed through K rather than
/// through its dual cone of opening 1/μ (whose projection overflows below ~1e-154).
pub const DUAL_THROUGH_K: f64 = 1e-100;

/// The criteria of one contact with friction coefficient `mu`, impulse `lambda` (N·s, normal
/// first) and contact velocity `c` (m/s).
pub fn contact_criteria<const R: usize>(
    mu: f64,
    lambda: &SVector<f64, R>,
    c: &SVector<f64, R>,
) -> ContactCriteria {
    let tangential = |v: &SVector<f64, R>| (1..R).map(|r| v[r] * v[r]).sum::<f64>().sqrt();
    let (lambda_t, c_t) = (tangential(lambda), tangential(c));
    let dot_t: f64 = (1..R).map(|r| lambda[r] * c[r]).sum();
    let mut c_hat = *c;
    c_hat[0] += mu * c_t;
    let primal = (lambda - project_cone(lambda, mu)).norm();
    // K* = {c_n ≥ μ‖c_T‖}: the cone of opening 1/μ, whose projection squares 1/μ and overflows
    // (μ⁻² = ∞, and every ĉ outside K* projected to 0) for μ below ~1e-154. Below
    // `DUAL_THROUGH_K` the distance is taken through K instead: K*'s polar cone is −K, so by
    // Moreau's decomposition dist_K*(ĉ) = ‖proj_K(−ĉ)‖, which for μ = 0 is max(−ĉ_n, 0), the
    // distance to the half-space c_n ≥ 0. (Both are exact; above the threshold the first is
    // kept so that reported values stay what they were to the bit.)
    let dual = if mu >= DUAL_THROUGH_K {
        (c_hat - project_cone(&c_hat, 1.0 / mu)).norm()
    } else {
        project_cone(&(-c_hat), mu).norm()
    };
    ContactCriteria {
        primal,
        dual,
        complementarity: lambda.dot(&c_hat).abs(),
        signorini: (lambda[0] * c[0]).abs(),
        cone_boundary: (c_t * (mu * lambda[0] - lambda_t)).abs(),
        max_dissipation: lambda_t * c_t + dot_t,
    }
}

/// The criteria of every constraint of `problem` (either form) for impulses `lambda`, with c
/// computed through the bodies (or W), and their maximum over the contacts. A joint's (free)
/// rows have none (zeros). Allocates; for reports.
pub fn criteria<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> (Vec<ContactCriteria>, ContactCriteria) {
    let c = problem.constraint_velocity(lambda);
    let each: Vec<ContactCriteria> = (0..problem.count())
        .map(|k| match problem.bounds(k) {
            RowBounds::Contact => contact_criteria(problem.mu(k), &lambda[k], &c[k]),
            RowBounds::Free => ContactCriteria::default(),
        })
        .collect();
    let worst = each
        .iter()
        .fold(ContactCriteria::default(), |a, b| a.max(b));
    (each, worst)
}
