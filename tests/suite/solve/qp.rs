//! The convex programs clarabel solves (src/solve/qp.rs, docs/contact.md §"Convex formulations"):
//! the objective, the variable scaling, and each formulation's answer against PGS's where they
//! must agree. Found by mutation testing (docs/verification.md §"Mutation testing"): the
//! crosscheck tests compare the two solvers only through the command line.

use crate::common;

use common::problems::{build, physical_spec, spec};
use nalgebra::{DVector, SVector};
use proptest::prelude::*;
use rigidref::problem::FrictionModel;
use rigidref::solve::qp::{QpFormulation, QpSettings, diagonal_scaling, objective, solve_qp};
use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings, PgsWorkspace, solve_pgs};

/// PGS to a tight tolerance (1e-11 m/s), the given local solve; None if it did not converge.
fn converged_pgs(
    problem: &rigidref::problem::ContactProblem3,
    local: LocalSolve,
) -> Option<Vec<SVector<f64, 3>>> {
    let settings = PgsSettings {
        max_iterations: 50_000,
        tolerance: Some(1e-11),
        order: ContactOrder::Sequential,
        local,
    };
    let mut lambda = Vec::new();
    let report = solve_pgs(problem, &settings, &mut PgsWorkspace::new(0), &mut lambda);
    report.converged.then_some(lambda)
}

/// Largest difference of the constraint velocities w = Aλ + b the two impulse lists give, over
/// the largest |b| (at least 1e-3 m/s). The optimal w of a convex program is unique where λ
/// need not be (four corners of a box share its weight in many ways).
fn velocity_gap(
    problem: &rigidref::problem::ContactProblem3,
    a: &[SVector<f64, 3>],
    b: &[SVector<f64, 3>],
) -> f64 {
    let scale = problem
        .contacts
        .iter()
        .map(|c| c.b.amax())
        .fold(1e-3, f64::max);
    let (wa, wb) = (
        problem.constraint_velocity(a),
        problem.constraint_velocity(b),
    );
    wa.iter()
        .zip(&wb)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max)
        / scale
}

/// Largest difference between two impulse lists over the largest impulse (at least 1e-3 N·s).
fn relative_gap(a: &[SVector<f64, 3>], b: &[SVector<f64, 3>]) -> f64 {
    let scale = a.iter().map(|l| l.amax()).fold(1e-3, f64::max);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max)
        / scale
}

proptest! {
    #![proptest_config(common::seeded(64))]

    /// f(λ) = ½ λᵀ(A + C)λ + bᵀλ, computed through the bodies by `objective`, equals the same
    /// form evaluated with the dense matrices, for any λ and compliance; and `solve_qp` reports
    /// f at the λ it returns. 1e-10 relative: two orders of summation of numbers of order 1–100.
    #[test]
    fn objective_is_half_lambda_a_plus_c_lambda_plus_b_lambda(
        s in spec(1..4, 1..6),
        compliance in 0.0..0.5f64,
        values in proptest::collection::vec(-2.0..2.0f64, 18),
    ) {
        let problem = build(&s, 0.3, compliance, FrictionModel::Box);
        let lambda: Vec<SVector<f64, 3>> = (0..problem.contacts.len())
            .map(|k| SVector::<f64, 3>::from_column_slice(&values[3 * k..3 * k + 3]))
            .collect();
        let x = DVector::from_iterator(3 * lambda.len(), lambda.iter().flat_map(|l| l.iter().copied()));
        let p = problem.dense_delassus() + problem.dense_compliance();
        let dense = 0.5 * x.dot(&(&p * &x)) + problem.dense_b().dot(&x);
        let f = objective(&problem, &lambda);
        prop_assert!((f - dense).abs() <= 1e-10 * (1.0 + dense.abs()), "{f} vs {dense}");
        let qp = solve_qp(&problem, &QpFormulation::Frictionless, &QpSettings::default()).unwrap();
        prop_assert_eq!(qp.objective, objective(&problem, &qp.lambda));
    }

    /// The scaling S = diag(1/√P_ii) gives Sᵀ(A + C)S a unit diagonal (to round-off), so that
    /// clarabel's absolute tolerances mean the same for a 1 kg body and a 100 kg one.
    #[test]
    fn scaling_gives_the_program_a_unit_diagonal(s in spec(1..4, 1..6), compliance in 0.0..0.5f64) {
        let problem = build(&s, 0.3, compliance, FrictionModel::Box);
        let p = problem.dense_delassus() + problem.dense_compliance();
        let scale = diagonal_scaling(&p);
        for (i, si) in scale.iter().enumerate() {
            if p[(i, i)] > 0.0 {
                prop_assert!((p[(i, i)] * si * si - 1.0).abs() <= 1e-14);
            }
        }
    }

    /// With compliance, the frictionless program minimises ½λᵀ(A + C)λ + bᵀλ: its λ is PGS's,
    /// which solves the same LCP with the compliance on each normal row's diagonal. 1e-5 of the
    /// largest impulse: clarabel's tolerance 1e-10 on the scaled problem, amplified by the
    /// conditioning (docs/verification.md §"clarabel").
    #[test]
    fn clarabel_matches_pgs_on_compliant_frictionless_problems(s in physical_spec(1..3, 1..5), compliance in 0.01..0.5f64) {
        let problem = build(&s, 0.0, compliance, FrictionModel::Box);
        let Some(pgs) = converged_pgs(&problem, LocalSolve::Rows) else { return Ok(()); };
        let qp = solve_qp(&problem, &QpFormulation::Frictionless, &QpSettings::default()).unwrap();
        prop_assume!(qp.solved);
        let gap = relative_gap(&pgs, &qp.lambda);
        prop_assert!(gap <= 1e-5, "PGS {pgs:?} clarabel {:?} gap {gap:e}", qp.lambda);
    }

    /// Box and disk friction with the bounds frozen at PGS's λn are convex programs whose
    /// minimiser is PGS's answer (the fixed-point check the crosscheck makes): clarabel returns
    /// the same contact velocities, for every contact of multi-contact problems (1e-5 of the
    /// largest |b|, as above).
    #[test]
    fn fixed_bound_programs_return_pgs_answer(s in physical_spec(1..3, 2..5), mu in 0.1..1.0f64) {
        for (friction, local) in [(FrictionModel::Box, LocalSolve::Rows), (FrictionModel::Cone, LocalSolve::Exact)] {
            let problem = build(&s, mu, 0.0, friction);
            let Some(pgs) = converged_pgs(&problem, local) else { continue; };
            let fixed: Vec<f64> = pgs.iter().map(|l| l[0]).collect();
            let formulation = match friction {
                FrictionModel::Box => QpFormulation::BoxFixed(fixed),
                FrictionModel::Cone => QpFormulation::ConeFixed(fixed),
            };
            let qp = solve_qp(&problem, &formulation, &QpSettings::default()).unwrap();
            if !qp.solved { continue; }
            let gap = velocity_gap(&problem, &pgs, &qp.lambda);
            prop_assert!(gap <= 1e-5, "{}: PGS {pgs:?} clarabel {:?} gap {gap:e}", formulation.name(), qp.lambda);
        }
    }
}

#[test]
fn a_sliding_box_keeps_its_coulomb_answer_with_the_disks_fixed_but_not_in_the_free_cone() {
    // The box of solver::coulomb sliding at 2 m/s, μ = 0.5: with the disks frozen at PGS's λn
    // the program's minimiser is PGS's sliding answer (w_n = 0, friction μλn against the
    // motion), while the free cone (Anitescu's relaxation) lifts the box (w_n = μ‖w_t‖ > 0).
    let (g, h, mu) = (9.8, 0.01, 0.5);
    let problem = super::pgs::box_on_ground(
        nalgebra::Vector3::new(2.0, -g * h, 0.0),
        nalgebra::Vector3::zeros(),
        mu,
        FrictionModel::Cone,
    );
    let pgs = converged_pgs(&problem, LocalSolve::Exact).expect("PGS converges on the box");
    let fixed: Vec<f64> = pgs.iter().map(|l| l[0]).collect();
    let settings = QpSettings::default();
    let frozen = solve_qp(&problem, &QpFormulation::ConeFixed(fixed), &settings).unwrap();
    let free = solve_qp(&problem, &QpFormulation::Cone, &settings).unwrap();
    assert!(frozen.solved && free.solved);
    let gap = velocity_gap(&problem, &pgs, &frozen.lambda);
    assert!(gap <= 1e-6, "frozen disks: velocity gap {gap:e}");
    for (k, l) in frozen.lambda.iter().enumerate() {
        // Sliding: the friction impulse is on the disk's rim, μλn (1e-6 relative: clarabel).
        let rim = mu * pgs[k][0];
        assert!(
            (l[1].hypot(l[2]) - rim).abs() <= 1e-6 * rim,
            "contact {k}: {l:?}"
        );
    }
    let lift = problem.constraint_velocity(&free.lambda);
    assert!(
        lift.iter().all(|w| w[0] > 0.5),
        "the free cone lifts the box: {lift:?}"
    );
}

#[test]
fn formulation_names_say_which_program_each_is() {
    // The crosscheck report and its JSON name the program with these words.
    assert_eq!(QpFormulation::Frictionless.name(), "frictionless QP");
    assert_eq!(
        QpFormulation::BoxFixed(vec![]).name(),
        "box QP, bounds fixed at PGS's λn"
    );
    assert_eq!(
        QpFormulation::ConeFixed(vec![]).name(),
        "SOCP, disks fixed at PGS's λn"
    );
    assert_eq!(QpFormulation::Cone.name(), "SOCP, Anitescu cone");
}

#[test]
fn a_problem_without_contacts_is_solved_with_no_impulses() {
    // Every cone of the program would be empty and clarabel's factorisation panics on an empty
    // problem (found by this test): solve_qp answers it itself, the empty λ with objective 0.
    let s = common::problems::ProblemSpec {
        bodies: vec![(
            1.0,
            [1.0, 1.0, 1.0],
            nalgebra::Vector3::zeros(),
            nalgebra::Vector3::zeros(),
        )],
        contacts: vec![],
    };
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let problem = build(&s, 0.5, 0.0, friction);
        for formulation in [
            QpFormulation::Frictionless,
            QpFormulation::BoxFixed(vec![]),
            QpFormulation::ConeFixed(vec![]),
            QpFormulation::Cone,
        ] {
            let qp = solve_qp(&problem, &formulation, &QpSettings::default()).unwrap();
            assert!(qp.solved, "{}: {}", formulation.name(), qp.status);
            assert!(qp.lambda.is_empty());
            assert_eq!(qp.objective, 0.0);
        }
    }
}
