//! A PGS solve's convergence bookkeeping: the residual of the current λ with the bodies' Δu,
//! after each sweep (the tolerance's test) and at the end (the report), and the Coulomb
//! residual of the report. docs/contact.md §"Residual".

use super::pgs_lanes::{LANES, LaneGroup};
use super::pgs_rows::lane_copies;
use super::pgs_workspace::PgsWorkspace;
use super::residual::{
    contact_coulomb_residual, contact_residual_of_rows, coulomb_scale, free_residual,
};
use super::sweep_entry::{Entry, RowLaw};
use crate::problem::{ContactProblem, FrictionModel, RowBounds};
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

    pub(super) fn coulomb_residual(&self, lambda: &[SVector<f64, R>]) -> f64 {
        let mut largest = 0.0;
        for_each_velocity(
            &self.groups,
            &self.entries,
            &self.entry_contact,
            &self.delta_velocity,
            lambda,
            |k, w, law, bounds| {
                let term = if bounds == RowBounds::Free {
                    free_residual(w)
                } else {
                    let rho = coulomb_scale(&self.scales[k]);
                    contact_coulomb_residual(law.mu, &lambda[k], w, rho)
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
            problem.friction,
            &self.groups,
            &self.entries,
            &self.entry_contact,
            &self.delta_velocity,
            lambda,
        )
    }
}

/// Calls `f(k, w_k, law_k, bounds_k)` for every contact k, w_k its full velocity (compliance
/// included) and law_k its row scales, μ and compliance as the sweeps read them (the problem's
/// μ and compliance; the row scales' diagonal and ρ), in the order the entries are stored: the
/// groups lane by lane, then the one-at-a-time entries. So the pass reads the groups and
/// entries front to back and, of what is kept in the problem's order, only λ: not the
/// problem's contacts or the row scales, which a grouped contact would fetch from a place
/// that jumps with the colouring (on the cube stack grid 16×16 this pass was about 8 % of the
/// step's time while it read them).
fn for_each_velocity<const D: usize, const R: usize>(
    groups: &[LaneGroup<D, R>],
    entries: &[Entry<D, R>],
    entry_contact: &[usize],
    delta_velocity: &[SVector<f64, D>],
    lambda: &[SVector<f64, R>],
    mut f: impl FnMut(usize, &SVector<f64, R>, &RowLaw<R>, RowBounds),
) {
    for group in groups {
        for lane in 0..LANES {
            let k = group.contact(lane);
            let u = lane_copies(group, lane, delta_velocity);
            // Grouped contacts are contacts, never a joint's free rows (`solve_pgs`).
            let (law, bounds) = (group.law(lane), RowBounds::Contact);
            let w = SVector::<f64, R>::from_fn(|r, _| {
                group.lane_velocity(lane, &u, r)
                    + bounds.row_compliance(law.compliance, r) * lambda[k][r]
            });
            f(k, &w, &law, bounds);
        }
    }
    for (entry, &k) in entries.iter().zip(entry_contact) {
        let (law, bounds) = (&entry.law, entry.bounds);
        let w = SVector::<f64, R>::from_fn(|r, _| {
            entry.velocity(delta_velocity, r)
                + bounds.row_compliance(law.compliance, r) * lambda[k][r]
        });
        f(k, &w, law, bounds);
    }
}

/// The residual (docs/contact.md §"Residual") of λ with the bodies' Δu, m/s: the largest row
/// term over all contacts (taken in the order the entries are stored; the largest of the same
/// terms in any order), each [`constraint_residual`]'s on the numbers it reads.
pub(super) fn row_residual<const D: usize, const R: usize>(
    friction: FrictionModel,
    groups: &[LaneGroup<D, R>],
    entries: &[Entry<D, R>],
    entry_contact: &[usize],
    delta_velocity: &[SVector<f64, D>],
    lambda: &[SVector<f64, R>],
) -> f64 {
    let mut largest = 0.0;
    for_each_velocity(
        groups,
        entries,
        entry_contact,
        delta_velocity,
        lambda,
        |k, w, law, bounds| {
            let term = match bounds {
                RowBounds::Contact => contact_residual_of_rows(
                    friction,
                    law.mu,
                    &lambda[k],
                    w,
                    &law.diagonal,
                    law.tangent_rho,
                ),
                RowBounds::Free => free_residual(w),
            };
            largest = f64::max(largest, term);
        },
    );
    largest
}
