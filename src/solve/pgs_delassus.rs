//! Projected Gauss–Seidel on the local form ([`LocalProblem`]: W, q): the same visits as
//! [`super::pgs`] — normal row, then friction rows, or the exact local solve — reading a
//! contact's velocity through W instead of the bodies' Δu. With exact visits
//! ([`super::LocalSolve::Exact`]) this is Siconos' NSGS; with row visits it is a projected
//! Gauss–Seidel on W's rows, which Siconos does not have.
//! docs/contact.md §"The local form".
//!
//! A visit of contact k starts from w_k = q_k + Σ_j W_kj λ_j (its block row: the contacts it is
//! coupled to) and, as the visit changes λ_k,r by δ, updates w_k += W_kk e_r δ: within a visit
//! only contact k's own rows are read, so this is exact. The cost of a visit is its block row;
//! the body form's is its two bodies.

use super::local::LocalSolve;
use super::pgs_settings::{ContactOrder, PgsSettings};
use super::pgs_visit::{ContactRows, solve_contact, solve_free_rows, visit_exactly};
use super::projection::project_feasible;
use super::residual::{RowScales, coulomb_residual, residual, row_scales};
use super::sweep_entry::RowLaw;
use crate::problem::{FrictionModel, LocalProblem, RowBounds, SolveMethod, SolveReport};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// Contact k's rows during a visit: its velocity w_k (compliance included, since W holds it)
/// and its diagonal block.
struct BlockRows<'a, const R: usize> {
    block: &'a SMatrix<f64, R, R>,
    w: SVector<f64, R>,
}

impl<const R: usize> ContactRows<R> for BlockRows<'_, R> {
    #[inline(always)]
    fn velocity(&self, r: usize) -> f64 {
        self.w[r]
    }
    #[inline(always)]
    fn apply(&mut self, r: usize, delta: f64) {
        self.w.axpy(delta, &self.block.column(r), 1.0);
    }
}

/// Solves the local problem by projected Gauss–Seidel from each contact's `lambda0` (projected
/// onto its feasible set), in problem order or in a fresh permutation per sweep from a ChaCha8
/// generator seeded with `seed`. On return `lambda` holds one impulse per contact (N·s).
/// The report's residuals are recomputed from the answer ([`residual`], [`coulomb_residual`]).
pub fn solve_pgs_local<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &PgsSettings,
    seed: u64,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    pgs_local(problem, settings, seed, None, lambda)
}

/// As [`solve_pgs_local`], but stopping after the first sweep where `stop(λ)` holds instead of
/// at the settings' tolerance (for `rigidref solve-problems`, which stops every solver on
/// Siconos' error measure). The report's `converged` says whether `stop` held.
pub fn solve_pgs_local_until<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &PgsSettings,
    seed: u64,
    stop: &mut super::Stop<R>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    pgs_local(problem, settings, seed, Some(stop), lambda)
}

fn pgs_local<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &PgsSettings,
    seed: u64,
    mut stop: Option<&mut super::Stop<R>>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    let count = problem.contacts.len();
    let scales: Vec<RowScales<R>> = (0..count).map(|k| row_scales(problem, k)).collect();
    let laws: Vec<RowLaw<R>> = (0..count)
        .map(|k| RowLaw {
            diagonal: scales[k].diagonal,
            tangent_rho: scales[k].tangent_rho,
            mu: problem.contacts[k].mu,
            // W holds the compliance: the velocity the visit reads includes it.
            compliance: 0.0,
        })
        .collect();
    lambda.clear();
    lambda.extend(problem.contacts.iter().map(|c| match c.bounds {
        RowBounds::Contact => project_feasible(&c.lambda0, c.mu, problem.friction),
        RowBounds::Free => c.lambda0,
    }));
    let mut order: Vec<usize> = (0..count).collect();
    if settings.order == ContactOrder::Coloured {
        order = coloured_order(problem);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut fallbacks = 0;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < settings.max_iterations {
        // The local form has no groups of four: its random coloured order is the random order.
        if settings.order.is_random() {
            order.shuffle(&mut rng);
        }
        for &k in &order {
            let contact = &problem.contacts[k];
            let mut w = contact.q;
            for (j, block) in &contact.row {
                w += block * lambda[*j];
            }
            let block = problem.diagonal_block(k);
            let mut rows = BlockRows { block, w };
            let l = &mut lambda[k];
            match (contact.bounds, settings.local) {
                (bounds, LocalSolve::Exact) => {
                    let q = rows.w - block * *l;
                    let (law, scales) = (&laws[k], &scales[k]);
                    if !visit_exactly(problem.friction, bounds, scales, law, &q, &mut rows, l) {
                        fallbacks += 1;
                    }
                }
                (RowBounds::Free, LocalSolve::Rows) => solve_free_rows(&laws[k], &mut rows, l),
                (RowBounds::Contact, LocalSolve::Rows) => {
                    solve_contact(problem.friction, &laws[k], &contact.lambda0, &mut rows, l)
                }
            }
        }
        iterations += 1;
        let done = match stop.as_mut() {
            Some(stop) => stop(lambda),
            None => settings
                .tolerance
                .is_some_and(|tolerance| residual(problem, lambda) <= tolerance),
        };
        if done {
            converged = true;
            break;
        }
    }
    SolveReport {
        iterations,
        residual: residual(problem, lambda),
        converged,
        coulomb_residual: (problem.friction == FrictionModel::Cone)
            .then(|| coulomb_residual(problem, lambda)),
        method: SolveMethod::Pgs,
        local_fallbacks: fallbacks,
    }
}

/// The coloured order of the local form (docs/contact.md §"Coloured order"): contacts coupled
/// through W (an off-diagonal block W_kj, either way round) never share a colour; greedy in
/// problem order, colours in turn, problem order within a colour. The local form has no bodies,
/// so W's couplings stand for the shared bodies.
fn coloured_order<const R: usize>(problem: &LocalProblem<R>) -> Vec<usize> {
    let count = problem.contacts.len();
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (k, c) in problem.contacts.iter().enumerate() {
        for (j, _) in &c.row {
            if *j != k {
                neighbours[k].push(*j);
                neighbours[*j].push(k);
            }
        }
    }
    let mut colour = vec![usize::MAX; count];
    let mut used = Vec::new();
    for k in 0..count {
        used.clear();
        used.extend(
            neighbours[k]
                .iter()
                .map(|&j| colour[j])
                .filter(|&c| c != usize::MAX),
        );
        used.sort_unstable();
        used.dedup();
        colour[k] = used
            .iter()
            .enumerate()
            .find(|(i, c)| i != *c)
            .map_or(used.len(), |(i, _)| i);
    }
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_by_key(|&k| (colour[k], k));
    order
}
