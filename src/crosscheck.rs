//! Cross-checking PGS against clarabel on one contact problem. docs/verification.md §"clarabel".
//!
//! PGS is run to convergence (not the scene's `pgs_iterations`: the question here is whether its
//! fixed point is the problem's solution, not how far 100 sweeps get), clarabel solves the convex
//! formulation that has the same solution ([`crate::solve::qp`]), and the two answers are
//! compared: by λ where the solution is unique, by the objective where it is not.

use crate::problem::{ContactProblem, FrictionModel};
use crate::solve::qp::{QpFormulation, QpSettings, objective, solve_qp};
use crate::solve::{PgsSettings, PgsWorkspace, residual, solve_pgs};
use nalgebra::{DMatrix, SVector};
use serde::Serialize;

/// Velocities below this (m/s) set no scale for comparing impulses (see [`check_problem`]).
pub const VELOCITY_FLOOR: f64 = 0.1;

/// How the two answers were compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Comparison {
    /// The objective is strictly convex on the free rows: λ is unique and compared directly.
    Lambda,
    /// It is not (e.g. four corners of a rigid brick share its weight in infinitely many ways):
    /// only the optimal value is unique, so the objectives are compared.
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
    /// The number held against the tolerance: `lambda_difference` or `objective_gap`.
    pub disagreement: f64,
    /// PGS's residual (docs/contact.md §"Residual"), m/s.
    pub residual_pgs: f64,
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
}

impl Default for CrosscheckSettings {
    fn default() -> Self {
        CrosscheckSettings {
            pgs: PgsSettings {
                max_iterations: 200_000,
                tolerance: Some(1e-12),
                order: crate::solve::ContactOrder::Sequential,
                faults: crate::faults::Faults::NONE,
            },
            qp: QpSettings::default(),
            uniqueness_threshold: 1e-8,
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

/// Runs PGS to convergence and clarabel on `problem` and compares them.
pub fn check_problem<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &CrosscheckSettings,
) -> Result<ProblemCheck, String> {
    problem.validate()?;
    let mut workspace = PgsWorkspace::new(0);
    let mut lambda = Vec::new();
    let report = solve_pgs(problem, &settings.pgs, &mut workspace, &mut lambda);
    let frictionless = problem.contacts.iter().all(|c| c.mu == 0.0);
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
            let bound = problem.contacts[k].mu * lambda[k][0];
            (0..R)
                .filter(move |&r| r == 0 || (!frictionless && bound > 0.0))
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
    let comparison = if unique {
        Comparison::Lambda
    } else {
        Comparison::Objective
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
        disagreement: if unique {
            lambda_difference
        } else {
            objective_gap
        },
        residual_pgs: report.residual,
        residual_qp: residual(problem, &qp.lambda),
        pgs_iterations: report.iterations,
        qp_status: qp.status,
        qp_iterations: qp.iterations,
        anitescu,
    })
}
