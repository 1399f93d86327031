//! A body under gravity alone: symplectic Euler's discrete trajectory has a closed form, and it
//! differs from the exact parabola by a first-order term. docs/dynamics.md §"Projectile".

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::rigid3d::world::World;

/// With h = dt/substeps and n substeps taken, symplectic Euler gives
/// v_n = v0 + n h g and x_n = x0 + n h v0 + h² g n(n+1)/2.
#[test]
fn projectile_matches_the_closed_form_of_symplectic_euler_to_round_off() {
    let scene = load_scene(&common::project_root().join("scenes/projectile.json")).unwrap();
    let (x0, v0, g, h) = (
        scene.bodies[0].x0,
        scene.bodies[0].v0,
        scene.params.gravity,
        scene.params.h(),
    );
    let mut world = World::new(&scene).unwrap();
    let mut worst = 0.0f64;
    common::run(&mut world, 300, |world, _| {
        let n = (world.step * scene.params.substeps as u64) as f64;
        let v = v0 + g * (n * h);
        let x = x0 + v0 * (n * h) + g * (h * h * n * (n + 1.0) / 2.0);
        let b = &world.bodies[0];
        // Round-off only: each of the n additions may lose half an ulp of |x| (~1e-16 · 20 m).
        let err = (b.x - x).norm().max((b.v - v).norm());
        worst = worst.max(err);
        assert!(
            (b.x - x).norm() < 1e-12 * n.max(1.0) * x.norm(),
            "step {}: {} vs {}",
            world.step,
            b.x,
            x
        );
        assert!((b.v - v).norm() < 1e-12 * n.max(1.0) * v.norm().max(1.0));
    });
    eprintln!("largest deviation from the discrete closed form over 300 steps: {worst:.2e}");
}

/// x_n − (x0 + v0 t + ½ g t²) = ½ g h t exactly (t = n h): first order in h. Halving h halves it.
#[test]
fn projectile_differs_from_the_parabola_by_half_g_h_t() {
    let mut scene = load_scene(&common::project_root().join("scenes/projectile.json")).unwrap();
    let (x0, v0, g) = (scene.bodies[0].x0, scene.bodies[0].v0, scene.params.gravity);
    let mut errors = Vec::new();
    for substeps in [1, 2, 4] {
        scene.params.substeps = substeps;
        let mut world = World::new(&scene).unwrap();
        common::run(&mut world, 200, |_, _| {});
        let t = world.time();
        let exact = x0 + v0 * t + g * (0.5 * t * t);
        let error = world.bodies[0].x - exact;
        let predicted = g * (0.5 * scene.params.h() * t);
        assert!(
            (error - predicted).norm() < 1e-9,
            "substeps {substeps}: error {error} vs ½ g h t = {predicted}"
        );
        errors.push(error.norm());
    }
    eprintln!("|x − parabola| at t = 2 s for h = 10, 5, 2.5 ms: {errors:.3?}");
    assert!(
        (errors[0] / errors[1] - 2.0).abs() < 1e-6 && (errors[1] / errors[2] - 2.0).abs() < 1e-6
    );
}
