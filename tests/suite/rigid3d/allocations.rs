//! Steady state allocates nothing (issue 33): once a resting scene's buffers have grown, a step
//! makes no heap allocation on its thread, with the assignment's methods (the vertex rule in 3D,
//! PGS in both systems) and with `collision: complete` (GJK/EPA's working memory kept,
//! `rigid3d::collide::convex`).

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::rigid3d::world::World;

/// Allocations per step over `steps` steps after `warm` steps of warm-up.
fn allocations_per_step(mut step: impl FnMut(), warm: u64, steps: u64) -> f64 {
    for _ in 0..warm {
        step();
    }
    let before = common::allocations();
    for _ in 0..steps {
        step();
    }
    (common::allocations() - before) as f64 / steps as f64
}

#[test]
fn a_resting_stack_steps_without_allocating_in_both_systems() {
    // The tapered five-cube stack (detection, assembly, PGS, warm start, the solve record, the
    // penetration measure) after 3 s, and the 2D pyramid after 15 time units (with
    // post-stabilisation).
    let path = common::project_root().join("scenes/box_stack.json");
    let mut world = World::new(&load_scene(&path).unwrap()).unwrap();
    let per_step = allocations_per_step(|| world.step().unwrap(), 300, 100);
    assert_eq!(per_step, 0.0, "box_stack: {per_step} allocations per step");
    let path = common::project_root().join("scenes/blocks/pyramid.json");
    let mut world = rigidref::blocks2d::scene::load_scene2(&path).unwrap().world;
    let per_step = allocations_per_step(|| world.step().unwrap(), 300, 100);
    assert_eq!(per_step, 0.0, "pyramid: {per_step} allocations per step");
}

#[test]
fn complete_collision_steps_without_allocating_once_at_rest() {
    // The four equal cubes (box pieces: manifolds by GJK/EPA and clipping, the penetration
    // measure by the boxes' separating axes) and the tee on its box (a non-convex body: two
    // pieces, the penetration measure by GJK/EPA), each after 3 s at rest.
    for name in ["cube_stack", "tee_on_box"] {
        let path = common::project_root().join(format!("scenes/{name}.json"));
        let mut world = World::new(&load_scene(&path).unwrap()).unwrap();
        let per_step = allocations_per_step(|| world.step().unwrap(), 300, 100);
        assert_eq!(per_step, 0.0, "{name}: {per_step} allocations per step");
    }
}
