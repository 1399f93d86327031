//! `collision: complete` and the penetration measure (docs/contact.md §"Convex pieces",
//! §"Complete collision detection", §"Penetration measure"): equal boxes stack, edges landing on
//! edges are caught, non-convex bodies rest, the vertex rule's contacts are all kept, and the
//! penetration measure agrees with its separating-axis oracle.

use crate::common;

use nalgebra::{Matrix3, Rotation3, Vector3};
use proptest::prelude::*;
use rigidref::rigid3d::collide::penetration::{
    PENETRATION_BOUND, body_size, brute_force_pair_depth, pair_depth,
};
use rigidref::rigid3d::collide::persistent::{KeepRule, KeptCounts, KeptFeatures, kept_contact};
use rigidref::rigid3d::collide::pieces::ConvexPieces;
use rigidref::rigid3d::collide::separating_axes::{AXIS_TIE_TOLERANCE, Placement, SatBuffers};
use rigidref::rigid3d::collide::{
    CollisionMethod, Contact, Feature, MeshCollider, detect_contacts,
};
use rigidref::rigid3d::mesh::TriMesh;
use rigidref::rigid3d::penetration_watch::InterpenetrationWatch;
use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::rigid3d::world::World;
use std::path::Path;
use std::sync::Arc;

/// Edge of the project's box mesh (scenes/data/box), m.
const BOX: f64 = 0.5;

fn canonical(name: &str) -> Scene {
    load_scene(&common::project_root().join("scenes").join(name)).expect("canonical scene loads")
}

fn turn_about_y(angle: f64) -> Matrix3<f64> {
    *Rotation3::from_axis_angle(&Vector3::y_axis(), angle).matrix()
}

/// Two project boxes: the lower resting on the ground, the upper 1 cm above it, turned `turn`
/// about y, with the given collision method.
fn two_boxes(turn: f64, collision: CollisionMethod) -> Scene {
    let mut scene = canonical("edge_landing.json");
    scene.params.collision = collision;
    scene.bodies[0].x0 = Vector3::new(0.0, 0.249, 0.0);
    scene.bodies[0].r0 = Matrix3::identity();
    scene.bodies[1].x0 = Vector3::new(0.0, 0.249 + BOX + 0.01, 0.0);
    scene.bodies[1].r0 = turn_about_y(turn);
    scene
}

fn world(scene: &Scene) -> World {
    World::new(scene).expect("world builds")
}

#[test]
fn equal_cubes_stand_on_each_other_whatever_their_turn() {
    for (turn, what) in [
        (0.0, "aligned"),
        (0.1, "turned 5.7°"),
        (std::f64::consts::FRAC_PI_4, "turned 45°"),
    ] {
        let mut w = world(&two_boxes(turn, CollisionMethod::Complete));
        common::run(&mut w, 500, |_, _| {});
        let (lower, upper) = (&w.bodies[0], &w.bodies[1]);
        // 1% of the cube's size, as the issue asks; the rest depth is set by the 5 mm slop.
        let gap = upper.x.y - lower.x.y;
        assert!(
            (gap - BOX).abs() <= 0.01 * BOX,
            "{what}: upper centre {gap} m above the lower, not {BOX}"
        );
        let horizontal = (upper.x - lower.x).xz().norm();
        assert!(horizontal < 0.01 * BOX, "{what}: upper slid {horizontal} m");
        assert!(
            w.deepest_penetration() < 0.01 * BOX,
            "{what}: {:?}",
            w.penetrations
        );
    }
}

#[test]
fn the_vertex_rule_lets_equal_cubes_sink_and_the_watch_names_the_pair() {
    for (turn, what) in [
        (0.0, "aligned"),
        (0.1, "turned 5.7°"),
        (std::f64::consts::FRAC_PI_4, "turned 45°"),
    ] {
        let mut w = world(&two_boxes(turn, CollisionMethod::Vertices));
        let mut watch = InterpenetrationWatch::default();
        let mut warnings = Vec::new();
        common::run(&mut w, 500, |w, _| warnings.extend(watch.observe(w)));
        // Today's behaviour: the upper box ends inside the lower one.
        let gap = w.bodies[1].x.y - w.bodies[0].x.y;
        assert!(
            gap < 0.1 * BOX,
            "{what}: the upper box did not sink ({gap} m)"
        );
        assert!(
            watch.deepest > PENETRATION_BOUND * BOX,
            "{what}: {}",
            watch.deepest
        );
        assert_eq!(
            warnings.len(),
            1,
            "{what}: one warning per pair: {warnings:?}"
        );
        let warning = &warnings[0];
        for fragment in [
            "warning: step ",
            "body 0 (\"lower box\") and body 1",
            "collision: complete",
        ] {
            assert!(warning.contains(fragment), "{what}: {warning}");
        }
    }
}

#[test]
fn the_vertex_rule_lets_the_stack_and_the_edge_landing_sink_and_warns() {
    for (file, pairs) in [("cube_stack.json", 6), ("edge_landing.json", 1)] {
        let mut scene = canonical(file);
        scene.params.collision = CollisionMethod::Vertices;
        let mut w = world(&scene);
        let mut watch = InterpenetrationWatch::default();
        let mut warnings = Vec::new();
        common::run(&mut w, 500, |w, _| warnings.extend(watch.observe(w)));
        assert!(
            watch.deepest > PENETRATION_BOUND * BOX,
            "{file}: {}",
            watch.deepest
        );
        // One warning per pair that went too deep: every pair of the stack ends in a heap.
        assert_eq!(warnings.len(), pairs, "{file}: {warnings:?}");
        assert!(
            warnings.iter().all(|w| w.contains("collision: complete")),
            "{warnings:?}"
        );
    }
}

#[test]
fn a_stack_of_four_equal_cubes_stands_for_ten_seconds() {
    let scene = canonical("cube_stack.json");
    assert_eq!(scene.params.collision, CollisionMethod::Complete);
    assert_eq!(scene.bodies.len(), 4);
    let start: Vec<Vector3<f64>> = scene.bodies.iter().map(|b| b.x0).collect();
    let mut w = world(&scene);
    let mut worst = 0.0_f64;
    common::run(&mut w, 1000, |w, _| {
        for (b, x0) in w.bodies.iter().zip(&start) {
            worst = worst.max((b.x - x0).norm());
        }
    });
    // 2% of the cube's size, as the issue asks.
    assert!(worst <= 0.02 * BOX, "a centre moved {worst} m");
}

#[test]
fn an_edge_landing_across_an_edge_ends_separated() {
    let scene = canonical("edge_landing.json");
    assert_eq!(scene.params.collision, CollisionMethod::Complete);
    let mut w = world(&scene);
    let mut first_pair_contacts: Option<Vec<Contact>> = None;
    let mut deepest = 0.0_f64;
    common::run(&mut w, 500, |w, k| {
        for p in &w.penetrations {
            assert!(!p.exceeds_bound(), "step {k}: {p:?}");
            deepest = deepest.max(p.depth);
        }
        if first_pair_contacts.is_none() {
            let between: Vec<Contact> = w
                .solves
                .iter()
                .flat_map(|s| s.contacts.iter().copied())
                .filter(|c| c.body2.is_some())
                .collect();
            if !between.is_empty() {
                first_pair_contacts = Some(between);
            }
        }
    });
    // The upper box's lowest edge (along x, over x ∈ [0, 0.5]) lands across the lower box's top
    // edge x = 0.25: the first contacts include the crossing of the two edges, at
    // (0.25, 0.499, 0), which no vertex marks and only the manifold finds. (The vertex rule
    // sees only the edge's end over the face, and the other end then falls into the box.)
    let first = first_pair_contacts.expect("the boxes touched");
    let crossing = Vector3::new(0.25, 0.499, 0.0);
    assert!(
        first
            .iter()
            .any(|c| matches!(c.feature, Feature::Manifold { .. })
                && (c.point - crossing).norm() < 0.01),
        "{first:?}"
    );
    // It tipped off the lower box and lies on the ground beside it.
    let (lower, upper) = (&w.bodies[0], &w.bodies[1]);
    assert!(
        upper.x.y < 0.3 && (upper.x - lower.x).xz().norm() > BOX,
        "{upper:?}"
    );
    let pair = w.penetrations.iter().find(|p| p.body2.is_some());
    assert!(pair.is_none(), "still interpenetrating: {pair:?}");
    println!("edge landing: deepest interpenetration {deepest:.4} m");
}

/// The assignment's `thing` (a bar with a post: non-convex) resting bar-down on the
/// assignment's cube, 1 cm above it at the start.
fn thing_on_cube(data: &Path) -> Scene {
    // The scene is read whole (meshes included), so the folder may go when this returns.
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    std::os::unix::fs::symlink(data, dir.join("data")).unwrap();
    let text = r#"{"sim_parameters": [{"name": "thing on cube", "dt": 0.01, "gravity": [0, -9.8, 0],
        "mu": 0.5, "collision": "complete"}],
      "bodies": [{"name": "cube", "file_root": "data/cube", "x0": [0, 1, 0]},
                 {"name": "thing", "file_root": "data/thing", "x0": [0, 3, 0]}]}"#;
    std::fs::write(dir.join("scenes/s.json"), text).unwrap();
    let mut scene = load_scene(&dir.join("scenes/s.json")).unwrap();
    let lowest = scene.bodies[1]
        .mesh
        .vertices
        .iter()
        .map(|v| v.y)
        .fold(f64::INFINITY, f64::min);
    scene.bodies[1].x0.y = 2.0 + 0.01 - lowest;
    scene.bodies[1].r0 = turn_about_y(0.3);
    scene
}

#[test]
fn the_thing_rests_on_a_cube() {
    let mut scenes = vec![("tee on box", canonical("tee_on_box.json"))];
    if let Some(dir) = common::rigid3d_assignment() {
        scenes.push(("thing on cube", thing_on_cube(&dir.join("data"))));
    }
    for (what, scene) in scenes {
        let mut w = world(&scene);
        assert!(
            !w.colliders()[1].pieces.convex,
            "{what}: the body is non-convex"
        );
        common::run(&mut w, 500, |_, _| {});
        let start = scene.bodies[1].x0;
        let moved = (w.bodies[1].x - start).norm();
        // It starts at most 1 cm above its support and must end resting on it, not in it.
        assert!(moved < 0.015, "{what}: moved {moved} m");
        assert!(
            w.bodies[1].v.norm() < 1e-2,
            "{what}: still moving {:?}",
            w.bodies[1].v
        );
        let size = body_size(&w.bodies[1]);
        assert!(
            w.deepest_penetration() < 0.05 * size,
            "{what}: {:?}",
            w.penetrations
        );
    }
}

#[test]
fn convex_pieces_cover_each_mesh_within_the_documented_volume_error() {
    let data = common::project_root().join("scenes/data");
    let mut meshes: Vec<(String, TriMesh)> = ["ball", "block", "box", "brick", "slab", "tee"]
        .iter()
        .map(|m| {
            (
                m.to_string(),
                TriMesh::load_obj(&data.join(format!("{m}.obj"))).unwrap(),
            )
        })
        .collect();
    if let Some(dir) = common::rigid3d_assignment() {
        for m in ["brick", "cube", "sphere", "thing"] {
            let path = dir.join(format!("data/{m}.obj"));
            meshes.push((format!("assignment {m}"), TriMesh::load_obj(&path).unwrap()));
        }
    }
    for (name, mesh) in meshes {
        let pieces = ConvexPieces::of_mesh(&mesh).unwrap();
        let non_convex = name.ends_with("tee") || name.ends_with("thing");
        assert_eq!(pieces.convex, !non_convex, "{name}");
        if pieces.convex {
            assert_eq!(pieces.pieces.len(), 1, "{name}");
            let volume = mesh.topology().signed_volume;
            assert!(
                (pieces.pieces[0].volume() - volume).abs() <= 1e-9 * volume,
                "{name}"
            );
        } else {
            // docs/contact.md §"Convex pieces": the bar and the post, within 2% in volume.
            assert!(
                pieces.pieces.len() >= 2,
                "{name}: {} pieces",
                pieces.pieces.len()
            );
            assert!(
                pieces.volume_error.abs() <= 0.02,
                "{name}: {}",
                pieces.volume_error
            );
            println!(
                "{name}: {} pieces, volume error {:+.4}",
                pieces.pieces.len(),
                pieces.volume_error
            );
        }
        // Every vertex of the mesh lies in some piece (within round-off).
        for v in &mesh.vertices {
            let inside = pieces.pieces.iter().any(|p| {
                p.normals.iter().all(|n| {
                    let support = p
                        .vertices
                        .iter()
                        .map(|q| n.dot(q))
                        .fold(f64::NEG_INFINITY, f64::max);
                    n.dot(v) <= support + 1e-9
                })
            });
            assert!(inside, "{name}: vertex {v:?} is in no piece");
        }
    }
}

/// Every assignment scene (when ../shared is present) and every canonical scene.
fn all_scenes() -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    if let Some(dir) = common::rigid3d_assignment() {
        for k in 1..=7 {
            let path = dir.join(format!("scenes/scene{k}.json"));
            out.push((format!("scene{k}"), load_scene(&path).unwrap()));
        }
    }
    for path in
        rigidref::verify::golden::canonical_scenes(&common::project_root().join("scenes")).unwrap()
    {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        out.push((name, load_scene(&path).unwrap()));
    }
    out
}

#[test]
fn complete_holds_every_contact_the_vertex_rule_finds() {
    // On the states of runs with either method (so also configurations only `complete` reaches,
    // such as equal boxes standing on each other).
    for (name, scene) in all_scenes() {
        for method in [CollisionMethod::Vertices, CollisionMethod::Complete] {
            let mut scene = scene.clone();
            scene.params.collision = method;
            scene.params.check_collisions = true;
            let mut w = world(&scene);
            let (mut vertex_contacts, mut complete_contacts) = (Vec::new(), Vec::new());
            let (mut checked, mut added) = (0usize, 0usize);
            common::run(&mut w, 200, |w, k| {
                if k % 10 != 0 {
                    return;
                }
                detect_contacts(
                    &w.bodies,
                    w.colliders(),
                    CollisionMethod::Vertices,
                    &mut vertex_contacts,
                );
                detect_contacts(
                    &w.bodies,
                    w.colliders(),
                    CollisionMethod::Complete,
                    &mut complete_contacts,
                );
                // The same contact: same bodies, vertex, point, frame and depth, bit for bit.
                for c in &vertex_contacts {
                    assert!(
                        complete_contacts.contains(c),
                        "{name}, step {k}: {c:?} missing"
                    );
                }
                checked += vertex_contacts.len();
                added += complete_contacts.len() - vertex_contacts.len();
                // What complete adds are manifold contacts between bodies (penetrating, or
                // speculative within the margin: depth down to minus the margin) and speculative
                // ground contacts (vertices within the margin above the plane: depth ≤ 0).
                for c in &complete_contacts {
                    if !vertex_contacts.contains(c) {
                        let radius = match c.body2 {
                            Some(j) => w.colliders()[c.body1]
                                .radius()
                                .min(w.colliders()[j].radius()),
                            None => w.colliders()[c.body1].radius(),
                        };
                        let margin =
                            rigidref::rigid3d::collide::manifold::speculative_margin(radius);
                        match (c.body2, c.feature) {
                            (Some(_), Feature::Manifold { .. }) => {
                                assert!(c.depth >= -margin, "{c:?}")
                            }
                            (None, Feature::Vertex(_)) => {
                                assert!(c.depth <= 0.0 && c.depth > -margin, "{c:?}")
                            }
                            _ => panic!("{name}, step {k}: complete added {c:?}"),
                        }
                        assert!((c.frame.n.norm() - 1.0).abs() < 1e-12);
                    }
                }
            });
            println!(
                "{name} run with {}: {checked} vertex contacts all held by complete, which adds {added}",
                method.name()
            );
        }
    }
}

/// Every assignment scene and every canonical scene that checks collisions, run for 5 s with
/// `collision: complete`:
/// no pair ever interpenetrates beyond the warning bound (the measure after every step).
#[test]
fn every_scene_runs_with_complete_collision_within_the_bound() {
    for (name, mut scene) in all_scenes() {
        if !scene.params.check_collisions {
            continue; // e.g. the projectile: it is meant to fall through the ground.
        }
        scene.params.collision = CollisionMethod::Complete;
        let steps = (5.0 / scene.params.dt).round() as u64;
        let mut w = world(&scene);
        let mut watch = InterpenetrationWatch::default();
        let mut warnings = watch.observe(&w);
        common::run(&mut w, steps, |w, _| warnings.extend(watch.observe(w)));
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        println!("{name}: deepest interpenetration {:.4} m", watch.deepest);
    }
}

fn collider(mesh: &Arc<TriMesh>) -> MeshCollider {
    MeshCollider::new(mesh.clone()).unwrap()
}

fn project_mesh(name: &str) -> Arc<TriMesh> {
    let path = common::project_root().join(format!("scenes/data/{name}.obj"));
    Arc::new(TriMesh::load_obj(&path).unwrap())
}

fn posed(
    mesh: &Arc<TriMesh>,
    x: Vector3<f64>,
    axis_angle: Vector3<f64>,
) -> rigidref::rigid3d::body::RigidBody {
    let mut b =
        rigidref::rigid3d::body::RigidBody::new("b", 1.0, Matrix3::identity(), mesh.clone());
    b.x = x;
    b.rotation = *Rotation3::new(axis_angle).matrix();
    b
}

#[test]
fn penetration_measure_matches_the_separating_axis_oracle() {
    let meshes = [
        project_mesh("box"),
        project_mesh("ball"),
        project_mesh("tee"),
    ];
    let colliders: Vec<MeshCollider> = meshes.iter().map(collider).collect();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let overlapping = std::cell::Cell::new(0usize);
    proptest!(common::seeded(300), |(
        a in 0usize..3,
        b in 0usize..3,
        offset in v3(0.7),
        turn_a in v3(3.0),
        turn_b in v3(3.0),
    )| {
        let body_a = posed(&meshes[a], Vector3::zeros(), turn_a);
        let body_b = posed(&meshes[b], offset, turn_b);
        let fast = pair_depth(&body_a, &colliders[a], &body_b, &colliders[b]);
        let oracle = brute_force_pair_depth(&body_a, &colliders[a], &body_b, &colliders[b]);
        // EPA stops within about 1e-10 m of the minimum translation distance on these
        // half-metre bodies; 1e-6 m is far below anything a contact or a warning depends on.
        prop_assert!((fast - oracle).abs() <= 1e-6, "fast {fast}, oracle {oracle}");
        if oracle > 0.0 {
            overlapping.set(overlapping.get() + 1);
        }
    });
    // The cases must exercise overlap, not only separation.
    assert!(
        overlapping.get() > 50,
        "{} overlapping cases",
        overlapping.get()
    );
}

/// The penetration measure's box shortcut (`Cuboid`, docs/contact.md §"Penetration measure"):
/// the project's box meshes (cube, brick, slab) are recognised as boxes with their half sides,
/// and the ball and the rattleback are not (the tee's decomposed pieces, hulls of voxels, take
/// whichever path they are, and are checked against the oracle in
/// `penetration_measure_matches_the_separating_axis_oracle`); on 300 random poses of box pairs the shortcut's
/// depth agrees with the brute-force separating-axis oracle to 1e-12 m (the same minimum over a
/// superset of the same axes, so round-off only).
#[test]
fn box_pieces_are_recognised_and_their_depth_matches_the_oracle() {
    use rigidref::rigid3d::collide::pieces::{Cuboid, pose};
    let boxes = ["box", "brick", "slab"].map(project_mesh);
    for (name, mesh) in ["box", "brick", "slab"].iter().zip(&boxes) {
        let pieces = ConvexPieces::of_mesh(mesh).unwrap();
        let cuboid = pieces.pieces[0]
            .cuboid
            .unwrap_or_else(|| panic!("{name} is a box"));
        // Its half sides are the mesh's half extents along its edges (the meshes are axis-aligned).
        let mut half: Vec<f64> = cuboid.half.iter().copied().collect();
        half.sort_by(f64::total_cmp);
        let mut extents: Vec<f64> = (0..3)
            .map(|k| {
                let (lo, hi) = mesh
                    .vertices
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(v[k]), h.max(v[k])));
                (hi - lo) / 2.0
            })
            .collect();
        extents.sort_by(f64::total_cmp);
        for (h, e) in half.iter().zip(&extents) {
            assert!(
                (h - e).abs() <= 1e-12,
                "{name}: {half:?} against {extents:?}"
            );
        }
    }
    for name in ["ball", "rattleback"] {
        let pieces = ConvexPieces::of_mesh(&project_mesh(name)).unwrap();
        assert!(
            pieces.pieces.iter().all(|p| p.cuboid.is_none()),
            "{name} is not a box"
        );
    }

    let colliders: Vec<MeshCollider> = boxes.iter().map(collider).collect();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let overlapping = std::cell::Cell::new(0usize);
    proptest!(common::seeded(300), |(
        a in 0usize..3,
        b in 0usize..3,
        offset in v3(0.6),
        turn_a in v3(3.0),
        turn_b in v3(3.0),
    )| {
        let body_a = posed(&boxes[a], Vector3::zeros(), turn_a);
        let body_b = posed(&boxes[b], offset, turn_b);
        let (pa, pb) = (&colliders[a].pieces.pieces[0], &colliders[b].pieces.pieces[0]);
        let (pose_a, pose_b) = (pose(&body_a), pose(&body_b));
        let shortcut = Cuboid::depth(pa.cuboid.as_ref().unwrap(), &pose_a, pb.cuboid.as_ref().unwrap(), &pose_b);
        let oracle = brute_force_pair_depth(&body_a, &colliders[a], &body_b, &colliders[b]);
        prop_assert!((shortcut - oracle).abs() <= 1e-12, "box {shortcut}, oracle {oracle}");
        prop_assert_eq!(pair_depth(&body_a, &colliders[a], &body_b, &colliders[b]), shortcut);
        if shortcut > 0.0 {
            overlapping.set(overlapping.get() + 1);
        }
    });
    assert!(
        overlapping.get() > 50,
        "{} overlapping cases",
        overlapping.get()
    );
}

/// The pruned oracle behind the penetration measure (docs/contact.md §"Penetration measure"):
/// on 250 random poses of pieces of the project's ball, box, slab, rattleback and tee, apart or
/// overlapping, the GJK verdict it starts from is a certificate — "apart" only where the
/// brute-force separating-axis oracle finds a separating axis, "overlap" only where it finds none
/// — and "undecided" is rare; and the pruned depth, called directly (no box shortcut), is the
/// brute force's to round-off (the same minimum over a subset of the axes that holds the
/// minimising one; 1e-12 m on these half-metre pieces).
#[test]
fn gjk_verdicts_are_certificates_and_the_pruned_oracle_matches_brute_force() {
    use rigidref::rigid3d::collide::gjk::{Verdict, hulls_overlap};
    use rigidref::rigid3d::collide::sat::OracleBuffers;
    let meshes = ["ball", "box", "slab", "rattleback", "tee"].map(project_mesh);
    let pieces: Vec<_> = meshes
        .iter()
        .flat_map(|m| ConvexPieces::of_mesh(m).unwrap().pieces)
        .collect();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let counts = std::cell::RefCell::new([0usize; 3]);
    let oracle = std::cell::RefCell::new(OracleBuffers::default());
    proptest!(common::seeded(250), |(
        a in 0..pieces.len(),
        b in 0..pieces.len(),
        offset in v3(0.8),
        turn_a in v3(3.0),
        turn_b in v3(3.0),
    )| {
        let (ra, rb) = (*Rotation3::new(turn_a).matrix(), *Rotation3::new(turn_b).matrix());
        let (xa, xb) = (Vector3::zeros(), offset);
        let mut oracle = oracle.borrow_mut();
        let brute = oracle.depth((&pieces[a], &ra, &xa), (&pieces[b], &rb, &xb), false);
        let pruned = oracle.depth((&pieces[a], &ra, &xa), (&pieces[b], &rb, &xb), true);
        prop_assert!((pruned - brute).abs() <= 1e-12, "pruned {pruned}, brute force {brute}");
        let world = |p: &rigidref::rigid3d::collide::pieces::Piece, r: &Matrix3<f64>, x: &Vector3<f64>| {
            p.vertices.iter().map(|v| r * v + x).collect::<Vec<_>>()
        };
        let (va, vb) = (world(&pieces[a], &ra, &xa), world(&pieces[b], &rb, &xb));
        let verdict = hulls_overlap(&va, &vb, &-offset);
        match verdict {
            Verdict::Apart => prop_assert_eq!(brute, 0.0),
            Verdict::Overlap => prop_assert!(brute > 0.0, "overlap certified, yet an axis separates"),
            Verdict::Undecided => {}
        }
        counts.borrow_mut()[verdict as usize] += 1;
    });
    let [overlap, apart, undecided] = *counts.borrow();
    println!("verdicts: {overlap} overlap, {apart} apart, {undecided} undecided");
    // Both verdicts must be exercised; undecided is for the origin on the boundary of A − B,
    // which random poses almost never give.
    assert!(
        overlap > 40 && apart > 40,
        "{overlap} overlap, {apart} apart"
    );
    assert!(undecided <= 3, "{undecided} undecided of 250");
}

/// The GJK certificate on the degenerate poses users write: a piece against itself (overlap),
/// boxes face to face with no gap or 1 ulp apart, and a ball resting on a box with its lowest
/// vertex exactly on the face. Touching may be called either "overlap" (they share a point) or
/// "undecided", never "apart"; 1 ulp apart may be "apart" or "undecided". The pruned oracle's
/// depth is the brute force's to round-off: a piece against itself ties many axes (the ball's
/// depth came 1 ulp apart), so 1e-12 m as in the random campaign, and 0 exactly where the brute
/// force's is 0.
#[test]
fn gjk_verdicts_on_touching_and_identical_pieces() {
    use rigidref::rigid3d::collide::gjk::{Verdict, hulls_overlap};
    use rigidref::rigid3d::collide::sat::OracleBuffers;
    let piece = |name: &str| {
        ConvexPieces::of_mesh(&project_mesh(name))
            .unwrap()
            .pieces
            .remove(0)
    };
    let (cube, ball) = (piece("box"), piece("ball"));
    let lowest = ball
        .vertices
        .iter()
        .map(|v| v.y)
        .fold(f64::INFINITY, f64::min);
    let top = cube
        .vertices
        .iter()
        .map(|v| v.y)
        .fold(f64::NEG_INFINITY, f64::max);
    let one = Matrix3::identity();
    let mut oracle = OracleBuffers::default();
    for (name, a, b, dy, touching) in [
        ("the box against itself", &cube, &cube, 0.0, false),
        ("the ball against itself", &ball, &ball, 0.0, false),
        ("box on box, no gap", &cube, &cube, 2.0 * top, true),
        (
            "box on box, 1 ulp apart",
            &cube,
            &cube,
            (2.0 * top).next_up(),
            true,
        ),
        (
            "ball on box, lowest vertex on the face",
            &cube,
            &ball,
            top - lowest,
            true,
        ),
    ] {
        let x_b = Vector3::new(0.0, dy, 0.0);
        let vb: Vec<_> = b.vertices.iter().map(|v| v + x_b).collect();
        let verdict = hulls_overlap(&a.vertices, &vb, &-x_b);
        let brute = oracle.depth((a, &one, &Vector3::zeros()), (b, &one, &x_b), false);
        let pruned = oracle.depth((a, &one, &Vector3::zeros()), (b, &one, &x_b), true);
        println!("{name}: {verdict:?}, depth {pruned} (brute force {brute})");
        assert!(
            (pruned - brute).abs() <= 1e-12,
            "{name}: {pruned} against {brute}"
        );
        assert_eq!(
            pruned == 0.0,
            brute == 0.0,
            "{name}: {pruned} against {brute}"
        );
        if touching {
            assert!(brute <= 1e-15, "{name}: {brute}");
            if name.contains("ulp") {
                assert_ne!(verdict, Verdict::Overlap, "{name}");
            } else {
                assert_ne!(verdict, Verdict::Apart, "{name}");
            }
        } else {
            assert_eq!(verdict, Verdict::Overlap, "{name}");
            assert!(brute > 0.1, "{name}: {brute}");
        }
    }
}

#[test]
fn penetration_measure_is_zero_for_separated_bodies() {
    let meshes = [
        project_mesh("box"),
        project_mesh("ball"),
        project_mesh("tee"),
    ];
    let colliders: Vec<MeshCollider> = meshes.iter().map(collider).collect();
    for a in 0..3 {
        for b in 0..3 {
            // Side by side 1 mm apart along x (bounding boxes close, bodies apart), and far apart.
            let reach = |m: &TriMesh, sign: f64| {
                m.vertices
                    .iter()
                    .map(|v| sign * v.x)
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            for gap in [1e-3, 10.0] {
                let dx = reach(&meshes[a], 1.0) + reach(&meshes[b], -1.0) + gap;
                let body_a = posed(&meshes[a], Vector3::zeros(), Vector3::zeros());
                let body_b = posed(&meshes[b], Vector3::new(dx, 0.0, 0.0), Vector3::zeros());
                assert_eq!(
                    pair_depth(&body_a, &colliders[a], &body_b, &colliders[b]),
                    0.0
                );
                assert_eq!(
                    brute_force_pair_depth(&body_a, &colliders[a], &body_b, &colliders[b]),
                    0.0
                );
            }
        }
    }
}

/// The exhaustive oracles for `complete`'s contacts, on random poses of two convex bodies (away
/// from the ground) that are apart or overlap by at most the warning bound: the separating-axis
/// test over every face normal and edge pair says whether and how deep they overlap, and the
/// brute-force signed distance (every triangle, winding number) says where each contact point
/// lies.
///
/// - found exactly when they overlap: a penetrating contact (deeper than 1e-6 of the radius)
///   between the pair exactly when the SAT depth exceeds that (none missed, none invented;
///   speculative contacts of negative depth are allowed either way);
/// - as deep as the overlap: the deepest contact's depth is within the face preferences' bounds
///   of the SAT depth d: at least 0.9 d and at most d / (0.9 · 0.98) (docs/contact.md §"Exact
///   convex contact"; the measured range is printed);
/// - sound points: each contact point lies inside body 2 (a speculative one within its gap of
///   it), and for a manifold contact the point `depth` along n from it (its witness on body 2's
///   surface) inside body 1 likewise.
#[test]
fn complete_contacts_agree_with_the_exhaustive_oracles() {
    use rigidref::rigid3d::collide::closest_point::brute_force_signed_distance;
    let meshes = [
        project_mesh("box"),
        project_mesh("brick"),
        project_mesh("ball"),
        project_mesh("slab"),
    ];
    let colliders: Vec<MeshCollider> = meshes.iter().map(collider).collect();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    // (overlapping poses, manifold contacts, deepest overlap, witnesses outside body 1)
    let stats = std::cell::RefCell::new((0usize, 0usize, 0.0_f64, 0usize));
    let shortest = std::cell::Cell::new(f64::INFINITY);
    let config = ProptestConfig {
        max_global_rejects: 5000,
        ..common::seeded(200)
    };
    proptest!(config, |(
        a in 0usize..4,
        b in 0usize..4,
        direction in v3(1.0),
        distance in 0.2..0.9f64,
        turn_a in v3(3.0),
        turn_b in v3(3.0),
    )| {
        prop_assume!(direction.norm() > 0.1);
        let offset = direction.normalize() * distance;
        let high = Vector3::new(0.0, 10.0, 0.0);
        let bodies = [posed(&meshes[a], high, turn_a), posed(&meshes[b], high + offset, turn_b)];
        let pair = [colliders[a].clone(), colliders[b].clone()];
        let mut contacts = Vec::new();
        detect_contacts(&bodies, &pair, CollisionMethod::Complete, &mut contacts);
        let sat = brute_force_pair_depth(&bodies[0], &pair[0], &bodies[1], &pair[1]);
        let radius = meshes[a].bounding_radius().min(meshes[b].bounding_radius());
        let tolerance = 1e-6 * radius;
        // Penetrating contacts (depth above the tolerance) exist exactly when the bodies overlap.
        if sat <= tolerance {
            prop_assert!(contacts.iter().all(|c| c.depth <= tolerance), "sat {sat}: {contacts:?}");
            return Ok(());
        }
        // The regime runs live in: overlap within the bound past which a run warns of missed
        // contacts (a quarter of the smaller body). Far deeper, the vertex rule's nearest-face
        // depths drift from the exact answer; the penetration measure, not the contacts, is what
        // reports such states (and the campaign of tests/suite/rigid3d/exact_contact.rs checks
        // the manifolds there too).
        let bound = PENETRATION_BOUND * body_size(&bodies[0]).min(body_size(&bodies[1]));
        prop_assume!(sat <= bound);
        prop_assert!(!contacts.is_empty(), "overlap {sat} m, no contact");
        // The deepest contact reaches the exact depth and exceeds it by no more than the face
        // preferences allow (docs/contact.md §"Exact convex contact").
        let deepest = contacts.iter().map(|c| c.depth).fold(f64::NEG_INFINITY, f64::max);
        let allowed = rigidref::verify::detection::preferred_depth_bound(sat, radius) + tolerance;
        let least = sat - (1.0 - rigidref::rigid3d::collide::separating_axes::EDGE_PREFERENCE) * sat - tolerance;
        prop_assert!(deepest >= least && deepest <= allowed, "deepest contact {deepest}, SAT {sat}");
        shortest.set(shortest.get().min(deepest / sat));
        for c in &contacts {
            let (one, two) = (c.body1, c.body2.unwrap());
            let local = |body: &rigidref::rigid3d::body::RigidBody, p: Vector3<f64>| {
                body.rotation.transpose() * (p - body.x)
            };
            // A speculative contact (depth < 0) lies outside body 2 by its gap.
            let gap = (-c.depth).max(0.0);
            let in_two = brute_force_signed_distance(&meshes[[a, b][two]], &local(&bodies[two], c.point));
            prop_assert!(in_two.distance <= tolerance + gap, "{c:?}: point {} outside body 2", in_two.distance);
            if matches!(c.feature, Feature::Manifold { .. }) {
                // The manifold's other witness, on body 2's surface: the clipped incident point's
                // projection along n onto the reference face, or the edges' closest points. Where
                // the incident face is not parallel to the reference face, a corner's projection
                // along n can leave its own body by a fraction of d (docs/contact.md §"Exact
                // convex contact"): allowed a quarter, for under 5 % of manifold contacts (the
                // count is asserted below).
                let partner = c.point + c.frame.n * c.depth;
                let in_one = brute_force_signed_distance(&meshes[[a, b][one]], &local(&bodies[one], partner));
                prop_assert!(in_one.distance <= tolerance + gap + 0.25 * c.depth.max(0.0), "{c:?}: partner {} outside body 1", in_one.distance);
                if in_one.distance > tolerance {
                    stats.borrow_mut().3 += 1;
                }
            }
        }
        let mut s = stats.borrow_mut();
        s.0 += 1;
        s.1 += contacts.iter().filter(|c| matches!(c.feature, Feature::Manifold { .. })).count();
        s.2 = s.2.max(sat);
    });
    let (overlapping, manifold, deepest, outside) = *stats.borrow();
    println!(
        "{overlapping} overlapping poses, {manifold} manifold contacts ({outside} with the witness on body 2 outside body 1), deepest {deepest:.3} m, deepest contact at least {:.4} of the SAT depth",
        shortest.get()
    );
    assert!(
        overlapping > 50 && manifold > 50,
        "{overlapping} overlapping, {manifold} manifold contacts"
    );
    assert!(
        outside * 20 <= manifold,
        "{outside} of {manifold} witnesses outside body 1"
    );
}

/// Bodies never pass through each other at ordinary speeds: a box or the tee dropped from up to
/// 1 m (landing at up to 4.5 m/s, 4.5 cm per frame) in any orientation onto a resting box never
/// interpenetrates it (or the ground) beyond the warning bound at any step. (Without continuous
/// detection an impact is found after up to one frame of travel, hence the measured 0.63 of the
/// bound, on the thin tee.)
#[test]
fn dropped_bodies_never_pass_through_each_other_at_ordinary_speeds() {
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let deepest = std::cell::Cell::new(0.0_f64);
    proptest!(common::seeded(24), |(
        tee in any::<bool>(),
        height in 0.05..1.0f64,
        turn in v3(3.0),
        shift in (-0.2..0.2f64, -0.2..0.2f64),
    )| {
        let mut scene = if tee { canonical("tee_on_box.json") } else { canonical("edge_landing.json") };
        let clearance = scene.bodies[1].mesh.bounding_radius();
        scene.bodies[1].x0 = Vector3::new(shift.0, 0.499 + clearance + height, shift.1);
        scene.bodies[1].r0 = *Rotation3::new(turn).matrix();
        let mut w = world(&scene);
        let mut worst = 0.0_f64;
        common::run(&mut w, 200, |w, _| {
            for p in &w.penetrations {
                worst = worst.max(p.depth / p.bound);
            }
        });
        prop_assert!(worst < 1.0, "deepest at {worst} of the bound");
        deepest.set(deepest.get().max(worst));
    });
    println!(
        "deepest interpenetration: {:.3} of the bound",
        deepest.get()
    );
}

/// The convex pieces of the project's box, ball and tee meshes.
/// The project box B placed on box A (A's frame): one side up, lifted by `lift` (negative:
/// overlapping), turned `turn` about y and shifted sideways by half of `offset`'s x and z.
fn box_on_box(
    turn: f64,
    offset: Vector3<f64>,
    lift: f64,
) -> rigidref::rigid3d::collide::separating_axes::Placement {
    rigidref::rigid3d::collide::separating_axes::Placement {
        rotation: turn_about_y(turn),
        translation: Vector3::new(offset.x * 0.5, BOX + lift, offset.z * 0.5),
    }
}

fn project_pieces() -> Vec<rigidref::rigid3d::collide::pieces::Piece> {
    ["box", "ball", "tee"]
        .iter()
        .flat_map(|name| {
            rigidref::rigid3d::collide::pieces::ConvexPieces::of_mesh(&project_mesh(name))
                .unwrap()
                .pieces
        })
        .collect()
}

/// The separating-axis query reads its Gauss-map arc tests off tables made once per query
/// (docs/contact.md §"Exact convex contact", "The arcs tabled"): on 300 random placements of
/// the project's pieces (box, ball, the tee's pieces), the edge pairs the tables say cross are
/// exactly those `arcs_cross` finds on the faces' normals (A's, and B's placed and negated), so
/// the query tries the same edge axes as before the tables. Placements with the pieces' faces
/// parallel (a turn of zero or of a quarter about y, as stacks rest) are among them: there the
/// arcs touch at their ends and the decision rests on exact zeros.
#[test]
fn tabled_arc_tests_match_arcs_cross() {
    use rigidref::rigid3d::collide::separating_axes::{Placement, SatBuffers, arcs_cross};
    let pieces = project_pieces();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let crossing = std::cell::Cell::new(0usize);
    let buffers = std::cell::RefCell::new((SatBuffers::default(), Vec::new()));
    proptest!(common::seeded(300), |(
        a in 0..pieces.len(),
        b in 0..pieces.len(),
        offset in v3(0.7),
        turn in v3(3.0),
        square in 0usize..3,
    )| {
        // A third of the cases turned by a multiple of a quarter about y only.
        let rotation = match square {
            0 => *Rotation3::new(turn).matrix(),
            k => turn_about_y(k as f64 * std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_2),
        };
        let at = Placement { rotation, translation: offset };
        let (pa, pb) = (&pieces[a].polytope, &pieces[b].polytope);
        let (sat, tabled) = &mut *buffers.borrow_mut();
        sat.crossing_edges(pa, pb, &at, tabled);
        let mut brute = Vec::new();
        for (ea, edge_a) in pa.edges.iter().enumerate() {
            let (n1, n2) = (pa.faces[edge_a.faces[0]].normal, pa.faces[edge_a.faces[1]].normal);
            for (eb, edge_b) in pb.edges.iter().enumerate() {
                let (m1, m2) = (
                    rotation * pb.faces[edge_b.faces[0]].normal,
                    rotation * pb.faces[edge_b.faces[1]].normal,
                );
                if arcs_cross(&n1, &n2, &-m1, &-m2) {
                    brute.push((ea, eb));
                }
            }
        }
        prop_assert_eq!(&*tabled, &brute);
        crossing.set(crossing.get() + brute.len());
    });
    // The cases must have crossing arcs to compare, not only empty lists.
    assert!(crossing.get() > 1000, "{} crossing pairs", crossing.get());
}

/// The separating-axis query skips a crossing edge pair whose bound (the distance between the
/// two edges' lines along its axis, an upper bound on its computed gap) is at most the best face
/// gap (docs/contact.md §"Exact convex contact", "Edge pairs bounded"). On 400 random placements
/// of the project's pieces (box, ball, the tee's pieces), a third of them resting poses (a box
/// turned about y only, 1 mm above to 1 mm into the one below, shifted sideways), the query with
/// the skip gives the same axis, gaps and contact points, bit for bit, as the query that
/// computes every edge pair's gap, at two stopping gaps (the speculative margin's scale, and
/// none); and it skipped pairs (else the comparison would be empty).
#[test]
fn edge_pairs_skipped_by_their_bound_change_nothing() {
    use rigidref::rigid3d::collide::separating_axes::{Placement, SatBuffers};
    let pieces = project_pieces();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let both = std::cell::RefCell::new((SatBuffers::default(), SatBuffers::every_edge_gap()));
    let edges_chosen = std::cell::Cell::new(0usize);
    proptest!(common::seeded(400), |(
        a in 0..pieces.len(),
        b in 0..pieces.len(),
        offset in v3(0.7),
        turn in v3(3.0),
        resting in 0usize..3,
        lift in -0.001..0.001f64,
    )| {
        let (a, b, at) = if resting == 0 {
            (0, 0, box_on_box(turn.x, offset, lift))
        } else {
            (a, b, Placement { rotation: *Rotation3::new(turn).matrix(), translation: offset })
        };
        let (pa, pb) = (&pieces[a].polytope, &pieces[b].polytope);
        let (fast, every) = &mut *both.borrow_mut();
        for stop in [0.005, f64::INFINITY] {
            let with_skip = fast.contact_or_apart(pa, pb, &at, stop);
            let without = every.contact_or_apart(pa, pb, &at, stop);
            prop_assert_eq!(with_skip, without);
            prop_assert_eq!(&fast.points, &every.points);
            if let Ok(found) = with_skip
                && matches!(found.axis, rigidref::rigid3d::collide::separating_axes::Axis::Edges(..))
            {
                edges_chosen.set(edges_chosen.get() + 1);
            }
        }
    });
    let (fast, every) = both.into_inner();
    assert!(
        fast.edge_pairs_skipped > 1000,
        "{} pairs skipped",
        fast.edge_pairs_skipped
    );
    assert_eq!(every.edge_pairs_skipped, 0);
    // Edge axes were chosen too: the comparison covers the case where an edge pair matters.
    assert!(
        edges_chosen.get() > 20,
        "an edge axis chosen {} times",
        edges_chosen.get()
    );
}

/// `at` moved by a motion whose bound (docs/contact.md §"Persistent manifolds",
/// ‖ΔR‖ (ρ + |t₀|) plus |Δt|) is at most `allowed`, m: half as a turn about `axis`
/// (‖R − R₀‖ ≤ √2 θ), half as a shift along `shift`. `radius`: the larger body radius ρ.
fn moved_within(
    at: &rigidref::rigid3d::collide::separating_axes::Placement,
    axis: Vector3<f64>,
    shift: Vector3<f64>,
    allowed: f64,
    radius: f64,
) -> rigidref::rigid3d::collide::separating_axes::Placement {
    let theta = 0.5 * allowed / (std::f64::consts::SQRT_2 * (radius + at.translation.norm()));
    rigidref::rigid3d::collide::separating_axes::Placement {
        rotation: Rotation3::new(axis.normalize() * theta).matrix() * at.rotation,
        translation: at.translation + shift.normalize() * (0.5 * allowed),
    }
}

/// The largest distance of a piece's vertices from its body's origin, m: the radius detection
/// passes for the motion bound.
fn body_reach(p: &rigidref::rigid3d::collide::polytope::Polytope) -> f64 {
    p.vertices.iter().map(|v| v.norm()).fold(0.0, f64::max)
}

/// A piece pair keeps the face axis its full search chose, with that axis's lead ℓ
/// (docs/contact.md §"Temporal coherence", "Leading axes"): moved by less than ℓ − τ since, the
/// kept axis gives the full search's manifold, bit for bit. On 400 random overlapping
/// placements of the project's pieces (a third of them box on box, overlapping by up to 1 mm,
/// turned about y: the stacks' case), each moved twice from the search (a turn about a random
/// axis and a shift, scaled so that the motion bound is 0.49 and 0.98 of ℓ − τ), the kept
/// answer against a fresh search at the moved placement: the normal and every point as bits.
/// The kept axes must serve many of them, or the comparison shows nothing.
#[test]
fn a_kept_face_axis_gives_the_full_search_while_the_pair_moves_less_than_its_lead() {
    let pieces = project_pieces();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let buffers = std::cell::RefCell::new((SatBuffers::default(), SatBuffers::default()));
    let (served, led) = (std::cell::Cell::new(0u64), std::cell::Cell::new(0u64));
    proptest!(common::seeded(400), |(
        a in 0..pieces.len(),
        b in 0..pieces.len(),
        offset in v3(0.5),
        turn in v3(3.0),
        resting in 0usize..3,
        lift in -0.001..0.0f64,
        axis in v3(1.0),
        shift in v3(1.0),
    )| {
        let (a, b, at) = if resting == 0 {
            (0, 0, box_on_box(turn.x, offset, lift))
        } else {
            (a, b, Placement { rotation: *Rotation3::new(turn).matrix(), translation: offset })
        };
        let (pa, pb) = (&pieces[a].polytope, &pieces[b].polytope);
        let radius = body_reach(pa).max(body_reach(pb));
        let tie = AXIS_TIE_TOLERANCE * pa.radius.max(pb.radius);
        let stop = 0.005;
        let (sat, fresh) = &mut *buffers.borrow_mut();
        let mut counts = KeptCounts::default();
        let mut kept = KeptFeatures::Unknown;
        let first = kept_contact(sat, (pa, pb), &at, stop, radius, KeepRule::Exact, &mut kept, &mut counts);
        prop_assert_eq!(first, fresh.contact(pa, pb, &at, stop).map(|f| f.normal));
        prop_assert_eq!(&sat.points, &fresh.points);
        let KeptFeatures::Touching { lead, .. } = kept else { return Ok(()) };
        if lead <= tie {
            return Ok(());
        }
        led.set(led.get() + 1);
        for fraction in [0.49, 0.98] {
            let moved_to = moved_within(&at, axis, shift, fraction * (lead - tie), radius);
            let moved = (moved_to.rotation - at.rotation).norm() * (radius + at.translation.norm())
                + (moved_to.translation - at.translation).norm();
            prop_assert!(moved + tie < lead, "{moved} {lead}");
            let mut again = kept;
            let before = counts.served;
            let normal = kept_contact(sat, (pa, pb), &moved_to, stop, radius, KeepRule::Exact, &mut again, &mut counts);
            let search = fresh.contact(pa, pb, &moved_to, stop);
            prop_assert_eq!(normal, search.map(|f| f.normal));
            prop_assert_eq!(&sat.points, &fresh.points);
            served.set(served.get() + counts.served - before);
        }
    });
    eprintln!(
        "{} placements with a lead; the kept axis served {} of their {} moves",
        led.get(),
        served.get(),
        2 * led.get()
    );
    assert!(
        led.get() > 100 && served.get() > led.get(),
        "{} of the placements had a lead; the kept axis served {} of their moves",
        led.get(),
        served.get()
    );
}

/// Teeth of `a_kept_face_axis_gives_the_full_search_while_the_pair_moves_less_than_its_lead`:
/// with the motion test left out (a deliberate bug, `axis_lead_motion_unchecked`), the same
/// placements moved 10 and 40 times their lead (a turn and a shift, at most 2 mm) give answers
/// that differ from the full search's: the lead is what makes the kept axis exact.
#[test]
fn a_kept_face_axis_is_wrong_when_the_pair_moves_past_its_lead() {
    use rigidref::verify::faults::{Faults, with_faults};
    let pieces = project_pieces();
    let v3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c));
    let buffers = std::cell::RefCell::new((SatBuffers::default(), SatBuffers::default()));
    let (moves, differ) = (std::cell::Cell::new(0u64), std::cell::Cell::new(0u64));
    let faults = Faults {
        axis_lead_motion_unchecked: true,
        ..Faults::NONE
    };
    with_faults(faults, || {
        proptest!(common::seeded(200), |(
            offset in v3(0.5),
            turn in v3(3.0),
            lift in -0.001..0.0f64,
            axis in v3(1.0),
            shift in v3(1.0),
        )| {
            // Box on box, the stacks' case.
            let at = box_on_box(turn.x, offset, lift);
            let p = &pieces[0].polytope;
            let radius = body_reach(p);
            let tie = AXIS_TIE_TOLERANCE * p.radius;
            let stop = 0.005;
            let (sat, fresh) = &mut *buffers.borrow_mut();
            let mut counts = KeptCounts::default();
            let mut kept = KeptFeatures::Unknown;
            kept_contact(sat, (p, p), &at, stop, radius, KeepRule::Exact, &mut kept, &mut counts);
            let KeptFeatures::Touching { lead, .. } = kept else { return Ok(()) };
            if lead <= tie {
                return Ok(());
            }
            for times in [10.0, 40.0] {
                let allowed = (times * (lead - tie)).min(0.002);
                let moved_to = moved_within(&at, axis, shift, allowed, radius);
                let mut again = kept;
                let normal = kept_contact(sat, (p, p), &moved_to, stop, radius, KeepRule::Exact, &mut again, &mut counts);
                let search = fresh.contact(p, p, &moved_to, stop).map(|f| f.normal);
                moves.set(moves.get() + 1);
                differ.set(differ.get() + u64::from(normal != search || sat.points != fresh.points));
            }
        });
    });
    assert!(
        differ.get() > 0,
        "none of {} moves past the lead gave another answer than the search",
        moves.get()
    );
    eprintln!(
        "{} of {} moves past the lead differ",
        differ.get(),
        moves.get()
    );
}

/// The lead of a kept face axis (docs/contact.md §"Temporal coherence", "Leading axes", the
/// table), on hand-made search results: each of its three terms the least in one case (among
/// the piece's own faces; against the other piece's best face, for a face of A and of B; against
/// the edge pairs, with the shortfall ε = 8τ), and no lead at all where the search chose an edge
/// pair, fell back from its preferred face, found the pieces not clearly overlapping (G ≥ −τ)
/// or a gap that is not a number. The expected values are the table's formulas worked by hand;
/// 1e-12 relative: a few roundings.
#[test]
fn the_lead_of_a_kept_face_is_the_tables_least_term() {
    use rigidref::rigid3d::collide::persistent::axis_lead;
    use rigidref::rigid3d::collide::separating_axes::{Axis, SearchGaps};
    let tie = 1e-9;
    let gaps = |a: f64, a2: f64, b: f64, b2: f64, exact: f64, preferred: Axis| SearchGaps {
        face_a: a,
        face_a_second: a2,
        face_b: b,
        face_b_second: b2,
        exact,
        preferred,
    };
    let close = |lead: f64, expected: f64| {
        assert!(
            (lead - expected).abs() <= 1e-12 * expected.abs(),
            "{lead:e} against {expected:e}"
        );
    };
    // Equal boxes face on face: A's and B's faces tie, only B's 2 % preference separates them.
    let a = Axis::FaceOfA(2);
    close(
        axis_lead(&gaps(-0.01, -0.5, -0.01, -0.5, -0.01, a), a, tie),
        0.0002 / 2.02,
    );
    // A face of B that beats A's by more than 2 %: the edge term is the least.
    let b = Axis::FaceOfB(1);
    close(
        axis_lead(&gaps(-0.02, -0.5, -0.01, -0.5, -0.01, b), b, tie),
        (0.001 - 8e-9) / 2.1,
    );
    // A face of B nearer A's: its lead over A's best face is the least.
    close(
        axis_lead(&gaps(-0.0105, -0.5, -0.01, -0.5, -0.01, b), b, tie),
        (0.00029 - 2e-9) / 2.02,
    );
    // A's second face close behind its best: the term among its own faces is the least.
    close(
        axis_lead(&gaps(-0.01, -0.0102, -0.05, -0.5, -0.01, a), a, tie),
        0.0001,
    );
    // An edge pair's gap above the face's (not by the 10 % that would make it the axis).
    close(
        axis_lead(&gaps(-0.01, -0.5, -0.05, -0.5, -0.0095, a), a, tie),
        (0.0005 - 8e-9) / 2.1,
    );
    // No lead: an edge pair chosen; the search fell back from its preferred face; the pieces not
    // clearly overlapping; a gap not a number, or infinite.
    let none = |lead: f64| assert_eq!(lead, f64::NEG_INFINITY);
    let edges = Axis::Edges(3, 4);
    none(axis_lead(
        &gaps(-0.02, -0.5, -0.02, -0.5, -0.01, edges),
        edges,
        tie,
    ));
    none(axis_lead(&gaps(-0.01, -0.5, -0.01, -0.5, -0.01, b), a, tie));
    none(axis_lead(
        &gaps(-0.01, -0.5, -0.01, -0.5, -0.5e-9, a),
        a,
        tie,
    ));
    none(axis_lead(
        &gaps(f64::NAN, -0.5, -0.01, -0.5, -0.01, a),
        a,
        tie,
    ));
    none(axis_lead(
        &gaps(-0.01, -0.5, f64::NAN, -0.5, -0.01, a),
        a,
        tie,
    ));
    none(axis_lead(
        &gaps(-0.01, -0.5, -0.01, -0.5, f64::NEG_INFINITY, a),
        a,
        tie,
    ));
}
