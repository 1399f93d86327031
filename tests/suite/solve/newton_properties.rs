//! What the Newton solver's convergence rests on (docs/contact.md §"Newton solver", issue 48's
//! expert list): its Jacobian against finite differences on every branch, counted; the
//! Newton-derivative property at each kind of kink; the local quadratic rate; the invariances
//! under W → sW, q → αq and a turn of the tangents; the six criteria on its answers; the
//! Painlevé example, μ = 0 and μ > 2; and the robustness of its tests (round-off diagonals,
//! the round-off floor of large impulses, tiny velocities, the box tie).

use crate::common;

use common::problems::{build, physical_spec, spec};
use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, SMatrix, SVector, Vector3};
use proptest::prelude::*;
use rigidref::problem::{FrictionModel, LocalProblem, RowBounds, SolveMethod};
use rigidref::solve::criteria::criteria;
use rigidref::solve::newton::{newton_function_local, round_off_floor};
use rigidref::solve::residual::{RowScales, coulomb_residual, residual, siconos_error};
use rigidref::solve::{
    NewtonSettings, Regularisation, SolveReport, solve_newton_local, solve_newton_local_until,
};
use std::cell::RefCell;
use std::collections::BTreeMap;

/// Newton on a local problem from its λ0, with `tolerance` (m/s): λ and the report.
fn newton<const R: usize>(
    problem: &LocalProblem<R>,
    tolerance: f64,
) -> (Vec<SVector<f64, R>>, SolveReport) {
    let settings = NewtonSettings {
        tolerance,
        ..NewtonSettings::default()
    };
    let mut lambda = Vec::new();
    let report = solve_newton_local(problem, &settings, &mut lambda);
    (lambda, report)
}

/// A local problem of one contact: W = `w` (kg⁻¹), q (m/s), μ.
fn one_contact<const R: usize>(
    w: SMatrix<f64, R, R>,
    q: SVector<f64, R>,
    mu: f64,
    friction: FrictionModel,
) -> LocalProblem<R> {
    let dense = DMatrix::from_fn(R, R, |i, j| w[(i, j)]);
    let q = DVector::from_fn(R, |i, _| q[i]);
    LocalProblem::from_dense(friction, &dense, &q, &[mu]).unwrap()
}

/// A random 2D local problem: W = BᵀB + 0.1 I (kg⁻¹) from `entries`, q and μ given.
fn random_2d(entries: &[f64], q: &[f64], mu: &[f64], friction: FrictionModel) -> LocalProblem<2> {
    let n = 2 * mu.len();
    let b = DMatrix::from_fn(n, n, |i, j| entries[i * 8 + j]);
    let w = b.transpose() * &b + DMatrix::identity(n, n) * 0.1;
    LocalProblem::from_dense(friction, &w, &DVector::from_fn(n, |i, _| q[i]), mu).unwrap()
}

/// λ (stacked) as impulses of R rows.
fn impulses<const R: usize>(x: &DVector<f64>) -> Vec<SVector<f64, R>> {
    x.as_slice()
        .chunks(R)
        .map(|c| SVector::from_iterator(c.iter().copied()))
        .collect()
}

fn stacked<const R: usize>(lambda: &[SVector<f64, R>]) -> DVector<f64> {
    DVector::from_iterator(
        R * lambda.len(),
        lambda.iter().flat_map(|l| l.iter().copied()),
    )
}

/// The branch each row of `problem` is on at λ (docs/contact.md §"Newton solver", the table of
/// D_λ and D_w), recomputed here from W, q and μ, with the proximal term (η, λ_c) when given:
/// "μ′" marks a friction row whose radius moves with the normal row (s_n > 0, μ > 0), which
/// puts the normal column in its Jacobian.
fn branches<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    proximal: Option<(f64, &[SVector<f64, R>])>,
) -> Vec<Vec<String>> {
    let w = problem.velocity(lambda);
    let prefix = format!(
        "{}{}",
        if R == 2 { "2D " } else { "" },
        if proximal.is_some() { "proximal " } else { "" }
    );
    (0..problem.contacts.len())
        .map(|k| {
            let c = &problem.contacts[k];
            if c.bounds == RowBounds::Free {
                return vec![format!("{prefix}free"); R];
            }
            let scales = RowScales::of_block(*problem.diagonal_block(k));
            let (mut a, mut rho, mut wk) = (scales.diagonal, scales.tangent_rho, w[k]);
            if let Some((eta, centre)) = proximal {
                wk += a.component_mul(&(lambda[k] - centre[k])) * eta;
                rho += eta * (1..R).map(|r| a[r]).fold(0.0, f64::max);
                a *= 1.0 + eta;
            }
            let l = lambda[k];
            let s_n = l[0] - wk[0] / a[0];
            let kappa = c.mu * s_n.max(0.0);
            let moving = if s_n > 0.0 && c.mu > 0.0 {
                ", μ′"
            } else {
                ""
            };
            let mut out = vec![format!(
                "{prefix}normal {}",
                if s_n > 0.0 { "active" } else { "inactive" }
            )];
            if R == 3 && problem.friction == FrictionModel::Cone {
                let z = Vector3::new(0.0, l[1] - wk[1] / rho, l[2] - wk[2] / rho).norm();
                let name = if z <= kappa && kappa > 0.0 {
                    "disk interior".to_string()
                } else if z > 0.0 {
                    format!("disk rim{moving}")
                } else {
                    "disk tip".to_string()
                };
                out.extend([format!("{prefix}{name}"), format!("{prefix}{name}")]);
            } else {
                for r in 1..R {
                    let z = l[r] - wk[r] / a[r];
                    let name = if z.abs() > kappa {
                        format!("bound{moving}")
                    } else if kappa > 0.0 {
                        "interior".to_string()
                    } else {
                        "tie".to_string()
                    };
                    out.push(format!("{prefix}{name}"));
                }
            }
            out
        })
        .collect()
}

/// Central finite differences (step 1e-6 N·s) of F against its Jacobian at λ, every entry
/// away from a kink, counted by the branch of its row in `counts` (and, for the rows marked
/// μ′, their entry in the normal column separately).
fn check_jacobian<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    proximal: Option<(f64, &[SVector<f64, R>])>,
    counts: &mut BTreeMap<String, usize>,
) -> Result<(), TestCaseError> {
    let (f0, jacobian) = newton_function_local(problem, lambda, proximal);
    let names = branches(problem, lambda, proximal);
    let (n, step) = (f0.len(), 1e-6);
    for col in 0..n {
        let at = |delta: f64| {
            let mut moved = lambda.to_vec();
            moved[col / R][col % R] += delta;
            newton_function_local(problem, &moved, proximal).0
        };
        let (plus, minus) = (at(step), at(-step));
        for row in 0..n {
            let (right, left) = (plus[row] - f0[row], f0[row] - minus[row]);
            let central = (right + left) / (2.0 * step);
            // A kink inside [−step, step]: the one-sided slopes differ; skip it.
            if (right - left).abs() > 1e-6 * (1.0 + central.abs()) * step {
                continue;
            }
            let name = &names[row / R][row % R];
            *counts.entry(name.clone()).or_default() += 1;
            if name.contains("μ′") && row % R > 0 && col == R * (row / R) {
                *counts.entry(format!("{name}: normal column")).or_default() += 1;
            }
            // 1e-5 relative: central differences of a piecewise-smooth function with entries
            // of order 1–100 at step 1e-6.
            prop_assert!(
                (central - jacobian[(row, col)]).abs() <= 1e-5 * (1.0 + central.abs()),
                "{name}: row {row} col {col}: finite difference {central}, Jacobian {}",
                jacobian[(row, col)]
            );
        }
    }
    Ok(())
}

#[test]
fn generalized_jacobian_matches_finite_differences_on_every_branch() {
    let counts = RefCell::new(BTreeMap::<String, usize>::new());
    // 3D: the assembled random problems of every shape (thin rods included), cone and box, a
    // joint's free rows in place of the last contact in half of them, and the proximal
    // subproblem's function (η from 1e-3 to 10 about a random centre) in half of them.
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(200), |(
            s in spec(1..4, 1..5),
            mu in 0.0..2.0f64,
            l in proptest::collection::vec(-30.0..30.0f64, 12),
            centre in proptest::collection::vec(-30.0..30.0f64, 12),
            free in any::<bool>(),
            eta in prop_oneof![Just(0.0), 1e-3..10.0f64],
        )| {
            let mut problem = build(&s, mu, 0.0, friction).to_local();
            let count = problem.contacts.len();
            if free && count > 1 {
                problem.contacts[count - 1].bounds = RowBounds::Free;
            }
            let at = |v: &[f64]| impulses::<3>(&DVector::from_column_slice(&v[..3 * count]));
            let (lambda, centre) = (at(&l), at(&centre));
            let proximal = (eta > 0.0).then_some((eta, centre.as_slice()));
            check_jacobian(&problem, &lambda, proximal, &mut counts.borrow_mut())?;
        });
    }
    // 2D: random local problems (the interval law, both models alike), free rows and the
    // proximal function as above.
    proptest!(common::seeded(200), |(
        entries in proptest::collection::vec(-1.0..1.0f64, 64),
        q in proptest::collection::vec(-3.0..3.0f64, 8),
        mu in proptest::collection::vec(0.0..2.0f64, 1..5),
        l in proptest::collection::vec(-5.0..5.0f64, 8),
        centre in proptest::collection::vec(-5.0..5.0f64, 8),
        free in any::<bool>(),
        eta in prop_oneof![Just(0.0), 1e-3..10.0f64],
    )| {
        let mut problem = random_2d(&entries, &q, &mu, FrictionModel::Box);
        let count = mu.len();
        if free && count > 1 {
            problem.contacts[0].bounds = RowBounds::Free;
        }
        let at = |v: &[f64]| impulses::<2>(&DVector::from_column_slice(&v[..2 * count]));
        let (lambda, centre) = (at(&l), at(&centre));
        let proximal = (eta > 0.0).then_some((eta, centre.as_slice()));
        check_jacobian(&problem, &lambda, proximal, &mut counts.borrow_mut())?;
    });
    let counts = counts.into_inner();
    eprintln!("entries checked per branch: {counts:#?}");
    // Every branch a random point reaches, in every setting, with enough entries that a wrong
    // entry of that branch could not hide (the ties, "disk tip" and "tie", are kinks: a random
    // point never lands on them, and newton_derivative_remainder_vanishes_at_every_kind_of_kink
    // checks them).
    for prefix in ["", "proximal ", "2D ", "2D proximal "] {
        let mut names = vec![
            "normal active",
            "normal inactive",
            "free",
            "bound",
            "bound, μ′",
            "bound, μ′: normal column",
            "interior",
        ];
        if !prefix.starts_with("2D") {
            names.extend([
                "disk rim",
                "disk rim, μ′",
                "disk rim, μ′: normal column",
                "disk interior",
            ]);
        }
        for name in names {
            let key = format!("{prefix}{name}");
            let got = counts.get(&key).copied().unwrap_or(0);
            assert!(got >= 20, "{key}: {got} entries checked");
        }
    }
    assert!(counts.values().sum::<usize>() > 20_000);
}

/// max over the directions of ‖F(λ* + h) − F(λ*) − V(λ* + h) h‖ / ‖h‖ at ‖h‖ = `size`, with V
/// the Jacobian the solver uses at λ* + h, and the branches the points λ* + h were on.
fn remainder<const R: usize>(
    problem: &LocalProblem<R>,
    star: &[SVector<f64, R>],
    size: f64,
    branches_seen: &mut BTreeMap<String, usize>,
) -> f64 {
    let f_star = newton_function_local(problem, star, None).0;
    let n = f_star.len();
    let mut worst: f64 = 0.0;
    for i in 0..200 {
        // Directions spread over the sphere (deterministic).
        let h = DVector::from_fn(n, |r, _| ((i * n + r) as f64 * 12.9898 + 0.5).sin());
        let h = h.normalize() * size;
        let moved = impulses::<R>(&(stacked(star) + &h));
        let (f, v) = newton_function_local(problem, &moved, None);
        worst = worst.max((f - &f_star - v * &h).norm() / size);
        for b in branches(problem, &moved, None).concat() {
            *branches_seen.entry(b).or_default() += 1;
        }
    }
    worst
}

#[test]
fn newton_derivative_remainder_vanishes_at_every_kind_of_kink() {
    // ∂F is a Newton derivative: F(λ* + h) − F(λ*) − ∂F(λ* + h) h = o(‖h‖). At the kinks where
    // every piece around is affine (the box tie κ = 0 with z_r = 0, a box row on its bound
    // |z_r| = κ, the normal tie s_n = 0) and at the cone's tip (F positively homogeneous of
    // degree one about it), the remainder is zero up to round-off; at the disk's rim ‖z‖ = κ
    // it is O(‖h‖²). Sizes 1e-2 … 1e-6; 200 directions each.
    let w = Matrix3::new(1.0, 0.3, 0.1, 0.3, 2.0, 0.2, 0.1, 0.2, 1.5);
    let q_for = |lambda: Vector3<f64>| -(w * lambda);
    let zero = Vector3::zeros();
    // (name, problem, λ*, branches the points around must reach)
    let kinks: Vec<(&str, LocalProblem<3>, Vector3<f64>, Vec<&str>)> = vec![
        (
            "cone tip (q = 0, λ* = 0: s_n = 0, z = 0, κ = 0)",
            one_contact(w, zero, 0.5, FrictionModel::Cone),
            zero,
            vec![
                "normal active",
                "normal inactive",
                "disk rim, μ′",
                "disk rim",
            ],
        ),
        (
            "disk rim ‖z‖ = κ (λ* = (1, 0.375, 0.5), w* = 0, μ = 0.625)",
            one_contact(
                w,
                q_for(Vector3::new(1.0, 0.375, 0.5)),
                0.625,
                FrictionModel::Cone,
            ),
            Vector3::new(1.0, 0.375, 0.5),
            vec!["disk rim, μ′", "disk interior"],
        ),
        (
            "box tie κ = 0, z = 0 (separating, λ* = 0, q = (1, 0, 0))",
            one_contact(w, Vector3::new(1.0, 0.0, 0.0), 0.5, FrictionModel::Box),
            zero,
            vec!["normal inactive", "bound"],
        ),
        (
            "box tip (q = 0, λ* = 0: s_n = 0 and κ = 0)",
            one_contact(w, zero, 0.5, FrictionModel::Box),
            zero,
            vec!["normal active", "normal inactive", "bound, μ′", "interior"],
        ),
        (
            "box bound |z_1| = κ (λ* = (1, 0.5, −0.25), w* = 0, μ = 0.5)",
            one_contact(
                w,
                q_for(Vector3::new(1.0, 0.5, -0.25)),
                0.5,
                FrictionModel::Box,
            ),
            Vector3::new(1.0, 0.5, -0.25),
            vec!["bound, μ′", "interior"],
        ),
    ];
    for (name, problem, star, expect) in kinks {
        let star = vec![star];
        let mut seen = BTreeMap::new();
        let rim = name.starts_with("disk rim");
        for size in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6] {
            let ratio = remainder(&problem, &star, size, &mut seen);
            // Affine pieces: round-off only (F of order 1: a few ε/‖h‖ ≤ 1e-9 at 1e-6). The rim:
            // the curvature of κẑ, ρκ‖h_t‖²/‖z‖² with ρ ≤ 2.2, κ = ‖z‖ = 0.625, under 10‖h‖.
            let bound = if rim { 10.0 * size } else { 1e-8 };
            assert!(
                ratio <= bound,
                "{name}: remainder/‖h‖ = {ratio:e} at ‖h‖ = {size:e}"
            );
        }
        for b in expect {
            assert!(
                seen.contains_key(b),
                "{name}: the points around never on {b}: {seen:?}"
            );
        }
    }
    // 2D: the tie κ = 0, z = 0 and the bound |z| = κ of the interval law.
    let w2 = Matrix2::new(0.91, -1.8, -1.8, 4.1);
    for (name, q, star) in [
        (
            "2D tie",
            SVector::<f64, 2>::new(1.0, 0.0),
            SVector::<f64, 2>::zeros(),
        ),
        (
            "2D bound",
            -(w2 * SVector::<f64, 2>::new(1.0, 0.5)),
            SVector::<f64, 2>::new(1.0, 0.5),
        ),
    ] {
        let problem = one_contact(w2, q, 0.5, FrictionModel::Box);
        let mut seen = BTreeMap::new();
        for size in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6] {
            let ratio = remainder(&problem, &[star], size, &mut seen);
            assert!(
                ratio <= 1e-8,
                "{name}: remainder/‖h‖ = {ratio:e} at ‖h‖ = {size:e}"
            );
        }
        assert!(seen.len() >= 2, "{name}: {seen:?}");
    }
}

#[test]
fn box_tie_at_zero_radius_takes_the_clamped_branch_and_keeps_the_matrix_regular() {
    // Two coincident contacts (W = [[A, A], [A, A]], singular), separating (q_n = 1 > 0) with
    // no slip (q_t = 0): at λ = 0 every friction row is at the tie κ = 0, z_r = 0. The clamped
    // branch gives rows a_r e_r and the matrix diag(W) (regular); the interior branch would put
    // W's two equal rows in it.
    let a = Matrix3::new(1.0, 0.3, 0.1, 0.3, 2.0, 0.2, 0.1, 0.2, 1.5);
    let mut dense = DMatrix::zeros(6, 6);
    for (i, j) in [(0, 0), (0, 3), (3, 0), (3, 3)] {
        dense.view_mut((i, j), (3, 3)).copy_from(&a);
    }
    let q = DVector::from_vec(vec![1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let problem =
        LocalProblem::<3>::from_dense(FrictionModel::Box, &dense, &q, &[0.5, 0.5]).unwrap();
    let zero = vec![SVector::<f64, 3>::zeros(); 2];
    let (f, jacobian) = newton_function_local(&problem, &zero, None);
    assert_eq!(f.amax(), 0.0);
    let diagonal = DMatrix::from_diagonal(&dense.diagonal());
    assert_eq!(jacobian, diagonal);
    assert!(jacobian.determinant() > 0.0);
    // And the solver answers the problem from there at once: λ = 0.
    let (lambda, report) = newton(&problem, 1e-12);
    assert!(report.converged && report.iterations == 0, "{report:?}");
    assert!(lambda.iter().all(|l| l.amax() == 0.0));
}

/// A random non-degenerate 3D problem's local form: physical bodies, compliance 1e-2 kg⁻¹ (W
/// positive definite), cone friction.
fn compliant_cone(s: &common::problems::ProblemSpec, mu: f64) -> LocalProblem<3> {
    build(s, mu, 1e-2, FrictionModel::Cone).to_local()
}

/// Whether answer λ of `problem` is strictly complementary by `margin` (each contact clearly
/// separating, sticking or sliding): there the solution is isolated and Newton's local rate is
/// quadratic.
fn non_degenerate<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    margin: f64,
) -> bool {
    let w = problem.velocity(lambda);
    problem.contacts.iter().enumerate().all(|(k, c)| {
        let (l, v) = (lambda[k], w[k]);
        let (lt, vt) = (
            (1..R).map(|r| l[r] * l[r]).sum::<f64>().sqrt(),
            (1..R).map(|r| v[r] * v[r]).sum::<f64>().sqrt(),
        );
        if l[0] <= margin {
            v[0] > margin
        } else {
            vt > margin || lt < c.mu * l[0] - margin
        }
    })
}

#[test]
fn newton_converges_quadratically_near_non_degenerate_solutions() {
    // Every iterate's law norm ‖F_k‖∞ (read through the stop rule, which sees every iterate),
    // on random compliant cone problems whose answer is strictly complementary: once ‖F_k‖ is
    // below 1e-2 m/s, ‖F_{k+1}‖ ≤ C ‖F_k‖² with C = 100 s/m (measured up to ~5), until round-off
    // (‖F_{k+1}‖ ≤ 1e-13 m/s).
    converges_quadratically_near_non_degenerate_solutions(NewtonSettings::default());
}

#[test]
fn regularised_newton_keeps_the_quadratic_rate_near_non_degenerate_solutions() {
    // The regularisation ε = c (‖F‖∞ / max|b|)^δ, δ = 1.5, changes a step by O(ε ‖Δ‖) =
    // O(‖F‖^2.5) near an isolated solution, below the quadratic term: the same bound holds
    // (docs/contact.md §"Newton solver", **Regularisation following ‖F‖**). A linear ε (δ = 1
    // with a large c) would not keep it.
    converges_quadratically_near_non_degenerate_solutions(NewtonSettings {
        regularisation: Some(Regularisation::MEASURED),
        ..NewtonSettings::default()
    });
}

fn converges_quadratically_near_non_degenerate_solutions(settings: NewtonSettings) {
    let (pairs, worst) = (RefCell::new(0usize), RefCell::new(0.0f64));
    proptest!(common::seeded(200), |(s in physical_spec(1..4, 1..6), mu in 0.05..0.8f64)| {
        let problem = compliant_cone(&s, mu);
        let norms = RefCell::new(Vec::new());
        let mut stop = |l: &[SVector<f64, 3>]| {
            let f = newton_function_local(&problem, l, None).0.amax();
            norms.borrow_mut().push(f);
            f <= 1e-12
        };
        let mut lambda = Vec::new();
        solve_newton_local_until(&problem, &settings, &mut stop, &mut lambda);
        let norms = norms.into_inner();
        if *norms.last().unwrap() > 1e-12 || !non_degenerate(&problem, &lambda, 1e-3) {
            return Ok(());
        }
        for pair in norms.windows(2) {
            if pair[0] < 1e-2 && pair[1] > 1e-13 {
                *pairs.borrow_mut() += 1;
                let c = pair[1] / (pair[0] * pair[0]);
                let largest = worst.borrow().max(c);
                *worst.borrow_mut() = largest;
                prop_assert!(c <= 100.0, "‖F‖ {:e} → {:e}: {norms:?}", pair[0], pair[1]);
            }
        }
    });
    eprintln!(
        "{} pairs, largest ‖F_k+1‖/‖F_k‖² = {}",
        pairs.borrow(),
        worst.borrow()
    );
    assert!(*pairs.borrow() >= 50, "{}", pairs.borrow());
}

/// `problem` with each contact's tangents turned about its normal by `turn` + k radians: W_kj
/// → T_k W_kj T_jᵀ, q_k → T_k q_k, T_k = diag(1, rotation).
fn turned(problem: &LocalProblem<3>, turn: f64) -> (LocalProblem<3>, Vec<Matrix3<f64>>) {
    let t: Vec<Matrix3<f64>> = (0..problem.contacts.len())
        .map(|k| {
            let (s, c) = (turn + k as f64).sin_cos();
            Matrix3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c)
        })
        .collect();
    let mut out = problem.clone();
    for (k, c) in out.contacts.iter_mut().enumerate() {
        for (j, block) in &mut c.row {
            *block = t[k] * *block * t[*j].transpose();
        }
        c.q = t[k] * c.q;
    }
    (out, t)
}

#[test]
fn newton_answers_follow_scalings_and_turns_of_the_problem() {
    // The law is invariant under W → sW (λ → λ/s; every mass scaled by 1/s), q → αq (λ → αλ,
    // with the tolerance scaled by α) and a turn of each contact's tangents (λ → Tλ; cone
    // friction). Newton's iteration is built of the same invariants (row scales W_rr, ρ an
    // eigenvalue, ε diag(W)), so it follows the same path: bit for bit where s and α are
    // powers of two (every operation commutes with them), to round-off otherwise.
    let compared = RefCell::new(0usize);
    proptest!(common::seeded(100), |(s in physical_spec(1..4, 1..6), mu in 0.0..1.0f64, turn in 0.0..6.3f64)| {
        let problem = compliant_cone(&s, mu);
        let tolerance = 1e-11;
        let (lambda, report) = newton(&problem, tolerance);
        if !report.converged {
            return Ok(());
        }
        *compared.borrow_mut() += 1;
        let largest = lambda.iter().map(|l| l.amax()).fold(1.0, f64::max);
        // W → sW.
        for scale in [4.0, 1e3] {
            let mut scaled = problem.clone();
            for c in &mut scaled.contacts {
                for (_, block) in &mut c.row {
                    *block *= scale;
                }
            }
            let (got, scaled_report) = newton(&scaled, tolerance);
            prop_assert!(scaled_report.converged);
            prop_assert_eq!(residual(&scaled, &got) <= tolerance, true);
            for (g, l) in got.iter().zip(&lambda) {
                if scale == 4.0 {
                    prop_assert_eq!(g * 4.0, *l);
                } else {
                    // 1e-8 of the largest impulse: the same path up to round-off.
                    prop_assert!((g * scale - l).amax() <= 1e-8 * largest, "{g} {l}");
                }
            }
        }
        // q → αq.
        for alpha in [8.0, 1e3] {
            let mut scaled = problem.clone();
            for c in &mut scaled.contacts {
                c.q *= alpha;
            }
            let (got, scaled_report) = newton(&scaled, alpha * tolerance);
            prop_assert!(scaled_report.converged);
            for (g, l) in got.iter().zip(&lambda) {
                if alpha == 8.0 {
                    prop_assert_eq!(*g, l * 8.0);
                } else {
                    prop_assert!((g - l * alpha).amax() <= 1e-8 * alpha * largest, "{g} {l}");
                }
            }
        }
        // A turn of the tangents.
        let (turned_problem, t) = turned(&problem, turn);
        let (got, turned_report) = newton(&turned_problem, tolerance);
        prop_assert!(turned_report.converged);
        for (k, (g, l)) in got.iter().zip(&lambda).enumerate() {
            prop_assert!((g - t[k] * l).amax() <= 1e-8 * largest, "{g} {}", t[k] * l);
        }
    });
    assert!(*compared.borrow() >= 80, "{}", compared.borrow());
}

/// What "converged" promises for λ with the default tolerance 1e-10 m/s: both residuals within
/// it or within the answer's round-off floor where that is larger (NewtonSettings::tolerance).
fn limit<const R: usize>(problem: &LocalProblem<R>, lambda: &[SVector<f64, R>]) -> f64 {
    round_off_floor(problem, lambda).max(1e-10)
}

/// The six criteria of a converged answer within the bounds the tolerance implies (see the
/// test): `primal` ≤ 10 tol/ρ (N·s), `dual` ≤ 10 tol (m/s), the four J-valued ≤ 10 tol (‖λ‖ +
/// ‖ĉ‖/ρ + 1e-3) (1 + μ), with ρ the contact's Coulomb scale (its block's trace).
fn assert_criteria_hold<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    tolerance: f64,
) -> Result<(), TestCaseError> {
    let (each, _) = criteria(problem, lambda);
    let w = problem.velocity(lambda);
    for (k, c) in each.iter().enumerate() {
        let mu = problem.contacts[k].mu;
        let rho = problem.diagonal_block(k).trace();
        let w_hat_norm = w[k].norm() * (1.0 + mu);
        let energy = 10.0 * tolerance * (lambda[k].norm() + w_hat_norm / rho + 1e-3) * (1.0 + mu);
        prop_assert!(c.primal <= 10.0 * tolerance / rho, "{k}: {c:?}");
        prop_assert!(c.dual <= 10.0 * tolerance, "{k}: {c:?}");
        for (name, v) in [
            ("complementarity", c.complementarity),
            ("signorini", c.signorini),
            ("cone_boundary", c.cone_boundary),
            ("max_dissipation", c.max_dissipation),
        ] {
            prop_assert!(
                v.abs() <= energy,
                "{k}: {name} {v:e} above {energy:e}: {c:?}"
            );
        }
    }
    Ok(())
}

#[test]
fn converged_newton_answers_meet_all_six_criteria_in_3d_and_2d() {
    // The residuals bound the criteria: with r = ρ‖λ − p‖ ≤ tol, p = proj_K(λ − ŵ/ρ) and
    // λ − ŵ/ρ = p + p° (Moreau), dist_K(λ) ≤ tol/ρ, dist_K*(ŵ) ≤ ρ‖λ − p‖ ≤ tol and |λ·ŵ| ≤
    // tol (‖λ‖ + ‖ŵ‖/ρ) + O(tol²); each part of the complementarity is within as much of zero
    // (the factor 10 covers the parts' share and the box-shaped residual's other scale).
    let checked = RefCell::new([0usize; 2]);
    proptest!(common::seeded(150), |(s in physical_spec(1..4, 1..6), mu in 0.0..1.5f64)| {
        let problem = build(&s, mu, 0.0, FrictionModel::Cone).to_local();
        let (lambda, report) = newton(&problem, 1e-10);
        if report.converged {
            checked.borrow_mut()[0] += 1;
            assert_criteria_hold(&problem, &lambda, limit(&problem, &lambda))?;
        }
    });
    proptest!(common::seeded(150), |(
        entries in proptest::collection::vec(-1.0..1.0f64, 64),
        q in proptest::collection::vec(-3.0..3.0f64, 8),
        mu in proptest::collection::vec(0.0..1.5f64, 1..5),
    )| {
        let problem = random_2d(&entries, &q, &mu, FrictionModel::Cone);
        let (lambda, report) = newton(&problem, 1e-10);
        if report.converged {
            checked.borrow_mut()[1] += 1;
            assert_criteria_hold(&problem, &lambda, limit(&problem, &lambda))?;
        }
    });
    let checked = checked.into_inner();
    assert!(checked[0] >= 120 && checked[1] >= 120, "{checked:?}");
}

#[test]
fn newton_solves_the_painleve_example_frictionless_and_large_friction_problems() {
    // The 2D Painlevé-type example (docs/contact-problem-format.md; three solutions: separate,
    // slide, stick): Newton from rest ends at one of them, and started at each stays there.
    let problem = super::derivations::painleve([1.0, -5.0]).to_local();
    let solutions = [
        SVector::<f64, 2>::zeros(),
        SVector::<f64, 2>::repeat(1.0 / 0.89),
        SVector::<f64, 2>::new(4.9, 2.75) / 0.491,
    ];
    let (lambda, report) = newton(&problem, 1e-12);
    assert!(report.converged, "{report:?}");
    assert!(
        solutions.iter().any(|s| (lambda[0] - s).amax() <= 1e-10),
        "{lambda:?}"
    );
    for solution in solutions {
        let mut warm = problem.clone();
        warm.contacts[0].lambda0 = solution;
        let (lambda, report) = newton(&warm, 1e-12);
        assert!(report.converged && report.iterations == 0, "{report:?}");
        assert_eq!(lambda[0], solution);
    }
    // The same body pushed out (b = (−1, 0)): it sticks with λ = A⁻¹β̃ = (4.1, 1.8)/0.491.
    let stuck = super::derivations::painleve([-1.0, 0.0]).to_local();
    let (lambda, report) = newton(&stuck, 1e-12);
    assert!(report.converged, "{report:?}");
    assert!(
        (lambda[0] - SVector::from([4.1, 1.8]) / 0.491).amax() <= 1e-10,
        "{lambda:?}"
    );

    // μ = 0 (cone and box) and μ > 2 on random physical problems: μ = 0 converges on every one
    // with no friction impulse at all; μ in [2, 10] converges on most (existence asks more the
    // larger μ is), and wherever it says so the law holds.
    let counts = RefCell::new([0usize; 4]);
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        proptest!(common::seeded(100), |(s in physical_spec(1..4, 1..7))| {
            let problem = build(&s, 0.0, 0.0, friction).to_local();
            let (lambda, report) = newton(&problem, 1e-10);
            prop_assert!(report.converged, "{report:?}");
            // No friction impulse: zero up to the LU's round-off.
            let largest = lambda.iter().map(|l| l.amax()).fold(1.0, f64::max);
            prop_assert!(lambda.iter().all(|l| l[1].abs().max(l[2].abs()) <= 1e-12 * largest), "{lambda:?}");
            counts.borrow_mut()[0] += 1;
        });
        proptest!(common::seeded(100), |(s in physical_spec(1..4, 1..7), mu in 2.0..10.0f64)| {
            let problem = build(&s, mu, 0.0, friction).to_local();
            let (lambda, report) = newton(&problem, 1e-10);
            counts.borrow_mut()[1] += 1;
            if report.converged {
                counts.borrow_mut()[2] += 1;
                let limit = limit(&problem, &lambda);
                prop_assert!(residual(&problem, &lambda) <= limit);
                if friction == FrictionModel::Cone {
                    prop_assert!(coulomb_residual(&problem, &lambda) <= limit);
                    counts.borrow_mut()[3] += 1;
                    assert_criteria_hold(&problem, &lambda, limit)?;
                }
            }
        });
    }
    let c = counts.into_inner();
    eprintln!("[μ = 0 converged, μ > 2 tried, converged, of which cone] = {c:?}");
    // Measured: all 202 with μ = 0; 162 of 202 with μ > 2 (83 of 101 cone).
    assert!(c[0] == c[1] && c[2] >= 150 && c[3] >= 70, "{c:?}");
    // A hand-made one with μ = 5: sticking inside the wide cone, λ = −A⁻¹ q.
    let a = Matrix3::new(1.0, 0.3, 0.1, 0.3, 2.0, 0.2, 0.1, 0.2, 1.5);
    let q = Vector3::new(-1.0, 2.0, -1.5);
    let problem = one_contact(a, q, 5.0, FrictionModel::Cone);
    let (lambda, report) = newton(&problem, 1e-12);
    assert!(report.converged);
    assert!(
        (lambda[0] + a.try_inverse().unwrap() * q).amax() <= 1e-12,
        "{lambda:?}"
    );
}

#[test]
fn a_round_off_diagonal_counts_as_zero() {
    // Contact 1's block is round-off of zero (1e-18 kg⁻¹ beside entries of order 1): no
    // impulse of its own moves it. Taking 1e-18 as its scale, the residual of λn = 1e7 N·s
    // on it while it separates at 1 m/s was |min(1e-18 · 1e7, 1)| = 1e-11 m/s, "converged";
    // as a zero-diagonal row it is |min(λn, w_n)| = 1.
    let mut dense = DMatrix::<f64>::zeros(6, 6);
    dense
        .view_mut((0, 0), (3, 3))
        .copy_from(&Matrix3::new(1.0, 0.3, 0.1, 0.3, 2.0, 0.2, 0.1, 0.2, 1.5));
    dense.view_mut((3, 3), (3, 3)).fill_with_identity();
    dense.view_mut((3, 3), (3, 3)).scale_mut(1e-18);
    let q = DVector::from_vec(vec![-1.0, 0.5, 0.0, 1.0, 0.0, 0.0]);
    let problem =
        LocalProblem::<3>::from_dense(FrictionModel::Cone, &dense, &q, &[0.5, 0.5]).unwrap();
    let (lambda, report) = newton(&problem, 1e-10);
    assert!(report.converged, "{report:?}");
    assert_eq!(lambda[1], SVector::<f64, 3>::zeros());
    let mut pushed = lambda.clone();
    pushed[1][0] = 1e7;
    assert!(
        residual(&problem, &pushed) >= 1.0,
        "{}",
        residual(&problem, &pushed)
    );
    assert!(coulomb_residual(&problem, &pushed) >= 1.0);
    // An exactly zero block reads the same as before.
    let mut exact = dense.clone();
    exact.view_mut((3, 3), (3, 3)).fill(0.0);
    let problem =
        LocalProblem::<3>::from_dense(FrictionModel::Cone, &exact, &q, &[0.5, 0.5]).unwrap();
    assert!(residual(&problem, &pushed) >= 1.0);
}

/// A problem no impulse can move (W = 0: every contact between bodies that cannot move), its
/// contacts separating (q_n > 0) and warm-started with impulses left from an earlier step: the
/// only answer is λ = 0 (λn w_n = 0 with w = q, and the friction bound μλn = 0). A zero diagonal
/// is no row scale (W's largest diagonal is 0, so the round-off floor is 0 too, and a diagonal
/// at the floor must count as zero, not as a scale of 0 that makes F vanish everywhere): Newton
/// scales such rows by 1 (F_n = min(λn, w_n)) and reaches λ = 0 exactly (one step of the
/// identity), box and cone, to the default tolerance.
#[test]
fn newton_answers_a_problem_no_impulse_can_move_with_zero_impulses() {
    for friction in [FrictionModel::Box, FrictionModel::Cone] {
        let dense = DMatrix::<f64>::zeros(6, 6);
        let q = DVector::from_vec(vec![1.0, 0.5, -0.3, 2.0, 0.0, 0.1]);
        let mut problem = LocalProblem::<3>::from_dense(friction, &dense, &q, &[0.5, 0.0]).unwrap();
        problem.contacts[0].lambda0 = Vector3::new(0.5, 0.2, -0.1);
        problem.contacts[1].lambda0 = Vector3::new(1.5, 0.0, 0.3);
        let (lambda, report) = newton(&problem, 1e-10);
        assert!(report.converged, "{friction:?}: {report:?}");
        assert!(
            lambda.iter().all(|l| l.amax() == 0.0),
            "{friction:?}: {lambda:?}"
        );
    }
}

#[test]
fn large_impulses_converge_to_their_round_off_floor() {
    // q scaled by 1e9: impulses of order 1e9 N·s, where w = Wλ + q carries rounding errors of
    // order ε ‖W‖ ‖λ‖ ≈ 1e-7 m/s, far above the default 1e-10. Newton stops at that floor and
    // says converged; the answer is the unscaled one's times 1e9 (the law is homogeneous in q)
    // to 1e-9 relative.
    proptest!(common::seeded(40), |(s in physical_spec(1..3, 1..5), mu in 0.0..0.8f64)| {
        let problem = compliant_cone(&s, mu);
        let (lambda, report) = newton(&problem, 1e-13);
        prop_assume!(report.converged);
        let mut large = problem.clone();
        for c in &mut large.contacts {
            c.q *= 1e9;
        }
        let largest = lambda.iter().map(|l| l.amax()).fold(0.0, f64::max);
        prop_assume!(largest > 1e-3);
        let (got, large_report) = newton(&large, 1e-10);
        let floor = round_off_floor(&large, &got);
        prop_assert!(floor > 1e-10, "{floor:e}");
        prop_assert!(large_report.converged, "{large_report:?}, floor {floor:e}");
        prop_assert!(residual(&large, &got) <= floor.max(1e-10));
        for (g, l) in got.iter().zip(&lambda) {
            // 1e-9 relative: the unscaled answer is within 1e-13 m/s, the scaled one within its
            // floor, and W's smallest eigenvalue is at least the compliance 1e-2 kg⁻¹.
            prop_assert!((g - l * 1e9).amax() <= 1e-9 * 1e9 * largest, "{g} {}", l * 1e9);
        }
    });
}

/// Where the tolerance is below the round-off floor of the answer (impulses of order 1e9 N·s,
/// as in the test above), the first Newton run's end is accepted at the floor: no fallback runs
/// after it (the proximal loops could not go below the floor either), so the report names
/// Newton and counts the iterations of that one run, at most `max_iterations` (50). Both
/// friction models: a box answer is judged by its own residual at the floor, not by the exact
/// Coulomb residual, which a box answer sliding off an axis leaves far above it (counted: at
/// least 3 such box cases, so that judging box answers by the cone's law would fail here).
#[test]
fn large_impulses_are_accepted_at_their_floor_after_the_first_run() {
    let box_off_cone = RefCell::new(0usize);
    proptest!(common::seeded(40), |(s in physical_spec(1..3, 1..5), mu in 0.0..0.8f64, boxed in any::<bool>())| {
        let friction = if boxed { FrictionModel::Box } else { FrictionModel::Cone };
        let problem = build(&s, mu, 1e-2, friction).to_local();
        let (lambda, report) = newton(&problem, 1e-13);
        prop_assume!(report.converged);
        let largest = lambda.iter().map(|l| l.amax()).fold(0.0, f64::max);
        prop_assume!(largest > 1e-3);
        let mut large = problem.clone();
        for c in &mut large.contacts {
            c.q *= 1e9;
        }
        let (got, large_report) = newton(&large, 1e-10);
        let floor = round_off_floor(&large, &got);
        prop_assume!(floor > 1e-10);
        if boxed && coulomb_residual(&large, &got) > floor {
            *box_off_cone.borrow_mut() += 1;
        }
        prop_assert!(large_report.converged, "{friction:?} {large_report:?}");
        prop_assert_eq!(large_report.method, SolveMethod::Newton);
        prop_assert!(
            large_report.iterations <= NewtonSettings::default().max_iterations,
            "{friction:?} {large_report:?}"
        );
    });
    eprintln!("{} box answers off the cone", box_off_cone.borrow());
    assert!(*box_off_cone.borrow() >= 3, "{}", box_off_cone.borrow());
}

#[test]
fn tiny_velocities_pass_at_zero_impulse_only_within_the_tolerance() {
    // q scaled by 1e-11: every velocity is below the tolerance 1e-10 m/s, so λ = 0 passes the
    // absolute test at once; harmless in the sense the tolerance promises, since the contact
    // velocities (q itself) are within 1e-10 m/s of the exact answer's. Where a relative answer
    // is wanted the stop rule on Siconos' relative error gives it: the exact answer scaled by
    // 1e-11 to 1e-6 relative.
    proptest!(common::seeded(40), |(s in physical_spec(1..3, 1..5), mu in 0.0..0.8f64)| {
        let problem = compliant_cone(&s, mu);
        let (lambda, report) = newton(&problem, 1e-13);
        prop_assume!(report.converged);
        let mut tiny = problem.clone();
        for c in &mut tiny.contacts {
            c.q *= 1e-11;
        }
        let (got, tiny_report) = newton(&tiny, 1e-10);
        prop_assert!(tiny_report.converged && tiny_report.iterations == 0);
        prop_assert!(got.iter().all(|g| g.amax() == 0.0));
        let exact: Vec<SVector<f64, 3>> = lambda.iter().map(|l| l * 1e-11).collect();
        let (w_exact, w_got) = (tiny.velocity(&exact), tiny.velocity(&got));
        for (a, b) in w_exact.iter().zip(&w_got) {
            prop_assert!((a - b).amax() <= 1e-10);
        }
        let mut stop = |l: &[SVector<f64, 3>]| siconos_error(&tiny, l) <= 1e-12;
        let mut relative = Vec::new();
        solve_newton_local_until(&tiny, &NewtonSettings::default(), &mut stop, &mut relative);
        let largest = exact.iter().map(|l| l.amax()).fold(1e-300, f64::max);
        prop_assert!(largest > 0.0);
        for (r, e) in relative.iter().zip(&exact) {
            prop_assert!((r - e).amax() <= 1e-6 * largest, "{r} {e}");
        }
    });
}

/// The law norm the solver compares points by (src/solve/newton/system.rs `law_norm`): per
/// contact the larger of |F_n| and ‖F_t‖, the largest over contacts (m/s).
fn disk_law_norm(problem: &LocalProblem<3>, lambda: &[SVector<f64, 3>]) -> f64 {
    let f = newton_function_local(problem, lambda, None).0;
    f.as_slice()
        .chunks(3)
        .map(|c| c[0].abs().max((c[1] * c[1] + c[2] * c[2]).sqrt()))
        .fold(0.0, f64::max)
}

/// Newton with one iteration per run and no proximal subproblem, under a stop rule that accepts
/// nothing: `measure` of every iterate the rule sees, in order, the report and the answer.
fn one_iteration_runs<const R: usize>(
    problem: &LocalProblem<R>,
    measure: impl Fn(&[SVector<f64, R>]) -> f64,
) -> (Vec<f64>, SolveReport, Vec<SVector<f64, R>>) {
    let seen = RefCell::new(Vec::new());
    let mut stop = |l: &[SVector<f64, R>]| {
        seen.borrow_mut().push(measure(l));
        false
    };
    let settings = NewtonSettings {
        max_iterations: 1,
        proximal_iterations: 0,
        ..NewtonSettings::default()
    };
    let mut lambda = Vec::new();
    let report = solve_newton_local_until(problem, &settings, &mut stop, &mut lambda);
    (seen.into_inner(), report, lambda)
}

/// Where nothing is accepted, every stage runs (docs/contact.md §"Proximal-point
/// globalisation"): the first Newton run, the adaptive proximal loop, plain Newton from the
/// start, the tenfold proximal loop. With no proximal iteration allowed each loop is only its
/// closing Newton run from the best centre; with one iteration per run the four runs take one
/// step each (from λ = 0, from the first run's end, from 0 again, from the plain run's end), and
/// the stop rule sees two iterates per run. A step from a point already at round-off can fail
/// its line search and end the run one call early, so only problems whose first step ends
/// above 1e-10 m/s are used (counted: at least 20; measured all of them). The report counts the four
/// iterations, and the answer is the best iterate any stage showed the stop rule: the closing
/// runs go on from where the runs before them ended, and each stage keeps the better of its
/// entry and its end.
#[test]
fn every_stage_counts_its_iterations_and_the_best_point_is_returned_when_none_is_accepted() {
    let used = RefCell::new(0usize);
    proptest!(common::seeded(100), |(s in physical_spec(1..4, 1..6), mu in 0.05..0.8f64)| {
        let problem = compliant_cone(&s, mu);
        let (norms, report, lambda) = one_iteration_runs(&problem, |l| disk_law_norm(&problem, l));
        prop_assume!(norms.len() >= 2 && norms[1] > 1e-10);
        *used.borrow_mut() += 1;
        prop_assert_eq!(norms.len(), 8, "{:?}", norms);
        prop_assert_eq!(report.iterations, 4, "{:?}", report);
        let best = norms.iter().copied().fold(f64::INFINITY, f64::min);
        prop_assert_eq!(disk_law_norm(&problem, &lambda), best, "{:?}", norms);
    });
    eprintln!("{} problems used", used.borrow());
    assert!(*used.borrow() >= 20, "{}", used.borrow());
}

/// A problem without contacts is answered at once with the empty answer, whatever the stop rule:
/// there is no row to step on (a stop rule that accepted nothing made the first run step on
/// none, which failed in nalgebra's slicing; found while writing this test for the mutant
/// `newton/mod.rs:487:22`, `n > 0` → `n >= 0` in the guard of the fallbacks, a guard the early
/// return now makes unnecessary).
#[test]
fn a_problem_without_contacts_is_answered_at_once_whatever_the_stop_rule() {
    for friction in [FrictionModel::Cone, FrictionModel::Box] {
        let empty = LocalProblem::<3> {
            friction,
            contacts: Vec::new(),
        };
        let mut never = |_: &[SVector<f64, 3>]| false;
        let mut lambda = vec![SVector::repeat(1.0)];
        let report =
            solve_newton_local_until(&empty, &NewtonSettings::default(), &mut never, &mut lambda);
        assert!(lambda.is_empty());
        assert!(report.converged && report.iterations == 0, "{report:?}");
        assert_eq!(report.residual, 0.0);
        let report = solve_newton_local(&empty, &NewtonSettings::default(), &mut lambda);
        assert!(report.converged && report.iterations == 0, "{report:?}");
        let empty_2d = LocalProblem::<2> {
            friction,
            contacts: Vec::new(),
        };
        let mut never = |_: &[SVector<f64, 2>]| false;
        let mut lambda = Vec::new();
        let report = solve_newton_local_until(
            &empty_2d,
            &NewtonSettings::default(),
            &mut never,
            &mut lambda,
        );
        assert!(report.converged && report.iterations == 0 && lambda.is_empty());
    }
}

/// The line search's sufficient decrease (docs/contact.md §"Newton solver"): a step is taken
/// only where θ = ½‖F‖² falls below the largest θ of the last iterations by 2σtθ (σ = 1e-4), so
/// the first step of a run, whose reference is θ₀, lowers θ. Built so that the full Newton step
/// raises θ by a factor inside the margin, 1 + 1e-4 < 1 + 2σ: two frictionless 2D contacts,
/// W_nn = [[1, c], [c, 4]] (c = −1.5, positive definite), q_n = (−1, p), from λ = 0. Contact 1
/// approaches and is active, contact 2 separates and is not; the step solves w₁ = 0 with
/// λ₂ = 0, λ = (1, 0), where c pushes contact 2 into approach: w₂ = c + p, θ = ½(c + p)², against
/// θ₀ = ½. With (c + p)² = 1 + 1e-4 the full step must be refused and a shorter one taken
/// (t = ½: θ = 0.156). A search that accepted any step within +2σtθ of the reference (the
/// mutant `newton/mod.rs:322:62`, `−` → `+`) takes the full step, and θ rises.
#[test]
fn the_first_step_lowers_theta_even_where_the_full_step_raises_it_by_less_than_the_margin() {
    let c = -1.5;
    let p = -c - (1.0f64 + 1e-4).sqrt();
    let w = DMatrix::from_row_slice(
        4,
        4,
        &[
            1.0, 0.0, c, 0.0, //
            0.0, 1.0, 0.0, 0.0, //
            c, 0.0, 4.0, 0.0, //
            0.0, 0.0, 0.0, 1.0,
        ],
    );
    let q = DVector::from_vec(vec![-1.0, 0.0, p, 0.0]);
    let problem = LocalProblem::<2>::from_dense(FrictionModel::Cone, &w, &q, &[0.0, 0.0]).unwrap();
    let theta =
        |l: &[SVector<f64, 2>]| 0.5 * newton_function_local(&problem, l, None).0.norm_squared();
    let start = vec![SVector::<f64, 2>::zeros(); 2];
    let full = vec![nalgebra::Vector2::new(1.0, 0.0), SVector::zeros()];
    let ratio = theta(&full) / theta(&start);
    assert!(
        ratio > 1.0 && ratio < 1.0 + 2e-4,
        "the full step's θ ratio {ratio}"
    );
    let (seen, _, _) = one_iteration_runs(&problem, theta);
    assert!(seen.len() >= 2, "{seen:?}");
    assert_eq!(seen[0], 0.5);
    assert!(
        seen[1] < seen[0] * (1.0 - 1e-4),
        "the first step took θ from {} to {}",
        seen[0],
        seen[1]
    );
}

/// The round-off floor is `ROUND_OFF_FACTOR` ε · (W's largest diagonal entry) · ‖λ‖∞, and 0
/// where that is above `ROUND_OFF_CAP` times the largest |q_r| (docs/contact.md §"Newton
/// solver", "Large impulses"): one contact whose W has diagonal (1000, 2000, 500) kg⁻¹ (a light body:
/// far from 1, so that a floor dividing by the diagonal, or ignoring it, is told apart), λ with
/// largest entry 5 N·s. Equal to 1e-15 relative (the diagonal is recovered from the residual's
/// scaled floor, which may round). Kills `newton/mod.rs:149:49` (`*` → `/`: 64 ε λ / d).
#[test]
fn the_round_off_floor_scales_with_the_largest_diagonal_and_impulse_below_its_cap() {
    use rigidref::solve::newton::{ROUND_OFF_CAP, ROUND_OFF_FACTOR};
    let w = Matrix3::new(1000.0, 10.0, 0.0, 10.0, 2000.0, 5.0, 0.0, 5.0, 500.0);
    let problem = super::local_solve_problem(
        w,
        SVector::from([-1.0, 0.4, -0.2]),
        0.5,
        FrictionModel::Cone,
    )
    .to_local();
    let lambda = [SVector::from([3.0, -5.0, 1.0])];
    let expected = ROUND_OFF_FACTOR * f64::EPSILON * 2000.0 * 5.0;
    let floor = round_off_floor(&problem, &lambda);
    assert!(
        (floor - expected).abs() <= 1e-15 * expected,
        "{floor:e} against {expected:e}"
    );
    // Above the cap (1e-6 × max |q| = 1e-6 m/s): impulses of 1e7 N·s give 64 ε · 2000 · 1e7
    // ≈ 2.8e-4 m/s, which is the size of λ going wrong, not rounding: no floor.
    assert!(ROUND_OFF_FACTOR * f64::EPSILON * 2000.0 * 1e7 > ROUND_OFF_CAP);
    assert_eq!(
        round_off_floor(&problem, &[SVector::from([1e7, 0.0, 0.0])]),
        0.0
    );
}

/// Where b (q) is zero everywhere, the regularisation's velocity scale is 1 m/s, not max|b| = 0
/// (docs/contact.md §"Newton solver", **Regularisation following ‖F‖**): ε = c (‖F‖∞ / 1)^δ,
/// which vanishes as Newton converges. From a start off the answer λ = 0 (every contact pressed
/// and sliding), regularised Newton reaches it within a few iterations, as plain Newton does; a
/// scale of 0 would make ε the largest allowed at every iteration, a gradient step of length
/// about ‖F‖ / (ε W_rr), and the runs would creep.
#[test]
fn regularised_newton_on_a_zero_b_starts_from_a_unit_velocity_scale() {
    let most = RefCell::new(0);
    proptest!(common::seeded(40), |(s in physical_spec(1..4, 1..6), mu in 0.05..0.8f64)| {
        let mut problem = compliant_cone(&s, mu);
        for c in &mut problem.contacts {
            c.q = SVector::zeros();
            c.lambda0 = SVector::<f64, 3>::new(2.0, 0.3 * mu, -0.2 * mu);
        }
        for settings in [
            NewtonSettings::default(),
            NewtonSettings {
                regularisation: Some(Regularisation::MEASURED),
                ..NewtonSettings::default()
            },
        ] {
            let mut lambda = Vec::new();
            let report = solve_newton_local(&problem, &settings, &mut lambda);
            prop_assert!(report.converged, "{settings:?}: {report:?}");
            // 10: measured at most 8 over these cases, plain or regularised; with a zero
            // scale the regularised runs took 14 (they converge, but creep).
            prop_assert!(report.iterations <= 10, "{settings:?}: {report:?}");
            let largest = most.borrow().max(report.iterations);
            *most.borrow_mut() = largest;
        }
    });
    eprintln!("at most {} iterations", most.borrow());
}
