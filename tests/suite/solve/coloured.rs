//! The coloured contact order and its threads (docs/contact.md §"Coloured order"): the same
//! solutions as the problem order, bit-identical results for any number of threads, and the
//! problem order (`found`) kept bit for bit.

use crate::common;

use common::problems::{build, spec, tiled};
use nalgebra::SVector;
use proptest::prelude::*;
use rigidref::problem::{ContactProblem3, FrictionModel};
use rigidref::solve::pgs::Lanes;
use rigidref::solve::{ContactOrder, LocalSolve, PgsSettings};

/// [`super::solve_seeded`] from seed 0: λ and the report.
fn solve(
    problem: &ContactProblem3,
    iterations: u32,
    tolerance: Option<f64>,
    order: ContactOrder,
    threads: usize,
) -> (Vec<SVector<f64, 3>>, rigidref::solve::SolveReport) {
    let (lambda, report, _) =
        super::solve_seeded(problem, iterations, tolerance, order, 0, threads);
    (lambda, report)
}

/// On random frictionless problems with a well-conditioned normal block (a unique λ), the
/// coloured order converges to the residual tolerance as the problem order does, to the same λ
/// (within 1e-6 of its scale: both stop at residual 1e-9 m/s, the normal block's condition
/// number is at most 1e3), in the body form and in the local form (coloured by W's couplings); and with two threads every bit of λ and of the report is the one
/// thread's, converged or not (5 and 20 000 sweeps).
#[test]
fn coloured_sweeps_converge_to_the_problem_orders_solution_on_any_number_of_threads() {
    proptest!(common::seeded(200), |(s in spec(2..6, 2..10))| {
        let problem = build(&s, 0.0, 0.0, FrictionModel::Box);
        let a = problem.dense_delassus();
        let normal: Vec<usize> = (0..problem.contacts.len()).map(|k| 3 * k).collect();
        let an = a.select_rows(&normal).select_columns(&normal);
        let eigenvalues = an.symmetric_eigenvalues();
        prop_assume!(eigenvalues.min() > 1e-3 * eigenvalues.max());
        let (found, report) = solve(&problem, 20_000, Some(1e-9), ContactOrder::Sequential, 1);
        prop_assert!(report.converged);
        let (coloured, report) = solve(&problem, 20_000, Some(1e-9), ContactOrder::Coloured, 1);
        prop_assert!(report.converged, "{report:?}");
        let scale = found.iter().map(|l| l.amax()).fold(1e-12, f64::max);
        for (a, b) in found.iter().zip(&coloured) {
            prop_assert!((a - b).amax() <= 1e-6 * scale, "{a} against {b}");
        }
        // The local form (W, q) colours by W's couplings: the same λ again.
        let local = problem.to_local();
        let mut local_lambda = Vec::new();
        let settings = PgsSettings {
            max_iterations: 20_000,
            tolerance: Some(1e-9),
            order: ContactOrder::Coloured,
            local: LocalSolve::Rows,
        };
        let report = rigidref::solve::solve_pgs_local(&local, &settings, 0, &mut local_lambda);
        prop_assert!(report.converged, "local form: {report:?}");
        for (a, b) in found.iter().zip(&local_lambda) {
            prop_assert!((a - b).amax() <= 1e-6 * scale, "local form: {a} against {b}");
        }
        for sweeps in [5, 20_000] {
            let one = solve(&problem, sweeps, Some(1e-9), ContactOrder::Coloured, 1);
            let two = solve(&problem, sweeps, Some(1e-9), ContactOrder::Coloured, 2);
            prop_assert_eq!(&one.0, &two.0);
            prop_assert_eq!(one.1.iterations, two.1.iterations);
            prop_assert_eq!(one.1.residual.to_bits(), two.1.residual.to_bits());
        }
    });
}

/// The records of a run (its trace without the header, which names the overrides).
fn records(dir: &std::path::Path, args: &[&str]) -> String {
    let o = common::rigidref(args, dir);
    common::assert_success(&o);
    let out = args[args.iter().position(|a| *a == "--out").unwrap() + 1];
    let text = std::fs::read_to_string(dir.join(out)).unwrap();
    text.lines().skip(1).collect::<Vec<_>>().join("\n")
}

/// Whole runs: the coloured order on 1 and 2 threads gives bit-identical traces (3D cube_stack
/// and the tapered box_stack, 2D stack and dominoes); `found` is the default problem
/// order, bit for bit (3D `pgs_order`, 2D `order`). These problems are too small for the
/// threads to start (`MIN_CONTACTS_PER_THREAD`), so the two runs also check that the fallback
/// is the same order; the threads themselves are checked on large solves below.
#[test]
fn coloured_runs_are_bit_identical_on_one_and_two_threads_and_found_is_the_default_order() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let root = common::project_root();
    let scene = |name: &str| root.join("scenes").join(name).to_str().unwrap().to_string();
    for (name, key, time) in [
        ("cube_stack.json", "pgs_order", "2"),
        ("box_stack.json", "pgs_order", "2"),
        ("blocks/stack.json", "order", "5"),
        ("blocks/dominoes.json", "order", "20"),
    ] {
        let s = scene(name);
        let coloured = format!("{key}=coloured");
        let one = records(
            dir,
            &[
                "run",
                &s,
                "--time",
                time,
                "-q",
                "--set",
                &coloured,
                "--out",
                "one.jsonl",
            ],
        );
        let two = records(
            dir,
            &[
                "run",
                &s,
                "--time",
                time,
                "-q",
                "--set",
                &coloured,
                "--threads",
                "2",
                "--out",
                "two.jsonl",
            ],
        );
        assert!(
            one == two,
            "{name}: the two-thread run differs from the one-thread run"
        );
        let sequential = format!("{key}=sequential");
        let found = format!("{key}=found");
        let a = records(
            dir,
            &[
                "run",
                &s,
                "--time",
                time,
                "-q",
                "--set",
                &sequential,
                "--out",
                "a.jsonl",
            ],
        );
        let b = records(
            dir,
            &[
                "run", &s, "--time", time, "-q", "--set", &found, "--out", "b.jsonl",
            ],
        );
        assert!(a == b, "{name}: found is not the problem order");
        assert!(
            a != one,
            "{name}: the coloured order changed nothing (not exercised)"
        );
    }
}

/// `cases` random problems with friction (μ 0.5, box; 8 bodies, 10 to 19 contacts), drawn from
/// the runner seeded with `cases` as the threads' tests have always drawn them.
fn friction_problems(cases: u32) -> Vec<ContactProblem3> {
    let mut runner = proptest::test_runner::TestRunner::new(common::seeded(cases));
    let strategy = spec(8..9, 10..20);
    (0..cases)
        .map(|_| {
            let s =
                proptest::strategy::ValueTree::current(&strategy.new_tree(&mut runner).unwrap());
            build(&s, 0.5, 0.0, FrictionModel::Box)
        })
        .collect()
}

/// Solves large enough for the threads (200 disjoint copies of a random problem with friction,
/// 2 000 to 4 000 contacts): two threads run (the workspace says so) and give every bit of the
/// one thread's λ and report, after 3 sweeps and after 200; and every copy's λ is the small
/// problem's own, bit for bit (the copies are independent, and a coloured sweep visits each
/// copy's contacts in the small problem's coloured order).
#[test]
fn two_threads_give_the_one_threads_bits_on_large_coloured_solves() {
    for small in friction_problems(20) {
        let big = tiled(&small, 200);
        for sweeps in [3, 200] {
            let (one, _, one_report, _, one_threads) =
                super::solve_on(&big, sweeps, Lanes::Native, 1);
            let (two, _, two_report, _, two_threads) =
                super::solve_on(&big, sweeps, Lanes::Native, 2);
            assert_eq!(
                (one_threads, two_threads),
                (1, 2),
                "the threads did not run"
            );
            assert!(
                one == two,
                "{sweeps} sweeps: λ differs between 1 and 2 threads"
            );
            // Equal bits prove something only where the impulses are not all zero.
            assert!(
                one.iter().any(|l| l.iter().any(|&v| v != 0.0)),
                "{sweeps} sweeps: every impulse is zero, the comparison would be empty"
            );
            assert_eq!(one_report.iterations, two_report.iterations);
            assert_eq!(one_report.residual.to_bits(), two_report.residual.to_bits());
            let (alone, _) = solve(&small, sweeps, None, ContactOrder::Coloured, 1);
            for (k, l) in two.iter().enumerate() {
                assert_eq!(*l, alone[k % small.contacts.len()], "contact {k}");
            }
        }
    }
}

/// Two threads stop at a tolerance where one thread does: on problems large enough for the
/// threads to run (a random friction problem tiled 200 times), with the tolerance set to the
/// residual one thread reaches after 5 sweeps, both stop after the same number of sweeps (more
/// than one), converged, with the same bits of λ and of the residual. Covers the threaded
/// sweep's own stop test (`pgs_sweep.rs`, `after_sweep`), which the small problems of the test
/// above never reach (their threads do not start); kills the mutant `pgs_sweep.rs:135:86`
/// (`<=` → `>`: stop after the first sweep not converged).
#[test]
fn two_threads_stop_at_the_tolerance_after_the_one_threads_sweeps() {
    for small in friction_problems(5) {
        let big = tiled(&small, 200);
        let (_, five) = solve(&big, 5, None, ContactOrder::Coloured, 1);
        let tolerance = Some(five.residual);
        let (one, one_report, _) =
            super::solve_seeded(&big, 200, tolerance, ContactOrder::Coloured, 0, 1);
        let (two, two_report, workspace) =
            super::solve_seeded(&big, 200, tolerance, ContactOrder::Coloured, 0, 2);
        assert_eq!(workspace.last_threads(), 2, "the threads did not run");
        assert!(
            one_report.converged && two_report.converged,
            "{two_report:?}"
        );
        assert!((2..=5).contains(&one_report.iterations), "{one_report:?}");
        assert_eq!(one_report.iterations, two_report.iterations);
        assert_eq!(one_report.residual.to_bits(), two_report.residual.to_bits());
        assert!(one == two, "λ differs between 1 and 2 threads");
    }
}

/// The threads start exactly where the docs say (`solve_pgs`; docs/contact.md §"Coloured
/// order"): where the problem has at least `MIN_CONTACTS_PER_THREAD` contacts per thread and
/// colour. Random friction problems tiled 1, 2, 3, … times (the copies are disjoint, so the
/// colour count is the small problem's) up to past that size, solved on two threads: the
/// workspace reports two threads at every size at or above 64 × 2 × colours contacts and one
/// below; each problem has more than one colour, so a threshold that adds the colours instead
/// of multiplying by them starts the threads too early.
#[test]
fn threads_start_at_the_contacts_per_thread_and_colour_the_docs_give() {
    use rigidref::solve::pgs::MIN_CONTACTS_PER_THREAD;
    let settings = PgsSettings {
        max_iterations: 1,
        tolerance: None,
        order: ContactOrder::Coloured,
        local: LocalSolve::Rows,
    };
    let mut below = 0;
    for small in friction_problems(5) {
        for copies in 1.. {
            let problem = tiled(&small, copies);
            let mut workspace = rigidref::solve::PgsWorkspace::new(0);
            workspace.set_threads(2);
            let mut lambda = Vec::new();
            rigidref::solve::solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
            let colours = workspace.colours();
            assert!(colours > 1, "one colour: the test cannot tell × from +");
            let threshold = MIN_CONTACTS_PER_THREAD * 2 * colours;
            let n = problem.contacts.len();
            let expected = if n >= threshold { 2 } else { 1 };
            assert_eq!(
                workspace.last_threads(),
                expected,
                "{n} contacts, {colours} colours (threshold {threshold})"
            );
            below += usize::from(n < threshold && n >= MIN_CONTACTS_PER_THREAD * 2 + colours);
            if n >= threshold + small.contacts.len() {
                break;
            }
        }
    }
    assert!(below > 0, "no size between the two thresholds was tried");
}
