//! Collision detection: the fast signed distance (parry3d's BVH) against the brute-force oracle,
//! ground contacts, and the broad phase against all pairs (docs/contact.md §"Collision
//! detection").

use crate::common;

use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;
use rigidref::common::broad::{Aabb, BroadGrid, overlapping_pairs, sweep_and_prune_pairs};
use rigidref::rigid3d::body::RigidBody;
use rigidref::rigid3d::collide::closest_point::brute_force_signed_distance;
use rigidref::rigid3d::collide::ground::ground_contacts;
use rigidref::rigid3d::collide::{MeshCollider, detect_contacts};
use rigidref::rigid3d::mesh::TriMesh;
use rigidref::rigid3d::rotation::exp_so3;
use std::sync::Arc;

/// The meshes to test on: the project's own, and the assignment's when ../shared is present.
fn meshes() -> Vec<(String, Arc<TriMesh>)> {
    let mut out = Vec::new();
    let mut add = |dir: std::path::PathBuf, names: &[&str]| {
        for name in names {
            let path = dir.join(format!("{name}.obj"));
            let mesh = TriMesh::load_obj(&path).expect("mesh loads");
            out.push((path.display().to_string(), Arc::new(mesh)));
        }
    };
    add(
        common::project_root().join("scenes/data"),
        &["ball", "box", "brick", "slab", "block", "cube20"],
    );
    if let Some(dir) = common::rigid3d_assignment() {
        add(dir.join("data"), &["sphere", "cube", "brick", "thing"]);
    }
    out
}

#[test]
fn parry_signed_distance_matches_the_brute_force_oracle() {
    let mut compared = 0;
    for (name, mesh) in meshes() {
        let collider = MeshCollider::new(mesh.clone()).unwrap();
        let radius = mesh.bounding_radius();
        let lo = Aabb::around(mesh.vertices.iter().copied());
        let span = lo.max - lo.min;
        // Points in the bounding box grown by 20% each side: inside, outside and near the surface.
        let config = common::seeded(400);
        proptest!(config, |(f in (-0.2..1.2f64, -0.2..1.2f64, -0.2..1.2f64))| {
            let p = lo.min + Vector3::new(f.0 * span.x, f.1 * span.y, f.2 * span.z);
            let fast = collider.signed_distance(&p);
            let slow = brute_force_signed_distance(&mesh, &p);
            // Distances agree to round-off of the closest-point arithmetic on metre-sized meshes.
            prop_assert!((fast.distance.abs() - slow.distance.abs()).abs() <= 1e-9 * radius,
                "{name}: at {p:?} parry {} oracle {}", fast.distance, slow.distance);
            // The inside/outside decision agrees except within 1e-9 of the surface, where either
            // answer is right.
            if slow.distance.abs() > 1e-9 * radius {
                prop_assert_eq!(fast.distance < 0.0, slow.distance < 0.0,
                    "{}: at {:?} parry {} oracle {}", name, p, fast.distance, slow.distance);
            }
            // The normal is a unit vector, and moving the point along it by the distance lands
            // on the surface (the closest point), inside or out.
            prop_assert!((fast.normal.norm() - 1.0).abs() < 1e-12);
            let landed = p - fast.normal * fast.distance;
            prop_assert!((landed - fast.closest).norm() <= 1e-9 * radius);
        });
        compared += 1;
    }
    assert!(compared >= 6);
}

#[test]
fn a_unique_nearest_triangle_gives_the_bvh_answer_while_the_point_moves_less_than_half_the_gap() {
    // The kept nearest features of temporal coherence (docs/contact.md §"Temporal coherence"):
    // where `unique_nearest_triangle` names a triangle with gap g, the signed distance on that
    // triangle is the BVH's, bit for bit, at the point and at points up to 0.49 g away in any
    // direction. g is the detection margin of a body this size (MARGIN_FRACTION of the radius).
    let (kept, declined) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    for (name, mesh) in meshes() {
        let collider = MeshCollider::new(mesh.clone()).unwrap();
        let radius = mesh.bounding_radius();
        let gap = rigidref::rigid3d::collide::coherence::MARGIN_FRACTION * radius;
        let lo = Aabb::around(mesh.vertices.iter().copied());
        let span = lo.max - lo.min;
        let config = common::seeded(300);
        proptest!(config, |(f in (-0.1..1.1f64, -0.1..1.1f64, -0.1..1.1f64),
                            d in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64))| {
            let p = lo.min + Vector3::new(f.0 * span.x, f.1 * span.y, f.2 * span.z);
            let Some(triangle) = collider.unique_nearest_triangle(&p, gap) else {
                declined.set(declined.get() + 1);
                return Ok(());
            };
            kept.set(kept.get() + 1);
            let direction = Vector3::new(d.0, d.1, d.2);
            let moved = p + direction.normalize() * 0.49 * gap;
            // Bit for bit: the distance, closest point and normal as integers (so that 0.0 and
            // −0.0 differ), and the triangle.
            let bits = |sd: rigidref::rigid3d::collide::closest_point::SignedDistance| {
                let v = |x: &Vector3<f64>| x.map(f64::to_bits);
                (sd.distance.to_bits(), v(&sd.closest), v(&sd.normal), sd.triangle)
            };
            for q in [p, moved] {
                prop_assert_eq!(bits(collider.signed_distance_on(&q, triangle)),
                    bits(collider.signed_distance(&q)), "{} at {:?}, triangle {}", name, q, triangle);
            }
        });
    }
    // Both answers occur: most points have a clear nearest triangle, and points near edges,
    // corners and medial planes do not.
    let (kept, declined) = (kept.get(), declined.get());
    assert!(
        kept > 500 && declined > 100,
        "kept {kept}, declined {declined}"
    );
}

#[test]
fn a_leading_triangle_gives_the_bvh_answer_while_the_point_moves_less_than_half_its_lead() {
    // The leading triangles of temporal coherence (docs/contact.md §"Temporal coherence",
    // "Leading triangles"): a point within the gap g of the surface whose nearest triangle is
    // nearer than every other by a lead ℓ ≤ g (near an edge, a corner or a medial plane of the
    // mesh) keeps that triangle while it moves by less than (ℓ − 1e-9 ρ) / 2 from where it was
    // searched: there its signed distance on the triangle is the BVH search's, bit for bit.
    // Points 0.49 (ℓ − 1e-9 ρ) away in a random direction are answered on the triangle and
    // compared with the search; points just past half the lead must be searched again. g is
    // detection's: twice the margin (MARGIN_FRACTION of the radius) plus 1e-9 ρ.
    use rigidref::rigid3d::collide::mesh_pair::{LEAD_ROUND_OFF, NearestTriangle, VertexQuery};
    let (leading, other) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    for (name, mesh) in meshes() {
        let collider = MeshCollider::new(mesh.clone()).unwrap();
        let radius = mesh.bounding_radius();
        let gap =
            2.0 * rigidref::rigid3d::collide::coherence::MARGIN_FRACTION * radius + 1e-9 * radius;
        let round_off = LEAD_ROUND_OFF * radius;
        let lo = Aabb::around(mesh.vertices.iter().copied());
        let span = lo.max - lo.min;
        let config = common::seeded(300);
        proptest!(config, |(f in (-0.1..1.1f64, -0.1..1.1f64, -0.1..1.1f64),
                            o in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
                            d in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64))| {
            // A point within the gap of the surface: a surface point, moved by up to 0.6 g.
            let far = lo.min + Vector3::new(f.0 * span.x, f.1 * span.y, f.2 * span.z);
            let p = collider.signed_distance(&far).closest + Vector3::new(o.0, o.1, o.2) * 0.35 * gap;
            let mut state = NearestTriangle::Unknown;
            let (first, answer) = collider.signed_distance_keeping(&p, &mut state, gap);
            prop_assert_eq!(answer, VertexQuery::Searched);
            let bits = |sd: rigidref::rigid3d::collide::closest_point::SignedDistance| {
                let v = |x: &Vector3<f64>| x.map(f64::to_bits);
                (sd.distance.to_bits(), v(&sd.closest), v(&sd.normal), sd.triangle)
            };
            prop_assert_eq!(bits(first), bits(collider.signed_distance(&p)));
            let NearestTriangle::Leading { triangle, lead, .. } = state else {
                other.set(other.get() + 1);
                return Ok(());
            };
            leading.set(leading.get() + 1);
            prop_assert!(lead > round_off && lead <= gap, "{}: lead {}", name, lead);
            prop_assert_eq!(triangle as usize, first.triangle);
            let direction = Vector3::new(d.0, d.1, d.2).normalize();
            let near = p + direction * 0.49 * (lead - round_off);
            let (sd, answer) = collider.signed_distance_keeping(&near, &mut state, gap);
            prop_assert_eq!(answer, VertexQuery::OnLeading);
            prop_assert_eq!(bits(sd), bits(collider.signed_distance(&near)),
                "{} at {:?}, triangle {}, lead {}", name, near, triangle, lead);
            // Still leading from the first search's point; past half the lead it searches.
            let past = p + direction * (0.5 * lead + round_off);
            let (sd, answer) = collider.signed_distance_keeping(&past, &mut state, gap);
            prop_assert_eq!(answer, VertexQuery::Searched);
            prop_assert_eq!(bits(sd), bits(collider.signed_distance(&past)));
        });
    }
    // Both occur: points near edges, corners and medial planes lead by less than the gap, the
    // others keep their triangle for the list's life (or are too deep, or tie).
    let (leading, other) = (leading.get(), other.get());
    assert!(
        leading > 200 && other > 200,
        "leading {leading}, other {other}"
    );
}

fn body_with(mesh: Arc<TriMesh>, x: Vector3<f64>, rotation: Matrix3<f64>) -> RigidBody {
    let mut b = RigidBody::new("b", 1.0, Matrix3::identity(), mesh);
    b.x = x;
    b.rotation = rotation;
    b.update_world_inertia();
    b
}

#[test]
fn ground_contacts_are_exactly_the_vertices_below_the_plane() {
    let mesh =
        Arc::new(TriMesh::load_obj(&common::project_root().join("scenes/data/ball.obj")).unwrap());
    proptest!(common::seeded(300), |(
        y in -0.6..0.6f64,
        w in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
    )| {
        let rotation = exp_so3(&Vector3::new(w.0, w.1, w.2));
        let body = body_with(mesh.clone(), Vector3::new(0.3, y, -0.2), rotation);
        let mut contacts = Vec::new();
        ground_contacts(4, &body, 0.0, &mut contacts);
        let below: Vec<usize> = (0..mesh.vertices.len())
            .filter(|&i| (body.x + body.rotation * mesh.vertices[i]).y < 0.0)
            .collect();
        prop_assert_eq!(contacts.iter().map(|c| c.vertex().unwrap()).collect::<Vec<_>>(), below);
        for c in &contacts {
            prop_assert_eq!(c.body1, 4);
            prop_assert_eq!(c.body2, None);
            prop_assert_eq!(c.frame.n, Vector3::y());
            prop_assert_eq!(c.depth, -c.point.y);
            prop_assert!(c.depth > 0.0);
        }
    });
}

/// The grid broad phase and the sweep and prune both give exactly the pairs that testing all
/// pairs gives: random boxes of mixed sizes, some wide enough (up to 40 m against cells of about
/// 1 m) to be tested against every box instead of entered in the grid, some degenerate (a point)
/// and some empty (min beyond max), which overlap nothing. One `BroadGrid` serves every case in
/// turn (its working memory kept from the last, larger or smaller), as the detectors keep theirs.
#[test]
fn broad_phase_finds_exactly_the_overlapping_pairs() {
    let grid = std::cell::RefCell::new(BroadGrid::default());
    proptest!(common::seeded(300), |(
        boxes in proptest::collection::vec(
            ((-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64), (0.0..2.0f64, 0.0..2.0f64, 0.0..2.0f64), 0..10u8),
            0..60)
    )| {
        let boxes: Vec<Aabb> = boxes.iter().map(|(lo, size, kind)| {
            let min = Vector3::new(lo.0, lo.1, lo.2);
            let size = Vector3::new(size.0, size.1, size.2);
            match kind {
                0 => Aabb { min, max: min + size * 20.0 },     // wide
                1 => Aabb { min, max: min },                   // a point
                2 => Aabb { min: min + size, max: min - size }, // empty unless size is 0
                _ => Aabb { min, max: min + size },
            }
        }).collect();
        let mut all_pairs = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if boxes[i].overlaps(&boxes[j]) {
                    all_pairs.push((i, j));
                }
            }
        }
        prop_assert_eq!(&overlapping_pairs(&boxes), &all_pairs);
        prop_assert_eq!(&sweep_and_prune_pairs(&boxes), &all_pairs);
        let mut reused = vec![(7, 7)];
        grid.borrow_mut().pairs_into(&boxes, &mut reused);
        prop_assert_eq!(&reused, &all_pairs);
    });
}

/// The broad phase with temporal coherence (docs/contact.md §"Temporal coherence"): boxes that
/// drift a little, jump, and are added, step after step; every step the kept grown pairs,
/// filtered, are exactly the pairs the grid finds afresh (and all three ways of keeping them are
/// used: nothing moved, a few movers updated, everything found again).
#[test]
fn kept_pairs_are_exactly_the_overlapping_pairs_while_boxes_move_and_are_added() {
    use rigidref::common::broad::KeptPairs;
    let ways = std::cell::Cell::new([0u64; 3]);
    proptest!(common::seeded(60), |(
        start in proptest::collection::vec(((-6.0..6.0f64, -6.0..6.0f64, -6.0..6.0f64), 0.2..1.5f64), 1..150),
        moves in proptest::collection::vec((0..200usize, (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 0..4u8), 0..400),
    )| {
        let mut centres: Vec<Vector3<f64>> = start.iter().map(|(c, _)| Vector3::new(c.0, c.1, c.2)).collect();
        let mut sizes: Vec<f64> = start.iter().map(|(_, s)| *s).collect();
        let mut kept: KeptPairs<Vector3<f64>> = KeptPairs::default();
        let mut pairs = Vec::new();
        for (step, chunk) in moves.chunks(8).enumerate() {
            for &(k, d, kind) in chunk {
                let d = Vector3::new(d.0, d.1, d.2);
                match kind {
                    // Drift (within the margin over a few steps), a jump, or a new box.
                    0 | 1 => { let k = k % centres.len(); centres[k] += d * 0.01; }
                    2 => { let k = k % centres.len(); centres[k] += d * 2.0; }
                    _ => { centres.push(d * 5.0); sizes.push(0.7); }
                }
            }
            let boxes: Vec<Aabb> = centres.iter().zip(&sizes).map(|(c, s)| Aabb {
                min: c.add_scalar(-s), max: c.add_scalar(*s),
            }).collect();
            kept.overlapping(&boxes, |k| 0.1 * sizes[k], |k| centres[k], |k, a| (centres[k] - a).norm(), &mut pairs);
            prop_assert_eq!(&pairs, &overlapping_pairs(&boxes), "step {}", step);
        }
        let w = ways.get();
        ways.set([w[0] + kept.kept, w[1] + kept.updated, w[2] + kept.found]);
    });
    let [unmoved, updated, found] = ways.get();
    assert!(
        unmoved > 0 && updated > 0 && found > 0,
        "kept {unmoved}, updated {updated}, found {found}"
    );
}

/// A grid of 30 × 30 equal boxes just touching their neighbours (and a floor box under them
/// all): every touching pair is found once, by the grid as by the sweep.
#[test]
fn broad_phase_finds_touching_neighbours_once_on_a_regular_grid() {
    let mut boxes = vec![Aabb {
        min: Vector3::new(-1.0, -1.0, -1.0),
        max: Vector3::new(31.0, 0.0, 31.0),
    }];
    for i in 0..30 {
        for k in 0..30 {
            let min = Vector3::new(i as f64, 0.0, k as f64);
            boxes.push(Aabb {
                min,
                max: min + Vector3::repeat(1.0),
            });
        }
    }
    let grid = overlapping_pairs(&boxes);
    assert_eq!(grid, sweep_and_prune_pairs(&boxes));
    // Each box touches the floor, its 4 side neighbours and 4 diagonal ones (corners touch):
    // 900 floor pairs + 2·30·29 side + 2·29·29 diagonal.
    assert_eq!(grid.len(), 900 + 2 * 30 * 29 + 2 * 29 * 29);
}

/// A 2D scene's boxes as its detector grows them (z from −0.25 to 0.25 about the plane z = 0,
/// the 2D margin): thickened along z by less than a cell's side, each is entered in as many
/// cells as the same box flat (z = 0), not twice as many (the grid's cells are counted from the
/// boxes' smallest corner, not from 0, which splits z = −0.25 … 0.25 in two), and the pairs are
/// the same. 20 × 10 boxes of 1.5 × 1 blocks, 0.25 apart, in a running bond.
#[test]
fn a_flat_scene_s_boxes_thickened_by_the_margin_fill_one_layer_of_cells() {
    let layout = |z: f64| -> Vec<Aabb> {
        let mut boxes = Vec::new();
        for row in 0..10 {
            for k in 0..20 {
                let x = 1.75 * k as f64 + if row % 2 == 1 { 0.875 } else { 0.0 };
                let min = Vector3::new(x, 1.25 * row as f64, -z);
                boxes.push(Aabb {
                    min,
                    max: min + Vector3::new(1.5 + 0.25, 1.0 + 0.25, 2.0 * z),
                });
            }
        }
        boxes
    };
    let (flat, thick) = (layout(0.0), layout(0.25));
    let mut grid = BroadGrid::default();
    let mut pairs = Vec::new();
    grid.pairs_into(&flat, &mut pairs);
    let (flat_entries, flat_pairs) = (grid.entered(), pairs.clone());
    grid.pairs_into(&thick, &mut pairs);
    assert_eq!(pairs, flat_pairs);
    assert_eq!(pairs, sweep_and_prune_pairs(&thick));
    assert!(flat_entries >= 200, "{flat_entries}");
    assert_eq!(grid.entered(), flat_entries);
}

#[test]
fn mesh_contacts_come_from_both_bodies_with_normals_out_of_body_2() {
    // Two boxes overlapping along x by 1 cm, the second turned 30° about y and raised 5 cm so
    // that its leading bottom corner pokes into the first. (Level with each other, every
    // penetrating vertex would lie in the plane of a face: on the surface, not inside, which the
    // vertex method does not count; docs/contact.md §"Mesh contacts".)
    let root = common::project_root();
    let mesh = Arc::new(TriMesh::load_obj(&root.join("scenes/data/box.obj")).unwrap());
    let a = body_with(
        mesh.clone(),
        Vector3::new(0.0, 1.0, 0.0),
        Matrix3::identity(),
    );
    let turn = exp_so3(&Vector3::new(0.0, 30f64.to_radians(), 0.0));
    // The turned box's half-width along x is 0.25 (cos 30° + sin 30°).
    let reach = 0.25 * (30f64.to_radians().cos() + 30f64.to_radians().sin());
    let b = body_with(
        mesh.clone(),
        Vector3::new(0.25 + reach - 0.01, 1.05, 0.0),
        turn,
    );
    let colliders = vec![
        MeshCollider::new(mesh.clone()).unwrap(),
        MeshCollider::new(mesh).unwrap(),
    ];
    let mut contacts = Vec::new();
    detect_contacts(
        &[a, b],
        &colliders,
        rigidref::rigid3d::collide::CollisionMethod::Vertices,
        &mut contacts,
    );
    assert!(
        !contacts.is_empty(),
        "the boxes overlap, so there are contacts"
    );
    for c in &contacts {
        // Body 1 owns the vertex; the normal points out of body 2 toward body 1.
        let toward_body1 = if c.body1 == 0 {
            -Vector3::x()
        } else {
            Vector3::x()
        };
        assert!(c.frame.n.dot(&toward_body1) > 0.5, "{c:?}");
        assert!(c.depth > 0.0 && c.depth <= 0.01 + 1e-12, "{c:?}");
    }
    // The turned box's leading bottom corner is inside the first box.
    assert!(
        contacts.iter().any(|c| c.body1 == 1 && c.body2 == Some(0)),
        "{contacts:?}"
    );
}

/// The broad phase's grid cells are ⌊coordinate / side⌋ by `broad::floor`, which avoids the
/// library call: it must be `f64::floor` bit for bit, signed zeros, values ±1 ulp about integers,
/// the 2⁵² boundary where it hands over to `f64::floor`, huge, tiny, infinite and NaN values
/// included, and on 20 000 random values of every magnitude.
#[test]
fn the_grid_floor_is_the_library_floor_bit_for_bit() {
    use rigidref::common::broad::floor;
    let same = |x: f64| {
        let (ours, library) = (floor(x), x.floor());
        (ours.is_nan() && library.is_nan()) || ours.to_bits() == library.to_bits()
    };
    let two52 = 4_503_599_627_370_496.0f64;
    let mut values = vec![
        0.0,
        -0.0,
        0.5,
        -0.5,
        1.0,
        -1.0,
        2.5,
        -2.5,
        1e-300,
        -1e-300,
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        two52,
        -two52,
        two52 - 0.5,
        -(two52 - 0.5),
        2.0 * two52 + 2.0,
        1e300,
        -1e300,
        f64::MAX,
        f64::MIN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    for k in -40..=40 {
        let x = k as f64 * 0.75;
        values.extend([
            x,
            f64::from_bits(x.to_bits() + 1),
            f64::from_bits(x.to_bits().wrapping_sub(1)),
        ]);
    }
    for x in values {
        assert!(same(x), "{x:e}: {} against {}", floor(x), x.floor());
    }
    proptest!(common::seeded(20_000), |(bits in any::<u64>())| {
        let x = f64::from_bits(bits);
        prop_assert!(same(x), "{:e}", x);
    });
}

/// Boxes whose sides lie exactly on the grid's cell boundaries (unit cubes at integer
/// positions, negative ones included, touching their neighbours face to face, edge to edge and
/// corner to corner), and the same shifted by ±1 ulp: the grid finds exactly the overlapping
/// pairs, touching included.
#[test]
fn broad_phase_finds_the_touching_pairs_on_cell_boundaries() {
    for shift in [0.0, 1.0, -1.0] {
        let mut boxes = Vec::new();
        for x in -2..2 {
            for y in -2..1 {
                for z in -1..1 {
                    let min = Vector3::new(x as f64, y as f64, z as f64);
                    let nudge = |v: f64| {
                        if shift == 0.0 || v == 0.0 {
                            v
                        } else if (shift > 0.0) == (v > 0.0) {
                            f64::from_bits(v.to_bits() + 1)
                        } else {
                            f64::from_bits(v.to_bits() - 1)
                        }
                    };
                    let min = min.map(nudge);
                    boxes.push(Aabb {
                        min,
                        max: min.add_scalar(1.0),
                    });
                }
            }
        }
        let mut all_pairs = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if boxes[i].overlaps(&boxes[j]) {
                    all_pairs.push((i, j));
                }
            }
        }
        // Unshifted, every box touches each of its neighbours in the 4 × 3 × 2 block, faces,
        // edges and corners: ((3·4 − 2)(3·3 − 2)(3·2 − 2) − 24) / 2 = 128 pairs.
        assert!(
            shift != 0.0 || all_pairs.len() == 128,
            "{}",
            all_pairs.len()
        );
        assert_eq!(overlapping_pairs(&boxes), all_pairs, "shift {shift}");
    }
}
