//! 2D physics: momentum through contact, restitution, post-stabilisation, and the one shared
//! solver (docs/blocks2d.md, docs/one-solver.md).

use crate::common;
use common::blocks::{blob, body_of};
use common::rigidref;

use nalgebra::Vector2;
use proptest::prelude::*;
use rigidref::blocks2d::image::{Block, BlockGroup, ImageSettings, block_mass, load_image};
use rigidref::blocks2d::params::Params2;
use rigidref::blocks2d::world::World2;
use rigidref::solve::ContactOrder;

#[test]
fn momentum_is_conserved_through_contacts_without_gravity_or_pins() {
    // Bodies thrown at each other in zero gravity; post-stabilisation moves positions, not
    // velocities, so it cannot change linear momentum; it is off here so that angular momentum
    // about the origin (which depends on positions too) is also exact through contact.
    // Set-up that guarantees contact: centres 7 blocks apart on a near-horizontal line (each
    // blob covers the heights around its centre), neighbours closing at speed s ≥ 0.7, so they
    // meet within 10 time units; 15 are run. Every case must have touched, or it tests nothing.
    proptest!(common::seeded(40), |(
        shapes in proptest::collection::vec((blob(), -0.05..0.05f64, -0.1..0.1f64), 2..5),
        closing in 0.7..1.5f64,
        mu in 0.0..1.0f64,
        restitution in 0.0..1.0f64,
    )| {
        let mut world = World2::new(&[], Params2 { gravity: 0.0, mu, restitution, iterations: 20, post_stabilization: false, ..common::one_substep_ten_sweeps_in_order() });
        let middle = (shapes.len() - 1) as f64 / 2.0;
        for (k, (cells, vy, omega)) in shapes.iter().enumerate() {
            let mut b = body_of(cells, false);
            b.x = Vector2::new(7.0 * k as f64, 0.3 * k as f64);
            b.v = Vector2::new(-(k as f64 - middle) * closing, *vy);
            b.omega = *omega;
            world.add_body(b);
        }
        let m0 = world.momentum();
        let (p0, l0) = (Vector2::from(m0.linear), m0.angular);
        let mut contact_steps = 0;
        common::run(&mut world, 300, |world, _| {
            contact_steps += usize::from(!world.contacts.is_empty());
        });
        prop_assert!(contact_steps > 0, "no contact: the case tests nothing");
        let m1 = world.momentum();
        let (p1, l1) = (Vector2::from(m1.linear), m1.angular);
        // Relative to the sum of the magnitudes that cancel in the totals: round-off in a sum of
        // terms of size S is a few ε S, and 300 steps of impulses accumulate it; 1e-9 is the
        // issue's bound.
        let scale_p = world.bodies.iter().map(|b| b.mass * b.v.norm()).sum::<f64>().max(1e-12);
        let scale_l = world.bodies.iter().map(|b| b.mass * b.x.norm() * b.v.norm() + b.inertia * b.omega.abs()).sum::<f64>().max(1e-12);
        prop_assert!((p1 - p0).norm() <= 1e-9 * scale_p, "Δp {:?}", p1 - p0);
        prop_assert!((l1 - l0).abs() <= 1e-9 * scale_l, "ΔL {}", l1 - l0);
    });
}

/// Restitution (docs/blocks2d.md §"Contact problem"): a block dropped on a pinned floor bounces
/// back up with e times the speed it arrived with, so each bounce's height is about e² of the
/// last (e = 0.5: 0.25), and with e = 1 the bounces repeat without growing. The approach speed
/// is taken before the substep's gravity kick; taken after it, e = 1 gained 0.1 block per bounce.
#[test]
fn restitution_scales_bounce_heights_by_e_squared_and_repeats_them_at_e_one() {
    const START: f64 = -3.0;
    // The tops of the bounces (y grows downward: where v_y turns from negative to positive),
    // the final height and the largest speed.
    let bounces = |e: f64| {
        let floor: Vec<(i64, i64)> = (0..10).map(|x| (x, 0)).collect();
        let mut world = World2::new(
            &[],
            Params2 {
                restitution: e,
                ..common::one_substep_ten_sweeps_in_order()
            },
        );
        let mut block = body_of(&[(0, 0)], false);
        block.x = Vector2::new(4.0, START);
        world.add_body(block);
        world.add_body(body_of(&floor, true));
        let (mut tops, mut previous_vy, mut fastest) = (Vec::new(), 0.0, 0.0f64);
        common::run_until(&mut world, u64::MAX, |world, _| {
            let b = &world.bodies[0];
            fastest = fastest.max(b.v.norm());
            if previous_vy < 0.0 && b.v.y >= 0.0 {
                tops.push(b.x.y);
            }
            previous_vy = b.v.y;
            world.time() >= 30.0
        });
        (tops, world.bodies[0].x.y, fastest, world.params.h())
    };
    let (half, rest, _, _) = bounces(0.5);
    let heights: Vec<f64> = half.iter().map(|y| rest - y).collect();
    let drop = rest - START;
    println!("e = 0.5: drop height {drop:.3}, bounce heights {heights:.3?}");
    assert!(heights.len() >= 2, "{heights:?}");
    let ratios = [heights[0] / drop, heights[1] / heights[0]];
    // e² = 0.25; the discrete step (h = 0.05, a few per cent of a bounce's duration) moves it
    // by a few per cent.
    for r in &ratios {
        assert!((r - 0.25).abs() < 0.03, "height ratios {ratios:?}");
    }

    let (tops, _, fastest, h) = bounces(1.0);
    let heights: Vec<f64> = tops.iter().map(|y| rest - y).collect();
    println!("e = 1: drop height {drop:.3}, bounce heights {heights:.4?}");
    assert!(heights.len() >= 5, "{heights:?}");
    // After the first bounce they repeat to round-off: no energy is gained or lost.
    for x in &heights[1..] {
        assert!((x - heights[0]).abs() < 1e-9, "{heights:?}");
    }
    // The first may top the drop height by the impact's penetration, at most one step's travel
    // (fastest · h), which post-stabilisation lifts out without slowing the body.
    assert!(
        heights[0] <= drop + fastest * h,
        "bounced {} above the drop height",
        heights[0] - drop
    );
}

/// Post-stabilisation (docs/blocks2d.md §"Post-stabilisation") corrects positions alone: two
/// squares placed deep in each other, at rest and without gravity, are pushed apart until no
/// disc pair overlaps by more than the slop, their velocities stay exactly zero (no energy is
/// added), and their common centre of mass stays where it was (the correction is equal and
/// opposite). Switched off, nothing moves them: the velocity-level solve sees b = 0.
#[test]
fn post_stabilisation_removes_penetration_by_moving_positions_alone() {
    let run = |post_stabilization: bool| {
        let mut world = World2::new(
            &[],
            Params2 {
                gravity: 0.0,
                iterations: 50,
                post_stabilization,
                ..common::one_substep_ten_sweeps_in_order()
            },
        );
        for (k, x) in [0.0, 1.5].into_iter().enumerate() {
            let mut b = body_of(&[(0, 0), (1, 0), (0, 1), (1, 1)], false);
            b.x = Vector2::new(x, 0.1 * k as f64);
            world.add_body(b);
        }
        let centre = |w: &World2| -> Vector2<f64> {
            w.bodies.iter().map(|b| b.x * b.mass).sum::<Vector2<f64>>()
                / w.bodies.iter().map(|b| b.mass).sum::<f64>()
        };
        let c0 = centre(&world);
        common::run(&mut world, 1, |_, _| {});
        let first = world.deepest_overlap();
        common::run(&mut world, 10, |_, _| {});
        let speed = world
            .bodies
            .iter()
            .map(|b| b.v.norm() + b.omega.abs())
            .fold(0.0, f64::max);
        (
            first,
            world.deepest_overlap(),
            speed,
            (centre(&world) - c0).norm(),
            world.params.slop,
        )
    };
    let (first, last, speed, shift, slop) = run(true);
    println!(
        "post-stabilisation: overlap {first:.3} → {last:.2e}, speed {speed}, centre moved {shift:.1e}"
    );
    assert!(first > 0.5, "the squares were placed overlapping: {first}");
    // PGS at 50 sweeps on the position rows; 1e-6 is far below the 0.9 removed.
    assert!(last <= slop + 1e-6, "overlap left: {last}");
    assert_eq!(speed, 0.0);
    // Σ m δx = h Σ (Jᵀλ)_linear = 0 up to round-off in positions of order 1.
    assert!(shift < 1e-12, "centre of mass moved {shift}");
    let (first_off, last_off, speed_off, _, _) = run(false);
    assert_eq!(speed_off, 0.0);
    assert_eq!(
        first_off, last_off,
        "without post-stabilisation nothing separates them"
    );
}

#[test]
fn post_stabilisation_changes_angular_momentum_by_h_sum_m_dv_cross_v() {
    // docs/blocks2d.md: the velocity solve keeps L about the origin at fixed positions, then the
    // positions move by x₁ − x₀ = h v₁ + δx (δx the post-stabilisation's correction), so
    // L₁ − L₀ = Σ m (x₁ − x₀) × v₁ = Σ m δx × v₁: exactly zero without post-stabilisation, not with
    // it. Two overlapping 2 × 2 squares (0.5 deep along x) sliding past each other along y at
    // ±1 (μ = 0), one step with the starter's settings and post-stabilisation on.
    let mut world = World2::new(
        &[],
        Params2 {
            gravity: 0.0,
            mu: 0.0,
            iterations: 50,
            post_stabilization: true,
            ..common::one_substep_ten_sweeps_in_order()
        },
    );
    for (k, (x, vy)) in [(0.0, 1.0), (1.5, -1.0)].into_iter().enumerate() {
        let mut b = body_of(&[(0, 0), (1, 0), (0, 1), (1, 1)], false);
        b.x = Vector2::new(x, 0.1 * k as f64);
        b.v = Vector2::new(0.0, vy);
        world.add_body(b);
    }
    let (p0, l0) = {
        let m = world.momentum();
        (m.linear, m.angular)
    };
    let x0: Vec<Vector2<f64>> = world.bodies.iter().map(|b| b.x).collect();
    common::run(&mut world, 1, |_, _| {});
    let m = world.momentum();
    let predicted: f64 = world
        .bodies
        .iter()
        .zip(&x0)
        .map(|(b, x0)| {
            let d = b.x - x0;
            b.mass * (d.x * b.v.y - d.y * b.v.x)
        })
        .sum();
    let scale: f64 = world
        .bodies
        .iter()
        .map(|b| b.mass * b.x.norm() * b.v.norm())
        .sum::<f64>()
        .max(1.0);
    // Linear momentum: positions do not enter it; exact to round-off.
    assert!(
        (m.linear[0] - p0[0]).abs() <= 1e-12 * scale
            && (m.linear[1] - p0[1]).abs() <= 1e-12 * scale
    );
    let change = m.angular - l0;
    assert!(
        (change - predicted).abs() <= 1e-12 * scale,
        "ΔL {change}, Σ m (x₁ − x₀) × v₁ {predicted}"
    );
    println!("post-stabilisation changed L by {change:.4} (Σ m δx × v)");
    assert!(
        change.abs() > 0.1,
        "the correction must change L here: {change}"
    );
}

#[test]
fn the_2d_and_3d_systems_call_the_same_pgs() {
    // In the source: both steps call the one switch, solve::solve, whose PGS is solve_pgs, and
    // there is one PGS in the crate.
    let root = common::project_root();
    let read = |p: &str| std::fs::read_to_string(root.join(p)).unwrap();
    let world3 = read("src/rigid3d/world.rs");
    assert!(
        world3.contains("use crate::solve::{")
            && world3.contains("solve(\n                &record.problem,")
    );
    assert!(read("src/blocks2d/world/solve.rs").contains("crate::solve::solve("));
    assert!(read("src/solve/mod.rs").contains("Solver::Pgs => solve_pgs("));
    let mut definitions = 0;
    let mut stack = vec![root.join("src")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                definitions += std::fs::read_to_string(&p)
                    .unwrap()
                    .matches("fn solve_pgs<")
                    .count();
            }
        }
    }
    assert_eq!(definitions, 1, "one PGS implementation");
    // The local form's PGS (W, q) visits with the same functions; it defines none of its own.
    let local = read("src/solve/pgs_delassus.rs");
    assert!(local.contains("solve_contact(") && local.contains("visit_exactly("));
    assert!(!local.contains("fn solve_contact") && !local.contains("fn visit_exactly"));
    // In behaviour: re-solving a 2D world's last problem with that function gives its impulses.
    let groups = vec![
        BlockGroup {
            blocks: (0..10)
                .map(|j| Block {
                    pixel: Vector2::new(j as f64, 5.0),
                    colour: [0.0, 0.0, 0.64],
                    mass: block_mass([0.0, 0.0, 0.64]),
                })
                .collect(),
            pinned: true,
            boundary: None,
        },
        BlockGroup {
            blocks: (3..6)
                .map(|j| Block {
                    pixel: Vector2::new(j as f64, 3.6),
                    colour: [0.0; 3],
                    mass: 1.0,
                })
                .collect(),
            pinned: false,
            boundary: None,
        },
    ];
    let mut world = World2::new(
        &groups,
        Params2 {
            warm_start: false,
            ..common::one_substep_ten_sweeps_in_order()
        },
    );
    common::run(&mut world, 1, |_, _| {});
    let problem = world
        .solves
        .last()
        .expect("a contact problem")
        .problem
        .clone();
    let mut workspace = rigidref::solve::PgsWorkspace::<3, 2>::new(0);
    let mut lambda = Vec::new();
    let settings = rigidref::solve::PgsSettings {
        max_iterations: 10,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: rigidref::solve::LocalSolve::Rows,
    };
    rigidref::solve::solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
    assert_eq!(lambda, world.solves.last().unwrap().lambda);
}

#[test]
fn clarabel_crosscheck_runs_on_2d_contact_problems() {
    let Some(dir) = common::blocks2d_assignment() else {
        return;
    };
    let groups = load_image(&dir.join("delicate.png"), &ImageSettings::default()).unwrap();
    let mut world = World2::new(
        &groups,
        Params2 {
            substeps: 4,
            iterations: 50,
            order: ContactOrder::Random,
            ..common::one_substep_ten_sweeps_in_order()
        },
    );
    let tmp = tempfile::tempdir().unwrap();
    let mut checked = 0;
    common::run(&mut world, 200, |world, step| {
        if step % 20 == 0
            && let Some(problem) = world.solves.last().map(|s| s.problem.clone())
        {
            let c =
                rigidref::verify::crosscheck::check_problem(&problem, &Default::default()).unwrap();
            println!(
                "delicate step {step}: {} contacts, {:?} {:.2e}, PGS residual {:.1e}",
                c.contacts, c.comparison, c.disagreement, c.residual_answer
            );
            if c.residual_answer <= 1e-10 {
                let tol = match c.comparison {
                    rigidref::verify::crosscheck::Comparison::Lambda => 1e-5,
                    rigidref::verify::crosscheck::Comparison::Objective => 1e-8,
                };
                assert!(c.disagreement <= tol, "{c:?}");
                checked += 1;
            }
            let file = rigidref::problem::json::ProblemFile::new(&problem);
            std::fs::write(
                tmp.path().join(format!("p{step:04}.json")),
                serde_json::to_string(&file).unwrap(),
            )
            .unwrap();
        }
    });
    assert!(checked >= 5, "only {checked} problems converged");
    // And through the command, from problem files with 3 degrees of freedom per body.
    let out = std::process::Command::new(common::rigidref_bin())
        .arg("crosscheck")
        .arg(tmp.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    // Some of delicate's problems PGS cannot converge on (the tolerance is 1e-10 m/s): those are
    // unverified (exit status 3), none may disagree (exit status 1).
    let unverified = stdout.contains("result           unverified: ");
    assert_eq!(
        out.status.code(),
        Some(if unverified { 3 } else { 0 }),
        "{stdout}{}",
        common::stderr(&out)
    );
    assert!(
        stdout.contains("problems         9 ") || stdout.contains("problems         10 "),
        "{stdout}"
    );
    // And on a 2D scene directly: every problem of 4 time units of the project's stack. Its
    // step 79 is a problem where clarabel reports "Solved" short of the optimum (residual 1.8e-3,
    // PGS 9e-13 with an objective 6e-9 lower): it must count as agreement, not as PGS's error.
    let out = rigidref(
        &["crosscheck", "stack.json", "--time", "4"],
        &common::project_root().join("scenes/blocks"),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(out.status.success(), "{stdout}{}", common::stderr(&out));
    assert!(
        stdout.contains("problems         178 (178 compared"),
        "{stdout}"
    );
    assert!(stdout.contains("result           agree"), "{stdout}");
}

/// Restitution between two moving bodies (docs/blocks2d.md §"Contact problem"): the approach
/// speed is the two bodies' relative normal velocity, so two equal single blocks meeting
/// head-on at ±1 in zero gravity, without friction, leave at ∓e: with e = 1 they exchange
/// velocities, with e = ½ they part at half the speed. Taking either body's velocity alone, or
/// the sum of the two, would give another answer (for this symmetric case, no bounce at all).
#[test]
fn two_moving_bodies_part_at_e_times_their_closing_speed() {
    for e in [0.5, 1.0] {
        let mut world = World2::new(
            &[],
            Params2 {
                gravity: 0.0,
                mu: 0.0,
                restitution: e,
                iterations: 50,
                post_stabilization: false,
                ..common::one_substep_ten_sweeps_in_order()
            },
        );
        for (x, v) in [(0.0, 1.0), (3.0, -1.0)] {
            let mut b = body_of(&[(0, 0)], false);
            b.x = Vector2::new(x, 0.0);
            b.v = Vector2::new(v, 0.0);
            world.add_body(b);
        }
        let mut touched = false;
        common::run(&mut world, 400, |w, _| touched |= !w.contacts.is_empty());
        assert!(touched, "e = {e}: the blocks never met");
        let (v0, v1) = (world.bodies[0].v, world.bodies[1].v);
        // 1e-6: one contact, solved exactly by PGS in a sweep; the rest is round-off.
        assert!(
            (v0.x + e).abs() < 1e-6 && (v1.x - e).abs() < 1e-6,
            "e = {e}: velocities after {v0:?} {v1:?}"
        );
    }
}

/// Post-stabilisation solves the normal rows alone where it can (PGS row by row, no pin;
/// docs/blocks2d.md §"Post-stabilisation", "Normal rows only"), and that gives the solve of both
/// rows to the bit: a pile of 200 bricks, 60 steps of the factory's settings and of the other
/// orders (the 2D scenes' random order with their 4 substeps, the problem order, the fixed
/// coloured order), run both ways, ends with the same positions, angles, velocities and
/// post-stabilisation residual, as bits. The pile's post-stabilisation does move it (a run
/// without it ends elsewhere), and a world with a pin solves both rows.
#[test]
fn normal_rows_alone_post_stabilise_to_the_full_solves_bits() {
    use rigidref::blocks2d::joints::{Anchor, Pin2};
    use rigidref::tools::experiments::factory::{Pieces, packed_pile};
    let cases = [
        (ContactOrder::RandomColoured, 1),
        (ContactOrder::Random, 4),
        (ContactOrder::Sequential, 1),
        (ContactOrder::Coloured, 1),
    ];
    for (order, substeps) in cases {
        let run = |normal_rows: bool, post_stabilization: bool| {
            let mut world = packed_pile(200, Pieces::Bricks, 7);
            world.params.order = order;
            world.params.substeps = substeps;
            world.params.post_stabilization = post_stabilization;
            world.set_normal_rows_post_stabilization(normal_rows);
            assert_eq!(
                world.post_stabilization_rows(),
                if normal_rows { 1 } else { 2 }
            );
            for _ in 0..60 {
                world.step().unwrap();
            }
            world
        };
        let state = |w: &World2| -> Vec<[u64; 6]> {
            (w.bodies.iter())
                .map(|b| [b.x.x, b.x.y, b.theta, b.v.x, b.v.y, b.omega].map(f64::to_bits))
                .collect()
        };
        let (fast, full) = (run(true, true), run(false, true));
        assert!(state(&fast) == state(&full), "{order:?}: the runs differ");
        assert_eq!(
            fast.post_stabilization_residual.to_bits(),
            full.post_stabilization_residual.to_bits(),
            "{order:?}"
        );
        let without = run(true, false);
        assert!(
            state(&without) != state(&full),
            "{order:?}: post-stabilisation changed nothing, so the comparison tests nothing"
        );
    }
    let mut pinned = packed_pile(20, Pieces::Bricks, 7);
    let at = pinned.bodies[1].x;
    pinned.pins.push(Pin2 {
        ends: [
            Anchor::at(&pinned.bodies, Some(1), &at),
            Anchor::at(&pinned.bodies, None, &at),
        ],
    });
    assert_eq!(
        pinned.post_stabilization_rows(),
        2,
        "a pin's free rows need both rows"
    );
}
