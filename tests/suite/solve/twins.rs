//! Near-duplicate contacts left out (docs/contact.md §"Near-duplicate contacts left out"):
//! the law at a contact left out, the reduced problem, the pairs found, the swap of a wrong
//! first choice, and RockPile_tob1 solved from λ = 0 by `rigidref solve-problems`' newton-twins.

use crate::common;

use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use proptest::prelude::*;
use rigidref::problem::siconos::{AnyLocalProblem, read_dat};
use rigidref::problem::{FrictionModel, LocalProblem, ProblemView, RowBounds};
use rigidref::solve::residual::{coulomb_residual, residual};
use rigidref::solve::residual::{siconos_error, siconos_error_measures, siconos_share};
use rigidref::solve::solve_newton_local_until;
use rigidref::solve::twins::{
    TwinSettings, first_choice, solve_twins_local_until, solve_without_twins, twin_pairs,
};
use rigidref::tools::experiments::problem_library::{
    LibrarySettings, LibrarySolver, attempt, library_error,
};

/// A contact with zero impulse satisfies the law (its term of Siconos' error is zero) exactly
/// where its normal velocity is ≥ 0, whatever μ and the tangential velocity: the argument that
/// makes an answer of the reduced problem, extended by zeros, exact for the whole one. Exact
/// ties included (w_n = +0 and −0, the smallest positive subnormal), 3D and 2D. In floating
/// point a negative w_n is seen where it is not lost to rounding: ŵ_n = w_n + μ‖w_T‖ absorbs a
/// w_n below half an ulp of μ‖w_T‖, and the term, a square, underflows below 1.5e-154; so the
/// negative cases are −1e-6 and −1 m/s, and −1e-150 without tangential velocity.
#[test]
fn a_contact_with_zero_impulse_satisfies_the_law_exactly_where_it_does_not_approach() {
    let edges = [0.0, -0.0, 5e-324, 1e-300, -1e-6, -1.0];
    let law3 =
        |mu: f64, w: SVector<f64, 3>| siconos_share(RowBounds::Contact, mu, &SVector::zeros(), &w);
    let law2 =
        |mu: f64, w: SVector<f64, 2>| siconos_share(RowBounds::Contact, mu, &SVector::zeros(), &w);
    for &wn in &edges {
        for mu in [0.0, 0.3, 1.0, 7.0] {
            for wt in [0.0, 1e-9, 2.5] {
                let share = law3(mu, nalgebra::Vector3::new(wn, wt, -wt));
                assert_eq!(
                    share == 0.0,
                    wn >= 0.0,
                    "3D μ {mu}, w_n {wn:e}, w_T {wt}: {share}"
                );
                let share = law2(mu, nalgebra::Vector2::new(wn, wt));
                assert_eq!(
                    share == 0.0,
                    wn >= 0.0,
                    "2D μ {mu}, w_n {wn:e}, w_T {wt}: {share}"
                );
            }
        }
    }
    assert!(law3(1.0, nalgebra::Vector3::new(-1e-150, 0.0, 0.0)) > 0.0);
    proptest!(common::seeded(500), |(
        mu in 0.0f64..3.0,
        w in prop::array::uniform3(-10.0f64..10.0),
    )| {
        let share = law3(mu, SVector::from(w));
        prop_assert_eq!(share == 0.0, w[0] >= 0.0, "μ {} w {:?}: {}", mu, w, share);
    });
}

/// A random problem of `n` contacts with W = H M⁻¹ Hᵀ (one 6-dof body per pair of contacts, so
/// that W is coupled and singular like a real one).
fn random_problem(n: usize, seed: u64) -> (LocalProblem<3>, DMatrix<f64>, DVector<f64>) {
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let h = DMatrix::from_fn(3 * n, 6, |_, _| next());
    let w = &h * h.transpose() + DMatrix::identity(3 * n, 3 * n) * 0.1;
    let q = DVector::from_fn(3 * n, |_, _| next());
    let mu: Vec<f64> = (0..n).map(|k| 0.2 + 0.1 * k as f64).collect();
    let problem = LocalProblem::from_dense(FrictionModel::Cone, &w, &q, &mu).unwrap();
    (problem, w, q)
}

/// The reduced problem is the whole one's rows and columns of the contacts kept, in order, with
/// their q and μ and the start given; and its velocities are the whole problem's where the
/// contacts left out carry nothing (to the bit: the same products summed in the same order,
/// with the left-out terms zero).
#[test]
fn the_problem_without_some_contacts_is_the_others_rows_and_columns_of_w() {
    let (problem, w, q) = random_problem(6, 7);
    let left_out = [false, true, false, false, true, false];
    let start: Vec<SVector<f64, 3>> = (0..6).map(|k| SVector::repeat(k as f64)).collect();
    let (reduced, kept) = problem.without(&left_out, &start);
    assert_eq!(kept, vec![0, 2, 3, 5]);
    let rows: Vec<usize> = kept.iter().flat_map(|&k| 3 * k..3 * k + 3).collect();
    let w_kept = DMatrix::from_fn(12, 12, |i, j| w[(rows[i], rows[j])]);
    assert_eq!(reduced.dense_w(), w_kept);
    assert_eq!(reduced.dense_q(), DVector::from_fn(12, |i, _| q[rows[i]]));
    for (i, &k) in kept.iter().enumerate() {
        assert_eq!(reduced.contacts[i].mu, problem.contacts[k].mu);
        assert_eq!(reduced.contacts[i].lambda0, start[k]);
    }
    reduced.validate().unwrap();
    let part: Vec<SVector<f64, 3>> = (0..4)
        .map(|i| nalgebra::Vector3::new(1.0 + i as f64, 0.1, -0.2))
        .collect();
    let mut full = vec![SVector::zeros(); 6];
    for (i, &k) in kept.iter().enumerate() {
        full[k] = part[i];
    }
    let (w_part, w_full) = (reduced.velocity(&part), problem.velocity(&full));
    for (i, &k) in kept.iter().enumerate() {
        assert_eq!(w_part[i], w_full[k]);
    }
    let nothing = problem.without(&[false; 6], &start).0;
    assert_eq!(nothing.dense_w(), w);
}

/// One point mass (1 kg) on the ground, touched twice at the same point ("twins": the same
/// normal row of W, W = [[I, I], [I, I]], singular): contact 0 approaches at 1 m/s and slides
/// at 0.2 m/s, contact 1 the same but δ = 1e-6 m/s slower in the normal. The one exact answer
/// loads contact 0 (λ = (1, −0.2, 0) N·s: sticking, μ = 1) and leaves contact 1 with w_n = δ.
fn twin_point() -> LocalProblem<3> {
    let i = SMatrix::<f64, 3, 3>::identity();
    let mut w = DMatrix::zeros(6, 6);
    for (r, c) in [(0, 0), (0, 3), (3, 0), (3, 3)] {
        w.fixed_view_mut::<3, 3>(r, c).copy_from(&i);
    }
    let q = DVector::from_vec(vec![-1.0, 0.2, 0.0, -1.0 + 1e-6, 0.2, 0.0]);
    LocalProblem::from_dense(FrictionModel::Cone, &w, &q, &[1.0, 1.0]).unwrap()
}

/// The pairs are found among the contacts that carry the error, each with the contact whose
/// normal row is parallel: the point's twins at an answer that loads the wrong one; none where
/// the error is zero; none on a random problem whose rows are not parallel; and never a joint.
#[test]
fn twin_pairs_are_the_contacts_carrying_the_error_with_a_parallel_normal_row() {
    let problem = twin_point();
    // Contact 1 loaded: contact 0 would penetrate at δ.
    let wrong = vec![
        SVector::zeros(),
        nalgebra::Vector3::new(1.0 - 1e-6, -0.2, 0.0),
    ];
    assert!(siconos_error(&problem, &wrong) > 0.0);
    assert_eq!(twin_pairs(&problem, &wrong, 0.99, 1e-8), vec![(0, 1)]);
    let right = vec![nalgebra::Vector3::new(1.0, -0.2, 0.0), SVector::zeros()];
    assert_eq!(siconos_error(&problem, &right), 0.0);
    assert!(twin_pairs(&problem, &right, 0.99, 1e-8).is_empty());
    let mut joint = problem.clone();
    joint.contacts[1].bounds = RowBounds::Free;
    assert!(twin_pairs(&joint, &wrong, 0.99, 1e-8).is_empty());
    let (random, _, _) = random_problem(6, 3);
    let zero = vec![SVector::zeros(); 6];
    assert!(siconos_error(&random, &zero) > 0.0);
    assert!(twin_pairs(&random, &zero, 1.0, 1e-8).is_empty());
}

/// The pairs are looked for among the largest terms of the error until they make up `share`
/// of it, and each contact is paired once: two point masses at rest, the first touched three
/// times at one point (contacts 0–2, q_n = −0.3 m/s, the second and third 1 and 2 µm/s slower),
/// the second twice (contacts 3–4, q_n = −0.1 m/s); at λ = 0 the terms are q_n², 0.29 in all.
/// - share 1: (0, 1) and (3, 4); contact 1, paired, is not paired again with 2, and 2 has no
///   unpaired twin left;
/// - share 0.3: contact 0's term (0.09) is already 0.3 of the total, so only (0, 1);
/// - contact 3 a joint (its term ‖w‖² is not zero): it is never paired, with share 1.
#[test]
fn twin_pairs_take_the_largest_terms_up_to_the_share_and_pair_each_contact_once() {
    let mut w = DMatrix::zeros(15, 15);
    for (lo, hi) in [(0, 2), (3, 4)] {
        for a in lo..=hi {
            for b in lo..=hi {
                w.fixed_view_mut::<3, 3>(3 * a, 3 * b)
                    .copy_from(&SMatrix::<f64, 3, 3>::identity());
            }
        }
    }
    let qn = [-0.3, -0.3 + 1e-6, -0.3 + 2e-6, -0.1, -0.1 + 1e-6];
    let q = DVector::from_iterator(15, qn.iter().flat_map(|&n| [n, 0.0, 0.0]));
    let problem = LocalProblem::from_dense(FrictionModel::Cone, &w, &q, &[0.5; 5]).unwrap();
    let zero = vec![SVector::<f64, 3>::zeros(); 5];
    let total: f64 = qn.iter().map(|n| n * n).sum();
    assert!((total - 0.29).abs() < 1e-5);
    assert_eq!(twin_pairs(&problem, &zero, 1.0, 1e-8), vec![(0, 1), (3, 4)]);
    assert_eq!(twin_pairs(&problem, &zero, 0.3, 1e-8), vec![(0, 1)]);
    let mut joint = problem.clone();
    joint.contacts[3].bounds = RowBounds::Free;
    assert!(siconos_share(RowBounds::Free, 0.5, &zero[3], &joint.velocity(&zero)[3]) > 0.0);
    assert_eq!(twin_pairs(&joint, &zero, 1.0, 1e-8), vec![(0, 1)]);
}

/// Two contacts' normal rows are compared over the blocks both have, whatever blocks only one
/// of them has: twins 1 and 2 (the same normal row of W) where only contact 2's block row holds
/// a block with contact 0 (W₂₀ couples contact 0's normal impulse to contact 2's first
/// tangent, 0.1 kg⁻¹; W₁₀ = 0, so contact 1's row has no such block). W is symmetric positive
/// semi-definite (eigenvalues 0 to 2.1). With share ½ only the twin with the larger term looks
/// for its pair; each twin in turn carries it, so the sparse rows are walked both ways (one
/// starts before the other); both find the pair (1, 2).
#[test]
fn twin_rows_are_compared_over_their_common_blocks_whatever_blocks_only_one_has() {
    let identity = SMatrix::<f64, 3, 3>::identity();
    let mut softer = identity;
    softer[(1, 1)] = 1.1;
    softer[(2, 2)] = 1.1;
    let mut coupling = SMatrix::<f64, 3, 3>::zeros();
    coupling[(1, 0)] = 0.1;
    let mut w = DMatrix::zeros(9, 9);
    for (r, c, block) in [
        (0, 0, identity),
        (1, 1, softer),
        (2, 2, softer),
        (1, 2, identity),
        (2, 1, identity),
        (2, 0, coupling),
        (0, 2, coupling.transpose()),
    ] {
        w.fixed_view_mut::<3, 3>(3 * r, 3 * c).copy_from(&block);
    }
    for (first, second) in [(-1.0, -1.0 + 1e-6), (-1.0, -1.0 - 1e-6)] {
        // Contact 0 separates (its term is zero); the twins approach.
        let q = DVector::from_vec(vec![1.0, 0.0, 0.0, first, 0.0, 0.0, second, 0.0, 0.0]);
        let problem = LocalProblem::from_dense(FrictionModel::Cone, &w, &q, &[0.5; 3]).unwrap();
        let rows: Vec<Vec<usize>> = problem
            .contacts
            .iter()
            .map(|c| c.row.iter().map(|(j, _)| *j).collect())
            .collect();
        assert_eq!(rows, vec![vec![0, 2], vec![1, 2], vec![0, 1, 2]]);
        let zero = vec![SVector::<f64, 3>::zeros(); 3];
        assert_eq!(
            twin_pairs(&problem, &zero, 0.5, 1e-8),
            vec![(1, 2)],
            "q {q:?}"
        );
    }
}

/// A wrong first choice is corrected: leaving out the loaded twin (contact 0), the reduced
/// answer loads contact 1 and contact 0 ends approaching (w_n = −δ < 0), so the pair swaps and
/// the second round leaves out contact 1: solved on the whole problem (each round stops where
/// the whole problem's error is at most the tolerance, 1e-8).
#[test]
fn a_twin_left_out_that_would_penetrate_swaps_with_its_twin() {
    let problem = twin_point();
    let settings = TwinSettings::default();
    let mut error = |l: &[SVector<f64, 3>]| siconos_error(&problem, l);
    let mut lambda = Vec::new();
    let zero = vec![SVector::zeros(); 2];
    let done = solve_without_twins(
        &problem,
        &settings,
        &[(0, 1)],
        vec![0],
        &zero,
        &mut error,
        &mut lambda,
    );
    assert_eq!(done.rounds, 2);
    assert_eq!(done.left_out, vec![1]);
    assert!(done.error <= settings.tolerance, "error {:e}", done.error);
    assert_eq!(done.error, siconos_error(&problem, &lambda));
    assert_eq!(lambda[1], SVector::<f64, 3>::zeros());
    assert!((lambda[0] - nalgebra::Vector3::new(1.0, -0.2, 0.0)).norm() <= 1e-7);
    let w = problem.velocity(&lambda);
    assert!(w[1][0] > 0.0, "contact 1 separates: w_n = {}", w[1][0]);
    // Every round's iterations together (each round at least one).
    assert_eq!(done.iterations(), done.report.iterations);
    assert!((2..1000).contains(&done.report.iterations), "{done:?}");
    // Held to one round, the wrong choice is all there is: contact 0 left out, the answer
    // better than the start (zero) but not solved (contact 0 approaches at −δ).
    let one_round = TwinSettings {
        rounds: 1,
        ..TwinSettings::default()
    };
    let mut error = |l: &[SVector<f64, 3>]| siconos_error(&problem, l);
    let held = solve_without_twins(
        &problem,
        &one_round,
        &[(0, 1)],
        vec![0],
        &zero,
        &mut error,
        &mut lambda,
    );
    assert_eq!(
        (held.rounds, held.left_out.clone()),
        (1, vec![0]),
        "{held:?}"
    );
    assert!(held.error > one_round.tolerance && held.error < siconos_error(&problem, &zero));
    assert!(problem.velocity(&lambda)[0][0] < 0.0);
    // Starting from the right choice takes one round.
    let mut error = |l: &[SVector<f64, 3>]| siconos_error(&problem, l);
    let once = solve_without_twins(
        &problem,
        &settings,
        &[(0, 1)],
        vec![1],
        &zero,
        &mut error,
        &mut lambda,
    );
    assert_eq!((once.rounds, once.left_out), (1, vec![1]));
}

/// The whole procedure on the twin point: exact, whichever path (Newton alone may solve so
/// small a problem), and the same bits twice.
#[test]
fn newton_twins_solves_the_twin_point_exactly_and_reproducibly() {
    let problem = twin_point();
    let run = || {
        let mut error = |l: &[SVector<f64, 3>]| siconos_error(&problem, l);
        let mut lambda = Vec::new();
        let report =
            solve_twins_local_until(&problem, &TwinSettings::default(), &mut error, &mut lambda);
        (report, lambda)
    };
    let (report, lambda) = run();
    assert!(siconos_error(&problem, &lambda) <= 1e-8, "{report:?}");
    let w = problem.velocity(&lambda);
    assert!(w.iter().all(|w| w[0] >= -1e-12), "{w:?}");
    let (again, lambda_again) = run();
    assert_eq!(report, again);
    assert_eq!(lambda, lambda_again);
    // Solved by the first run (no restart, no pair): the report counts that one run and its
    // iterations, as Newton alone reports them with the same stop rule.
    let mut stop = |l: &[SVector<f64, 3>]| siconos_error(&problem, l) <= 1e-8;
    let mut alone = Vec::new();
    let newton = solve_newton_local_until(
        &problem,
        &TwinSettings::default().newton,
        &mut stop,
        &mut alone,
    );
    assert_eq!((report.whole_runs, report.rounds), (1, 0));
    assert!(report.pairs.is_empty() && report.left_out.is_empty());
    assert!(newton.iterations > 0);
    assert_eq!(report.iterations, newton.iterations);
    assert_eq!(report.report.iterations, newton.iterations);
    assert_eq!(lambda, alone);
    // As `rigidref solve-problems --solver newton-twins` runs it.
    let a = attempt(
        &problem,
        LibrarySolver::NewtonTwins,
        &LibrarySettings::default(),
    );
    assert!(a.converged && a.error <= 1e-8, "{a:?}");
    assert_eq!(a.solver.name(), "newton-twins");
}

/// A restart that improves without solving is kept, and the next restart starts from it: on the
/// twin point with each Newton run held to one iteration and no proximal subproblem, the first
/// run and its restart stall and the third run, from the restart's answer, solves the whole
/// problem, so nothing is left out. With one restart the same start goes on to the reduction
/// (contact 1 left out), which shows the third run is what solved it. Kills the mutant
/// `twins.rs:101:61` (`e < b` → `e == b`: an improving restart is not kept and ends the
/// restarts), which reduces after two runs.
#[test]
fn an_improving_restart_is_kept_and_restarted_from() {
    let problem = twin_point();
    let held = |restarts| TwinSettings {
        newton: rigidref::solve::NewtonSettings {
            max_iterations: 1,
            proximal_iterations: 0,
            ..Default::default()
        },
        restarts,
        ..TwinSettings::default()
    };
    let run = |settings: &TwinSettings| {
        let mut error = |l: &[SVector<f64, 3>]| siconos_error(&problem, l);
        let mut lambda = Vec::new();
        let report = solve_twins_local_until(&problem, settings, &mut error, &mut lambda);
        (report, lambda)
    };
    let (once, once_lambda) = run(&held(1));
    assert_eq!(once.whole_runs, 2, "{once:?}");
    assert_eq!(
        (once.pairs.clone(), once.left_out.clone(), once.rounds),
        (vec![(0, 1)], vec![1], 1),
        "the first choice (contact 1, moving apart faster) is right: one round"
    );
    // The report after a reduction: every stage's iterations together (the two whole runs, as
    // Newton alone reports them, and the reduction's), and the residuals and `converged` of
    // the whole problem at the answer returned, not the reduced run's.
    let settings = held(1);
    let mut error = |l: &[SVector<f64, 3>]| siconos_error(&problem, l);
    let (mut first, mut second, mut reduced) = (Vec::new(), Vec::new(), Vec::new());
    let mut stop = |l: &[SVector<f64, 3>]| siconos_error(&problem, l) <= 1e-8;
    let r1 = solve_newton_local_until(&problem, &settings.newton, &mut stop, &mut first);
    let from_first = problem.without(&[false; 2], &first).0;
    let r2 = solve_newton_local_until(&from_first, &settings.newton, &mut stop, &mut second);
    assert!(siconos_error(&problem, &second) < siconos_error(&problem, &first));
    let reduction = solve_without_twins(
        &problem,
        &settings,
        &[(0, 1)],
        vec![1],
        &second,
        &mut error,
        &mut reduced,
    );
    assert_eq!(reduced, once_lambda);
    let expected = r1.iterations + r2.iterations + reduction.report.iterations;
    println!(
        "iterations: {} + {} + {} = {expected}, reported {}",
        r1.iterations, r2.iterations, reduction.report.iterations, once.iterations
    );
    assert_eq!(once.iterations, expected);
    assert_eq!(once.report.iterations, expected);
    let whole = residual(&problem, &once_lambda);
    assert_eq!(once.report.residual, whole);
    assert!(whole <= settings.newton.tolerance, "{whole:e}");
    assert!(once.report.converged);
    assert_eq!(
        once.report.coulomb_residual,
        Some(coulomb_residual(&problem, &once_lambda))
    );
    let (twice, lambda) = run(&held(2));
    assert_eq!(twice.whole_runs, 3, "{twice:?}");
    assert!(
        twice.left_out.is_empty() && twice.pairs.is_empty(),
        "{twice:?}"
    );
    assert!(siconos_error(&problem, &lambda) <= 1e-8);
}

/// The first choice leaves out, of each pair, the contact moving apart faster (the larger
/// w_n), and on an exact tie the later one: pairs with w_n (1, 0), (0, 1), (0.5, 0.5) and
/// (−0, +0) (equal: a tie).
#[test]
fn the_first_choice_leaves_out_the_twin_moving_apart_faster_and_the_later_on_a_tie() {
    let w: Vec<SVector<f64, 3>> = [1.0, 0.0, 0.0, 1.0, 0.5, 0.5, -0.0, 0.0]
        .iter()
        .map(|&n| nalgebra::Vector3::new(n, 0.3, -0.1))
        .collect();
    let pairs = [(0, 1), (2, 3), (4, 5), (6, 7)];
    assert_eq!(first_choice(&pairs, &w), vec![0, 3, 5, 7]);
}

/// Every stage is judged by the caller's error, and only by it: an error of exactly the
/// tolerance everywhere is solved at the first run (no restart, no pairs, no round); an error
/// that never changes (1 everywhere) makes the first restart no better, which ends the
/// restarts (2 whole runs of the 6 allowed), and no reduced answer is better, so nothing is
/// left out and the first run's answer is returned.
#[test]
fn the_caller_s_error_decides_every_stage() {
    let problem = twin_point();
    let settings = TwinSettings {
        restarts: 5,
        ..TwinSettings::default()
    };
    let mut at_tolerance = |_: &[SVector<f64, 3>]| settings.tolerance;
    let mut lambda = Vec::new();
    let solved = solve_twins_local_until(&problem, &settings, &mut at_tolerance, &mut lambda);
    assert_eq!((solved.whole_runs, solved.rounds), (1, 0), "{solved:?}");
    assert!(solved.pairs.is_empty() && solved.left_out.is_empty());
    let mut constant = |_: &[SVector<f64, 3>]| 1.0;
    let stalled = solve_twins_local_until(&problem, &settings, &mut constant, &mut lambda);
    assert_eq!(stalled.whole_runs, 2, "{stalled:?}");
    assert!(stalled.left_out.is_empty());
    let mut never = |_: &[SVector<f64, 3>]| false;
    let mut first = Vec::new();
    solve_newton_local_until(&problem, &settings.newton, &mut never, &mut first);
    assert_eq!(lambda, first);
}

/// The rounds are judged by the caller's error too (`solve_without_twins` alone, contact 1 left
/// out of the twin point from λ = 0):
/// - an error of exactly the tolerance at the start: no round;
/// - an error of 1 everywhere: a round runs (its reduced problem solved to Newton's own
///   tolerance), its answer is no better, so nothing is left out and λ stays the start;
/// - on exact twins (δ = 0), started from the exact answer (contact 0 carrying (1, −0.2, 0)),
///   the contact left out ends with w_n = 0 exactly: not approaching, so it does not swap (one
///   round, where a swap would try the other choice);
/// - sliding on a coupled body (q_t = 2 m/s, μ = 0.3: the reduced problem takes several Newton
///   iterations), an error that reaches the tolerance once contact 0 carries anything stops
///   the round after its first iteration, before the reduced problem is solved.
#[test]
fn the_rounds_are_judged_by_the_caller_s_error() {
    // W = [[A, A], [A, A]]: the point's (A = I), or a body whose contact couples its normal
    // and tangential impulses (A symmetric positive definite, eigenvalues 0.27 to 1.71).
    let coupled = SMatrix::<f64, 3, 3>::new(1.0, 0.6, 0.2, 0.6, 1.0, 0.1, 0.2, 0.1, 0.5);
    let point = |delta: f64, slide: f64, mu: f64, a: SMatrix<f64, 3, 3>| {
        let mut w = DMatrix::zeros(6, 6);
        for (r, c) in [(0, 0), (0, 3), (3, 0), (3, 3)] {
            w.fixed_view_mut::<3, 3>(r, c).copy_from(&a);
        }
        let q = DVector::from_vec(vec![-1.0, slide, 0.0, -1.0 + delta, slide, 0.0]);
        LocalProblem::from_dense(FrictionModel::Cone, &w, &q, &[mu, mu]).unwrap()
    };
    let settings = TwinSettings::default();
    let zero = vec![SVector::<f64, 3>::zeros(); 2];
    let mut lambda = Vec::new();
    let reduce = |problem: &LocalProblem<3>,
                  error: &mut dyn FnMut(&[SVector<f64, 3>]) -> f64,
                  lambda: &mut Vec<SVector<f64, 3>>| {
        solve_without_twins(problem, &settings, &[(0, 1)], vec![1], &zero, error, lambda)
    };
    let problem = twin_point();
    let none = reduce(&problem, &mut |_| settings.tolerance, &mut lambda);
    assert_eq!((none.rounds, none.left_out), (0, vec![]));
    let mut last = Vec::new();
    let mut constant = |l: &[SVector<f64, 3>]| {
        last = l.to_vec();
        1.0
    };
    let no_better = reduce(&problem, &mut constant, &mut lambda);
    assert_eq!((no_better.rounds, no_better.left_out), (1, vec![]));
    assert_eq!(lambda, zero);
    assert!(residual(&problem, &last) <= settings.newton.tolerance);
    let exact_twins = point(0.0, 0.2, 1.0, SMatrix::identity());
    let mut constant = |l: &[SVector<f64, 3>]| {
        last = l.to_vec();
        1.0
    };
    let exact = vec![nalgebra::Vector3::new(1.0, -0.2, 0.0), SVector::zeros()];
    let tie = solve_without_twins(
        &exact_twins,
        &settings,
        &[(0, 1)],
        vec![1],
        &exact,
        &mut constant,
        &mut lambda,
    );
    assert_eq!(exact_twins.velocity(&last)[1][0], 0.0, "{last:?}");
    assert_eq!(tie.rounds, 1, "{tie:?}");
    let sliding = point(1e-6, 2.0, 0.3, coupled);
    let mut error = |l: &[SVector<f64, 3>]| siconos_error(&sliding, l);
    let solved = reduce(&sliding, &mut error, &mut lambda);
    assert_eq!(solved.left_out, vec![1]);
    assert!(solved.report.iterations > 1, "{solved:?}");
    let mut carried = |l: &[SVector<f64, 3>]| {
        if l[0] == SVector::<f64, 3>::zeros() {
            1.0
        } else {
            settings.tolerance
        }
    };
    let early = reduce(&sliding, &mut carried, &mut lambda);
    assert_eq!((early.rounds, early.left_out.clone()), (1, vec![1]));
    assert_eq!(early.report.iterations, 1, "{early:?}");
    assert!(residual(&sliding, &lambda) > settings.newton.tolerance);
}

/// The report after a reduction is the whole problem's, the contacts left out included: twins
/// whose normal rows are parallel but of different lengths (W = v vᵀ ⊗ I, v = (1, 2)), each
/// Newton run held to its start (no iteration), both contacts loaded at the start (contact 0
/// with 1 N·s, which alone solves the problem without contact 1; contact 1 with 0.3), and a
/// caller's error met only where contact 1 carries nothing and contact 0 does. Contact 1 (w_n
/// 0.7 against 0.6 m/s at the start) is left out; the round stops at once and its answer is
/// kept: contact 0 exactly at rest (w_n = 0: the reduced problem solved, its own residual 0),
/// contact 1, left out, approaching at 0.5 m/s: the whole problem's residual 0.5, not converged.
#[test]
fn the_report_after_a_reduction_counts_the_contacts_left_out() {
    let mut w = DMatrix::zeros(6, 6);
    let v = [1.0, 2.0];
    for a in 0..2 {
        for b in 0..2 {
            w.fixed_view_mut::<3, 3>(3 * a, 3 * b)
                .copy_from(&(SMatrix::<f64, 3, 3>::identity() * (v[a] * v[b])));
        }
    }
    let q = DVector::from_vec(vec![-1.0, 0.0, 0.0, -2.5, 0.0, 0.0]);
    let mut problem = LocalProblem::from_dense(FrictionModel::Cone, &w, &q, &[0.5, 0.5]).unwrap();
    problem.contacts[0].lambda0 = nalgebra::Vector3::new(1.0, 0.0, 0.0);
    problem.contacts[1].lambda0 = nalgebra::Vector3::new(0.3, 0.0, 0.0);
    let settings = TwinSettings {
        newton: rigidref::solve::NewtonSettings {
            max_iterations: 0,
            proximal_iterations: 0,
            ..Default::default()
        },
        restarts: 0,
        ..TwinSettings::default()
    };
    let zero = SVector::<f64, 3>::zeros();
    let mut error = |l: &[SVector<f64, 3>]| {
        if l[1] == zero && l[0] != zero {
            settings.tolerance
        } else {
            1.0
        }
    };
    let mut lambda = Vec::new();
    let report = solve_twins_local_until(&problem, &settings, &mut error, &mut lambda);
    assert_eq!(
        (report.pairs.clone(), report.left_out.clone()),
        (vec![(0, 1)], vec![1])
    );
    let wv = problem.velocity(&lambda);
    assert_eq!((wv[0][0], wv[1][0]), (0.0, -0.5));
    let whole = residual(&problem, &lambda);
    assert_eq!(whole, 0.5);
    assert_eq!(report.report.residual, whole);
    assert!(!report.report.converged);
    assert_eq!(
        report.report.coulomb_residual,
        Some(coulomb_residual(&problem, &lambda))
    );
}

/// RockPile_tob1 (463 contacts, μ = 1), which no other solver of rigidref's or Siconos' solves
/// (docs/problem-library.md §"RockPile_tob1"), solved from λ = 0 by `solve-problems`'
/// newton-twins as `rigidref solve-problems --solver newton-twins` runs it: to 1e-8 in
/// Siconos' measure and in the ‖q‖-normalised one (‖q‖ = 399.5 m/s, so the absolute error is
/// at most 4e-6), with three contacts left out, one of each near-duplicate pair, each ending
/// with w_n ≥ 0 (to the 1e-8 the answer is accepted at: −4e-6 m/s at most) and zero impulse.
#[test]
fn newton_twins_solves_rockpile_from_zero_leaving_out_one_contact_of_each_stalled_pair() {
    let path = common::project_root().join("tests/data/siconos_hard/RockPile_tob1.dat");
    let problem = match read_dat(&path).unwrap() {
        AnyLocalProblem::Three(p) => p,
        AnyLocalProblem::Two(_) => panic!("RockPile is a 3D problem"),
    };
    // The settings `rigidref solve-problems` gives it (its attempt() builds the same).
    let library = LibrarySettings::default();
    let settings = TwinSettings {
        newton: rigidref::solve::NewtonSettings {
            max_iterations: library.newton_iterations,
            ..Default::default()
        },
        tolerance: library.tolerance,
        ..TwinSettings::default()
    };
    let mut error = |l: &[SVector<f64, 3>]| library_error(&problem, l);
    let mut lambda = Vec::new();
    let started = std::time::Instant::now();
    let report = solve_twins_local_until(&problem, &settings, &mut error, &mut lambda);
    let measures = siconos_error_measures(&problem, &lambda);
    println!(
        "RockPile, newton-twins: {} iterations, {:.1} s, error {:.2e} (‖q‖-normalised {:.2e}, \
         absolute {:.2e}), pairs {:?}, without {:?} after {} rounds",
        report.iterations,
        started.elapsed().as_secs_f64(),
        measures.relative(),
        measures.q_normalised(),
        measures.absolute,
        report.pairs,
        report.left_out,
        report.rounds
    );
    assert!(measures.relative() <= 1e-8 && measures.q_normalised() <= 1e-8);
    assert!(measures.absolute <= 1e-8 * 399.6);
    assert_eq!(report.whole_runs, 2, "the first run and one restart");
    assert_eq!(report.left_out.len(), 3, "one of each of three pairs");
    // The report's residuals are the whole problem's at the answer, the contacts left out
    // included, not the reduced run's.
    let whole = residual(&problem, &lambda);
    println!(
        "rigidref's residual: whole problem {whole:.3e} m/s, reported {:.3e}",
        report.report.residual
    );
    assert_eq!(report.report.residual, whole);
    assert_eq!(report.report.converged, whole <= settings.newton.tolerance);
    assert_eq!(
        report.report.coulomb_residual,
        Some(coulomb_residual(&problem, &lambda))
    );
    let w = problem.constraint_velocity(&lambda);
    let big_w = problem.dense_w();
    for &k in &report.left_out {
        println!("contact {k} left out: w_n = {:.2e} m/s", w[k][0]);
        assert_eq!(
            lambda[k],
            SVector::<f64, 3>::zeros(),
            "contact {k} carries nothing"
        );
        assert!(w[k][0] >= -4e-6, "contact {k}: w_n = {}", w[k][0]);
        let &(a, b) = report.pairs.iter().find(|p| p.0 == k || p.1 == k).unwrap();
        let twin = if a == k { b } else { a };
        assert!(lambda[twin][0] > 0.0, "its twin {twin} is loaded");
        let (ra, rb) = (big_w.row(3 * k), big_w.row(3 * twin));
        assert!(ra.dot(&rb) / (ra.norm() * rb.norm()) > 1.0 - 1e-8);
    }
}
