//! insta snapshots of compact run summaries (docs/verification.md §"Snapshots"): a change in
//! behaviour of any canonical or assignment scene shows as a reviewable diff in
//! tests/suite/verify/snapshots/. Review with `cargo insta review`; accept only intended changes.

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::verify::snapshots::{summary, summary2};

/// Checks `text` against tests/suite/verify/snapshots/snapshots__NAME.snap (the names the
/// snapshots had when each test file was its own binary, kept so that the files are unchanged).
fn assert_snapshot(name: &str, text: &str) {
    insta::with_settings!({prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!(format!("snapshots__{name}"), text);
    });
}

/// Seconds summarised per scene.
const SECONDS: u32 = 5;

#[test]
fn canonical_scene_summaries_are_unchanged() {
    let root = common::project_root();
    for path in rigidref::verify::golden::canonical_scenes(&root.join("scenes")).unwrap() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = summary(&load_scene(&path).unwrap(), SECONDS).unwrap();
        assert_snapshot(&format!("canonical_{name}"), &text);
    }
}

#[test]
fn assignment_scene_summaries_are_unchanged() {
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    for i in 1..=7 {
        let path = dir.join(format!("scenes/scene{i}.json"));
        let text = summary(&load_scene(&path).unwrap(), SECONDS).unwrap();
        assert_snapshot(&format!("assignment_scene{i}"), &text);
    }
}

/// The project's 2D scenes (scenes/blocks/*.json): every 4 time units to 20, energies, contacts
/// and every moving body's state, to four decimals.
#[test]
fn blocks_scene_summaries_are_unchanged() {
    let dir = common::project_root().join("scenes/blocks");
    for name in ["stack", "pyramid", "dominoes", "seesaw", "pendulum"] {
        let scene =
            rigidref::blocks2d::scene::load_scene2(&dir.join(format!("{name}.json"))).unwrap();
        let text = summary2(scene.world, 4.0, 20.0).unwrap();
        assert_snapshot(&format!("blocks_{name}"), &text);
    }
}

/// Every image of the 2D assignment, as loaded: its bodies, pinned bodies, blocks and the total
/// mass of its moving bodies. A change in loading (threshold, connectivity, mass formula) shows
/// here as a diff.
#[test]
fn assignment_image_loading_is_unchanged() {
    let Some(dir) = common::blocks2d_assignment() else {
        return;
    };
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    paths.sort();
    let mut text = String::new();
    for path in paths {
        let groups = rigidref::blocks2d::image::load_image(
            &path,
            &rigidref::blocks2d::image::ImageSettings::default(),
        )
        .unwrap();
        let blocks: usize = groups.iter().map(|g| g.blocks.len()).sum();
        let moving_mass: f64 = groups
            .iter()
            .filter(|g| !g.pinned)
            .flat_map(|g| &g.blocks)
            .map(|b| b.mass)
            .sum();
        text += &format!(
            "{}: {} bodies, {} pinned, {blocks} blocks, moving mass {:.4}\n",
            path.file_name().unwrap().to_string_lossy(),
            groups.len(),
            groups.iter().filter(|g| g.pinned).count(),
            moving_mass
        );
    }
    assert_snapshot("blocks2d_images", &text);
}
