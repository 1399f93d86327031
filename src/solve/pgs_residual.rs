//! A PGS solve's convergence bookkeeping: the residual of the current λ with the bodies' Δu,
//! after each sweep (the tolerance's test) and at the end (the report), and the Coulomb
//! residual of the report. docs/contact.md §"Residual".

use super::pgs_lanes::{LANES, LaneGroup};
use super::pgs_rows::lane_copies;
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
        let mut largest = 0.0;
        for_each_velocity(
            problem,
            &self.groups,
            &self.entries,
            &self.entry_contact,
            &self.delta_velocity,
            lambda,
            |k, w| {
                let term = if problem.contacts[k].bounds == RowBounds::Free {
                    free_residual(w)
                } else {
                    let rho = coulomb_scale(&self.scales[k]);
                    contact_coulomb_residual(problem.contacts[k].mu, &lambda[k], w, rho)
                };
                largest = f64::max(largest, term);
            },
        );
        largest
    }

    pub(super) fn residual(
        &self,
        problem: &ContactProblem<D, R>,
        lambda: &[SVector<f64, R>],
    ) -> f64 {
        row_residual(
            problem,
            &self.groups,
            &self.entries,
            &self.entry_contact,
            &self.scales,
            &self.delta_velocity,
            lambda,
        )
    }
}

/// Calls `f(k, w_k)` for every contact k, w_k its full velocity (compliance included), in the
/// order the entries are stored: the groups lane by lane, then the one-at-a-time entries (so
/// that the pass reads them front to back, wherever the problem order jumps).
fn for_each_velocity<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    groups: &[LaneGroup<D, R>],
    entries: &[Entry<D, R>],
    entry_contact: &[usize],
    delta_velocity: &[SVector<f64, D>],
    lambda: &[SVector<f64, R>],
    mut f: impl FnMut(usize, &SVector<f64, R>),
) {
    for group in groups {
        for lane in 0..LANES {
            let k = group.contact(lane);
            let u = lane_copies(group, lane, delta_velocity);
            let c = &problem.contacts[k];
            let w = SVector::<f64, R>::from_fn(|r, _| {
                group.lane_velocity(lane, &u, r) + c.row_compliance(r) * lambda[k][r]
            });
            f(k, &w);
        }
    }
    for (entry, &k) in entries.iter().zip(entry_contact) {
        let c = &problem.contacts[k];
        let w = SVector::<f64, R>::from_fn(|r, _| {
            entry.velocity(delta_velocity, r) + c.row_compliance(r) * lambda[k][r]
        });
        f(k, &w);
    }
}

/// The residual (docs/contact.md §"Residual") of λ with the bodies' Δu, m/s: the largest row
/// term over all contacts (taken in the order the entries are stored; the largest of the same
/// terms in any order).
pub(super) fn row_residual<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    groups: &[LaneGroup<D, R>],
    entries: &[Entry<D, R>],
    entry_contact: &[usize],
    scales: &[RowScales<R>],
    delta_velocity: &[SVector<f64, D>],
    lambda: &[SVector<f64, R>],
) -> f64 {
    let mut largest = 0.0;
    for_each_velocity(
        problem,
        groups,
        entries,
        entry_contact,
        delta_velocity,
        lambda,
        |k, w| {
            let c = &problem.contacts[k];
            let term =
                constraint_residual(problem.friction, c.bounds, c.mu, &lambda[k], w, &scales[k]);
            largest = f64::max(largest, term);
        },
    );
    largest
}
