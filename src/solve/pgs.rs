//! Projected Gauss–Seidel with delta velocities (Erleben 2007). docs/contact.md §"PGS".
//!
//! Instead of the dense w = (A + C) λ + b, each body carries Δu = M⁻¹ Jᵀ λ, the velocity change
//! that the current impulses cause. A row's velocity is then w_r = b_r + J₁,r Δu₁ + J₂,r Δu₂
//! (+ c λn on the normal row), and a change δ of λ_r costs one update Δu_s += (M_s⁻¹ J_sᵀ)_r δ per
//! body. One sweep visits every contact once: the normal row first, then its friction rows with
//! bounds from the λn just computed. A joint's rows (free bounds) are visited in the same sweep,
//! each unbounded.
//!
//! The solve in stages, one file each: what it is asked ([`super::pgs_settings`]), its
//! buffers ([`super::pgs_workspace`]), a contact's entry built ([`super::pgs_setup`]) and the
//! views a visit reads it through ([`super::pgs_rows`]), one constraint's update
//! ([`super::pgs_visit`]), a sweep ([`super::pgs_sweep`]), the residual after a sweep
//! ([`super::pgs_residual`]); here the driver, [`solve_pgs`].

use super::local::LocalSolve;
pub use super::pgs_settings::{ContactOrder, Lanes, MIN_CONTACTS_PER_THREAD, PgsSettings};
pub use super::pgs_workspace::{BATCH_CONTACTS, PgsWorkspace};
use crate::problem::{ContactProblem, FrictionModel, RowBounds, SolveReport};
use nalgebra::SVector;

/// Solves `problem` by projected Gauss–Seidel, starting from each contact's `lambda0` (projected
/// onto its feasible set). On return `lambda` holds one impulse per contact (N·s) and
/// `workspace.delta_velocity(i)` each body's velocity change. docs/contact.md §"PGS".
pub fn solve_pgs<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &PgsSettings,
    workspace: &mut PgsWorkspace<D, R>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    // What the threads and the groups of four exclude: a contact between a body and itself,
    // and (groups only) a joint's free rows.
    let (self_contact, joint) = (problem.contacts.iter()).fold((false, false), |(s, j), c| {
        (
            s || (c.bodies[0].is_some() && c.bodies[0] == c.bodies[1]),
            j || c.bounds == RowBounds::Free,
        )
    });
    // The groups of four at every size: their entries are built in place, in one pass
    // ([`PgsWorkspace::prepare`]).
    let lanes = settings.order.is_coloured()
        && settings.local == LocalSolve::Rows
        && workspace.lanes != Lanes::Off
        && !crate::common::faults::fault!(stale_friction_bound)
        && !self_contact
        && !joint
        && super::pgs_lanes::dimensions_fit::<D, R>();
    // The entries, and the warm start applied in problem order as they are built.
    // Island by island where every sweep runs on one thread: the same bits, one batch of
    // islands in the cache at a time (docs/contact.md §"Island by island").
    let batched = settings.tolerance.is_none() && workspace.threads == 1;
    let lanes = workspace.prepare(problem, settings.order, lanes, batched, lambda);
    workspace.draw_sweep_colours(settings.order, settings.max_iterations);
    let mut iterations = 0;
    let mut converged = false;
    // Threads only where a colour gives each at least MIN_CONTACTS_PER_THREAD visits on
    // average: below that, starting them and meeting at every colour's barrier costs more than
    // the visits (the result is the same bits either way).
    let colours = workspace.colours().max(1);
    let threaded = settings.order.is_coloured()
        && settings.local == LocalSolve::Rows
        && workspace.threads > 1
        && !self_contact
        && problem.contacts.len() >= MIN_CONTACTS_PER_THREAD * workspace.threads * colours;
    workspace.last_threads = if threaded { workspace.threads } else { 1 };
    if threaded {
        (iterations, converged) = workspace.sweep_in_threads(problem, settings, lanes, lambda);
    }
    if workspace.batches > 1 {
        for batch in 0..workspace.batches {
            for sweep in 0..settings.max_iterations {
                workspace.sweep(problem, settings, batch, sweep as usize, lanes, lambda);
            }
        }
        iterations = settings.max_iterations;
    }
    while !threaded && workspace.batches == 1 && iterations < settings.max_iterations {
        workspace.sweep(problem, settings, 0, iterations as usize, lanes, lambda);
        iterations += 1;
        if let Some(tolerance) = settings.tolerance
            && workspace.residual(problem, lambda) <= tolerance
        {
            converged = true;
            break;
        }
    }
    SolveReport {
        iterations,
        residual: workspace.residual(problem, lambda),
        converged,
        coulomb_residual: (problem.friction == FrictionModel::Cone)
            .then(|| workspace.coulomb_residual(lambda)),
        method: crate::problem::SolveMethod::Pgs,
        local_fallbacks: workspace.local_fallbacks,
    }
}
