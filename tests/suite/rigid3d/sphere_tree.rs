//! Sphere trees (docs/contact.md §"Sphere trees"): they cover each mesh's solid, and culling by
//! them finds exactly the contacts the default culling finds.

use crate::common;

use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;
use rigidref::rigid3d::body::RigidBody;
use rigidref::rigid3d::collide::closest_point::brute_force_signed_distance;
use rigidref::rigid3d::collide::sphere_tree::{DEFAULT_DEPTH, SphereTree};
use rigidref::rigid3d::collide::{CollisionMethod, MeshCollider, detect_contacts};
use rigidref::rigid3d::mesh::TriMesh;
use rigidref::rigid3d::rotation::exp_so3;
use std::cell::Cell;
use std::sync::Arc;

/// The assignment's meshes when ../shared is present, else none (with a printed reason), and the
/// project's non-convex tee.
fn meshes() -> Vec<(String, Arc<TriMesh>)> {
    let mut out = Vec::new();
    let tee = common::project_root().join("scenes/data/tee.obj");
    out.push((
        "tee".to_string(),
        Arc::new(TriMesh::load_obj(&tee).unwrap()),
    ));
    match common::rigid3d_assignment() {
        Some(dir) => {
            for name in ["cube", "brick", "sphere", "thing"] {
                let mesh = TriMesh::load_obj(&dir.join(format!("data/{name}.obj"))).unwrap();
                out.push((name.to_string(), Arc::new(mesh)));
            }
        }
        None => println!("../shared absent: the assignment's meshes are not tested"),
    }
    out
}

#[test]
fn sphere_trees_cover_each_mesh_and_every_sphere_holds_its_part_of_the_surface() {
    // Every point of the surface (random points on random triangles) and of the solid (random
    // points of the bounding box the brute-force oracle puts inside) is in a leaf sphere; every
    // inner sphere holds its children's; a point in no leaf is outside the mesh (the culling's
    // soundness). Exact: the covering holds in exact arithmetic, and the classification margin
    // (1e-9 relative) keeps round-off on its safe side.
    for (name, mesh) in meshes() {
        let tree = SphereTree::build_brute_force(&mesh, 4);
        for (i, node) in tree.nodes.iter().enumerate() {
            let (first, count) = node.children;
            for c in first..first + count {
                let child = &tree.nodes[c as usize];
                let reach = (child.centre - node.centre).norm() + child.radius;
                assert!(
                    reach <= node.radius * (1.0 + 1e-12),
                    "{name}: node {i} child {c}"
                );
            }
        }
        let (lo, hi) = mesh.vertices.iter().fold(
            (
                Vector3::repeat(f64::INFINITY),
                Vector3::repeat(f64::NEG_INFINITY),
            ),
            |(lo, hi), v| (lo.inf(v), hi.sup(v)),
        );
        let triangles = mesh.triangles.len();
        proptest!(common::seeded(300), |(
            t in 0..triangles,
            (u, v) in (0.0..1.0f64, 0.0..1.0f64),
            f in (-0.1..1.1f64, -0.1..1.1f64, -0.1..1.1f64),
        )| {
            let [a, b, c] = mesh.triangles[t].map(|k| mesh.vertices[k]);
            let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
            let on_surface = a + (b - a) * u + (c - a) * v;
            prop_assert!(tree.may_contain(&on_surface), "{}: surface point {:?}", name, on_surface);
            let p = lo + (hi - lo).component_mul(&Vector3::new(f.0, f.1, f.2));
            let d = brute_force_signed_distance(&mesh, &p).distance;
            if !tree.may_contain(&p) {
                prop_assert!(d > 0.0, "{}: {:?} is in no sphere but at distance {}", name, p, d);
            }
        });
    }
}

fn body(mesh: Arc<TriMesh>, x: Vector3<f64>, r: Matrix3<f64>) -> RigidBody {
    let mut b = RigidBody::new("b", 1.0, Matrix3::identity(), mesh);
    b.x = x;
    b.rotation = r;
    b.update_world_inertia();
    b
}

#[test]
fn sphere_tree_culling_finds_exactly_the_contacts_of_the_default_culling() {
    // 200 random configurations of the assignment's mesh pairs (and the tee): body B turned at
    // random and placed at a random offset within the sum of the two bounding radii of body A,
    // so that most pairs overlap. The contact lists (body, vertex, point, normal, depth, in
    // order) must be identical, bit for bit: the tree only skips vertices the BVH query would
    // have found outside.
    let meshes = meshes();
    let n = meshes.len();
    let plain: Vec<MeshCollider> = meshes
        .iter()
        .map(|(_, m)| MeshCollider::new(m.clone()).unwrap())
        .collect();
    let culled: Vec<MeshCollider> = plain
        .iter()
        .map(|c| {
            let tree = Arc::new(c.build_sphere_tree(DEFAULT_DEPTH));
            c.clone().with_sphere_tree(tree)
        })
        .collect();
    let (cases, with_contacts, total) = (Cell::new(0), Cell::new(0), Cell::new(0));
    let pruned = Cell::new(0);
    proptest!(common::seeded(200), |(
        a in 0..n, b in 0..n,
        turn_a in proptest::array::uniform3(-3.2..3.2f64),
        turn_b in proptest::array::uniform3(-3.2..3.2f64),
        offset in proptest::array::uniform3(-1.0..1.0f64),
    )| {
        let (ma, mb) = (&meshes[a].1, &meshes[b].1);
        let reach = ma.bounding_radius() + mb.bounding_radius();
        let bodies = [
            body(ma.clone(), Vector3::new(0.0, 5.0, 0.0), exp_so3(&Vector3::from(turn_a))),
            body(
                mb.clone(),
                Vector3::new(0.0, 5.0, 0.0) + Vector3::from(offset) * (0.6 * reach),
                exp_so3(&Vector3::from(turn_b)),
            ),
        ];
        let mut expected = Vec::new();
        detect_contacts(&bodies, &[plain[a].clone(), plain[b].clone()], CollisionMethod::Vertices, &mut expected);
        let mut found = Vec::new();
        detect_contacts(&bodies, &[culled[a].clone(), culled[b].clone()], CollisionMethod::Vertices, &mut found);
        prop_assert_eq!(&found, &expected, "{} against {}", &meshes[a].0, &meshes[b].0);
        // The tree must cull something: vertices of B inside A's box but in none of A's spheres.
        let tree = culled[a].sphere_tree.as_ref().unwrap();
        for v in &mb.vertices {
            let p = bodies[0].rotation.transpose() * (bodies[1].x + bodies[1].rotation * v - bodies[0].x);
            if plain[a].may_contain(&p) && !tree.may_contain(&p) {
                pruned.set(pruned.get() + 1);
            }
        }
        cases.set(cases.get() + 1);
        with_contacts.set(with_contacts.get() + usize::from(!expected.is_empty()));
        total.set(total.get() + expected.len());
    });
    let (cases, with_contacts, total) = (cases.get(), with_contacts.get(), total.get());
    let pruned = pruned.get();
    println!(
        "{cases} configurations, {with_contacts} with contacts, {total} contacts; {pruned} vertex queries culled by the trees beyond the boxes and bounding spheres"
    );
    assert!(
        pruned > 10,
        "the trees culled only {pruned} vertices the boxes and bounding spheres let through"
    );
    assert!(
        with_contacts >= 40,
        "only {with_contacts} of {cases} configurations touch"
    );
}

#[test]
fn a_scene_with_sphere_tree_culling_runs_like_the_default() {
    // The scene key: the tapered five-cube stack and the tee on a box, with `culling:
    // sphere_tree`, give the default's trace bit for bit (same contacts, same solves).
    for scene in ["box_stack.json", "tee_on_box.json"] {
        let path = common::project_root().join("scenes").join(scene);
        let run = |set: &[&str]| common::trace_records(&path, "1", set);
        let default = run(&[]);
        let culled = run(&["--set", "culling=sphere_tree"]);
        assert!(default.len() > 50);
        assert!(default == culled, "{scene}: the traces differ");
    }
}
