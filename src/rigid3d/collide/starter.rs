//! The 3D Python starter's collision detection (`collision: starter`), rule for rule, so that a
//! student who keeps the starter's `collision.py` finds the same contacts in the same order as
//! rigidref. docs/contact.md §"The starter's collision detection", which gives the file and
//! commit each rule was read from.
//!
//! - **Order**: body by body, its ground contacts, then its pairs with every later body
//!   (i < j), not every ground contact first.
//! - **Ground**: each vertex, in the OBJ file's order, strictly below y = 0; the point is the
//!   vertex, the normal +y.
//! - **Pairs**: only one direction: the vertices of the body whose mesh has more vertices
//!   (counted as libigl reads the file), against the other body's surface; on a tie, the later
//!   body's vertices against the earlier body. A vertex is a contact when its signed distance
//!   (libigl's, signed by the pseudonormal at the closest point) is negative; the point is the
//!   closest point of the other surface, not the vertex; the depth is the distance; the normal
//!   is the pseudonormal negated (into the other body).
//! - **Bodies**: the starter's contact is `Contact(vertex owner, other body, …)` with its normal
//!   pointing from the first into the second (the ground is the first of a ground contact);
//!   rigidref's normal points from body 2 into body 1, so here body 1 is the starter's second
//!   body (the body touching the ground, the body whose surface is penetrated) and body 2 the
//!   starter's first: the normal, the point and the Jacobian rows are the starter's own.
//!
//! The signed distance is libigl's `signed_distance` with `return_normals=True` (which switches
//! to the pseudonormal sign): the closest point over every triangle (libigl walks a tree; on an
//! exact tie of distance between two triangles whose closest points differ it may pick another
//! than the first in file order, taken here), its barycentric coordinates in that triangle
//! deciding whether the pseudonormal is the face's normal, an edge's (the normalised sum of its
//! two faces' normals) or a vertex's (the normalised angle-weighted sum of its faces' normals),
//! every normal computed from the world positions, as the starter passes them.

use super::closest_point::closest_point_on_triangle;
use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use nalgebra::Vector3;
use std::collections::HashMap;

/// libigl's threshold on a barycentric coordinate: at or below it the closest point is on the
/// opposite edge (or at a vertex, when two are), for the choice of pseudonormal.
const BARYCENTRIC_EPSILON: f64 = 1e-12;

/// Every contact of `bodies` by the starter's rules, replacing `out`: for each body in order,
/// its ground contacts ([`ground_contacts`]), then its pairs with every later body
/// ([`pair_contacts`]).
pub fn starter_contacts(bodies: &[RigidBody], out: &mut Vec<Contact>) {
    out.clear();
    for i in 0..bodies.len() {
        ground_contacts(i, &bodies[i], out);
        for j in i + 1..bodies.len() {
            pair_contacts((i, &bodies[i]), (j, &bodies[j]), out);
        }
    }
}

/// The world position of each vertex of `body`'s mesh, by index.
fn world_vertices(body: &RigidBody) -> Vec<Vector3<f64>> {
    body.mesh
        .vertices
        .iter()
        .map(|v| body.x + body.rotation * v)
        .collect()
}

/// `check_ground`: each vertex of body `index`, in the file's order, strictly below y = 0 is a
/// contact at the vertex with normal +y and depth −y. (An analytic ellipsoid is not the
/// starter's: its mesh is used.)
pub fn ground_contacts(index: usize, body: &RigidBody, out: &mut Vec<Contact>) {
    let frame = ContactFrame::from_normal(&Vector3::y());
    for vertex in body.mesh.file_order() {
        let point = body.x + body.rotation * body.mesh.vertices[vertex];
        if point.y < 0.0 {
            out.push(Contact {
                body1: index,
                body2: None,
                feature: Feature::Vertex(vertex),
                point,
                frame,
                depth: -point.y,
            });
        }
    }
}

/// `check_body_pair(body_i, body_j)`: the vertices of the body whose mesh has more vertices
/// (body i only when strictly more) against the other's surface, in the file's order.
pub fn pair_contacts(
    (i, body_i): (usize, &RigidBody),
    (j, body_j): (usize, &RigidBody),
    out: &mut Vec<Contact>,
) {
    let ((owner, owner_body), (other, other_body)) =
        if body_i.mesh.file_vertex_count() > body_j.mesh.file_vertex_count() {
            ((i, body_i), (j, body_j))
        } else {
            ((j, body_j), (i, body_i))
        };
    let surface = Surface::new(other_body);
    for vertex in owner_body.mesh.file_order() {
        let q = owner_body.x + owner_body.rotation * owner_body.mesh.vertices[vertex];
        let Some((closest, distance, pseudonormal)) = surface.signed_distance(&q) else {
            continue;
        };
        if distance < 0.0 {
            let normal = -pseudonormal;
            out.push(Contact {
                body1: other,
                body2: Some(owner),
                feature: Feature::StarterVertex(vertex),
                point: closest,
                frame: ContactFrame::from_normal(&normal),
                depth: -distance,
            });
        }
    }
}

/// A body's surface in world coordinates with libigl's normals: per face, per edge (uniform
/// weights) and per vertex (angle weights).
struct Surface<'a> {
    triangles: &'a [[usize; 3]],
    vertices: Vec<Vector3<f64>>,
    face_normals: Vec<Vector3<f64>>,
    edge_normals: HashMap<(usize, usize), Vector3<f64>>,
    vertex_normals: Vec<Vector3<f64>>,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
}

impl<'a> Surface<'a> {
    fn new(body: &'a RigidBody) -> Surface<'a> {
        let vertices = world_vertices(body);
        let triangles = &body.mesh.triangles[..];
        let face_normals: Vec<Vector3<f64>> = triangles
            .iter()
            .map(|t| {
                let n = (vertices[t[1]] - vertices[t[0]]).cross(&(vertices[t[2]] - vertices[t[0]]));
                let r = n.norm();
                if r == 0.0 { Vector3::zeros() } else { n / r }
            })
            .collect();
        let mut edge_normals: HashMap<(usize, usize), Vector3<f64>> = HashMap::new();
        let mut vertex_normals = vec![Vector3::zeros(); vertices.len()];
        for (t, n) in triangles.iter().zip(&face_normals) {
            for k in 0..3 {
                let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                *edge_normals.entry((a.min(b), a.max(b))).or_default() += n;
                let corner = t[k];
                let (u, v) = (
                    vertices[a] - vertices[corner],
                    vertices[b] - vertices[corner],
                );
                let angle = (u.dot(&v) / (u.norm() * v.norm())).clamp(-1.0, 1.0).acos();
                if angle.is_finite() {
                    vertex_normals[corner] += angle * n;
                }
            }
        }
        let unit = |n: &mut Vector3<f64>| {
            let r = n.norm();
            if r > 0.0 {
                *n /= r;
            }
        };
        edge_normals.values_mut().for_each(unit);
        vertex_normals.iter_mut().for_each(unit);
        let (mut lo, mut hi) = (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        );
        for v in &vertices {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
        Surface {
            triangles,
            vertices,
            face_normals,
            edge_normals,
            vertex_normals,
            lo,
            hi,
        }
    }

    /// libigl's signed distance of `q` with the pseudonormal sign: (closest point, signed
    /// distance, pseudonormal at the closest point), the distance negative when
    /// (q − c)·n < 0. `None` outside the surface's bounding box, where a closed surface has no
    /// inside (the distance there is positive, never a contact).
    fn signed_distance(&self, q: &Vector3<f64>) -> Option<(Vector3<f64>, f64, Vector3<f64>)> {
        if (0..3).any(|k| q[k] < self.lo[k] || q[k] > self.hi[k]) {
            return None;
        }
        let v = &self.vertices;
        let mut best: Option<(f64, Vector3<f64>, usize)> = None;
        for (f, t) in self.triangles.iter().enumerate() {
            let c = closest_point_on_triangle(q, &v[t[0]], &v[t[1]], &v[t[2]]);
            let d = (q - c).norm_squared();
            if best.is_none_or(|(b, _, _)| d < b) {
                best = Some((d, c, f));
            }
        }
        let (squared, closest, f) = best?;
        let n = self.pseudonormal(f, &closest);
        let sign = if (q - closest).dot(&n) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        Some((closest, sign * squared.sqrt(), n))
    }

    /// The pseudonormal at `c` on triangle `f`, chosen by its barycentric coordinates there as
    /// libigl does: none at or below [`BARYCENTRIC_EPSILON`] → the face's normal; one → the
    /// normal of the edge opposite it; two → the normal of the remaining vertex.
    fn pseudonormal(&self, f: usize, c: &Vector3<f64>) -> Vector3<f64> {
        let t = self.triangles[f];
        let b = barycentric(
            c,
            &self.vertices[t[0]],
            &self.vertices[t[1]],
            &self.vertices[t[2]],
        );
        let small: Vec<usize> = (0..3).filter(|&k| b[k] <= BARYCENTRIC_EPSILON).collect();
        match small.len() {
            1 => {
                let k = small[0];
                let (a, e) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                self.edge_normals[&(a.min(e), a.max(e))]
            }
            2 => {
                let k = (0..3).find(|k| !small.contains(k)).unwrap_or(0);
                self.vertex_normals[t[k]]
            }
            _ => self.face_normals[f],
        }
    }
}

/// Barycentric coordinates of `p` in triangle (a, b, c), libigl's formula (by dot products of
/// the edges from a).
fn barycentric(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> [f64; 3] {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(&v0), v0.dot(&v1), v1.dot(&v1));
    let (d20, d21) = (v2.dot(&v0), v2.dot(&v1));
    let denominator = d00 * d11 - d01 * d01;
    let l1 = (d11 * d20 - d01 * d21) / denominator;
    let l2 = (d00 * d21 - d01 * d20) / denominator;
    [1.0 - l1 - l2, l1, l2]
}
