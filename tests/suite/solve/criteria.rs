//! The physical criteria of an answer against Coulomb's law (docs/contact.md §"Physical
//! criteria"): hand-computed values on one contact, their decomposition, and what the box law
//! violates.

use crate::common;

use nalgebra::{Matrix3, SVector};
use proptest::prelude::*;
use rigidref::problem::FrictionModel;
use rigidref::solve::criteria::{ContactCriteria, contact_criteria, criteria};

/// The criteria at μ = 0.5 of impulse `l` (N·s) and contact velocity `c` (m/s).
fn at(l: [f64; 3], c: [f64; 3]) -> ContactCriteria {
    contact_criteria(0.5, &SVector::from(l), &SVector::from(c))
}

/// Each criterion of `got` against `want`, to round-off (1e-15 on values of order 1).
fn assert_criteria(got: ContactCriteria, want: [f64; 6]) {
    let values = [
        got.primal,
        got.dual,
        got.complementarity,
        got.signorini,
        got.cone_boundary,
        got.max_dissipation,
    ];
    for (i, (g, w)) in values.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= 1e-15,
            "criterion {i}: {g} against {w} ({got:?})"
        );
    }
}

#[test]
fn criteria_take_their_hand_computed_values_on_one_contact() {
    // [primal N·s, dual m/s, complementarity J, signorini J, cone boundary J, max dissipation J]
    // The law's three cases give zero everywhere.
    assert_criteria(at([0.0; 3], [1.0, 3.0, -2.0]), [0.0; 6]); // separating
    assert_criteria(at([2.0, 0.3, -0.4], [0.0; 3]), [0.0; 6]); // sticking inside the cone
    assert_criteria(at([2.0, -0.6, -0.8], [0.0, 3.0, 4.0]), [0.0; 6]); // sliding on the rim, against w_t
    // Pressing while separating: λ·ĉ = λn c_n = 1 · 0.5.
    assert_criteria(
        at([1.0, 0.0, 0.0], [0.5, 0.0, 0.0]),
        [0.0, 0.0, 0.5, 0.5, 0.0, 0.0],
    );
    // Sliding with friction inside the cone: ‖c_T‖ (μλn − ‖λ_T‖) = 2 (0.5 − 0.1) = 0.8; ĉ =
    // (μ‖c_T‖, 2, 0) = (1, 2, 0) is on K*'s boundary.
    assert_criteria(
        at([1.0, -0.1, 0.0], [0.0, 2.0, 0.0]),
        [0.0, 0.0, 0.8, 0.0, 0.8, 0.0],
    );
    // Friction along the motion: ‖λ_T‖‖c_T‖ + λ_T·c_T = 0.5 · 2 + 0.5 · 2 = 2.
    assert_criteria(
        at([1.0, 0.5, 0.0], [0.0, 2.0, 0.0]),
        [0.0, 0.0, 2.0, 0.0, 0.0, 2.0],
    );
    // An impulse outside the cone: its projection is (1.2, 0.6, 0), at distance √0.2 = 0.447.
    let outside = at([1.0, 1.0, 0.0], [0.0; 3]);
    assert!(
        (outside.primal - 0.2f64.sqrt()).abs() <= 1e-15,
        "{outside:?}"
    );
    // Approaching with no impulse: ĉ = (−1, 0, 0) is a unit away from K*.
    assert_criteria(
        at([0.0; 3], [-1.0, 0.0, 0.0]),
        [0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    );
    // Without friction (μ = 0) K* is the half-space c_n ≥ 0 and any tangential impulse is
    // outside K (the ray λ_T = 0).
    let frictionless = contact_criteria(
        0.0,
        &SVector::from([1.0, 0.3, 0.0]),
        &SVector::from([-0.2, 1.0, 0.0]),
    );
    assert!((frictionless.primal - 0.3).abs() <= 1e-15 && (frictionless.dual - 0.2).abs() <= 1e-15);
}

#[test]
fn box_friction_satisfies_signorini_and_violates_the_cone_off_the_axes() {
    // Box friction (μ = 0.5, λn = 1): sliding along a tangent axis it is Coulomb's law; sliding
    // along the diagonal its friction opposes the slip but has magnitude √2 μλn, outside the
    // cone; sliding in any other direction its friction does not oppose the slip either.
    assert_criteria(at([1.0, -0.5, 0.0], [0.0, 1.0, 0.0]), [0.0; 6]);
    let diagonal = at([1.0, -0.5, -0.5], [0.0, 1.0, 1.0]);
    let excess = 0.5f64.sqrt() - 0.5; // ‖λ_T‖ − μλn
    assert!(
        diagonal.primal > 0.1 && diagonal.signorini == 0.0,
        "{diagonal:?}"
    );
    assert!((diagonal.cone_boundary - 2f64.sqrt() * excess).abs() <= 1e-15);
    assert!(diagonal.max_dissipation.abs() <= 1e-15);
    let skew = at([1.0, -0.5, -0.5], [0.0, 2.0, 1.0]);
    assert!(
        skew.max_dissipation > 0.05 && skew.signorini == 0.0,
        "{skew:?}"
    );
    // The same on a real box-friction solve: a body sliding off the tangent axes on the ground.
    let a = Matrix3::identity();
    let problem =
        super::local_solve_problem(a, SVector::from([-1.0, 2.0, 1.0]), 0.5, FrictionModel::Box);
    let (lambda, report) = super::run_pgs(
        &problem,
        rigidref::solve::LocalSolve::Exact,
        10,
        Some(1e-13),
    );
    assert!(report.converged);
    let (_, worst) = criteria(&problem, &lambda);
    assert!(
        worst.signorini <= 1e-15 && worst.primal > 0.1 && worst.max_dissipation > 0.05,
        "{worst:?}"
    );
    // And the cone law's solve of the same problem satisfies every criterion.
    let cone =
        super::local_solve_problem(a, SVector::from([-1.0, 2.0, 1.0]), 0.5, FrictionModel::Cone);
    let (lambda, report) =
        super::run_pgs(&cone, rigidref::solve::LocalSolve::Exact, 10, Some(1e-13));
    assert!(report.converged);
    let (_, worst) = criteria(&cone, &lambda);
    for value in [
        worst.primal,
        worst.dual,
        worst.complementarity,
        worst.signorini,
        worst.cone_boundary,
        worst.max_dissipation,
    ] {
        assert!(value <= 1e-12, "{worst:?}");
    }
}

#[test]
fn complementarity_is_the_sum_of_its_three_parts() {
    // λ·ĉ = λn c_n + ‖c_T‖(μλn − ‖λ_T‖) + (‖λ_T‖‖c_T‖ + λ_T·c_T), an identity for any λ and c;
    // the reported parts are the magnitudes of the first two and the third itself (≥ 0).
    proptest!(common::seeded(500), |(l in proptest::array::uniform3(-3.0..3.0f64), c in proptest::array::uniform3(-3.0..3.0f64), mu in 0.0..2.0f64)| {
        let (l, c) = (SVector::from(l), SVector::from(c));
        let k = contact_criteria(mu, &l, &c);
        let (lt, ct) = ((l[1] * l[1] + l[2] * l[2]).sqrt(), (c[1] * c[1] + c[2] * c[2]).sqrt());
        let signed = l[0] * c[0] + ct * (mu * l[0] - lt) + k.max_dissipation;
        // 1e-12: sums of products of entries up to 3 · 2 · 3.
        prop_assert!((k.complementarity - signed.abs()).abs() <= 1e-12);
        prop_assert!(k.max_dissipation >= -1e-12);
        prop_assert!(k.signorini >= 0.0 && k.cone_boundary >= 0.0 && k.primal >= 0.0 && k.dual >= 0.0);
    });
}

#[test]
fn box_answers_cancel_on_an_axis_slide_with_a_loaded_row_and_not_on_the_diagonal() {
    // μ = 0.5, λn = 1 N·s. An axis slide c_T = (v, 0) with the other row loaded (τ = 0.3):
    // ‖λ_T‖ = √(0.25 + 0.09) > μλn, so the middle part −v(‖λ_T‖ − μλn) and the last
    // +v(‖λ_T‖ − μλn) cancel and the complementarity is zero though neither part is.
    let (v, tau) = (2.0, 0.3);
    let excess = (0.25f64 + tau * tau).sqrt() - 0.5;
    let axis = at([1.0, -0.5, tau], [0.0, v, 0.0]);
    assert!(axis.complementarity <= 1e-15, "{axis:?}");
    assert!((axis.cone_boundary - v * excess).abs() <= 1e-15, "{axis:?}");
    assert!(
        (axis.max_dissipation - v * excess).abs() <= 1e-15,
        "{axis:?}"
    );
    assert!(axis.primal > 0.05, "{axis:?}");
    // The diagonal slide c_T = (v, v), both rows at their bounds: nothing cancels. The middle
    // part is (√2 − 2) μλn v (reported as its magnitude), the last is zero, and the
    // complementarity is the middle part's magnitude.
    let diagonal = at([1.0, -0.5, -0.5], [0.0, v, v]);
    let middle = (2.0 - 2f64.sqrt()) * 0.5 * v;
    assert!(
        (diagonal.cone_boundary - middle).abs() <= 1e-15,
        "{diagonal:?}"
    );
    assert!(diagonal.max_dissipation.abs() <= 1e-15, "{diagonal:?}");
    assert!(
        (diagonal.complementarity - middle).abs() <= 1e-15,
        "{diagonal:?}"
    );
}

#[test]
fn the_dual_criterion_holds_for_friction_coefficients_down_to_the_smallest_double() {
    // K* = {c_n ≥ μ‖c_T‖}; for μ → 0 it tends to the half-space c_n ≥ 0, so the distance of an
    // approaching contact's ĉ = (−1 + μ·5, 3, 4) tends to 1. Computing it through the cone of
    // opening 1/μ overflowed below μ ≈ 1e-154 (μ⁻² = ∞) and gave ‖ĉ‖ = √26.
    for mu in [0.0, 1e-300, 1e-200, 1e-155, 1e-100, 1e-20] {
        let c = contact_criteria(
            mu,
            &SVector::from([0.0, 0.0, 0.0]),
            &SVector::from([-1.0, 3.0, 4.0]),
        );
        // Exact: the distance from (−1 + 5μ, 3, 4) to the cone ‖x_T‖ ≤ x_n/μ is 1 − 5μ to
        // first order in μ.
        assert!(
            (c.dual - 1.0).abs() <= 1e-15 + 10.0 * mu,
            "μ = {mu:e}: {c:?}"
        );
        // Inside K*: separating with a small slip, the dual criterion is zero.
        let inside = contact_criteria(mu, &SVector::zeros(), &SVector::from([1.0, 1e-3, 0.0]));
        assert_eq!(inside.dual, 0.0, "μ = {mu:e}");
    }
    // And it agrees with the distance computed through K* directly where that does not
    // overflow (μ = 0.5: K* has opening 2).
    let c = at([0.0; 3], [-1.0, 3.0, 4.0]);
    let c_hat = SVector::<f64, 3>::from([-1.0 + 0.5 * 5.0, 3.0, 4.0]);
    let direct = (c_hat - rigidref::solve::residual::project_cone(&c_hat, 2.0)).norm();
    assert!((c.dual - direct).abs() <= 1e-15, "{} {direct}", c.dual);
}
