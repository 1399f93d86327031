//! Benchmark: sphere-tree culling against the default (bounding box, then parry's BVH), side by
//! side in one run (docs/contact.md §"Sphere trees").
//!
//!     cargo bench --bench sphere_tree
//!
//! For the assignment's meshes (when ../shared is present), the project's tee and finely
//! subdivided meshes: the time to build the BVH (parry's triangle mesh) and the sphere tree, their
//! memory, and the time of the vertex tests of one body against another (every vertex of B
//! against A, over 200 random overlapping poses) with each culling. Ratios are the result: the
//! machine is shared.

use nalgebra::{Matrix3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigidref::rigid3d::body::RigidBody;
use rigidref::rigid3d::collide::MeshCollider;
use rigidref::rigid3d::collide::mesh_pair::vertex_contacts;
use rigidref::rigid3d::collide::pieces::ConvexPieces;
use rigidref::rigid3d::collide::sphere_tree::DEFAULT_DEPTH;
use rigidref::rigid3d::mesh::TriMesh;
use rigidref::rigid3d::rotation::exp_so3;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;
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

/// Each triangle split into four at its edge midpoints, `levels` times; with `radius`, the new
/// vertices pushed onto the sphere of that radius about the origin.
fn subdivide(mesh: &TriMesh, levels: u32, radius: Option<f64>) -> TriMesh {
    let mut m = mesh.clone();
    for _ in 0..levels {
        let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
        let mut triangles = Vec::with_capacity(4 * m.triangles.len());
        let mut vertices = m.vertices.clone();
        let mut mid = |a: usize, b: usize, vertices: &mut Vec<Vector3<f64>>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let mut p = (vertices[a] + vertices[b]) * 0.5;
                if let Some(r) = radius {
                    p *= r / p.norm();
                }
                vertices.push(p);
                vertices.len() - 1
            })
        };
        for &[a, b, c] in &m.triangles {
            let (ab, bc, ca) = (
                mid(a, b, &mut vertices),
                mid(b, c, &mut vertices),
                mid(c, a, &mut vertices),
            );
            triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        m = TriMesh {
            vertices,
            triangles,
            file_numbers: Vec::new(),
            file_vertex_count: 0,
        };
    }
    m
}

fn body(mesh: Arc<TriMesh>, x: Vector3<f64>, r: Matrix3<f64>) -> RigidBody {
    let mut b = RigidBody::new("b", 1.0, Matrix3::identity(), mesh);
    b.x = x;
    b.rotation = r;
    b.update_world_inertia();
    b
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut meshes: Vec<(String, TriMesh)> = Vec::new();
    let shared = root.join("../shared/assignments/rigid3d/data");
    for name in ["cube", "brick", "sphere", "thing"] {
        match TriMesh::load_obj(&shared.join(format!("{name}.obj"))) {
            Ok(m) => meshes.push((name.to_string(), m)),
            Err(_) => println!("../shared absent: no {name}"),
        }
    }
    let tee = TriMesh::load_obj(&root.join("scenes/data/tee.obj")).unwrap();
    meshes.push(("tee".into(), tee.clone()));
    meshes.push(("tee ×4³ (flat)".into(), subdivide(&tee, 3, None)));
    let ball = TriMesh::load_obj(&root.join("scenes/data/ball.obj")).unwrap();
    meshes.push(("ball ×4³ (round)".into(), subdivide(&ball, 3, Some(0.5))));
    println!(
        "{:<22} {:>7} {:>10} {:>10} {:>9} {:>9} {:>7} {:>11} {:>11} {:>7} {:>9}",
        "mesh",
        "verts",
        "BVH µs",
        "tree µs",
        "BVH kB",
        "tree kB",
        "leaves",
        "test BVH µs",
        "test tree µs",
        "ratio",
        "culled"
    );
    let rng = ChaCha8Rng::seed_from_u64(7);
    for (name, mesh) in meshes {
        let mesh = Arc::new(mesh);
        let pieces = Arc::new(ConvexPieces::of_mesh(&mesh).unwrap());
        let bvh_us = median_us(5, 3, || {
            MeshCollider::with_pieces(mesh.clone(), pieces.clone()).unwrap();
        });
        let plain = MeshCollider::with_pieces(mesh.clone(), pieces.clone()).unwrap();
        for depth in [3, DEFAULT_DEPTH, 6] {
            let tree_us = median_us(3, 1, || {
                plain.build_sphere_tree(depth);
            });
            let tree = Arc::new(plain.build_sphere_tree(depth));
            let culled = plain.clone().with_sphere_tree(tree.clone());
            // 200 poses of a second copy overlapping the first: offset within 0.6 of the two radii.
            let reach = 2.0 * mesh.bounding_radius();
            let mut rng = rng.clone();
            let a = body(mesh.clone(), Vector3::zeros(), Matrix3::identity());
            let poses: Vec<RigidBody> = (0..200)
                .map(|_| {
                    let turn = Vector3::new(
                        rng.random_range(-3.2..3.2),
                        rng.random_range(-3.2..3.2),
                        rng.random_range(-3.2..3.2),
                    );
                    let offset = Vector3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    body(mesh.clone(), offset * (0.6 * reach), exp_so3(&turn))
                })
                .collect();
            let mut out = Vec::new();
            let mut test = |collider: &MeshCollider| {
                median_us(5, 1, || {
                    for b in &poses {
                        out.clear();
                        vertex_contacts(1, b, 0, &a, collider, &mut out);
                    }
                }) / poses.len() as f64
            };
            let (t_bvh, t_tree) = (test(&plain), test(&culled));
            // Vertices the box lets through that the tree culls.
            let (mut through_box, mut culled_count) = (0usize, 0usize);
            for b in &poses {
                for v in &mesh.vertices {
                    let p = b.x + b.rotation * v;
                    if plain.may_contain(&p) {
                        through_box += 1;
                        culled_count += usize::from(!tree.may_contain(&p));
                    }
                }
            }
            println!(
                "{:<22} {:>7} {:>10.1} {:>10.1} {:>9.1} {:>9.1} {:>7} {:>11.2} {:>11.2} {:>7.2} {:>8.0}%",
                format!("{name} d{depth}"),
                mesh.vertices.len(),
                bvh_us,
                tree_us,
                plain.bvh_memory_bytes() as f64 / 1e3,
                tree.memory_bytes() as f64 / 1e3,
                tree.leaves().count(),
                t_bvh,
                t_tree,
                t_tree / t_bvh,
                100.0 * culled_count as f64 / through_box.max(1) as f64
            );
        }
    }
}
