//! One constraint's update in a PGS sweep, whichever form reads its rows: the normal row, then
//! the friction rows bounded by μ times the λn just computed; a joint's free rows unbounded; or
//! the exact local solve. docs/contact.md §"PGS", §"Row bounds", §"Exact local solve".
//!
//! A visit sees its constraint through [`ContactRows`]: the body form reads w through the
//! bodies' Δu (src/solve/pgs_workspace.rs), the local form through W
//! (src/solve/pgs_delassus.rs). A visit is the same code for both.

use super::local::{solve_linear, solve_local};
use super::projection::{positive_part, project_disk, project_feasible};
use super::residual::RowScales;
use super::sweep_entry::RowLaw;
use crate::problem::{FrictionModel, RowBounds};
use nalgebra::SVector;

/// One constraint's rows as a visit sees them: the current velocity of a row, and the update
/// a change of one row's impulse makes. The body form reads w through the bodies' Δu
/// ([`super::pgs_workspace`]); the local form through W ([`super::pgs_delassus`]). A visit is the same
/// code for both.
pub(super) trait ContactRows<const R: usize> {
    /// w_r without compliance, m/s.
    fn velocity(&self, r: usize) -> f64;
    /// λ_r changes by `delta` (N·s): update what [`Self::velocity`] reads.
    fn apply(&mut self, r: usize, delta: f64);
}

/// One constraint's exact update: its own R × R problem, W_kk λ + q with q the velocity the
/// rest of the problem gives it, solved for the others' current impulses (docs/contact.md
/// §"Exact local solve"); a joint's block solved as a linear system, left as it is where the
/// block is singular (a joint no impulse can move). Returns false where the contact's solve
/// took its best candidate because no case was exact to round-off.
pub(super) fn visit_exactly<const R: usize>(
    friction: FrictionModel,
    bounds: RowBounds,
    scales: &RowScales<R>,
    law: &RowLaw<R>,
    q: &SVector<f64, R>,
    rows: &mut impl ContactRows<R>,
    lambda: &mut SVector<f64, R>,
) -> bool {
    let (solution, exact) = match bounds {
        RowBounds::Contact => {
            solve_local(&scales.block, q, law.mu, friction, scales, Some(&*lambda))
        }
        RowBounds::Free => match solve_linear(&scales.block, &(-q)) {
            Some(solution) => (solution, true),
            None => return true,
        },
    };
    for r in 0..R {
        rows.apply(r, solution[r] - lambda[r]);
    }
    *lambda = solution;
    exact
}

/// One joint's Gauss–Seidel update: each row in turn, unbounded, λ_r ← λ_r − w_r / a_r
/// (docs/contact.md §"Row bounds").
#[inline(always)]
pub(super) fn solve_free_rows<const R: usize>(
    law: &RowLaw<R>,
    rows: &mut impl ContactRows<R>,
    lambda: &mut SVector<f64, R>,
) {
    let diagonal = law.diagonal;
    for r in 0..R {
        if diagonal[r] > 0.0 {
            let w_r = rows.velocity(r) + law.compliance * lambda[r];
            let delta = -w_r / diagonal[r];
            rows.apply(r, delta);
            lambda[r] += delta;
        }
    }
}

/// One contact's Gauss–Seidel update: normal row, then friction rows. `start` is the contact's
/// warm start (read only by the deliberate fault `stale_friction_bound`).
#[inline(always)]
pub(super) fn solve_contact<const R: usize>(
    friction: FrictionModel,
    law: &RowLaw<R>,
    start: &SVector<f64, R>,
    rows: &mut impl ContactRows<R>,
    lambda: &mut SVector<f64, R>,
) {
    let diagonal = &law.diagonal;

    // Normal row: λn ← max(0, λn − w_n / a_n); a row with a_n = 0 cannot move anything.
    if diagonal[0] > 0.0 {
        let w_n = rows.velocity(0) + law.compliance * lambda[0];
        let lambda_n = positive_part(lambda[0] - w_n / diagonal[0]);
        rows.apply(0, lambda_n - lambda[0]);
        lambda[0] = lambda_n;
    }

    // Friction rows, bounded by μ times the normal impulse just computed.
    let bound = if crate::common::faults::fault!(stale_friction_bound) {
        // The deliberate bug: the bound from the starting λn instead of the one just computed.
        law.mu * project_feasible(start, law.mu, friction)[0]
    } else {
        law.mu * lambda[0]
    };
    if bound == 0.0 {
        // μ λn = 0 (no friction, or no normal impulse): the friction rows' bounds are [0, 0] and
        // their projection is 0, whatever their velocities.
        for r in 1..R {
            if lambda[r] != 0.0 {
                rows.apply(r, -lambda[r]);
                lambda[r] = 0.0;
            }
        }
        return;
    }
    match friction {
        FrictionModel::Box => {
            for r in 1..R {
                if diagonal[r] > 0.0 {
                    let w_r = rows.velocity(r);
                    let lambda_r = (lambda[r] - w_r / diagonal[r]).clamp(-bound, bound);
                    rows.apply(r, lambda_r - lambda[r]);
                    lambda[r] = lambda_r;
                } else {
                    lambda[r] = lambda[r].clamp(-bound, bound);
                }
            }
        }
        FrictionModel::Cone => {
            // One projected-gradient step on the pair with the scalar step 1/ρ, then onto the
            // disk: a per-row step would converge to a point that is not the disk's solution.
            let rho = law.tangent_rho;
            let mut trial = *lambda;
            if rho > 0.0 {
                for r in 1..R {
                    trial[r] = lambda[r] - rows.velocity(r) / rho;
                }
            }
            let projected = project_disk(&trial, bound);
            for r in 1..R {
                rows.apply(r, projected[r] - lambda[r]);
                lambda[r] = projected[r];
            }
        }
    }
}
