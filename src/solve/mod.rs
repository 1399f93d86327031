//! Solvers of the contact problem ([`crate::problem::ContactProblem`]).
//!
//! - [`pgs`]: projected Gauss–Seidel with delta velocities (Erleben 2007), the project's solver;
//! - [`local`]: the exact solve of one contact's own problem, PGS's `exact` visit;
//! - [`projection`]: the feasible set of a contact's impulse and the projections onto it;
//! - [`residual`](mod@residual): the natural-map residual that says how far a λ is from a solution, for any
//!   solver's answer;
//! - [`shock`]: shock propagation, a layer-by-layer pass after PGS (an option);
//! - [`qp`]: the same problem as a convex QP/SOCP solved by clarabel, the independent reference.

pub mod local;
pub mod pgs;
pub mod projection;
pub mod qp;
pub mod residual;
pub mod shock;

pub use crate::problem::SolveReport;
pub use local::LocalSolve;
pub use pgs::{ContactOrder, PgsSettings, PgsWorkspace, solve_pgs};
pub use residual::residual;
