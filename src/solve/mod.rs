//! Solvers of the contact problem ([`crate::problem::ContactProblem`]), side by side, one file
//! each, picked by one switch ([`Solver`], the scene key `solver`, dispatched by [`solve`]):
//!
//! - [`pgs`]: projected Gauss–Seidel with delta velocities (Erleben 2007), the assignment's
//!   solver and the default;
//! - [`newton`]: the exact solver, a semismooth Newton method on the Alart–Curnier function with
//!   a proximal-point fallback, sharing nothing with PGS but the problem;
//! - [`qp`]: the same problem as a convex QP/SOCP solved by clarabel, the independent reference
//!   of the cross-check (not a step's solver);
//!
//! and what they share or are judged by:
//!
//! - [`local`]: the exact solve of one contact's own problem, PGS's `exact` visit;
//! - [`projection`]: the feasible set of a contact's impulse and the projections onto it;
//! - [`residual`](mod@residual): the natural-map residual that says how far a λ is from a solution, for any
//!   solver's answer;
//! - [`criteria`](mod@criteria): the physical criteria of an answer against Coulomb's law, per
//!   contact (primal, dual, complementarity and its Signorini, cone-boundary and
//!   maximum-dissipation parts);
//! - [`shock`]: shock propagation, a layer-by-layer pass after PGS (an option).

pub mod auto;
pub mod colour;
pub mod criteria;
mod islands;
pub mod local;
pub mod newton;
pub mod pgs;
pub mod pgs_delassus;
mod pgs_lanes;
mod pgs_residual;
mod pgs_rows;
mod pgs_settings;
mod pgs_setup;
mod pgs_sweep;
mod pgs_threads;
mod pgs_visit;
mod pgs_workspace;
mod prefetch;
pub mod projection;
pub mod qp;
pub mod residual;
pub mod shock;
mod sweep_entry;
pub mod twins;
mod wide;

pub use crate::problem::{SolveMethod, SolveReport};
pub use local::LocalSolve;
pub use newton::{
    NewtonSettings, NewtonWorkspace, Regularisation, solve_newton, solve_newton_local,
    solve_newton_local_until,
};
pub use pgs::{ContactOrder, PgsSettings, PgsWorkspace, solve_pgs};
pub use pgs_delassus::{solve_pgs_local, solve_pgs_local_until};
pub use residual::residual;

use crate::problem::ContactProblem;
use nalgebra::SVector;

/// Which solver a step uses (scene key `solver`).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum Solver {
    /// Projected Gauss–Seidel, the assignment's method (default): `pgs_iterations` sweeps.
    #[default]
    Pgs,
    /// The exact solver ([`newton`]): every solve to 1e-10 m/s or a report that it did not.
    Newton,
}

impl Solver {
    /// The scene-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Pgs => "pgs",
            Solver::Newton => "newton",
        }
    }
}

/// Everything the switch needs: which solver, and each solver's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// The solver used.
    pub solver: Solver,
    /// PGS's settings (used when `solver` is PGS).
    pub pgs: PgsSettings,
    /// Newton's settings (used when `solver` is Newton).
    pub newton: NewtonSettings,
}

/// Each solver's buffers, kept from solve to solve, and which one ran last.
#[derive(Clone, Debug)]
pub struct SolverWorkspace<const D: usize, const R: usize> {
    /// PGS's buffers and its seeded random order.
    pub pgs: PgsWorkspace<D, R>,
    /// Newton's buffers.
    pub newton: NewtonWorkspace<D>,
    last: Solver,
}

impl<const D: usize, const R: usize> SolverWorkspace<D, R> {
    /// Empty buffers whose coloured PGS sweeps run on `threads` threads
    /// ([`PgsWorkspace::set_threads`]).
    pub fn with_threads(seed: u64, threads: u32) -> Self {
        let mut workspace = SolverWorkspace::new(seed);
        workspace.pgs.set_threads(threads as usize);
        workspace
    }

    /// Empty buffers; PGS's random orders come from `seed`.
    pub fn new(seed: u64) -> Self {
        SolverWorkspace {
            pgs: PgsWorkspace::new(seed),
            newton: NewtonWorkspace::default(),
            last: Solver::Pgs,
        }
    }

    /// Δu of body `i` after the last solve (whichever solver ran): add it to its velocity.
    pub fn delta_velocity(&self, i: usize) -> &SVector<f64, D> {
        match self.last {
            Solver::Pgs => self.pgs.delta_velocity(i),
            Solver::Newton => self.newton.delta_velocity(i),
        }
    }
}

/// The one switch: solves `problem` with the solver `settings` names. On return `lambda` holds
/// one impulse per contact (N·s) and `workspace.delta_velocity(i)` each body's velocity change.
pub fn solve<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &SolverSettings,
    workspace: &mut SolverWorkspace<D, R>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    workspace.last = settings.solver;
    match settings.solver {
        Solver::Pgs => solve_pgs(problem, &settings.pgs, &mut workspace.pgs, lambda),
        Solver::Newton => solve_newton(problem, &settings.newton, &mut workspace.newton, lambda),
    }
}

/// A caller's stopping rule for a solver: true when the impulses given are good enough.
pub type Stop<'a, const R: usize> = dyn FnMut(&[SVector<f64, R>]) -> bool + 'a;

/// A problem every solver here takes, in either form (the body form of a run, the local form of
/// FCLIB and Siconos): what the cross-check and `rigidref solve-problems` call.
pub trait Solvable<const R: usize>: crate::problem::ProblemView<R> {
    /// PGS with `settings` (a random order seeded with 0). `lambda` gets one impulse per
    /// contact, N·s.
    fn pgs(&self, settings: &PgsSettings, lambda: &mut Vec<SVector<f64, R>>) -> SolveReport;
    /// The Newton solver with `settings`.
    fn newton(&self, settings: &NewtonSettings, lambda: &mut Vec<SVector<f64, R>>) -> SolveReport;
}

impl<const D: usize, const R: usize> Solvable<R> for ContactProblem<D, R> {
    fn pgs(&self, settings: &PgsSettings, lambda: &mut Vec<SVector<f64, R>>) -> SolveReport {
        solve_pgs(self, settings, &mut PgsWorkspace::new(0), lambda)
    }
    fn newton(&self, settings: &NewtonSettings, lambda: &mut Vec<SVector<f64, R>>) -> SolveReport {
        solve_newton(self, settings, &mut NewtonWorkspace::default(), lambda)
    }
}

impl<const R: usize> Solvable<R> for crate::problem::LocalProblem<R> {
    fn pgs(&self, settings: &PgsSettings, lambda: &mut Vec<SVector<f64, R>>) -> SolveReport {
        solve_pgs_local(self, settings, 0, lambda)
    }
    fn newton(&self, settings: &NewtonSettings, lambda: &mut Vec<SVector<f64, R>>) -> SolveReport {
        solve_newton_local(self, settings, lambda)
    }
}
