//! The exact Coulomb law's residual (docs/contact.md §"The exact Coulomb residual") and what each
//! solver's problem is (§"Which problem each solver answers").

use crate::common;

use common::problems::{build, spec};
use nalgebra::SVector;
use proptest::prelude::*;
use rigidref::problem::FrictionModel;
use rigidref::solve::qp::{QpFormulation, QpSettings, solve_qp};
use rigidref::solve::residual::{contact_coulomb_residual, coulomb_residual};
use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings, PgsWorkspace, solve_pgs};

#[test]
fn coulomb_residual_is_zero_exactly_at_coulomb_solutions() {
    let r = |lambda: [f64; 3], w: [f64; 3]| {
        contact_coulomb_residual(0.5, &SVector::from(lambda), &SVector::from(w), 1.0)
    };
    // The three cases of the law (μ = 0.5) give zero.
    // (1e-15: the cone projection's square root and division leave an ulp or two.)
    assert!(r([0.0, 0.0, 0.0], [1.0, 3.0, -2.0]) <= 1e-15); // separating, any tangential velocity
    assert!(r([2.0, 0.3, -0.4], [0.0, 0.0, 0.0]) <= 1e-15); // sticking, inside the disk
    assert!(r([2.0, -0.6, -0.8], [0.0, 3.0, 4.0]) <= 1e-15); // sliding, friction μλn against w_t
    // Each way of breaking it does not.
    assert!(r([2.0, 0.6, 0.8], [0.0, 3.0, 4.0]) > 1.0); // friction along the motion
    assert!(r([2.0, -0.3, -0.4], [0.0, 3.0, 4.0]) > 0.1); // sliding below the bound
    assert!(r([2.0, 0.0, 0.0], [0.5, 0.0, 0.0]) > 0.1); // pressing while separating (glue)
    assert!(r([0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]) > 0.1); // approaching with no impulse
    assert!(r([1.0, 1.0, 0.0], [0.0, 0.0, 0.0]) > 0.1); // outside the disk
    // Sliding with a normal velocity μ‖w_t‖ (what Anitescu's relaxation gives) is not Coulomb.
    assert!(r([2.0, -0.6, -0.8], [2.5, 3.0, 4.0]) > 0.1);

    // On random problems, cone-friction PGS converged to 1e-10 m/s also satisfies the exact law
    // to round-off times the conditioning (the two residuals measure the same conditions in
    // different ways: row by row against De Saxcé's single cone projection), and the measure does
    // not change when each contact's tangents are turned about its normal.
    proptest!(common::seeded(300), |(s in spec(1..4, 1..6), mu in 0.0..1.0f64, turn in 0.0..6.3f64)| {
        let problem = build(&s, mu, 0.0, FrictionModel::Cone);
        let settings = PgsSettings { max_iterations: 20_000, tolerance: Some(1e-10), order: ContactOrder::Sequential, local: LocalSolve::Exact };
        let mut lambda = Vec::new();
        let report = solve_pgs(&problem, &settings, &mut PgsWorkspace::new(0), &mut lambda);
        if report.converged {
            let c = report.coulomb_residual.unwrap();
            // 1e-12 m/s: PGS measures w from its accumulated Δu, the check from scratch.
            prop_assert!((c - coulomb_residual(&problem, &lambda)).abs() <= 1e-12);
            prop_assert!(c <= 1e-7, "{report:?}");
        }
        let (turned, turned_lambda) = super::derivations::turn_tangents(&problem, &lambda, turn);
        let (a, b) = (coulomb_residual(&problem, &lambda), coulomb_residual(&turned, &turned_lambda));
        // 1e-10: the turned J, b and λ carry their own round-off into w.
        prop_assert!((a - b).abs() <= 1e-10 * (1.0 + a), "{a} vs {b}");
    });
}

#[test]
fn anitescu_relaxation_lifts_a_sliding_box_exact_coulomb_does_not() {
    // The project's 0.5 m box (125 kg) on its four bottom corners, sliding at 2 m/s along x and
    // pressed by gravity over one step (b_n = −g h), μ = 0.5, h = 0.01 s: friction cannot stop it
    // in one step (μ g h = 0.049 m/s), so every contact slides.
    let (g, h, mu, speed) = (9.8, 0.01, 0.5, 2.0);
    let problem = super::pgs::box_on_ground(
        nalgebra::Vector3::new(speed, -g * h, 0.0),
        nalgebra::Vector3::zeros(),
        mu,
        FrictionModel::Cone,
    );
    // Exact Coulomb (cone PGS): every contact keeps w_n = 0: the box stays on the ground.
    let settings = PgsSettings {
        max_iterations: 10_000,
        tolerance: Some(1e-12),
        order: ContactOrder::Sequential,
        local: LocalSolve::Rows,
    };
    let mut lambda = Vec::new();
    let mut workspace = PgsWorkspace::new(0);
    let report = solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
    assert!(report.converged, "{report:?}");
    assert!(report.coulomb_residual.unwrap() <= 1e-12);
    let w = problem.constraint_velocity(&lambda);
    for wk in &w {
        assert!(wk[0].abs() <= 1e-12, "exact Coulomb: w_n = {}", wk[0]);
    }
    assert!(workspace.delta_velocity(0)[1] + problem.bodies[0].velocity[1] <= 1e-12);
    let v_after = speed - mu * g * h; // 1.951 m/s: the Coulomb deceleration μg over h
    assert!(
        (w[0][1].hypot(w[0][2]) - v_after).abs() < 1e-9,
        "{:?}",
        w[0]
    );

    // Anitescu's convex relaxation (clarabel's SOCP): each sliding contact gains w_n = μ‖w_t‖,
    // so the box leaves the ground at μ‖v_t‖ and rises μ‖v_t‖h in the step.
    let relaxed = solve_qp(&problem, &QpFormulation::Cone, &QpSettings::default()).unwrap();
    assert!(relaxed.solved, "{}", relaxed.status);
    let w = problem.constraint_velocity(&relaxed.lambda);
    for wk in &w {
        let wt = wk[1].hypot(wk[2]);
        // 1e-6: clarabel's tolerance 1e-10 on the scaled problem, in velocity units here.
        assert!(
            (wk[0] - mu * wt).abs() <= 1e-6,
            "relaxation: w_n = {}, μ‖w_t‖ = {}",
            wk[0],
            mu * wt
        );
        // The lift also costs tangential speed (a larger λn, so more friction): w_t ≈ 1.56 m/s
        // here against Coulomb's 1.951, and w_n ≈ 0.78 m/s.
        assert!(wk[0] > 0.5, "the box must be lifted: w_n = {}", wk[0]);
    }
    let delta = problem.velocity_change(&relaxed.lambda);
    let rise = (problem.bodies[0].velocity[1] + delta[0][1]) * h;
    let wt = w[0][1].hypot(w[0][2]);
    assert!(
        (rise - mu * wt * h).abs() <= 1e-8,
        "rise {rise} m, μ‖v_t‖h = {}",
        mu * wt * h
    );
    println!(
        "sliding at {wt:.4} m/s, the relaxation lifts the box {:.2} mm per 10 ms step; Coulomb keeps it down",
        rise * 1e3
    );
    // And the exact Coulomb residual says which answer is Coulomb's.
    assert!(coulomb_residual(&problem, &relaxed.lambda) > 0.1);
}
