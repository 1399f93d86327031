//! 3D worlds from small scenes: the input is as `scene3d`'s (scene JSON, body JSON, OBJ,
//! separated by 0xFF bytes). What parses with at most 4 bodies of at most 64 vertices each is
//! made into a world (the convex pieces, the BVHs) and stepped twice: detection, assembly, the
//! solve and the integration on whatever numbers the parser let through. Nothing may panic. The
//! size bound keeps detection cheap; a mesh that is not exactly convex is still decomposed into
//! convex pieces (about a second), which bounds this target's rate (docs/fuzzing.md).
//! `scene3d` parses the larger meshes.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "scene_input.rs"]
mod scene_input;

fuzz_target!(|data: &[u8]| {
    let Some(scene) = scene_input::scene(data) else { return };
    if scene.bodies.len() > 4 || scene.bodies.iter().any(|b| b.mesh.vertices.len() > 64) {
        return;
    }
    if let Ok(mut world) = rigidref::rigid3d::world::World::new(&scene) {
        for _ in 0..2 {
            if rigidref::sim::Simulation::step(&mut world).is_err() {
                break;
            }
        }
    }
});
