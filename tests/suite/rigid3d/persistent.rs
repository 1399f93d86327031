//! Persistent contact manifolds (docs/contact.md §"Persistent manifolds"): kept features give
//! fresh detection's contacts bit for bit at an unchanged pose, differ from them elsewhere only
//! within the bound fresh detection itself meets (the oracle's), and the check that says so can
//! fail.

use crate::common;

use rigidref::rigid3d::collide::audit::kept_manifolds_agree;
use rigidref::rigid3d::collide::detect::{CollisionMethod, Detector, detect_contacts};
use rigidref::rigid3d::collide::manifold::speculative_margin;
use rigidref::rigid3d::collide::pieces::pose;
use rigidref::rigid3d::collide::sat::OracleBuffers;
use rigidref::rigid3d::collide::{Contact, Feature};
use rigidref::rigid3d::frame::ContactFrame;
use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::rigid3d::world::World;

/// The project's scenes that use `collision: complete`.
fn complete_scenes() -> Vec<(String, Scene)> {
    let dir = common::project_root().join("scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    paths.sort();
    let mut scenes = Vec::new();
    for path in paths {
        let Ok(scene) = load_scene(&path) else {
            continue; // a 2D scene, or a scene of another format
        };
        if scene.params.collision == CollisionMethod::Complete {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            scenes.push((name, scene));
        }
    }
    scenes
}

fn persistent(scene: &mut Scene) {
    scene.params.detection_cache = true;
    scene.params.persistent_manifolds = true;
}

#[test]
fn kept_manifolds_agree_with_fresh_detection_within_the_bound_on_the_canonical_complete_scenes() {
    let scenes = complete_scenes();
    assert!(
        scenes.len() >= 5,
        "too few complete scenes: {}",
        scenes.len()
    );
    let (mut kept, mut searched) = (0, 0);
    for (name, mut scene) in scenes {
        persistent(&mut scene);
        scene.params.check_detection = true;
        let mut world = World::new(&scene).unwrap();
        let frames = (2.0 / scene.params.dt).round() as u64;
        common::run(&mut world, frames, |_, _| {});
        let stats = world.detection_stats();
        assert_eq!(
            stats.mismatches,
            0,
            "{name}: cached detection differed from fresh beyond what a kept manifold may: {}",
            world.detection_check_example().unwrap_or("")
        );
        eprintln!(
            "{name}: {} substeps checked, {} differed within the bound; manifolds kept {} / searched {}",
            stats.checked, stats.kept_differs, stats.manifolds_kept, stats.manifolds_searched
        );
        kept += stats.manifolds_kept;
        searched += stats.manifolds_searched;
    }
    // Resting and slowly moving piece pairs are most of these scenes: the kept features must
    // serve most manifolds, or the option saves nothing.
    assert!(
        kept > searched,
        "kept features served {kept} manifolds, the full search ran {searched} times"
    );
}

#[test]
fn kept_features_give_the_fresh_manifold_bit_for_bit_at_an_unchanged_pose() {
    for name in [
        "cube_stack.json",
        "touching_pyramid.json",
        "edge_landing.json",
    ] {
        let mut scene = load_scene(&common::project_root().join("scenes").join(name)).unwrap();
        persistent(&mut scene);
        let mut world = World::new(&scene).unwrap();
        let mut served = 0;
        for _ in 0..10 {
            common::run(&mut world, 10, |_, _| {});
            // Features found at this pose, then used again at it.
            let mut detector = Detector::cached(false).with_persistent_manifolds(true);
            let (mut first, mut second, mut fresh) = (Vec::new(), Vec::new(), Vec::new());
            let method = CollisionMethod::Complete;
            detector.detect(&world.bodies, world.colliders(), method, &mut first);
            detector.detect(&world.bodies, world.colliders(), method, &mut second);
            detect_contacts(&world.bodies, world.colliders(), method, &mut fresh);
            assert_eq!(
                first, fresh,
                "{name}: first call differs from fresh detection"
            );
            assert_eq!(
                second, fresh,
                "{name}: kept features differ at the same pose"
            );
            served += detector.stats().manifolds_kept;
        }
        assert!(served > 0, "{name}: the kept features never served");
    }
}

#[test]
fn the_check_rejects_a_manifold_contact_along_a_wrong_axis() {
    let scene = load_scene(&common::project_root().join("scenes/cube_stack.json")).unwrap();
    let mut world = World::new(&scene).unwrap();
    common::run(&mut world, 50, |_, _| {});
    let mut fresh = Vec::new();
    detect_contacts(
        &world.bodies,
        world.colliders(),
        CollisionMethod::Complete,
        &mut fresh,
    );
    let mut oracle = OracleBuffers::default();
    assert!(
        kept_manifolds_agree(
            &world.bodies,
            world.colliders(),
            &fresh,
            &fresh,
            &mut oracle
        )
        .is_ok()
    );
    // A body-pair manifold contact turned to a horizontal normal: the boxes overlap along it
    // by a box's width, far beyond the bound.
    let mut wrong: Vec<Contact> = fresh.clone();
    let k = wrong
        .iter()
        .position(|c| matches!(c.feature, Feature::Manifold { .. }) && c.body2.is_some())
        .expect("cube_stack has manifold contacts between boxes");
    wrong[k].frame = ContactFrame::from_normal(&nalgebra::Vector3::x());
    assert!(
        kept_manifolds_agree(
            &world.bodies,
            world.colliders(),
            &wrong,
            &fresh,
            &mut oracle
        )
        .is_err()
    );
    // A vertex-rule or ground contact changed by a bit is not allowed either.
    let mut nudged = fresh.clone();
    let v = nudged
        .iter()
        .position(|c| !matches!(c.feature, Feature::Manifold { .. }))
        .expect("cube_stack has ground contacts");
    nudged[v].depth = f64::from_bits(nudged[v].depth.to_bits() + 1);
    assert!(
        kept_manifolds_agree(
            &world.bodies,
            world.colliders(),
            &nudged,
            &fresh,
            &mut oracle
        )
        .is_err()
    );
}

/// A detector keeps each body's pieces' world boxes for the rest of one detection only
/// (`PieceBoxes`, docs/performance.md §"Issue 49: the set-up in problem order"): one detector
/// asked at a pose where the upper bar of the edge-on-edge scene is lifted by 1.5 speculative
/// margins (the bodies' grown boxes still pair, the pieces' boxes are apart by more than the
/// margin), then at the pose where its edge rests across the lower bar's, gives fresh
/// detection's contacts both times (boxes kept from the first pose would keep the pieces apart at
/// the second and lose the crossing's manifold point, which no vertex gives), and so again
/// lifted.
#[test]
fn a_detector_forms_the_piece_boxes_afresh_at_each_detection() {
    let scene =
        load_scene(&common::project_root().join("scenes/touching_edge_on_edge.json")).unwrap();
    let mut world = World::new(&scene).unwrap();
    common::run(&mut world, 20, |_, _| {});
    let resting = world.bodies.clone();
    let mut lifted = resting.clone();
    let last = lifted.len() - 1;
    let radius = |k: usize| world.colliders()[k].radius();
    // Lifted so that the bars' pieces' world boxes are 1.5 margins apart in y.
    let piece_box = |k: usize| world.colliders()[k].pieces.pieces[0].world_aabb(&pose(&resting[k]));
    let overlap = piece_box(0).max.y - piece_box(last).min.y;
    lifted[last].x.y += overlap + 1.5 * speculative_margin(radius(0).min(radius(last)));
    let method = CollisionMethod::Complete;
    let mut detector = Detector::cached(false);
    for (name, bodies) in [
        ("lifted", &lifted),
        ("resting", &resting),
        ("lifted again", &lifted),
    ] {
        let (mut kept, mut fresh) = (Vec::new(), Vec::new());
        detector.detect(bodies, world.colliders(), method, &mut kept);
        detect_contacts(bodies, world.colliders(), method, &mut fresh);
        assert_eq!(
            kept, fresh,
            "{name}: the detector differs from fresh detection"
        );
    }
    let mut fresh = Vec::new();
    detect_contacts(&resting, world.colliders(), method, &mut fresh);
    let manifold = |c: &&Contact| {
        (c.body1 == last || c.body2 == Some(last)) && matches!(c.feature, Feature::Manifold { .. })
    };
    assert!(
        fresh.iter().filter(manifold).count() > 0,
        "the resting bar has a manifold contact: {fresh:?}"
    );
}
