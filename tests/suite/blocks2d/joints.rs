//! Springs, dampers and pins in 2D (docs/blocks2d.md §"Springs, dampers and pins"): the
//! analytic oscillator, the pin's drift and energy, the seesaw, and clarabel on problems with
//! joint rows.

use crate::common;
use common::blocks::body_of;

use nalgebra::Vector2;
use rigidref::blocks2d::joints::{Anchor, Pin2, Spring2};
use rigidref::blocks2d::params::Params2;
use rigidref::blocks2d::world::World2;

/// A world without gravity, small steps, the demonstration settings otherwise.
fn weightless(dt: f64) -> World2 {
    World2::new(
        &[],
        Params2 {
            gravity: 0.0,
            dt,
            ..Params2::demonstration()
        },
    )
}

/// One block at `x`, on a spring to the world point `to` (rest length 0, so linear in both
/// directions), stiffness k, damping c.
fn block_on_spring(dt: f64, x: Vector2<f64>, to: Vector2<f64>, k: f64, c: f64) -> World2 {
    let mut world = weightless(dt);
    let mut block = body_of(&[(0, 0)], false);
    block.x = x;
    world.add_body(block);
    let ends = [
        Anchor::at(&world.bodies, Some(0), &x),
        Anchor::at(&world.bodies, None, &to),
    ];
    world.springs.push(Spring2 {
        ends,
        stiffness: k,
        damping: c,
        rest_length: 0.0,
    });
    world
}

/// Times at which x − x_eq crosses zero going up, by linear interpolation between steps.
fn upward_crossings(samples: &[(f64, f64)]) -> Vec<f64> {
    samples
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1))
        .collect()
}

#[test]
fn a_mass_on_a_spring_oscillates_at_root_k_over_m_for_ten_periods() {
    // k = 4, m = the block's mass: ω = √(k/m). Symplectic Euler's discrete frequency is
    // ω (1 + ω²h²/24 + …): with h = 0.0025 that is 1e-6 relative, far inside the 1% asked.
    let (k, dt) = (4.0, 0.01);
    let mut world = block_on_spring(dt, Vector2::new(1.0, 0.0), Vector2::zeros(), k, 0.0);
    let m = world.bodies[0].mass;
    let omega = (k / m).sqrt();
    let period = 2.0 * std::f64::consts::PI / omega;
    let steps = (10.5 * period / dt) as u64;
    let mut samples = vec![(0.0, 1.0)];
    let mut largest = 0.0f64;
    common::run(&mut world, steps, |w, _| {
        samples.push((w.time(), w.bodies[0].x.x));
        largest = largest.max(w.bodies[0].x.x.abs());
    });
    let crossings = upward_crossings(&samples);
    eprintln!("spring: crossings {crossings:?}, amplitude {largest}, 2π/ω = {period}");
    assert!(crossings.len() >= 10, "{} crossings", crossings.len());
    let measured = (crossings[9] - crossings[0]) / 9.0;
    assert!(
        (measured / period - 1.0).abs() < 0.01,
        "period {measured} against 2π/√(k/m) = {period}"
    );
    // Symplectic Euler keeps a nearby energy: the amplitude stays within 1% too.
    assert!((largest - 1.0).abs() < 0.01, "amplitude {largest}");
    assert!(
        world.bodies[0].omega.abs() < 1e-12,
        "a spring at the centre of mass turns nothing"
    );
}

#[test]
fn a_damped_spring_decays_at_the_analytic_rate() {
    // m ẍ + c ẋ + k x = 0: the amplitude decays as exp(−c t / 2m); successive upward crossings
    // are the damped period 2π/√(k/m − (c/2m)²) apart.
    let (k, c, dt) = (4.0, 0.3, 0.01);
    let mut world = block_on_spring(dt, Vector2::new(1.0, 0.0), Vector2::zeros(), k, c);
    let m = world.bodies[0].mass;
    let rate = c / (2.0 * m);
    let omega_d = (k / m - rate * rate).sqrt();
    let mut samples = vec![(0.0, 1.0)];
    common::run(
        &mut world,
        (8.0 * 2.0 * std::f64::consts::PI / omega_d / dt) as u64,
        |w, _| {
            samples.push((w.time(), w.bodies[0].x.x));
        },
    );
    // Peaks: local maxima of x.
    let peaks: Vec<(f64, f64)> = samples
        .windows(3)
        .filter(|w| w[1].1 > w[0].1 && w[1].1 >= w[2].1 && w[1].1 > 0.0)
        .map(|w| w[1])
        .collect();
    assert!(peaks.len() >= 6, "{} peaks", peaks.len());
    let (first, last) = (peaks[0], peaks[5]);
    let measured = (first.1 / last.1).ln() / (last.0 - first.0);
    assert!(
        (measured / rate - 1.0).abs() < 0.01,
        "decay rate {measured} against c/2m = {rate}"
    );
    let period = (last.0 - first.0) / 5.0;
    eprintln!("damped: rate {measured} (c/2m {rate}), period {period}");
    let expected = 2.0 * std::f64::consts::PI / omega_d;
    assert!(
        (period / expected - 1.0).abs() < 0.01,
        "damped period {period} against {expected}"
    );
}

/// A pendulum: a pinned support block at the origin and a plank of `length` blocks from
/// x = 3, joined by a pin at the support's centre (the plank swings on a rigid arm through the
/// pin; the two bodies never touch).
fn pendulum(dt: f64, substeps: u32) -> World2 {
    let mut world = World2::new(
        &[],
        Params2 {
            dt,
            substeps,
            mu: 0.0,
            ..Params2::demonstration()
        },
    );
    world.add_body(body_of(&[(0, 0)], true));
    let plank: Vec<(i64, i64)> = (3..8).map(|x| (x, 0)).collect();
    world.add_body(body_of(&plank, false));
    let pin = Vector2::zeros();
    world.pins.push(Pin2 {
        ends: [
            Anchor::at(&world.bodies, Some(1), &pin),
            Anchor::at(&world.bodies, Some(0), &pin),
        ],
    });
    world
}

#[test]
fn a_pinned_pendulum_keeps_its_pin_closed_and_its_energy() {
    // Released horizontal under gravity (y down), it swings through the bottom and back. The
    // pin's error is closed by post-stabilisation each substep, so it stays at the O(h²) the
    // step leaves (bound 1e-3 blocks at h = 0.0025). Energy: the velocity-level pin removes the
    // radial velocity that turning the tangent by ω h makes, a loss of about (ω h)² per substep:
    // here ω ≤ 0.6, 4 000 substeps, ≲ 1e-3 of the energy; bound 1% (docs/blocks2d.md).
    let mut world = pendulum(0.01, 4);
    let e0 = world.energy().total;
    let drop = world.bodies[1].mass * 5.0; // m g Δy at the bottom: the energy's scale
    let (mut worst_error, mut worst_energy, mut lowest) = (0.0f64, 0.0f64, 0.0f64);
    common::run(&mut world, 1000, |w, _| {
        worst_error = worst_error.max(w.pins[0].error(&w.bodies).norm());
        worst_energy = worst_energy.max((w.energy().total - e0).abs());
        lowest = lowest.max(w.bodies[1].x.y);
    });
    eprintln!("pendulum: pin error ≤ {worst_error}, |ΔE| ≤ {worst_energy} (m g Δy {drop})");
    assert!(lowest > 4.0, "the plank swung down to y = {lowest}");
    assert!(worst_error < 1e-3, "pin error {worst_error} blocks");
    assert!(
        worst_energy < 0.01 * drop,
        "energy drift {worst_energy} against m g Δy = {drop}"
    );
}

/// A seesaw: a plank of 11 blocks pinned to the world at the middle of its top face (half a
/// block above its centre of mass, so that it rights itself), a block dropped onto each end from
/// two blocks above it. `right` is the cells of the right-hand load (one block on the left).
fn seesaw(right: &[(i64, i64)]) -> World2 {
    let mut world = World2::new(&[], Params2::demonstration());
    let plank: Vec<(i64, i64)> = (-5..=5).map(|x| (x, 0)).collect();
    world.add_body(body_of(&plank, false));
    world.add_body(body_of(&[(-4, -3)], false));
    world.add_body(body_of(right, false));
    let pin = Vector2::new(0.0, -0.5);
    world.pins.push(Pin2 {
        ends: [
            Anchor::at(&world.bodies, Some(0), &pin),
            Anchor::at(&world.bodies, None, &pin),
        ],
    });
    world
}

#[test]
fn a_seesaw_balances_two_equal_masses_and_tips_under_unequal_ones() {
    // Equal loads: the torques about the pin cancel, and the plank stays level once both have
    // landed (|θ| below 1e-6 rad over 20 time units; measured 7e-17: the two landings are mirror
    // images, and with 200 sweeps the solve is converged whatever the contact order). A double load on the right tips it (θ > 0: +x
    // toward +y, the right end down), so the test can tell the two apart.
    let mut equal = seesaw(&[(4, -3)]);
    let mut worst = 0.0f64;
    common::run(&mut equal, 400, |w, _| {
        worst = worst.max(w.bodies[0].theta.abs())
    });
    let mut unequal = seesaw(&[(4, -3), (4, -4)]);
    let mut tipped = 0.0f64;
    common::run(&mut unequal, 400, |w, _| {
        tipped = tipped.max(w.bodies[0].theta)
    });
    eprintln!("seesaw: equal |θ| ≤ {worst}, unequal θ up to {tipped}");
    assert!(worst < 1e-6, "equal loads: θ reached {worst} rad");
    assert!(
        tipped > 0.1,
        "a double load on the right: θ only {tipped} rad"
    );
    // The loads rest on the plank (block discs touching: centres 2r apart), and the pin held.
    let resting = -2.0 * rigidref::blocks2d::disc_tree::BLOCK_RADIUS;
    for b in &equal.bodies[1..] {
        assert!(
            (b.x.y - resting).abs() < 0.02,
            "load at y = {} (resting: {resting})",
            b.x.y
        );
        assert!(b.v.norm() < 1e-3, "load still moving at {}", b.v.norm());
    }
    assert!(equal.pins[0].error(&equal.bodies).norm() < 1e-3);
}

#[test]
fn clarabel_agrees_with_pgs_on_problems_with_joint_rows() {
    // The seesaw's problems hold contacts (box friction rows) and the pin's two free rows; the
    // pendulum's, the pin alone. clarabel poses the free rows as unconstrained variables of the
    // same objective (docs/contact.md §"Row bounds"). Tolerances as in the 2D contact
    // cross-check: 1e-5 on λ (relative), 1e-8 on the objective, at a converged PGS.
    use rigidref::problem::RowBounds;
    use rigidref::verify::crosscheck::{Comparison, check_problem};
    let mut checked = 0;
    for mut world in [seesaw(&[(4, -3)]), pendulum(0.01, 4)] {
        common::run(&mut world, 200, |w, step| {
            let Some(problem) = w.solves.last().map(|s| s.problem.clone()) else {
                return;
            };
            if step % 10 != 0 {
                return;
            }
            assert!(problem.contacts.iter().any(|c| c.bounds == RowBounds::Free));
            let c = check_problem(&problem, &Default::default()).unwrap();
            if c.residual_answer <= 1e-10 {
                let tol = match c.comparison {
                    Comparison::Lambda => 1e-5,
                    Comparison::Objective => 1e-8,
                };
                assert!(c.disagreement <= tol, "step {step}: {c:?}");
                checked += 1;
            }
        });
    }
    assert!(checked >= 20, "only {checked} problems converged");
}

#[test]
fn scene_files_declare_pins_and_springs_and_bad_ones_are_one_line_errors() {
    // The canonical pendulum: a plank pinned to a support swings, and a block on a spring
    // bounces below another; the seesaw: a plank pinned to its fulcrum with two equal loads.
    let dir = common::project_root().join("scenes/blocks");
    let scene = rigidref::blocks2d::scene::load_scene2(&dir.join("pendulum.json")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let mut world = scene.world;
    assert_eq!((world.pins.len(), world.springs.len()), (1, 1));
    // The spring's rest length is given (3); the pin's anchors coincide at the start.
    assert_eq!(world.springs[0].rest_length, 3.0);
    assert!(world.pins[0].error(&world.bodies).norm() < 1e-12);
    let (mut swing, mut worst) = (0.0f64, 0.0f64);
    common::run(&mut world, 500, |w, _| {
        swing = swing.max(w.bodies[2].theta.abs());
        worst = worst.max(w.pins[0].error(&w.bodies).norm());
    });
    assert!(swing > 1.0, "the plank swung only {swing} rad");
    assert!(worst < 1e-3, "pin error {worst}");
    let scene = rigidref::blocks2d::scene::load_scene2(&dir.join("seesaw.json")).unwrap();
    let mut world = scene.world;
    common::run(&mut world, 400, |_, _| {});
    assert!(
        world.bodies[2].theta.abs() < 1e-6,
        "seesaw θ {}",
        world.bodies[2].theta
    );

    // Bad declarations: one line naming the file and the entry.
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(dir.join("pendulum.png"), tmp.path().join("p.png")).unwrap();
    for (entry, message) in [
        (
            r#""pins": [{"bodies": [9, null], "point": [1, 1]}]"#,
            "pins[0]: body 9 does not exist (the image has 4 bodies, 0 to 3)",
        ),
        (
            r#""pins": [{"bodies": [2, 2], "point": [1, 1]}]"#,
            "pins[0]: joins body 2 to itself",
        ),
        (
            r#""springs": [{"bodies": [null, null], "points": [[1, 1], [2, 2]], "stiffness": 1}]"#,
            "springs[0]: joins the world to itself",
        ),
        (
            r#""springs": [{"bodies": [3, null], "points": [[1, 1], [2, 2]], "stiffness": -1}]"#,
            "springs[0].stiffness",
        ),
    ] {
        let file = tmp.path().join("bad.json");
        std::fs::write(&file, format!(r#"{{"image": "p.png", {entry}}}"#)).unwrap();
        let out = common::rigidref(&["run", "bad.json", "--time", "1"], tmp.path());
        let stderr = common::stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{entry}: {stderr}");
        assert!(
            stderr.contains("bad.json") && stderr.contains(message),
            "{entry}: {stderr}"
        );
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
}
