//! The exact solver (docs/contact.md §"Newton solver"): known exact solutions, agreement with
//! PGS where PGS converges, an honest convergence flag on random problems (its Jacobian, rate,
//! invariances and kinks: newton_properties.rs).

use crate::common;

use common::problems::{build, physical_spec, spec};
use nalgebra::{Matrix3, SVector, Vector3};
use proptest::prelude::*;
use rigidref::problem::{ContactProblem, FrictionModel, SolveMethod};
use rigidref::solve::residual::{coulomb_residual, residual};
use rigidref::solve::{LocalSolve, NewtonSettings, NewtonWorkspace, SolveReport, solve_newton};
use std::cell::RefCell;

/// The Newton solver on `problem` with the given tolerance (m/s), cold or warm as the problem
/// says; its impulses and report.
fn newton<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    tolerance: f64,
) -> (Vec<SVector<f64, R>>, SolveReport) {
    let settings = NewtonSettings {
        tolerance,
        ..NewtonSettings::default()
    };
    let mut lambda = Vec::new();
    let report = solve_newton(
        problem,
        &settings,
        &mut NewtonWorkspace::default(),
        &mut lambda,
    );
    (lambda, report)
}

/// One contact with Delassus block `a`, b = `b`, μ = `mu`: what Newton and PGS return, checked
/// against the `expected` impulse (N·s) and contact velocity (m/s).
fn check_known(
    a: Matrix3<f64>,
    b: [f64; 3],
    mu: f64,
    friction: FrictionModel,
    expected_lambda: [f64; 3],
    expected_w: [f64; 3],
) {
    let problem = super::local_solve_problem(a, SVector::from(b), mu, friction);
    let (lambda, report) = newton(&problem, 1e-12);
    let w = problem.constraint_velocity(&lambda);
    // 1e-12: the answers are exact up to the round-off of a 3 × 3 solve with entries of order 1.
    assert!(report.converged && report.residual <= 1e-12, "{report:?}");
    assert!(
        (lambda[0] - SVector::from(expected_lambda)).amax() <= 1e-12,
        "{lambda:?}"
    );
    assert!((w[0] - SVector::from(expected_w)).amax() <= 1e-12, "{w:?}");
    if friction == FrictionModel::Cone {
        assert!(coulomb_residual(&problem, &lambda) <= 1e-12);
    }
    // PGS converges on these one-contact problems (its exact visit in one sweep) and agrees.
    let (pgs, pgs_report) = super::run_pgs(&problem, LocalSolve::Exact, 10, Some(1e-13));
    assert!(pgs_report.converged, "{pgs_report:?}");
    assert!(
        (pgs[0] - lambda[0]).amax() <= 1e-12,
        "PGS {pgs:?} Newton {lambda:?}"
    );
}

#[test]
fn newton_solves_hand_made_problems_with_known_exact_solutions() {
    let (identity, mu) = (Matrix3::identity(), 0.5);
    // With A = I (kg⁻¹), b = (g_N, g_T), g_N < 0: the impulse that stops the normal motion is
    // λn = −g_N.
    // Sliding (‖g_T‖ > μ|g_N|): λt = −μλn g_T/‖g_T‖, so c_N = 0 and c_T = g_T (1 − μ|g_N|/‖g_T‖).
    let (g_n, g_t) = (-1.0, Vector3::new(0.0, 3.0, 4.0));
    let shrink = 1.0 - mu * 1.0 / 5.0;
    check_known(
        identity,
        [g_n, g_t[1], g_t[2]],
        mu,
        FrictionModel::Cone,
        [1.0, -mu * 3.0 / 5.0, -mu * 4.0 / 5.0],
        [0.0, 3.0 * shrink, 4.0 * shrink],
    );
    // Sticking (‖g_T‖ ≤ μ|g_N|): λ = −b and the contact does not move.
    check_known(
        identity,
        [-2.0, 0.3, -0.4],
        mu,
        FrictionModel::Cone,
        [2.0, -0.3, 0.4],
        [0.0; 3],
    );
    // Separating (g_N > 0): no impulse, the contact keeps b.
    check_known(
        identity,
        [0.7, 3.0, -1.0],
        mu,
        FrictionModel::Cone,
        [0.0; 3],
        [0.7, 3.0, -1.0],
    );
    // Box friction sliding at 45° between the tangent axes: both rows at their bound, so the
    // tangential impulse has magnitude √2 μλn (the square's corner, not the disk's rim).
    check_known(
        identity,
        [-1.0, 2.0, 2.0],
        mu,
        FrictionModel::Box,
        [1.0, -mu, -mu],
        [0.0, 2.0 - mu, 2.0 - mu],
    );
    let problem = super::local_solve_problem(
        identity,
        SVector::from([-1.0, 2.0, 2.0]),
        mu,
        FrictionModel::Box,
    );
    let (lambda, _) = newton(&problem, 1e-12);
    let tangential = (lambda[0][1].powi(2) + lambda[0][2].powi(2)).sqrt();
    assert!((tangential - 2f64.sqrt() * mu * lambda[0][0]).abs() <= 1e-12);
    // A coupled block (normal and tangent rows interact): sticking needs the whole block.
    let coupled = Matrix3::new(1.0, 0.3, 0.1, 0.3, 2.0, 0.2, 0.1, 0.2, 1.5);
    let b = [-1.0, 0.2, 0.1];
    let stick = -coupled.try_inverse().unwrap() * Vector3::from(b);
    check_known(coupled, b, 1.0, FrictionModel::Cone, stick.into(), [0.0; 3]);
}

#[test]
fn newton_agrees_with_pgs_where_pgs_converges() {
    // Frictionless problems with compliance have one solution (docs/contact.md §"Compliance"),
    // so the impulses themselves must agree wherever PGS converges; with friction the two may
    // pick different solutions of a problem that has several, and both must then be solutions
    // (residual) with the same contact law holding.
    let compared = RefCell::new(0);
    proptest!(common::seeded(150), |(s in physical_spec(1..4, 1..7), c in 1e-3..1e-1f64)| {
        let problem = build(&s, 0.0, c, FrictionModel::Box);
        let (pgs, report) = super::run_pgs(&problem, LocalSolve::Rows, 50_000, Some(1e-11));
        let (lambda, newton_report) = newton(&problem, 1e-11);
        prop_assert!(newton_report.converged, "{newton_report:?}");
        if report.converged {
            *compared.borrow_mut() += 1;
            let scale = pgs.iter().map(|l| l.amax()).fold(1e-3, f64::max);
            for (p, n) in pgs.iter().zip(&lambda) {
                // 1e-6 of the largest impulse: both answers are within 1e-11 m/s of the one
                // solution, and the compliant problem's conditioning (c ≥ 1e-3 kg⁻¹ against
                // diagonals up to ~10 kg⁻¹) turns that into at most ~1e-7 of λ.
                prop_assert!((p - n).amax() <= 1e-6 * scale, "PGS {p} Newton {n}");
            }
        }
    });
    assert!(*compared.borrow() >= 100, "{}", compared.borrow());
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(100), |(s in physical_spec(1..4, 1..6), mu in 0.0..1.0f64)| {
            let problem = build(&s, mu, 0.0, friction);
            let (_, report) = super::run_pgs(&problem, LocalSolve::Exact, 20_000, Some(1e-10));
            if report.converged {
                let (lambda, newton_report) = newton(&problem, 1e-10);
                prop_assert!(newton_report.converged, "PGS converged, Newton did not: {newton_report:?}");
                prop_assert!(residual(&problem, &lambda) <= 1e-10);
            }
        });
    }
}

#[test]
fn newton_reports_convergence_only_where_the_exact_law_holds() {
    // 600 random problems (300 cone, 300 box), including ones with no solution or with thin
    // rods struck at the far end: wherever Newton says "converged" the law holds to its tolerance
    // 1e-10 m/s by the measures recomputed from the problem and λ alone; where it does not, it says so. Counts: [not converged by Newton
    // alone, not converged after the fallback, converged by Newton, converged by the fallback].
    let counts = RefCell::new([0usize; 4]);
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(300), |(s in spec(1..5, 1..9), mu in 0.0..2.0f64)| {
            let problem = build(&s, mu, 0.0, friction);
            let (lambda, report) = newton(&problem, 1e-10);
            if report.converged {
                prop_assert!(residual(&problem, &lambda) <= 1e-10);
                if friction == FrictionModel::Cone {
                    prop_assert!(coulomb_residual(&problem, &lambda) <= 1e-10);
                }
            } else if friction == FrictionModel::Box {
                // The box law is judged by its own residual alone (a box answer is rarely a
                // Coulomb solution, so the exact Coulomb residual says nothing here).
                prop_assert!(residual(&problem, &lambda) > 1e-10, "reported unconverged at a solution: {report:?}");
            } else {
                prop_assert!(
                    residual(&problem, &lambda) > 1e-10
                        || coulomb_residual(&problem, &lambda) > 1e-10,
                    "reported unconverged at a solution: {report:?}"
                );
            }
            let proximal = report.method == SolveMethod::Proximal;
            counts.borrow_mut()[usize::from(report.converged) * 2 + usize::from(proximal)] += 1;
        });
    }
    let c = counts.into_inner();
    eprintln!("[not converged (newton, proximal), converged (newton, proximal)] = {c:?}");
    assert_eq!(c.iter().sum::<usize>(), 600);
    // Measured 551 of 600 (492 by Newton, 59 by a proximal loop); most of the rest have no
    // solution PGS can find either (newton_agrees_with_pgs_where_pgs_converges).
    assert!(c[2] + c[3] >= 500, "{c:?}");
}

#[test]
fn newton_solves_2d_problems_and_free_rows() {
    // The 2D one-contact problem: rows n and t, the interval [−μλn, μλn] for both models.
    use rigidref::problem::{ProblemBody, ProblemContact, RowBounds};
    let contact = |b: [f64; 2], bounds| ProblemContact::<3, 2> {
        bodies: [Some(0), None],
        jacobian: [
            nalgebra::SMatrix::<f64, 2, 3>::new(0.0, 1.0, 0.0, -1.0, 0.0, -0.5),
            nalgebra::SMatrix::zeros(),
        ],
        b: SVector::from(b),
        mu: 0.4,
        compliance: 0.0,
        lambda0: SVector::zeros(),
        bounds,
    };
    let body = ProblemBody {
        inverse_mass: nalgebra::Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 2.0)),
        velocity: Vector3::zeros(),
    };
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let problem = ContactProblem {
            friction,
            bodies: vec![body.clone()],
            contacts: vec![contact([-1.0, 2.0], RowBounds::Contact)],
        };
        let (lambda, report) = newton(&problem, 1e-12);
        assert!(report.converged, "{report:?}");
        // Sliding: λt at −μλn against w_t > 0, w_n = 0.
        let w = problem.constraint_velocity(&lambda);
        assert!(w[0][0].abs() <= 1e-12 && w[0][1] > 0.0);
        assert!((lambda[0][1] + 0.4 * lambda[0][0]).abs() <= 1e-12);
        // A joint (free rows) beside it that holds the rotation at ω = −0.5 (its second row
        // is empty, with b = 0): w = 0 on both of its rows, the contact still sliding.
        let mut with_joint = problem.clone();
        let mut joint = contact([0.5, 0.0], RowBounds::Free);
        joint.jacobian[0] = nalgebra::SMatrix::<f64, 2, 3>::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
        with_joint.contacts.push(joint);
        let (lambda, report) = newton(&with_joint, 1e-12);
        assert!(report.converged, "{report:?}");
        let w = with_joint.constraint_velocity(&lambda);
        assert!(w[1].amax() <= 1e-12 && w[0][0].abs() <= 1e-12, "{w:?}");
    }
}

#[test]
fn sparse_and_dense_factorisations_give_the_same_answer() {
    // Problems above DENSE_ROWS rows are factorised by faer's sparse LU: on the same problems
    // solved both ways (the threshold moved below and above them), the iterations follow the
    // same path, so the answers agree to round-off and both converge.
    let compared = RefCell::new(0);
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(60), |(s in physical_spec(2..6, 6..14), mu in 0.0..1.0f64)| {
            let problem = build(&s, mu, 1e-3, friction);
            let solve = |dense_rows| {
                let settings = NewtonSettings { dense_rows, ..NewtonSettings::default() };
                let mut lambda = Vec::new();
                let report = solve_newton(&problem, &settings, &mut NewtonWorkspace::default(), &mut lambda);
                (lambda, report)
            };
            let (dense, dense_report) = solve(usize::MAX);
            let (sparse, sparse_report) = solve(0);
            prop_assert_eq!(dense_report.converged, sparse_report.converged);
            if dense_report.converged {
                *compared.borrow_mut() += 1;
                let scale = dense.iter().map(|l| l.amax()).fold(1e-3, f64::max);
                for (d, s) in dense.iter().zip(&sparse) {
                    // 1e-8 of the largest impulse: two LU factorisations of the same matrices
                    // with different pivot orders, over a handful of iterations.
                    prop_assert!((d - s).amax() <= 1e-8 * scale, "dense {d} sparse {s}");
                }
            }
        });
    }
    assert!(*compared.borrow() >= 80, "{}", compared.borrow());
}
