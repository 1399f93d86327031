//! The 3D assignment's seven scenes load unchanged and run. Skipped, with a printed reason, where
//! ../shared is absent.

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::rigid3d::world::World;

#[test]
fn all_seven_assignment_scenes_load_and_run_two_seconds_without_collisions() {
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    for k in 1..=7 {
        let path = dir.join(format!("scenes/scene{k}.json"));
        let mut scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        // scene2, 5 and 6 give a reflection as R0, replaced (with a warning) by the equivalent
        // rotation; nothing else may warn.
        let unexpected: Vec<_> = scene
            .warnings
            .iter()
            .filter(|w| !w.contains("R0 has determinant −1"))
            .collect();
        assert!(unexpected.is_empty(), "scene{k}: {unexpected:?}");
        assert_eq!(
            scene.warnings.len(),
            usize::from([2, 5, 6].contains(&k)),
            "scene{k}: {:?}",
            scene.warnings
        );
        scene.params.check_collisions = false;
        let mut world = World::new(&scene).unwrap();
        let frames = (2.0 / scene.params.dt).round() as u64;
        // Panics naming the step if the state stops being finite.
        common::run(&mut world, frames, |_, _| {});
        assert!((world.time() - 2.0).abs() < 1e-12);
        eprintln!(
            "scene{k} ({}): {} bodies, 2 s, E = {:.6e} J",
            scene.params.name,
            world.bodies.len(),
            world.energy().total
        );
    }
}

/// The starter's defaults fill missing keys: scene3 gives only name, damping, substeps and dt.
#[test]
fn missing_keys_take_the_starter_defaults() {
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    let scene = load_scene(&dir.join("scenes/scene3.json")).unwrap();
    let p = &scene.params;
    assert_eq!(p.gravity, nalgebra::Vector3::zeros());
    assert_eq!(
        (
            p.mu,
            p.substeps,
            p.check_collisions,
            p.stop_on_contact,
            p.pgs_iterations
        ),
        (0.0, 1, true, false, 100)
    );
    // scene7 gives no R0, v0 or omega0: identity and zeros.
    let scene = load_scene(&dir.join("scenes/scene7.json")).unwrap();
    assert_eq!(scene.bodies.len(), 3);
    assert_eq!(scene.bodies[0].r0, nalgebra::Matrix3::identity());
    assert_eq!(scene.bodies[2].omega0, nalgebra::Vector3::zeros());
    // brick: mass 384, J = diag(66.56, 51.2, 25.6), as ../shared/README.md says.
    assert!((scene.bodies[0].mass - 384.0).abs() < 1e-9);
    assert!(
        (scene.bodies[0].inertia.diagonal() - nalgebra::Vector3::new(66.56, 51.2, 25.6)).norm()
            < 1e-9
    );
}
