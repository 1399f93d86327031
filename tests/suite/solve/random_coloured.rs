//! The random coloured order (docs/contact.md §"Random coloured order"): every sweep visits
//! every contact once, colour by colour with no moving body shared within a colour; the order
//! is the seed's, the same for the same seed and another for another; its colours' contacts go
//! four at a time, to the same bits on one and two threads; and it converges to the problem
//! order's solution.

use crate::common;

use common::problems::{build, spec, tiled};
use proptest::prelude::*;
use rigidref::problem::{ContactProblem3, FrictionModel};
use rigidref::solve::ContactOrder;
use rigidref::solve::pgs::Lanes;

use super::solve_seeded as solve;

/// A problem of many independent copies of a small random one: enough contacts per colour for
/// groups of four and for two threads.
fn large_problem(seed: u32) -> ContactProblem3 {
    let mut runner = proptest::test_runner::TestRunner::new(common::seeded(seed + 1));
    let strategy = spec(8..9, 10..20);
    let s = proptest::strategy::ValueTree::current(&strategy.new_tree(&mut runner).unwrap());
    tiled(&build(&s, 0.5, 0.0, FrictionModel::Box), 200)
}

/// Each sweep's order is a permutation of the contacts (every contact visited exactly once),
/// made of colours none of whose contacts share a moving body; and the sweeps do not all take
/// the colours in one order (each sweep draws its own).
#[test]
fn random_coloured_sweeps_visit_every_contact_once_colour_by_colour() {
    let problem = large_problem(0);
    let n = problem.contacts.len();
    let (_, report, workspace) = solve(&problem, 5, None, ContactOrder::RandomColoured, 7, 1);
    assert_eq!(report.iterations, 5);
    let moving: Vec<bool> = (problem.bodies.iter())
        .map(|b| b.inverse_mass.iter().any(|&m| m != 0.0))
        .collect();
    let sweeps: Vec<Vec<Vec<usize>>> = (0..5).map(|s| workspace.sweep_colours(s)).collect();
    assert!(workspace.colours() > 1);
    for colours in &sweeps {
        let mut sorted: Vec<usize> = colours.concat();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "not a permutation");
        for colour in colours {
            let mut used = vec![false; problem.bodies.len()];
            for &k in colour {
                for &b in problem.contacts[k].bodies.iter().flatten() {
                    if moving[b] {
                        assert!(!used[b], "a colour shares body {b}");
                        used[b] = true;
                    }
                }
            }
        }
    }
    assert!(
        sweeps.windows(2).any(|w| w[0] != w[1]),
        "every sweep took the colours in one order"
    );
}

/// The same seed gives the same orders and λ to the bit; other seeds other orders, and other λ
/// (after 3 sweeps, far from converged, where the order shows in the impulses) on at least one
/// of four random problems (one whose contacts the order cannot couple would give the same λ).
#[test]
fn random_coloured_order_is_the_seeds_and_differs_between_seeds() {
    let mut differing = 0;
    for p in 1..=4 {
        let mut problem = large_problem(p);
        // Every contact approaching (b_n < 0), so that every λn is positive and the contacts
        // sharing a body couple.
        for c in &mut problem.contacts {
            c.b[0] = -1.0 - c.b[0].abs();
        }
        let (a, _, wa) = solve(&problem, 3, None, ContactOrder::RandomColoured, 11, 1);
        let (b, _, wb) = solve(&problem, 3, None, ContactOrder::RandomColoured, 11, 1);
        assert!(a == b, "the same seed gave different λ");
        for s in 0..3 {
            assert_eq!(wa.sweep_colours(s), wb.sweep_colours(s));
        }
        for seed in [12, 13] {
            let (c, _, wc) = solve(&problem, 3, None, ContactOrder::RandomColoured, seed, 1);
            assert_ne!(
                wa.sweep_colours(0),
                wc.sweep_colours(0),
                "seed {seed}: the same order"
            );
            let largest = (a.iter().zip(&c))
                .map(|(x, y)| (x - y).amax())
                .fold(0.0, f64::max);
            let size = a.iter().map(|x| x.amax()).fold(0.0, f64::max);
            println!("problem {p}, seed {seed}: largest λ {size:e}, difference {largest:e} N·s");
            if a != c {
                differing += 1;
            }
        }
        // The coloured order does not depend on the seed: the random coloured order is not it.
        let (_, _, coloured) = solve(&problem, 3, None, ContactOrder::Coloured, 11, 1);
        assert_ne!(wa.sweep_colours(0), coloured.sweep_colours(0));
    }
    assert!(differing > 0, "no seed changed λ on any problem");
}

/// The random coloured order's colours go four at a time, to the bits of visiting them one
/// contact at a time (the groups switched off: each colour's contacts visited in turn), and two
/// threads give the one thread's bits (the orders are drawn before the sweeps, whatever the
/// threads).
#[test]
fn random_coloured_order_gives_the_same_bits_in_groups_one_at_a_time_and_on_two_threads() {
    let problem = large_problem(2);
    for sweeps in [3, 50] {
        let (one, one_report, w1) =
            solve(&problem, sweeps, None, ContactOrder::RandomColoured, 5, 1);
        let (two, two_report, w2) =
            solve(&problem, sweeps, None, ContactOrder::RandomColoured, 5, 2);
        assert!(w1.last_groups() > 0, "no groups of four");
        assert_eq!((w1.last_threads(), w2.last_threads()), (1, 2));
        assert!(
            one == two,
            "{sweeps} sweeps: λ differs between 1 and 2 threads"
        );
        assert_eq!(one_report.residual.to_bits(), two_report.residual.to_bits());
        let mut workspace = rigidref::solve::PgsWorkspace::new(5);
        workspace.set_lanes(Lanes::Off);
        let settings = rigidref::solve::PgsSettings {
            max_iterations: sweeps,
            tolerance: None,
            order: ContactOrder::RandomColoured,
            local: rigidref::solve::LocalSolve::Rows,
        };
        let mut alone = Vec::new();
        let report = rigidref::solve::solve_pgs(&problem, &settings, &mut workspace, &mut alone);
        assert_eq!(workspace.last_groups(), 0);
        assert!(
            one == alone,
            "{sweeps} sweeps: λ differs between the groups and one contact at a time"
        );
        assert_eq!(one_report.residual.to_bits(), report.residual.to_bits());
    }
}

/// On random frictionless problems with a well-conditioned normal block (a unique λ), the
/// random coloured order converges to the residual tolerance and to the problem order's λ
/// (within 1e-6 of its scale, as the coloured order: both stop at 1e-9 m/s, condition ≤ 1e3).
#[test]
fn random_coloured_sweeps_converge_to_the_problem_orders_solution() {
    proptest!(common::seeded(100), |(s in spec(2..6, 2..10), seed in 0u64..1000)| {
        let problem = build(&s, 0.0, 0.0, FrictionModel::Box);
        let a = problem.dense_delassus();
        let normal: Vec<usize> = (0..problem.contacts.len()).map(|k| 3 * k).collect();
        let an = a.select_rows(&normal).select_columns(&normal);
        let eigenvalues = an.symmetric_eigenvalues();
        prop_assume!(eigenvalues.min() > 1e-3 * eigenvalues.max());
        let (found, report, _) =
            solve(&problem, 20_000, Some(1e-9), ContactOrder::Sequential, 0, 1);
        prop_assert!(report.converged);
        let (random, report, _) =
            solve(&problem, 20_000, Some(1e-9), ContactOrder::RandomColoured, seed, 1);
        prop_assert!(report.converged, "{report:?}");
        let scale = found.iter().map(|l| l.amax()).fold(1e-12, f64::max);
        for (a, b) in found.iter().zip(&random) {
            prop_assert!((a - b).amax() <= 1e-6 * scale, "{a} against {b}");
        }
    });
}

/// In a solve, every colour of every sweep lists its contacts in problem order (ascending), on
/// one and two threads.
#[test]
fn random_coloured_sweeps_visit_each_colours_contacts_in_problem_order() {
    let problem = large_problem(3);
    for threads in [1, 2] {
        let (_, _, workspace) = solve(&problem, 4, None, ContactOrder::RandomColoured, 9, threads);
        assert!(workspace.colours() > 1);
        for sweep in 0..4 {
            for colour in workspace.sweep_colours(sweep) {
                assert!(
                    colour.windows(2).all(|w| w[0] < w[1]),
                    "{threads} threads, sweep {sweep}: a colour not in problem order"
                );
            }
        }
    }
}
