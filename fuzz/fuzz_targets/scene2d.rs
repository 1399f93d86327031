//! 2D scene files: the input is the scene JSON, written beside a copy of the project's
//! scenes/blocks/stack.png (its `image` key may name `stack.png` or anything else). Load, and
//! step the world twice. Nothing may panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    thread_local! {
        static DIR: tempfile::TempDir = {
            let dir = tempfile::tempdir().unwrap();
            let image = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/blocks/stack.png");
            std::fs::copy(image, dir.path().join("stack.png")).unwrap();
            dir
        };
    }
    DIR.with(|dir| {
        let path = dir.path().join("scene.json");
        std::fs::write(&path, data).unwrap();
        if let Ok(scene) = rigidref::blocks2d::scene::load_scene2(&path) {
            let mut world = scene.world;
            for _ in 0..2 {
                if rigidref::sim::Simulation::step(&mut world).is_err() {
                    break;
                }
            }
        }
    });
});
