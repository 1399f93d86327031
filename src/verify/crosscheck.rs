//! Cross-checking PGS against clarabel on one contact problem. docs/verification.md §"clarabel".
//!
//! PGS is run to convergence (not the scene's `pgs_iterations`: the question here is whether its
//! fixed point is the problem's solution, not how far 100 sweeps get), clarabel solves the convex
//! formulation that has the same solution ([`crate::solve::qp`]), and the two answers are
//! compared: by λ where the solution is unique, by the objective where it is not.

use crate::problem::{ContactProblem, FrictionModel, RowBounds};
use crate::solve::projection::project_friction;
use crate::solve::qp::{QpFormulation, QpSettings, objective, solve_qp};
use crate::solve::residual::coulomb_residual;
use crate::solve::{LocalSolve, PgsSettings, PgsWorkspace, residual, solve_pgs};
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
    /// PGS's residual (docs/contact.md §"Residual"), m/s.
    pub residual_pgs: f64,
    /// For cone friction, the exact Coulomb law's residual of PGS's λ (De Saxcé's natural map,
    /// docs/contact.md §"The exact Coulomb residual"), m/s.
    pub coulomb_residual_pgs: Option<f64>,
    /// The PGS visit that produced the answer checked: `rows` or `exact` (the scene's
    /// `pgs_local_solve`, or crosscheck's `--pgs-local-solve`).
    pub pgs_local_solve: &'static str,
    /// The same residual of clarabel's λ, m/s.
    pub residual_qp: f64,
    /// PGS sweeps used.
    pub pgs_iterations: u32,
    /// clarabel's status.
    pub qp_status: String,
    /// clarabel's iterations.
    pub qp_iterations: u32,
    /// For cone friction: ‖λ_pgs − λ_anitescu‖ / ‖λ_anitescu‖ against the Anitescu SOCP, and
    /// whether any contact slides (where the two are expected to differ).
    pub anitescu: Option<(f64, bool)>,
}

/// Settings of a cross-check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrosscheckSettings {
    /// PGS run to convergence: sweeps at most and residual target (m/s).
    pub pgs: PgsSettings,
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
fn solve_precisely<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
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
fn distance_bound<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    formulation: &QpFormulation,
    hessian: &DMatrix<f64>,
    lambda: &[SVector<f64, R>],
    (m, l): (f64, f64),
) -> f64 {
    let flat = DVector::from_iterator(R * lambda.len(), lambda.iter().flatten().copied());
    let w = hessian * &flat + problem.dense_b();
    let mut r2 = 0.0;
    for (k, (c, x)) in problem.contacts.iter().zip(lambda).enumerate() {
        let step = x - SVector::<f64, R>::from_fn(|r, _| w[R * k + r] / l);
        let r = x - project_feasible(formulation, c.mu, k, &step, c.bounds);
        r2 += r.norm_squared();
    }
    (2.0 + m / l) * (l / m) * r2.sqrt()
}

/// Runs PGS to convergence and clarabel on `problem` and compares them.
pub fn check_problem<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &CrosscheckSettings,
) -> Result<ProblemCheck, String> {
    problem.validate()?;
    let mut workspace = PgsWorkspace::new(0);
    let mut lambda = Vec::new();
    let report = solve_pgs(problem, &settings.pgs, &mut workspace, &mut lambda);
    let frictionless =
        (problem.contacts.iter()).all(|c| c.mu == 0.0 || c.bounds == RowBounds::Free);
    let fixed: Vec<f64> = lambda.iter().map(|l| l[0]).collect();
    let formulation = match (frictionless, problem.friction) {
        (true, _) => QpFormulation::Frictionless,
        (false, FrictionModel::Box) => QpFormulation::BoxFixed(fixed),
        (false, FrictionModel::Cone) => QpFormulation::ConeFixed(fixed),
    };
    let qp = solve_precisely(problem, &formulation, &settings.qp)?;

    // Free rows: the normal rows, and the friction rows whose bound is not zero.
    let free: Vec<usize> = (0..problem.contacts.len())
        .flat_map(|k| {
            let c = &problem.contacts[k];
            let bound = c.mu * lambda[k][0];
            let joint = c.bounds == RowBounds::Free;
            (0..R)
                .filter(move |&r| joint || r == 0 || (!frictionless && bound > 0.0))
                .map(move |r| R * k + r)
        })
        .collect();
    let hessian = problem.dense_delassus() + problem.dense_compliance();
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
    let anitescu = if !frictionless && problem.friction == FrictionModel::Cone {
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
        contacts: problem.contacts.len(),
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
        residual_pgs: report.residual,
        coulomb_residual_pgs: (problem.friction == FrictionModel::Cone)
            .then(|| coulomb_residual(problem, &lambda)),
        pgs_local_solve: settings.pgs.local.name(),
        residual_qp: residual(problem, &qp.lambda),
        pgs_iterations: report.iterations,
        qp_status: qp.status,
        qp_iterations: qp.iterations,
        anitescu,
    })
}
