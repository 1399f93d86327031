//! The convergence residual: zero exactly at a solution of the contact problem.
//! docs/contact.md §"Residual".
//!
//! Per contact, with a_r = (A + C)_rr the row's diagonal and w = (A + C) λ + b:
//!
//! - normal row: a_n |λn − max(0, λn − w_n / a_n)| = |min(a_n λn, w_n)|, the natural map of the
//!   complementarity 0 ≤ λn ⊥ w_n ≥ 0 in velocity units;
//! - box friction row r: a_r |λ_r − clamp(λ_r − w_r / a_r, ±μ λn)|;
//! - cone friction: ρ ‖λt − proj_disk(λt − w_t / ρ, μ λn)‖, one scalar ρ for the pair (a
//!   per-row scale would move the fixed point off the disk's true solution).
//!
//! The residual is the largest of these over all rows, in m/s: "how fast some constraint is still
//! being violated, or how far from its bound an impulse is, measured as a velocity".

use crate::problem::{ContactProblem, FrictionModel};
use nalgebra::SVector;

/// The scales of one contact's rows that PGS steps with and the residual measures with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowScales<const R: usize> {
    /// a_r = (A + C)_rr per row, kg⁻¹ (compliance on the normal row only).
    pub diagonal: SVector<f64, R>,
    /// ρ ≥ largest eigenvalue of the friction rows' block A_tt (Gershgorin: the largest absolute
    /// row sum), kg⁻¹; the cone step is 1/ρ. For one friction row (2D) it is that row's diagonal.
    pub tangent_rho: f64,
}

/// The row scales of contact `k`.
pub fn row_scales<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    k: usize,
) -> RowScales<R> {
    let a = problem.delassus_block(k);
    let mut diagonal = a.diagonal();
    diagonal[0] += problem.contacts[k].compliance;
    let tangent_rho = (1..R)
        .map(|r| (1..R).map(|s| a[(r, s)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    RowScales {
        diagonal,
        tangent_rho,
    }
}

/// One contact's residual (m/s) for impulse `lambda` and constraint velocity `w`.
pub fn contact_residual<const R: usize>(
    friction: FrictionModel,
    mu: f64,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
    scales: &RowScales<R>,
) -> f64 {
    let a = &scales.diagonal;
    // A row with a zero diagonal cannot be moved by its own impulse (both bodies pinned);
    // it counts only as far as it is violated.
    let normal = if a[0] > 0.0 {
        (a[0] * lambda[0]).min(w[0]).abs()
    } else {
        lambda[0].min(w[0]).abs()
    };
    let bound = mu * lambda[0].max(0.0);
    let friction = match friction {
        FrictionModel::Box => (1..R)
            .map(|r| {
                if a[r] > 0.0 {
                    a[r] * (lambda[r] - (lambda[r] - w[r] / a[r]).clamp(-bound, bound)).abs()
                } else {
                    (lambda[r].abs() - bound).max(0.0)
                }
            })
            .fold(0.0, f64::max),
        FrictionModel::Cone => {
            let rho = scales.tangent_rho;
            if rho > 0.0 {
                let mut trial = *lambda;
                for r in 1..R {
                    trial[r] = lambda[r] - w[r] / rho;
                }
                let projected = super::projection::project_disk(&trial, bound);
                rho * (1..R)
                    .map(|r| (lambda[r] - projected[r]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            } else {
                0.0
            }
        }
    };
    normal.max(friction)
}

/// The residual of impulses `lambda` for `problem` (m/s): the largest row residual, 0 for a
/// problem without contacts. Allocates; PGS computes the same number from its workspace.
pub fn residual<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    lambda: &[SVector<f64, R>],
) -> f64 {
    let w = problem.constraint_velocity(lambda);
    (0..problem.contacts.len())
        .map(|k| {
            contact_residual(
                problem.friction,
                problem.contacts[k].mu,
                &lambda[k],
                &w[k],
                &row_scales(problem, k),
            )
        })
        .fold(0.0, f64::max)
}
