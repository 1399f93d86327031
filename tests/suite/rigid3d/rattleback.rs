//! The rattleback (docs/contact.md §"The rattleback"): an analytic ellipsoid whose inertia's
//! principal axes are turned by δ = 0.8° about the vertical, on the ground with μ = 1.

use crate::common;

use nalgebra::{Matrix3, Vector3};
use rigidref::rigid3d::collide::ellipsoid::Ellipsoid;
use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::rigid3d::world::World;

fn scene() -> Scene {
    load_scene(&common::project_root().join("scenes/rattleback.json")).unwrap()
}

/// Runs the canonical rattleback with the vertical spin ω_y(0) = `spin` (the scene's small
/// rocking kept) and the inertia's tilt mirrored when `mirrored` (δ → −δ: the product of inertia
/// J_xz changes sign), for `seconds`; returns the times at which ω_y changed sign.
fn reversals(spin: f64, mirrored: bool, seconds: f64) -> Vec<f64> {
    let mut s = scene();
    s.bodies[0].omega0.y = spin;
    if mirrored {
        let j = &mut s.bodies[0].inertia;
        j[(0, 2)] = -j[(0, 2)];
        j[(2, 0)] = -j[(2, 0)];
    }
    let mut world = World::new(&s).unwrap();
    let mut last = spin.signum();
    let mut times = Vec::new();
    let steps = (seconds / s.params.dt).round() as u64;
    common::run(&mut world, steps, |w, _| {
        let now = w.bodies[0].omega.y.signum();
        if now != last && w.bodies[0].omega.y != 0.0 {
            times.push(w.time());
            last = now;
        }
    });
    times
}

#[test]
fn the_rattleback_reverses_one_way_and_spins_on_the_other() {
    // Sign convention: y up, spin ω_y > 0 counter-clockwise seen from above; the body file's
    // principal axes are turned by δ = +0.8° about +y (J_xz > 0). Spun clockwise (ω_y(0) = −3
    // rad/s) it starts to rock and its spin changes sign (measured 4.8 s); spun
    // counter-clockwise (+3) it keeps its sign for the same 6 s. With the tilt mirrored (δ < 0)
    // the two directions swap: the behaviour comes from the inertia's tilt, not from the
    // numerics.
    let reverse = reversals(-3.0, false, 6.0);
    let forward = reversals(3.0, false, 6.0);
    println!("ω_y(0) = −3: sign changes at {reverse:?}; +3: {forward:?}");
    assert!(
        !reverse.is_empty() && reverse[0] < 6.0,
        "−3 did not reverse: {reverse:?}"
    );
    assert!(forward.is_empty(), "+3 reversed at {forward:?}");
    let mirrored_forward = reversals(3.0, true, 6.0);
    let mirrored_reverse = reversals(-3.0, true, 6.0);
    println!("mirrored: +3 at {mirrored_forward:?}; −3 at {mirrored_reverse:?}");
    assert!(!mirrored_forward.is_empty(), "mirrored, +3 should reverse");
    assert!(mirrored_reverse.is_empty(), "mirrored, −3 should spin on");
}

#[test]
fn the_ellipsoid_touches_the_ground_at_its_exact_lowest_point() {
    // The support point c + A²u/‖Au‖ against the lowest of 200 000 points of the surface
    // (parametrised by angles) at random orientations: the analytic point is on the surface and
    // no sampled point is lower (to the sampling's resolution, 1e-6 m here).
    use proptest::prelude::*;
    let e = Ellipsoid {
        centre: Vector3::new(0.0, 0.01, 0.0),
        semi_axes: Vector3::new(0.2, 0.02, 0.03),
    };
    proptest!(common::seeded(20), |(w in proptest::array::uniform3(-3.0..3.0f64))| {
        let r: Matrix3<f64> = rigidref::rigid3d::rotation::exp_so3(&Vector3::from(w));
        let down = r.transpose() * -Vector3::y();
        let q = e.support(&down);
        let f = (q - e.centre).component_div(&e.semi_axes).norm_squared();
        prop_assert!((f - 1.0).abs() < 1e-12, "on the surface: f = {}", f);
        let lowest = (r * q).y;
        let mut sampled = f64::INFINITY;
        for i in 0..400 {
            for k in 0..500 {
                let (th, ph) = (std::f64::consts::PI * (i as f64 + 0.5) / 400.0, std::f64::consts::TAU * k as f64 / 500.0);
                let p = e.centre + Vector3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()).component_mul(&e.semi_axes);
                sampled = sampled.min((r * p).y);
            }
        }
        prop_assert!(lowest <= sampled + 1e-12, "analytic {} above sampled {}", lowest, sampled);
        prop_assert!(sampled - lowest < 1e-5, "sampled {} far above analytic {}", sampled, lowest);
    });
}
