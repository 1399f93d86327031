//! Temporal coherence in 3D detection (docs/contact.md §"Temporal coherence"): the kept
//! candidate lists find the same contacts as fresh detection, bit for bit, on every substep of
//! the canonical scenes, and the debug check that says so can fail.

use crate::common;

use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::rigid3d::world::World;
use rigidref::verify::faults::{Faults, with_faults};

/// The project's 3D scenes, and the assignment's seven where ../shared is present.
fn canonical_scenes() -> Vec<(String, Scene)> {
    let mut scenes = Vec::new();
    let dir = common::project_root().join("scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    paths.sort();
    if let Some(assignment) = common::rigid3d_assignment() {
        paths.extend((1..=7).map(|k| assignment.join(format!("scenes/scene{k}.json"))));
    } else {
        eprintln!("skipping the assignment's scenes: ../shared is absent");
    }
    for path in paths {
        let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        scenes.push((
            path.file_name().unwrap().to_string_lossy().into_owned(),
            scene,
        ));
    }
    scenes
}

/// The detection statistics of each of the project's scenes `names`, run for `seconds` with the
/// cache and its check on, after asserting that every substep was checked and none differed
/// from fresh detection.
fn stats_of_checked_runs(
    names: &[&str],
    seconds: f64,
) -> Vec<rigidref::common::pair_cache::CacheStats> {
    names
        .iter()
        .map(|name| {
            let mut scene = load_scene(&common::project_root().join("scenes").join(name)).unwrap();
            let world = run_checked(&mut scene, seconds);
            let stats = world.detection_stats();
            eprintln!("{name}: {stats:?}");
            assert_eq!(stats.checked, world.step * u64::from(scene.params.substeps));
            assert_eq!(
                stats.mismatches, 0,
                "{name}: cached detection differed from fresh"
            );
            stats
        })
        .collect()
}

/// Runs `frames` frames (at most 2 s) of `scene` with the cache and its check on; returns the
/// world.
fn run_checked(scene: &mut Scene, seconds: f64) -> World {
    scene.params.detection_cache = true;
    scene.params.check_detection = true;
    let mut world = World::new(scene).unwrap();
    let frames = (seconds / scene.params.dt).round() as u64;
    common::run(&mut world, frames, |_, _| {});
    world
}

#[test]
fn cached_detection_finds_the_fresh_contacts_on_every_substep_of_the_canonical_scenes() {
    let (mut reused, mut all) = (0, 0);
    let (mut nearest_kept, mut queries) = (0, 0);
    for (name, mut scene) in canonical_scenes() {
        let world = run_checked(&mut scene, 2.0);
        let stats = world.detection_stats();
        // Every substep that processed contacts compared the two (a scene without collision
        // checks has none).
        if scene.params.check_collisions {
            assert_eq!(
                stats.checked,
                world.step * u64::from(scene.params.substeps),
                "{name}: not every substep was checked"
            );
        }
        assert_eq!(
            stats.mismatches, 0,
            "{name}: cached detection differed from fresh"
        );
        eprintln!(
            "{name}: {} substeps checked, pair lists kept {} / found {} ({}), nearest triangles kept on {} of {} vertex queries",
            stats.checked,
            stats.reused,
            stats.refreshed,
            stats
                .hit_rate()
                .map_or("no pairs".into(), |r| format!("{:.1} % kept", 100.0 * r)),
            stats.nearest_kept,
            stats.queries,
        );
        reused += stats.reused;
        all += stats.reused + stats.refreshed;
        // The share of kept nearest triangles is measured on scenes whose bodies rest at some
        // depth: in the scenes written exactly touching every vertex lies on a face of the other
        // body, where no triangle is nearer than the rest by the gap, and the cache rightly
        // keeps none (their lists and contacts are still checked above).
        if !name.starts_with("touching_") {
            (nearest_kept, queries) = (nearest_kept + stats.nearest_kept, queries + stats.queries);
        }
    }
    // The kept nearest triangles answered a share of the vertex queries, with the same contacts.
    assert!(
        nearest_kept * 5 > queries && queries > 1000,
        "nearest triangles kept on {nearest_kept} of {queries} queries"
    );
    // The check is not vacuous: bodies met (pairs were visited) and the lists were used.
    assert!(all > 1000, "only {all} pair visits in all the scenes");
    assert!(
        reused * 2 > all,
        "the lists served only {reused} of {all} pair visits"
    );
}

#[test]
fn kept_nearest_triangles_give_the_fresh_contacts_while_a_body_slides_and_turns() {
    // The tapered stack without friction, its top cube sliding at 5 cm/s and turning at 0.1
    // rad/s on the cube below until it passes the edge and tips (after about 1 s): its candidate
    // lists are kept while it moves and found again each time it has moved half the margin, so
    // kept nearest triangles answer vertex queries at every distance from their anchor up to the
    // bound, and near the edge, where the nearest triangle changes. Every substep is compared
    // with fresh detection. (With the uniqueness test removed, so that a shallow vertex keeps
    // whichever triangle the search found, 21 substeps differ.)
    let path = common::project_root().join("scenes/box_stack.json");
    let run = |v: f64, omega: f64| {
        let mut scene = load_scene(&path).unwrap();
        scene.params.mu = 0.0;
        let top = scene.bodies.len() - 1;
        scene.bodies[top].v0 = nalgebra::Vector3::new(v, 0.0, 0.0);
        scene.bodies[top].omega0 = nalgebra::Vector3::new(0.0, omega, 0.0);
        let world = run_checked(&mut scene, 2.0);
        let stats = world.detection_stats();
        assert_eq!(stats.mismatches, 0, "cached detection differed from fresh");
        assert_eq!(stats.checked, world.step * u64::from(scene.params.substeps));
        stats
    };
    let (resting, sliding) = (run(0.0, 0.0), run(0.05, 0.1));
    eprintln!("resting {resting:?}\nsliding {sliding:?}");
    // The sliding pair's list was found again many times (motion, not only the first step), and
    // kept triangles still answered most of what they answer at rest.
    assert!(sliding.refreshed >= resting.refreshed + 20, "{sliding:?}");
    assert!(resting.nearest_kept > 1000, "{resting:?}");
    assert!(
        sliding.nearest_kept * 4 >= resting.nearest_kept * 3,
        "{resting:?} {sliding:?}"
    );
}

#[test]
fn a_complete_collision_scene_with_the_cache_finds_the_fresh_contacts_too() {
    // `collision: complete` adds the piece pairs to the lists: the tapered stack and the tee on
    // a box (a non-convex body in pieces) with it.
    for name in [
        "box_stack.json",
        "tee_on_box.json",
        "edge_landing.json",
        "collision.json",
    ] {
        let path = common::project_root().join("scenes").join(name);
        let mut scene = load_scene(&path).unwrap();
        scene.params.collision = rigidref::rigid3d::collide::CollisionMethod::Complete;
        let world = run_checked(&mut scene, 2.0);
        let stats = world.detection_stats();
        assert!(stats.checked > 0, "{name}: nothing checked");
        assert_eq!(
            stats.mismatches, 0,
            "{name}: cached detection differed from fresh"
        );
    }
}

#[test]
fn the_check_catches_lists_kept_after_the_bodies_have_moved() {
    // Teeth: with the lists never refreshed, a scene whose bodies fly into each other must show
    // differences (otherwise the check above proves nothing).
    let path = common::project_root().join("scenes").join("collision.json");
    let mut scene = load_scene(&path).unwrap();
    let faults = Faults {
        stale_detection_cache: true,
        ..Faults::NONE
    };
    let world = with_faults(faults, || run_checked(&mut scene, 2.0));
    let stats = world.detection_stats();
    assert!(
        stats.mismatches > 0,
        "stale lists went unnoticed over {} checked substeps",
        stats.checked
    );
}

#[test]
fn the_detection_cache_on_and_off_give_the_same_trace_bit_for_bit() {
    for scene in ["box_stack.json", "cube_stack.json", "collision.json"] {
        let path = common::project_root().join("scenes").join(scene);
        let run = |set: &[&str]| common::trace_records(&path, "1", set);
        let cached = run(&[]);
        let fresh = run(&["--set", "detection_cache=false"]);
        assert!(cached.len() > 50);
        assert!(cached == fresh, "{scene}: the traces differ");
    }
}

#[test]
fn run_reports_the_detection_check_when_it_is_switched_on() {
    // A user's switch: `--set check_detection=true` on a 3D and a 2D scene; the summary says how
    // many substeps were compared (a difference would be an error naming the scene).
    let tmp = tempfile::tempdir().unwrap();
    for scene in ["scenes/box_stack.json", "scenes/blocks/stack.json"] {
        let path = common::project_root().join(scene);
        let out = common::rigidref(
            &[
                "run",
                path.to_str().unwrap(),
                "--time",
                "1",
                "--set",
                "check_detection=true",
                "--out",
                "t.jsonl",
            ],
            tmp.path(),
        );
        common::assert_success(&out);
        let stderr = common::stderr(&out);
        assert!(
            stderr.contains("detection      checked on") && stderr.contains("bit for bit"),
            "{scene}: {stderr}"
        );
    }
}

/// The scenes written exactly touching (two cubes, ten cubes): every vertex of a body starts on
/// a face of the one below, where no nearest triangle is unique. Found on the surface by one
/// search, such a vertex skips the next while it stays within half the surface tolerance of the
/// same triangle (docs/contact.md §"Temporal coherence", "Vertices on the surface"). Over 1 s,
/// every substep against fresh detection: the same contacts, bit for bit, and queries answered
/// on the surface (else the check would prove nothing about the skip; its teeth are
/// `the_check_catches_vertices_skipped_after_they_left_the_surface`).
#[test]
fn vertices_on_the_surface_skip_the_search_and_give_the_fresh_contacts() {
    let (mut on_surface, mut queries) = (0, 0);
    for stats in stats_of_checked_runs(&["touching_two_cubes.json", "touching_ten_cubes.json"], 1.0)
    {
        (on_surface, queries) = (on_surface + stats.on_surface, queries + stats.queries);
    }
    // Measured: 7 992 of touching_two_cubes' 8 000 queries, none of touching_ten_cubes' 1 439
    // (its vertices are not within 0.5e-9 ρ of a face once it settles).
    assert!(
        on_surface > 1000,
        "{on_surface} of {queries} vertex queries answered on the surface"
    );
}

#[test]
fn the_check_catches_vertices_skipped_after_they_left_the_surface() {
    // Teeth: with the skip taken without checking that the vertex is still on the surface, the
    // scenes written exactly touching (every vertex on a face at first, sinking into it under
    // gravity) must show differences from fresh detection.
    let faults = Faults {
        surface_skip_unchecked: true,
        ..Faults::NONE
    };
    let mut mismatches = 0;
    for name in ["touching_two_cubes.json", "touching_ten_cubes.json"] {
        let mut scene = load_scene(&common::project_root().join("scenes").join(name)).unwrap();
        let world = with_faults(faults, || run_checked(&mut scene, 1.0));
        mismatches += world.detection_stats().mismatches;
    }
    assert!(
        mismatches > 0,
        "vertices skipped off the surface went unnoticed"
    );
}

/// Leading triangles (docs/contact.md §"Temporal coherence", "Leading triangles"): a vertex
/// whose nearest triangle leads every other by less than the kept triangles' gap (a cube's
/// corner over the edge of the cube below) is answered on it while it stays within half the
/// lead of where its search found it. Resting stacks and pyramids, every substep against fresh
/// detection: the same contacts, bit for bit, and most vertex queries answered on a leading
/// triangle (else the check would prove nothing about them; their teeth are
/// `the_check_catches_leading_triangles_kept_after_the_vertex_moved_too_far`).
#[test]
fn leading_triangles_answer_resting_vertices_and_give_the_fresh_contacts() {
    // Measured over 2 s: 2 075 of touching_pyramid's 2 605 queries, 1 173 of touching_ten_cubes'
    // 3 164 (its vertices exactly over the edges of the cubes below tie and are searched).
    let (mut leading, mut queries) = (0, 0);
    for stats in stats_of_checked_runs(&["touching_pyramid.json", "touching_ten_cubes.json"], 2.0) {
        (leading, queries) = (leading + stats.nearest_leading, queries + stats.queries);
    }
    assert!(
        leading * 2 > queries,
        "{leading} of {queries} vertex queries answered on a leading triangle"
    );
}

#[test]
fn the_check_catches_leading_triangles_kept_after_the_vertex_moved_too_far() {
    // Teeth: answered on its leading triangle however far the vertex has moved, a body sliding
    // and turning on another (the tapered stack's top cube, as in
    // `kept_nearest_triangles_give_the_fresh_contacts_while_a_body_slides_and_turns`) and the
    // canonical scenes with moving bodies must show differences from fresh detection.
    let faults = Faults {
        leading_motion_unchecked: true,
        ..Faults::NONE
    };
    let path = common::project_root().join("scenes/box_stack.json");
    let mut scene = load_scene(&path).unwrap();
    scene.params.mu = 0.0;
    let top = scene.bodies.len() - 1;
    scene.bodies[top].v0 = nalgebra::Vector3::new(0.05, 0.0, 0.0);
    scene.bodies[top].omega0 = nalgebra::Vector3::new(0.0, 0.1, 0.0);
    let world = with_faults(faults, || run_checked(&mut scene, 2.0));
    assert!(
        world.detection_stats().mismatches > 0,
        "vertices answered on a triangle they had left went unnoticed"
    );
}

/// With `collision: complete`, a piece pair whose full search chose a face with a lead ℓ (the
/// face would be chosen again while the pair moves less than ℓ less round-off) is answered on
/// that face alone, without the search (docs/contact.md §"Temporal coherence", "Leading axes").
/// Over 2 s of the resting complete scenes, every substep against fresh detection: the same
/// contacts, bit for bit, and manifolds answered on their kept axis (else the check proves
/// nothing about it; its teeth are `the_check_catches_leading_axes_kept_after_the_pair_moved_too_far`).
#[test]
fn leading_axes_answer_resting_piece_pairs_and_give_the_fresh_contacts() {
    let (mut kept, mut searched) = (0, 0);
    for stats in stats_of_checked_runs(
        &[
            "cube_stack.json",
            "touching_pyramid.json",
            "touching_ten_cubes.json",
        ],
        2.0,
    ) {
        (kept, searched) = (
            kept + stats.manifolds_kept,
            searched + stats.manifolds_searched,
        );
    }
    assert!(
        kept * 4 > kept + searched,
        "{kept} of {} piece-pair manifolds answered on a kept axis",
        kept + searched
    );
}

#[test]
fn the_check_catches_leading_axes_kept_after_the_pair_moved_too_far() {
    // Teeth: answered on its kept axis however far the pair has moved (up to the search's
    // stopping gap, which the answer still checks), the cubes of touching_pyramid.json settling
    // onto each other must show a difference from fresh detection (measured: 1 substep of 200;
    // the placements of `rigid3d::complete::a_kept_face_axis_is_wrong_when_the_pair_moves_past_its_lead`
    // show it more often).
    let faults = Faults {
        axis_lead_motion_unchecked: true,
        ..Faults::NONE
    };
    let path = common::project_root().join("scenes/touching_pyramid.json");
    let mut scene = load_scene(&path).unwrap();
    let world = with_faults(faults, || run_checked(&mut scene, 2.0));
    let stats = world.detection_stats();
    assert!(
        stats.mismatches > 0,
        "piece pairs answered on an axis they had left went unnoticed: {stats:?}"
    );
}
