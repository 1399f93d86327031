//! insta snapshots of compact run summaries (docs/verification.md §"Snapshots"): a change in
//! behaviour of any canonical or assignment scene shows as a reviewable diff in
//! tests/snapshots/. Review with `cargo insta review`; accept only intended changes.

mod common;

use rigidref::faults::Faults;
use rigidref::golden::summary;
use rigidref::scene::load_scene;

/// Seconds summarised per scene.
const SECONDS: u32 = 5;

#[test]
fn canonical_scene_summaries_are_unchanged() {
    let root = common::project_root();
    for path in rigidref::golden::canonical_scenes(&root.join("scenes")).unwrap() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = summary(&load_scene(&path).unwrap(), Faults::NONE, SECONDS).unwrap();
        insta::assert_snapshot!(format!("canonical_{name}"), text);
    }
}

#[test]
fn assignment_scene_summaries_are_unchanged() {
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    for i in 1..=7 {
        let path = dir.join(format!("scenes/scene{i}.json"));
        let text = summary(&load_scene(&path).unwrap(), Faults::NONE, SECONDS).unwrap();
        insta::assert_snapshot!(format!("assignment_scene{i}"), text);
    }
}
