//! A body's mesh as convex pieces, for `collision: complete` and for the penetration measure.
//! docs/contact.md §"Convex pieces".
//!
//! A convex mesh is one piece, its own hull (exact). A non-convex mesh (the assignment's `thing`)
//! is split by parry3d's approximate convex decomposition (V-HACD at [`DECOMPOSITION_RESOLUTION`]
//! voxels along the longest side), each piece the convex hull of the mesh triangles its voxels
//! touch; [`ConvexPieces::volume_error`] says how far the pieces' total volume is from the mesh's.

use super::polytope::Polytope;
use crate::common::broad::Aabb;
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::mesh::TriMesh;
use nalgebra::{Matrix3, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector as PVector};
use parry3d_f64::transformation::vhacd::{VHACD, VHACDParameters};

/// Voxels along the longest side of a non-convex mesh's bounding box in its decomposition.
/// 128 splits the assignment's `thing` into its bar and its post, with the pieces' volume 1.7 %
/// above the mesh's (the bar's piece reaches one voxel up the post).
pub const DECOMPOSITION_RESOLUTION: u32 = 128;

/// A mesh counts as convex when no vertex is further than this fraction of its bounding radius
/// in front of any triangle's plane.
pub const CONVEXITY_TOLERANCE: f64 = 1e-9;

/// One convex piece, body frame.
#[derive(Clone, Debug)]
pub struct Piece {
    /// The piece as a polytope: merged faces, their loops and planes, edges between faces
    /// (what `collision: complete`'s separating-axis query reads).
    pub polytope: Polytope,
    /// Its vertices, m (the hull's; the same as the polytope's).
    pub vertices: Vec<Vector3<f64>>,
    /// Its hull triangles (counter-clockwise seen from outside), those of non-zero area.
    pub triangles: Vec<[usize; 3]>,
    /// The outward unit normal of each of `triangles` (repeats included: what the oracle reads).
    pub normals: Vec<Vector3<f64>>,
    /// The hull triangles' edges as vertex index pairs, each once.
    pub edges: Vec<[usize; 2]>,
    /// The piece as a box, when it is one (the penetration measure's exact shortcut).
    pub cuboid: Option<Cuboid>,
}

/// A piece that is a rectangular box, body frame: centre, unit edge directions, half extents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    /// Centre, m.
    pub centre: Vector3<f64>,
    /// Unit directions of its three edges (orthogonal).
    pub axes: [Vector3<f64>; 3],
    /// Half the edge lengths along `axes`, m.
    pub half: Vector3<f64>,
}

impl Cuboid {
    /// `vertices` as a box: eight points that are a corner plus every sum of three orthogonal
    /// edge vectors from it, to 1e-9 of the box's size; `None` otherwise.
    pub fn of(vertices: &[Vector3<f64>]) -> Option<Cuboid> {
        if vertices.len() != 8 {
            return None;
        }
        let corner = vertices[0];
        // The corner's edges: the nearest other vertex, then the nearest at right angles to it,
        // then the nearest at right angles to both (a face diagonal can be nearer than the
        // longest edge).
        let mut others: Vec<Vector3<f64>> = vertices[1..].iter().map(|v| v - corner).collect();
        others.sort_by(|a, b| a.norm_squared().total_cmp(&b.norm_squared()));
        let size = others.last().map_or(0.0, |d| d.norm());
        let tolerance = 1e-9 * size;
        if size == 0.0 || others[0].norm() <= tolerance {
            return None;
        }
        let square = |a: &Vector3<f64>, b: &Vector3<f64>| a.dot(b).abs() <= tolerance * size;
        let e1 = others[0];
        let e2 = *others.iter().find(|d| square(d, &e1))?;
        let e3 = *others
            .iter()
            .find(|d| square(d, &e1) && square(d, &e2) && **d != e2)?;
        let edges = [e1, e2, e3];
        // Every vertex is the corner plus some of the edges, and every such sum is a vertex.
        let mut seen = [false; 8];
        for v in vertices {
            let d = v - corner;
            let bits = [0, 1, 2].map(|k| d.dot(&edges[k]) / edges[k].norm_squared());
            let mut index = 0;
            let mut rebuilt = Vector3::zeros();
            for k in 0..3 {
                let bit = bits[k].round();
                if !(bit == 0.0 || bit == 1.0) {
                    return None;
                }
                if bit == 1.0 {
                    index |= 1 << k;
                    rebuilt += edges[k];
                }
            }
            if (rebuilt - d).norm() > tolerance || seen[index] {
                return None;
            }
            seen[index] = true;
        }
        Some(Cuboid {
            centre: corner + (edges[0] + edges[1] + edges[2]) / 2.0,
            axes: edges.map(|e| e.normalize()),
            half: Vector3::new(edges[0].norm(), edges[1].norm(), edges[2].norm()) / 2.0,
        })
    }

    /// The penetration depth of boxes `a` and `b` placed by `pose_a` and `pose_b`, m: the
    /// smallest overlap of their projections over the 15 separating-axis candidates (3 + 3 face
    /// normals, 9 edge cross products; parallel edges give none), 0 when one separates them.
    /// For two convex polyhedra the minimum translation distance lies along one of these, so
    /// this is the exact depth. docs/contact.md §"Penetration measure".
    pub fn depth(a: &Cuboid, pose_a: &Pose, b: &Cuboid, pose_b: &Pose) -> f64 {
        let place = |c: &Cuboid, pose: &Pose| {
            (
                world_point(pose, to_parry(&c.centre)),
                c.axes.map(|u| world_vector(pose, to_parry(&u))),
            )
        };
        let (ca, ua) = place(a, pose_a);
        let (cb, ub) = place(b, pose_b);
        let t = cb - ca;
        let mut depth = f64::INFINITY;
        let mut test = |axis: Vector3<f64>| -> bool {
            let length = axis.norm();
            if length <= 1e-9 {
                return true; // parallel edges: no axis of its own
            }
            let l = axis / length;
            let reach = |u: &[Vector3<f64>; 3], half: &Vector3<f64>| {
                (0..3).map(|k| half[k] * u[k].dot(&l).abs()).sum::<f64>()
            };
            let overlap = reach(&ua, &a.half) + reach(&ub, &b.half) - t.dot(&l).abs();
            depth = depth.min(overlap);
            overlap > 0.0
        };
        for k in 0..3 {
            if !test(ua[k]) || !test(ub[k]) {
                return 0.0;
            }
        }
        for a_edge in &ua {
            for b_edge in &ub {
                if !test(a_edge.cross(b_edge)) {
                    return 0.0;
                }
            }
        }
        depth
    }
}

/// A body's convex pieces.
#[derive(Clone, Debug)]
pub struct ConvexPieces {
    /// The pieces, body frame.
    pub pieces: Vec<Piece>,
    /// Whether the mesh itself is convex (then there is one piece, exact).
    pub convex: bool,
    /// (Σ piece volumes − mesh volume) / mesh volume; 0 for a convex mesh.
    pub volume_error: f64,
}

fn to_parry(v: &Vector3<f64>) -> PVector {
    PVector::new(v.x, v.y, v.z)
}

fn from_parry(v: PVector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// A body's pose for parry: translation x, rotation R (re-orthonormalised through a quaternion).
pub fn pose(body: &RigidBody) -> Pose {
    Pose::from_parts(to_parry(&body.x), rotation(&body.rotation))
}

/// A rotation matrix as parry's (and rapier's) quaternion, normalised.
pub fn rotation(m: &Matrix3<f64>) -> Rotation {
    // glam matrices are column-major.
    let cols = parry3d_f64::math::Matrix::from_cols(
        to_parry(&m.column(0).into()),
        to_parry(&m.column(1).into()),
        to_parry(&m.column(2).into()),
    );
    Rotation::from_mat3(&cols).normalize()
}

/// World-frame direction of a body-frame vector under `pose`.
pub fn world_vector(pose: &Pose, v: PVector) -> Vector3<f64> {
    from_parry(pose.rotation * v)
}

/// World-frame position of a body-frame point under `pose`.
pub fn world_point(pose: &Pose, p: PVector) -> Vector3<f64> {
    from_parry(pose * p)
}

impl Piece {
    /// The convex hull of `points` as a piece; `None` when the points span no volume.
    pub fn hull(points: &[Vector3<f64>]) -> Option<Piece> {
        let parry_points: Vec<PVector> = points.iter().map(to_parry).collect();
        // The fallible hull: points that span no volume (a flat or degenerate piece) are no piece,
        // not a panic (found by fuzzing: tests/fuzz-regressions/scene3d/flat-piece).
        let (hull_points, hull_triangles) =
            parry3d_f64::transformation::try_convex_hull(&parry_points).ok()?;
        let vertices: Vec<Vector3<f64>> = hull_points.into_iter().map(from_parry).collect();
        let all: Vec<[usize; 3]> = hull_triangles
            .iter()
            .map(|t| t.map(|i| i as usize))
            .collect();
        let polytope = Polytope::from_hull(vertices.clone(), &all)?;
        if !(polytope.volume() > 0.0) {
            return None;
        }
        let mut triangles = Vec::with_capacity(all.len());
        let mut normals = Vec::with_capacity(all.len());
        let mut edges = Vec::new();
        for t in &all {
            let [a, b, c] = t.map(|i| vertices[i]);
            let n = (b - a).cross(&(c - a));
            if n.norm() > 0.0 {
                triangles.push(*t);
                normals.push(n.normalize());
            }
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                if i < j {
                    edges.push([i, j]);
                }
            }
        }
        let cuboid = Cuboid::of(&vertices);
        Some(Piece {
            polytope,
            vertices,
            triangles,
            normals,
            edges,
            cuboid,
        })
    }

    /// The piece's volume, m³.
    pub fn volume(&self) -> f64 {
        self.polytope.volume()
    }

    /// The piece's world bounding box under `pose`.
    pub fn world_aabb(&self, pose: &Pose) -> Aabb {
        Aabb::around(self.vertices.iter().map(|v| world_point(pose, to_parry(v))))
    }
}

impl ConvexPieces {
    /// The pieces of `mesh` (body frame, closed, outward oriented).
    pub fn of_mesh(mesh: &TriMesh) -> Result<ConvexPieces, String> {
        let radius = mesh.bounding_radius();
        if mesh.is_convex(CONVEXITY_TOLERANCE * radius) {
            let piece = Piece::hull(&mesh.vertices)
                .ok_or_else(|| "the mesh spans no volume".to_string())?;
            return Ok(ConvexPieces {
                pieces: vec![piece],
                convex: true,
                volume_error: 0.0,
            });
        }
        let points: Vec<PVector> = mesh.vertices.iter().map(to_parry).collect();
        let indices: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| t.map(|i| i as u32)).collect();
        let params = VHACDParameters {
            resolution: DECOMPOSITION_RESOLUTION,
            ..Default::default()
        };
        // parry's V-HACD unwraps its own convex hulls and panics on some folded meshes (found by
        // fuzzing: a cube with a vertex pushed through a face); that is a mesh it cannot
        // decompose, reported as such, not a crash.
        let hulls = quietly(|| {
            VHACD::decompose(&params, &points, &indices, true)
                .compute_exact_convex_hulls(&points, &indices)
        })
        .map_err(|_| {
            concat!(
                "the convex decomposition of the mesh failed inside parry's V-HACD; ",
                "the mesh may fold over itself"
            )
            .to_string()
        })?;
        let pieces: Vec<Piece> = hulls
            .iter()
            .filter_map(|(hull_points, _)| {
                let v: Vec<Vector3<f64>> = hull_points.iter().map(|p| from_parry(*p)).collect();
                Piece::hull(&v)
            })
            .collect();
        if pieces.is_empty() {
            return Err("the convex decomposition found no pieces".into());
        }
        let mesh_volume = mesh.topology().signed_volume;
        let pieces_volume: f64 = pieces.iter().map(Piece::volume).sum();
        Ok(ConvexPieces {
            pieces,
            convex: false,
            volume_error: (pieces_volume - mesh_volume) / mesh_volume,
        })
    }
}

thread_local! {
    /// Whether this thread is inside [`quietly`] (its panics are caught and reported).
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f` (a call into a dependency that may panic on input it cannot handle) and returns its
/// value, or the panic's message (for the caller to use or drop). The process's panic hook
/// (which prints the message and, under a fuzzer, aborts) is skipped for a panic inside `f` on
/// this thread and kept for every other: it is wrapped once, the first time this runs.
fn quietly<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    static WRAP: std::sync::Once = std::sync::Once::new();
    WRAP.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(|q| q.get()) {
                previous(info)
            }
        }));
    });
    QUIET.with(|q| q.set(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET.with(|q| q.set(false));
    result.map_err(|payload| {
        payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "a panic without a message".into())
    })
}
