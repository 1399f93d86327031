//! Every crash the fuzzers found (docs/fuzzing.md), replayed through the same harness as its
//! fuzz target: the input must give an answer or an error, never a panic. The inputs live in
//! tests/fuzz-regressions/TARGET/.

use crate::common;

use rigidref::rigid3d::scene::{Overrides, SameBodyFiles, parse_scene};

/// The 3D harness: scene, body JSON and OBJ separated by 0xFF; parse, make the world, step twice
/// (what the single 3D target did when it found the crash; it is now split into
/// fuzz/fuzz_targets/scene3d.rs, parsing, and world3d.rs, the world of small meshes). Returns
/// whether the world was made.
fn scene3d(data: &[u8]) -> bool {
    let parts: Vec<&[u8]> = data.splitn(3, |&b| b == 0xFF).collect();
    let [scene, json, obj] = parts[..] else {
        return false;
    };
    let text = |b: &[u8]| String::from_utf8_lossy(b).to_string();
    let files = SameBodyFiles {
        json: text(json),
        obj: text(obj),
    };
    let Ok(scene) = parse_scene(
        &text(scene),
        "fuzz.json",
        "fuzz",
        &files,
        &Overrides::default(),
    ) else {
        return false;
    };
    let Ok(mut world) = rigidref::rigid3d::world::World::new(&scene) else {
        return false;
    };
    for _ in 0..2 {
        if rigidref::sim::Simulation::step(&mut world).is_err() {
            break;
        }
    }
    true
}

/// The trace harness (fuzz/fuzz_targets/trace.rs): read, then compare with itself in both
/// modes. Returns whether the trace was read.
fn trace(data: &[u8]) -> bool {
    use rigidref::tools::grading::compare::{
        OutcomeTolerances, TrajectoryTolerances, compare_outcomes, compare_trajectories,
    };
    let Ok(trace) = rigidref::rigid3d::trace::read_trace(std::io::Cursor::new(data), "fuzz.jsonl")
    else {
        return false;
    };
    let _ = compare_trajectories(&trace, &trace, &TrajectoryTolerances::default());
    let _ = compare_outcomes(&trace, &trace, None, &OutcomeTolerances::default());
    true
}

/// The inputs, by target:
/// - scene3d/flat-piece: a mutated ball mesh whose convex decomposition yields a piece spanning
///   no volume; parry's panicking hull used to abort the run (now the fallible one: the piece is
///   dropped).
/// - trace/contact-body-out-of-range: a trace whose contact names body 2 of 1; outcome mode
///   indexed the header's bodies with it (now the trace is refused as naming other bodies).
/// - world3d/folded-cube-vhacd: a cube with a vertex pushed through a face; parry's V-HACD
///   unwrapped its own convex hull and panicked (now the world is refused: the mesh cannot be
///   decomposed).
#[test]
fn every_fuzz_crash_replays_without_a_panic() {
    let root = common::project_root().join("tests/fuzz-regressions");
    let mut n = 0;
    for (target, harness) in [
        ("scene3d", scene3d as fn(&[u8]) -> bool),
        ("world3d", scene3d),
        ("trace", trace),
    ] {
        for entry in std::fs::read_dir(root.join(target)).unwrap() {
            let path = entry.unwrap().path();
            let data = std::fs::read(&path).unwrap();
            let done = harness(&data);
            println!("{}: read and run: {done}", path.display());
            n += 1;
        }
    }
    assert!(n >= 3, "regression inputs missing in {}", root.display());
}

/// The folded cube's world is refused with a message saying what failed, not a panic (parry's
/// V-HACD panics inside; `src/rigid3d/collide/pieces.rs` catches it).
#[test]
fn a_mesh_the_convex_decomposition_cannot_handle_is_refused_in_one_line() {
    let data = std::fs::read(
        common::project_root().join("tests/fuzz-regressions/world3d/folded-cube-vhacd"),
    )
    .unwrap();
    let parts: Vec<&[u8]> = data.splitn(3, |&b| b == 0xFF).collect();
    let text = |b: &[u8]| String::from_utf8_lossy(b).to_string();
    let files = SameBodyFiles {
        json: text(parts[1]),
        obj: text(parts[2]),
    };
    let scene = parse_scene(
        &text(parts[0]),
        "fuzz.json",
        "fuzz",
        &files,
        &Overrides::default(),
    )
    .unwrap();
    let Err(e) = rigidref::rigid3d::world::World::new(&scene) else {
        panic!("the folded cube was decomposed");
    };
    assert!(
        e.contains("body.json: body \"light (2 g)\"")
            && e.ends_with("the convex decomposition of the mesh failed inside parry's V-HACD; the mesh may fold over itself"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}
