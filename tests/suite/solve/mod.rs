//! The shared core: the contact problem and PGS.

mod coloured;
mod coulomb;
mod criteria;
mod derivations;
mod islands;
mod lanes;
mod local_form;
mod local_solve;
mod newton;
mod newton_globalisation;
mod newton_properties;
mod pgs;
mod problem;
mod qp;
mod random_coloured;
mod siconos_error;
mod twins;

/// One contact whose Delassus block is `a` (kg⁻¹): one body with inverse mass `a` and J₁ = I.
fn local_solve_problem(
    a: nalgebra::SMatrix<f64, 3, 3>,
    b: nalgebra::SVector<f64, 3>,
    mu: f64,
    friction: rigidref::problem::FrictionModel,
) -> rigidref::problem::ContactProblem<3, 3> {
    use rigidref::problem::{ContactProblem, ProblemBody, ProblemContact, RowBounds};
    ContactProblem {
        friction,
        bodies: vec![ProblemBody {
            inverse_mass: a,
            velocity: nalgebra::SVector::zeros(),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [nalgebra::SMatrix::identity(), nalgebra::SMatrix::zeros()],
            b,
            mu,
            compliance: 0.0,
            lambda0: nalgebra::SVector::zeros(),
            bounds: RowBounds::Contact,
        }],
    }
}

/// PGS on `problem` with `local` visits, in problem order, cold started: at most `sweeps` sweeps,
/// stopping at `tolerance` when one is given. The impulses and the report.
fn run_pgs<const D: usize, const R: usize>(
    problem: &rigidref::problem::ContactProblem<D, R>,
    local: rigidref::solve::LocalSolve,
    sweeps: u32,
    tolerance: Option<f64>,
) -> (Vec<nalgebra::SVector<f64, R>>, rigidref::solve::SolveReport) {
    let settings = rigidref::solve::PgsSettings {
        max_iterations: sweeps,
        tolerance,
        order: rigidref::solve::ContactOrder::Sequential,
        local,
    };
    let mut lambda = Vec::new();
    let mut workspace = rigidref::solve::PgsWorkspace::new(0);
    let report = rigidref::solve::solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    (lambda, report)
}

/// What a solve gives: λ, every body's Δu, the report, the groups its sweeps visited, and the
/// threads they ran on.
pub(super) type Solved<const D: usize, const R: usize> = (
    Vec<nalgebra::SVector<f64, R>>,
    Vec<nalgebra::SVector<f64, D>>,
    rigidref::solve::SolveReport,
    usize,
    usize,
);

/// Solves `problem` in the coloured order, row by row, cold settings (no tolerance), on
/// `threads` threads, with the groups of four as `lanes` says.
pub(super) fn solve_on<const D: usize, const R: usize>(
    problem: &rigidref::problem::ContactProblem<D, R>,
    sweeps: u32,
    lanes: rigidref::solve::pgs::Lanes,
    threads: usize,
) -> Solved<D, R> {
    let mut workspace = rigidref::solve::PgsWorkspace::new(0);
    workspace.set_lanes(lanes);
    workspace.set_threads(threads);
    let mut lambda = Vec::new();
    let settings = rigidref::solve::PgsSettings {
        max_iterations: sweeps,
        tolerance: None,
        order: rigidref::solve::ContactOrder::Coloured,
        local: rigidref::solve::LocalSolve::Rows,
    };
    let report = rigidref::solve::solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    let delta_velocity = (0..problem.bodies.len())
        .map(|i| *workspace.delta_velocity(i))
        .collect();
    (
        lambda,
        delta_velocity,
        report,
        workspace.last_groups(),
        workspace.last_threads(),
    )
}

/// Solves `problem` in `order` from a workspace seeded with `seed` on `threads` threads:
/// λ, the report and the workspace (for its sweeps' orders and groups).
pub(super) fn solve_seeded(
    problem: &rigidref::problem::ContactProblem3,
    sweeps: u32,
    tolerance: Option<f64>,
    order: rigidref::solve::ContactOrder,
    seed: u64,
    threads: usize,
) -> (
    Vec<nalgebra::SVector<f64, 3>>,
    rigidref::solve::SolveReport,
    rigidref::solve::PgsWorkspace<6, 3>,
) {
    let mut workspace = rigidref::solve::PgsWorkspace::new(seed);
    workspace.set_threads(threads);
    let mut lambda = Vec::new();
    let settings = rigidref::solve::PgsSettings {
        max_iterations: sweeps,
        tolerance,
        order,
        local: rigidref::solve::LocalSolve::Rows,
    };
    let report = rigidref::solve::solve_pgs(problem, &settings, &mut workspace, &mut lambda);
    (lambda, report, workspace)
}
