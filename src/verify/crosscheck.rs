//! Cross-checking a solver's answer against clarabel, and against the exact solver, on one
//! contact problem. docs/verification.md §"clarabel", §"The exact reference".
//!
//! The answer checked is the solver under test's ([`CrosscheckSettings::solver`]): PGS run to
//! convergence (not the scene's `pgs_iterations`: the question here is whether its fixed point
//! is the problem's solution, not how far 100 sweeps get), or with the Newton solver the step's
//! own λ (the one the run applied). Its residual is recomputed from the problem alone
//! ([`residual`], [`coulomb_residual`]), clarabel solves the convex formulation that has the
//! same solution ([`crate::solve::qp`]), and the two answers are compared: by λ where the
//! solution is unique, by the objective where it is not. With PGS under test, the Newton solver
//! also solves every problem, and the distance of PGS's answers (and of the step's λ) to its
//! solution is reported ([`ExactReference`]), so that a problem PGS cannot converge on still
//! says how wrong the plain solver was.

use crate::problem::{FrictionModel, ProblemView, RowBounds};
use crate::solve::projection::project_friction;
use crate::solve::qp::{QpFormulation, QpSettings, objective, solve_qp};
use crate::solve::residual::coulomb_residual;
use crate::solve::{
    LocalSolve, NewtonSettings, PgsSettings, Solvable, SolveReport, Solver, residual,
};
use nalgebra::{DMatrix, DVector, SVector};
use serde::Serialize;

/// Velocities below this (m/s) set no scale for comparing impulses (see [`check_problem`]).
pub const VELOCITY_FLOOR: f64 = 0.1;

/// How the two answers were compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Comparison {
    /// The objective is strictly convex on the free rows, so λ is unique, and clarabel's answer
    /// is provably close to it (`lambda_uncertainty` within the limit): λ is compared directly.
    Lambda,
    /// It is not (e.g. four corners of a rigid brick share its weight in infinitely many ways),
    /// or it is so ill-conditioned that clarabel's λ does not pin the minimiser down: only the
    /// optimal value is unique or resolved, so the objectives are compared.
    Objective,
}

/// The comparison of PGS and clarabel on one problem.
#[derive(Clone, Debug, Serialize)]
pub struct ProblemCheck {
    /// Contacts in the problem.
    pub contacts: usize,
    /// The convex formulation clarabel solved.
    pub formulation: &'static str,
    /// Whether λ or only the objective is compared.
    pub comparison: Comparison,
    /// ‖λ_pgs − λ_qp‖ / max(‖λ_qp‖, λ_ref), λ_ref = max(‖b‖, [`VELOCITY_FLOOR`]) / max diag(A + C).
    pub lambda_difference: f64,
    /// max(f(λ_pgs) − f(λ_qp), 0) / max(|f(λ_qp)|, ½ ‖b‖ λ_ref): how far PGS's objective is
    /// above the optimum clarabel found. One-sided because λ_pgs is feasible for the program by
    /// construction (the bounds are fixed at its own λn), so f(λ_pgs) < f(λ_qp) proves clarabel
    /// stopped short of the optimum, not that PGS did (seen on a 2D stack: clarabel "Solved"
    /// with residual 1.8e-3, PGS 9e-13 and an objective 6e-9 lower).
    pub objective_gap: f64,
    /// f(λ_pgs) − f(λ_qp), signed, unscaled (negative: PGS found the lower objective).
    pub objective_difference: f64,
    /// An upper bound on ‖λ_qp − λ*‖ / max(‖λ_qp‖, λ_ref), λ* the program's exact minimiser,
    /// from clarabel's natural residual (`distance_bound`); `None` where λ* is not unique.
    pub lambda_uncertainty: Option<f64>,
    /// The number held against the tolerance: `lambda_difference` or `objective_gap`.
    pub disagreement: f64,
    /// The residual of the answer checked (docs/contact.md §"Residual"), m/s, recomputed from the
    /// problem and λ alone.
    pub residual_answer: f64,
    /// For cone friction, the exact Coulomb law's residual of the answer (De Saxcé's natural
    /// map, docs/contact.md §"The exact Coulomb residual"), m/s.
    pub coulomb_residual_answer: Option<f64>,
    /// The PGS visit that produced the answer checked: `rows` or `exact` (the scene's
    /// `pgs_local_solve`, or crosscheck's `--pgs-local-solve`).
    pub pgs_local_solve: &'static str,
    /// The same residual of clarabel's λ, m/s.
    pub residual_qp: f64,
    /// Iterations the answer took (PGS sweeps, or Newton iterations).
    pub iterations: u32,
    /// Whose answer was checked: `pgs` (run to convergence), `newton` or `proximal` (the step's
    /// Newton answer, or the Newton solver's on a problem file).
    pub solver: &'static str,
    /// With PGS under test: the exact solver's solution and the distances to it.
    pub exact: Option<ExactReference>,
    /// clarabel's status.
    pub qp_status: String,
    /// clarabel's iterations.
    pub qp_iterations: u32,
    /// For cone friction: ‖λ_pgs − λ_anitescu‖ / ‖λ_anitescu‖ against the Anitescu SOCP, and
    /// whether any contact slides (where the two are expected to differ).
    pub anitescu: Option<(f64, bool)>,
}

/// The exact solver's answer to a problem and how far the checked answers are from it.
#[derive(Clone, Debug, Serialize)]
pub struct ExactReference {
    /// `newton`, or `proximal` where its fallback produced the answer.
    pub method: &'static str,
    /// Whether it converged (residual and exact Coulomb residual ≤ its tolerance, 1e-10 m/s).
    pub converged: bool,
    /// Its residual, m/s.
    pub residual: f64,
    /// max |u⁺ − u⁺_exact| over every body's velocity components (m/s and rad/s; 2D: blocks and
    /// rad per time unit) for the answer checked (PGS run to convergence).
    pub answer_distance: f64,
    /// The same for the step's λ, the impulses the run applied (when checking a run).
    pub step_distance: Option<f64>,
    /// The step λ's violation of the contact law: its residual (m/s).
    pub step_residual: Option<f64>,
    /// The step λ's exact Coulomb residual (cone friction), m/s.
    pub step_coulomb_residual: Option<f64>,
}

/// Settings of a cross-check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrosscheckSettings {
    /// Whose answer is checked: PGS run to convergence (`pgs`, with [`Self::pgs`]) or the
    /// Newton solver's (the step's λ when checking a run).
    pub solver: Solver,
    /// PGS run to convergence: sweeps at most and residual target (m/s).
    pub pgs: PgsSettings,
    /// The Newton solver's settings (under test, or the exact reference).
    pub newton: NewtonSettings,
    /// clarabel's settings.
    pub qp: QpSettings,
    /// Smallest eigenvalue over largest of the objective's Hessian on the free rows below which
    /// λ counts as not unique.
    pub uniqueness_threshold: f64,
    /// λ is compared only where clarabel's answer is provably this close (relative, as
    /// `lambda_difference`) to the exact minimiser; otherwise the objectives are.
    pub lambda_uncertainty_limit: f64,
}

impl Default for CrosscheckSettings {
    fn default() -> Self {
        CrosscheckSettings {
            solver: Solver::Pgs,
            newton: NewtonSettings::default(),
            pgs: PgsSettings {
                max_iterations: 200_000,
                tolerance: Some(1e-12),
                order: crate::solve::ContactOrder::Sequential,
                local: LocalSolve::Rows,
            },

            qp: QpSettings::default(),
            uniqueness_threshold: 1e-8,
            // A tenth of the λ tolerance the tests and the command use (1e-5).
            lambda_uncertainty_limit: 1e-6,
        }
    }
}

fn norm<const R: usize>(v: &[SVector<f64, R>]) -> f64 {
    v.iter().map(|x| x.norm_squared()).sum::<f64>().sqrt()
}

/// clarabel at the given tolerance and, if it reports only reduced accuracy there
/// (`AlmostSolved`, or a failure), again at a tolerance 10× looser; the answer with the smaller
/// residual is kept. Interior-point methods stall short of very tight tolerances on some nearly
/// degenerate problems, and a clean solve at 1e-9 is better than a stalled one at 1e-10.
fn solve_precisely<const R: usize, P: ProblemView<R>>(
    problem: &P,
    formulation: &QpFormulation,
    settings: &QpSettings,
) -> Result<crate::solve::qp::QpSolution<R>, String> {
    let first = solve_qp(problem, formulation, settings)?;
    if first.status == "Solved" || first.status.contains("Infeasible") {
        return Ok(first);
    }
    let looser = QpSettings {
        tolerance: settings.tolerance * 10.0,
        ..*settings
    };
    let second = solve_qp(problem, formulation, &looser)?;
    let r1 = residual(problem, &first.lambda);
    let r2 = residual(problem, &second.lambda);
    Ok(if second.solved && (r2 < r1 || !first.solved) {
        second
    } else {
        first
    })
}

/// Projects λ of contact `k` onto the feasible set of `formulation` (the friction bounds fixed at
/// μ times the given normal impulses, or zero without friction).
fn project_feasible<const R: usize>(
    formulation: &QpFormulation,
    mu: f64,
    k: usize,
    lambda: &SVector<f64, R>,
    bounds: RowBounds,
) -> SVector<f64, R> {
    if bounds == RowBounds::Free {
        return *lambda;
    }
    let mut p = *lambda;
    p[0] = p[0].max(0.0);
    let (bound, friction) = match formulation {
        QpFormulation::Frictionless => (0.0, FrictionModel::Box),
        QpFormulation::BoxFixed(fixed) => (mu * fixed[k].max(0.0), FrictionModel::Box),
        QpFormulation::ConeFixed(fixed) => (mu * fixed[k].max(0.0), FrictionModel::Cone),
        QpFormulation::Cone => unreachable!("the Anitescu cone is not compared by λ"),
    };
    project_friction(&p, bound, friction)
}

/// An upper bound on ‖λ − λ*‖ (N·s), λ* the exact minimiser of f over the feasible set K of
/// `formulation`, from λ's natural residual (docs/verification.md §"clarabel"): with H = A + C,
/// L = its largest eigenvalue, m > 0 its smallest on the free rows (the subspace K lies in) and
/// r = λ − Π_K(λ − (Hλ + b)/L), ‖λ − λ*‖ ≤ (2 + m/L)(L/m) ‖r‖. It needs nothing of how λ was
/// found, so it says how far clarabel's answer can be from the true one.
fn distance_bound<const R: usize, P: ProblemView<R>>(
    problem: &P,
    formulation: &QpFormulation,
    hessian: &DMatrix<f64>,
    lambda: &[SVector<f64, R>],
    (m, l): (f64, f64),
) -> f64 {
    let flat = DVector::from_iterator(R * lambda.len(), lambda.iter().flatten().copied());
    let w = hessian * &flat + problem.dense_b();
    let mut r2 = 0.0;
    for (k, x) in lambda.iter().enumerate() {
        let step = x - SVector::<f64, R>::from_fn(|r, _| w[R * k + r] / l);
        let r = x - project_feasible(formulation, problem.mu(k), k, &step, problem.bounds(k));
        r2 += r.norm_squared();
    }
    (2.0 + m / l) * (l / m) * r2.sqrt()
}

/// Checks `problem` with the solver under test solving it ([`CrosscheckSettings::solver`]: PGS
/// to convergence, or Newton) against clarabel, and with PGS also against the exact solver.
pub fn check_problem<const R: usize, P: Solvable<R>>(
    problem: &P,
    settings: &CrosscheckSettings,
) -> Result<ProblemCheck, String> {
    check_step(problem, settings, None)
}

/// Checks one solve of a run: as [`check_problem`], with the step's λ and report. With the
/// Newton solver under test the step's λ is the answer checked (it is what the run applied);
/// with PGS, PGS is run to convergence and the step's λ is measured against the exact solution.
pub fn check_step<const R: usize, P: Solvable<R>>(
    problem: &P,
    settings: &CrosscheckSettings,
    step: Option<(&[SVector<f64, R>], &SolveReport)>,
) -> Result<ProblemCheck, String> {
    problem.validate()?;
    let hessian = problem.dense_operator();
    let asymmetry = (&hessian - hessian.transpose()).amax() / hessian.amax().max(1e-300);
    // 1e-9: a run's W is symmetric to round-off (its off-diagonal blocks are computed apart).
    if asymmetry > 1e-9 {
        return Err(format!(
            "W is not symmetric (max |W − Wᵀ| / max |W| = {asymmetry:.1e}): clarabel's convex \
             program would answer for its symmetric part, a different problem; solve it with \
             `rigidref solve-problems` instead"
        ));
    }
    let mut lambda = Vec::new();
    let report = match (settings.solver, step) {
        (Solver::Newton, Some((step_lambda, step_report))) => {
            lambda.extend_from_slice(step_lambda);
            *step_report
        }
        (Solver::Newton, None) => problem.newton(&settings.newton, &mut lambda),
        (Solver::Pgs, _) => problem.pgs(&settings.pgs, &mut lambda),
    };
    let exact = (settings.solver == Solver::Pgs)
        .then(|| exact_reference(problem, &settings.newton, &lambda, step.map(|(l, _)| l)));
    let count = problem.count();
    let frictionless =
        (0..count).all(|k| problem.mu(k) == 0.0 || problem.bounds(k) == RowBounds::Free);
    let fixed: Vec<f64> = lambda.iter().map(|l| l[0]).collect();
    let formulation = match (frictionless, problem.friction()) {
        (true, _) => QpFormulation::Frictionless,
        (false, FrictionModel::Box) => QpFormulation::BoxFixed(fixed),
        (false, FrictionModel::Cone) => QpFormulation::ConeFixed(fixed),
    };
    let qp = solve_precisely(problem, &formulation, &settings.qp)?;

    // Free rows: the normal rows, and the friction rows whose bound is not zero.
    let free: Vec<usize> = (0..count)
        .flat_map(|k| {
            let bound = problem.mu(k) * lambda[k][0];
            let joint = problem.bounds(k) == RowBounds::Free;
            (0..R)
                .filter(move |&r| joint || r == 0 || (!frictionless && bound > 0.0))
                .map(move |r| R * k + r)
        })
        .collect();
    let restricted: DMatrix<f64> = hessian.select_rows(&free).select_columns(&free);
    let eigenvalues = restricted.symmetric_eigenvalues();
    let unique = eigenvalues.is_empty()
        || eigenvalues.min() > settings.uniqueness_threshold * eigenvalues.max().max(1e-300);

    // Scales: λ_ref = max(‖b‖, 0.1 m/s) / max diag(A + C) is the impulse that stops the given
    // velocities, so differences are measured against max(‖λ_qp‖, λ_ref): an interior-point
    // answer is never exactly zero, and 1e-12 against an exact 0 is agreement, not a 100%
    // difference. The floor: where b ≈ 0 (two bodies resting against each other without
    // gravity: b ≈ 1e-17 m/s) the solution λ = 0, w = 0 is degenerate and an interior-point
    // method reaches it only to λ·w ≈ its gap tolerance, i.e. velocity errors of ~1e-7 m/s; a
    // 1e-5 tolerance against the impulse that stops 0.1 m/s resolves 1 µm/s, above that.
    let b_norm = problem.dense_b().norm().max(VELOCITY_FLOOR);
    let largest_diagonal = hessian.diagonal().max().max(1e-300);
    let lambda_ref = b_norm / largest_diagonal;
    let difference: Vec<SVector<f64, R>> =
        lambda.iter().zip(&qp.lambda).map(|(a, b)| a - b).collect();
    let lambda_scale = norm(&qp.lambda).max(lambda_ref).max(1e-300);
    let lambda_difference = norm(&difference) / lambda_scale;
    let f_pgs = objective(problem, &lambda);
    let f_scale = qp
        .objective
        .abs()
        .max(0.5 * b_norm * lambda_ref)
        .max(1e-300);
    let objective_gap = (f_pgs - qp.objective).max(0.0) / f_scale;
    // λ is compared only where clarabel's answer provably pins the minimiser down: on a nearly
    // singular problem with b ≈ 0 clarabel "Solved" at 9e-8 m/s stopped 3% of λ_ref from the
    // exact λ* = 0 that PGS found (an objective 2e-11 above PGS's).
    let lambda_uncertainty = unique.then(|| {
        if eigenvalues.is_empty() {
            return 0.0;
        }
        let largest = hessian.symmetric_eigenvalues().max();
        let bound = distance_bound(
            problem,
            &formulation,
            &hessian,
            &qp.lambda,
            (eigenvalues.min(), largest),
        );
        bound / lambda_scale
    });
    let comparison = match lambda_uncertainty {
        Some(u) if u <= settings.lambda_uncertainty_limit => Comparison::Lambda,
        _ => Comparison::Objective,
    };
    let anitescu = if !frictionless && problem.friction() == FrictionModel::Cone {
        let relaxed = solve_precisely(problem, &QpFormulation::Cone, &settings.qp)?;
        let d: Vec<SVector<f64, R>> = lambda
            .iter()
            .zip(&relaxed.lambda)
            .map(|(a, b)| a - b)
            .collect();
        let w = problem.constraint_velocity(&lambda);
        // Sliding: a pressed contact whose tangential velocity is not zero.
        let sliding = lambda.iter().zip(&w).any(|(l, w)| {
            let wt = (1..R).map(|r| w[r] * w[r]).sum::<f64>().sqrt();
            l[0] > 0.0 && wt > 1e-9 * (1.0 + w[0].abs())
        });
        Some((norm(&d) / norm(&relaxed.lambda).max(1e-300), sliding))
    } else {
        None
    };
    Ok(ProblemCheck {
        contacts: count,
        formulation: formulation.name(),
        comparison,
        lambda_difference,
        objective_gap,
        objective_difference: f_pgs - qp.objective,
        lambda_uncertainty,
        disagreement: match comparison {
            Comparison::Lambda => lambda_difference,
            Comparison::Objective => objective_gap,
        },
        residual_answer: residual(problem, &lambda),
        coulomb_residual_answer: (problem.friction() == FrictionModel::Cone)
            .then(|| coulomb_residual(problem, &lambda)),
        pgs_local_solve: settings.pgs.local.name(),
        residual_qp: residual(problem, &qp.lambda),
        iterations: report.iterations,
        solver: report.method.name(),
        exact,
        qp_status: qp.status,
        qp_iterations: qp.iterations,
        anitescu,
    })
}

/// The exact solver's solution of `problem` and the distances of `answer` and of the step's λ
/// to it, in the bodies' velocities after the impulses (u⁺ = u + M⁻¹Jᵀλ).
fn exact_reference<const R: usize, P: Solvable<R>>(
    problem: &P,
    settings: &NewtonSettings,
    answer: &[SVector<f64, R>],
    step: Option<&[SVector<f64, R>]>,
) -> ExactReference {
    let mut exact = Vec::new();
    let report = problem.newton(settings, &mut exact);
    let exact_outcome = problem.outcome(&exact);
    let distance = |lambda: &[SVector<f64, R>]| {
        problem
            .outcome(lambda)
            .iter()
            .zip(&exact_outcome)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let cone = problem.friction() == FrictionModel::Cone;
    ExactReference {
        method: report.method.name(),
        converged: report.converged,
        residual: report.residual,
        answer_distance: distance(answer),
        step_distance: step.map(distance),
        step_residual: step.map(|l| residual(problem, l)),
        step_coulomb_residual: step.filter(|_| cone).map(|l| coulomb_residual(problem, l)),
    }
}
