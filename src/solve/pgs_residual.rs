//! A PGS solve's convergence bookkeeping: the residual of the current λ with the bodies' Δu,
//! after each sweep (the tolerance's test) and at the end (the report), and the Coulomb
//! residual of the report. docs/contact.md §"Residual".

use super::pgs_workspace::PgsWorkspace;
use super::residual::{
    RowScales, constraint_residual, contact_coulomb_residual, coulomb_scale, free_residual,
};
use super::sweep_entry::Entry;
use crate::problem::{ContactProblem, RowBounds};
use nalgebra::SVector;

impl<const D: usize, const R: usize> PgsWorkspace<D, R> {
    /// The full constraint velocity w of contact `k`, compliance included.
    pub(super) fn contact_velocity(
        &self,
        problem: &ContactProblem<D, R>,
        k: usize,
        lambda: &SVector<f64, R>,
    ) -> SVector<f64, R> {
        let c = &problem.contacts[k];
        SVector::<f64, R>::from_fn(|r, _| self.row_velocity(k, r) + c.row_compliance(r) * lambda[r])
    }

    pub(super) fn coulomb_residual(
        &self,
        problem: &ContactProblem<D, R>,
        lambda: &[SVector<f64, R>],
    ) -> f64 {
        (0..problem.contacts.len())
            .map(|k| {
                let w = self.contact_velocity(problem, k, &lambda[k]);
                if problem.contacts[k].bounds == RowBounds::Free {
                    return free_residual(&w);
                }
                let rho = coulomb_scale(&self.scales[k]);
                contact_coulomb_residual(problem.contacts[k].mu, &lambda[k], &w, rho)
            })
            .fold(0.0, f64::max)
    }

    pub(super) fn residual(
        &self,
        problem: &ContactProblem<D, R>,
        lambda: &[SVector<f64, R>],
    ) -> f64 {
        row_residual(
            problem,
            &self.entries,
            &self.slot,
            &self.scales,
            &self.delta_velocity,
            lambda,
        )
    }
}

/// The residual (docs/contact.md §"Residual") of λ with the bodies' Δu, m/s: the largest row
/// term over all contacts.
pub(super) fn row_residual<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    entries: &[Entry<D, R>],
    slot: &[usize],
    scales: &[RowScales<R>],
    delta_velocity: &[SVector<f64, D>],
    lambda: &[SVector<f64, R>],
) -> f64 {
    (0..problem.contacts.len())
        .map(|k| {
            let c = &problem.contacts[k];
            let w = SVector::<f64, R>::from_fn(|r, _| {
                entries[slot[k]].velocity(delta_velocity, r) + c.row_compliance(r) * lambda[k][r]
            });
            constraint_residual(problem.friction, c.bounds, c.mu, &lambda[k], &w, &scales[k])
        })
        .fold(0.0, f64::max)
}
