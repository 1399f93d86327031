//! Benchmark: the cost of `collision: complete` against `vertices`, measured side by side in one
//! run on the same configurations (docs/contact.md §"Complete collision detection").
//!
//!     cargo bench --bench collision
//!
//! Prints, for the canonical equal-box stack (scenes/cube_stack.json) and the tapered stack
//! (scenes/box_stack.json): the time of one whole step with each method (the stack's own
//! configuration, run from its start), and of detection alone and of the penetration measure on
//! the same frozen states. Ratios, not absolute times, are the result: the machine is shared.

use rigidref::rigid3d::collide::penetration::penetrations;
use rigidref::rigid3d::collide::{CollisionMethod, detect_contacts};
use rigidref::rigid3d::scene::load_scene;
use rigidref::rigid3d::world::World;
use std::path::Path;
use std::time::Instant;

/// Median of `rounds` timings of `f`, each over `reps` calls, in µs per call.
fn median_us(rounds: usize, reps: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..rounds)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..reps {
                f();
            }
            start.elapsed().as_secs_f64() * 1e6 / reps as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[rounds / 2]
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    println!(
        "{:<16} {:>12} {:>12} {:>7}   {:>12} {:>12} {:>7}   {:>12}",
        "scene",
        "step vert µs",
        "step comp µs",
        "ratio",
        "detect vert",
        "detect comp",
        "ratio",
        "measure µs"
    );
    for name in ["cube_stack.json", "box_stack.json"] {
        let scene = load_scene(&root.join(name)).expect("scene loads");
        // Whole steps: each method from the scene's start, 300 frames (the stack settles).
        let step_us = |method: CollisionMethod| {
            let mut s = scene.clone();
            s.params.collision = method;
            let mut world = World::new(&s).unwrap();
            median_us(5, 60, || world.step().unwrap())
        };
        let (step_v, step_c) = (
            step_us(CollisionMethod::Vertices),
            step_us(CollisionMethod::Complete),
        );
        // Detection and the measure alone, on the stack's own settled state (complete keeps it
        // standing, so both methods see the same resting configuration).
        let mut s = scene.clone();
        s.params.collision = CollisionMethod::Complete;
        let mut world = World::new(&s).unwrap();
        for _ in 0..100 {
            world.step().unwrap();
        }
        let mut contacts = Vec::new();
        let mut detect_us = |method| {
            median_us(7, 300, || {
                detect_contacts(&world.bodies, world.colliders(), method, &mut contacts)
            })
        };
        let (det_v, det_c) = (
            detect_us(CollisionMethod::Vertices),
            detect_us(CollisionMethod::Complete),
        );
        let mut found = Vec::new();
        let measure = median_us(7, 300, || {
            penetrations(&world.bodies, world.colliders(), &mut found)
        });
        println!(
            "{:<16} {:>12.1} {:>12.1} {:>7.2}   {:>12.1} {:>12.1} {:>7.2}   {:>12.1}",
            name.trim_end_matches(".json"),
            step_v,
            step_c,
            step_c / step_v,
            det_v,
            det_c,
            det_c / det_v,
            measure
        );
    }
}
