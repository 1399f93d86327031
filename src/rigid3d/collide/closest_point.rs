//! The brute-force oracle: signed distance from a point to a closed triangle mesh by visiting
//! every triangle, inside/outside by the winding number. Slow (O(triangles) per query) and plain;
//! tests hold the fast path ([`super::mesh`]) against it. docs/contact.md §"Signed distance".

use crate::rigid3d::mesh::TriMesh;
use nalgebra::Vector3;

/// A point's signed distance to a closed surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistance {
    /// Distance to the surface, m: negative inside, positive outside.
    pub distance: f64,
    /// The closest point on the surface, same frame as the query.
    pub closest: Vector3<f64>,
    /// Unit outward direction at the query point: away from the surface outside, toward it
    /// inside (so moving the point along it increases the signed distance). The triangle's
    /// normal when the point is on the surface.
    pub normal: Vector3<f64>,
    /// Index of the triangle the closest point is on.
    pub triangle: usize,
}

/// The point of triangle (a, b, c) closest to `p` (Ericson, Real-Time Collision Detection
/// §5.1.5: test the vertex regions, then the edge regions, else the face).
pub fn closest_point_on_triangle(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> Vector3<f64> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denominator = 1.0 / (va + vb + vc);
    a + ab * (vb * denominator) + ac * (vc * denominator)
}

/// The generalised winding number of a closed mesh around `p`: Σ solid angles / 4π, 1 inside an
/// outward-oriented closed surface and 0 outside (Van Oosterom and Strackee's solid angle).
pub fn winding_number(mesh: &TriMesh, p: &Vector3<f64>) -> f64 {
    let mut total = 0.0;
    for t in &mesh.triangles {
        let a = mesh.vertices[t[0]] - p;
        let b = mesh.vertices[t[1]] - p;
        let c = mesh.vertices[t[2]] - p;
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let numerator = a.dot(&b.cross(&c));
        let denominator = la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la;
        total += 2.0 * numerator.atan2(denominator);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// Signed distance from `p` to `mesh` by visiting every triangle. Inside when the winding number
/// exceeds ½.
pub fn brute_force_signed_distance(mesh: &TriMesh, p: &Vector3<f64>) -> SignedDistance {
    let mut best = (f64::INFINITY, Vector3::zeros(), 0usize);
    for (index, t) in mesh.triangles.iter().enumerate() {
        let q = closest_point_on_triangle(
            p,
            &mesh.vertices[t[0]],
            &mesh.vertices[t[1]],
            &mesh.vertices[t[2]],
        );
        let d = (q - p).norm_squared();
        if d < best.0 {
            best = (d, q, index);
        }
    }
    let (distance_squared, closest, triangle) = best;
    let _ = distance_squared;
    let inside = winding_number(mesh, p) > 0.5;
    SignedDistance::new(mesh, mesh.bounding_radius(), p, closest, inside, triangle)
}

impl SignedDistance {
    /// The signed distance of `p` given its closest surface point (on `triangle`) and whether it
    /// is inside: the distance negated inside; the normal from the closest point toward `p`
    /// outside, from `p` toward it inside, and the triangle's normal when `p` is on the surface
    /// (closer than 1e-12 of the mesh's bounding radius `radius`, m, where that direction is
    /// undefined). Shared by the oracle and the fast path, which differ in how they find the
    /// closest point and the side. `radius` is [`TriMesh::bounding_radius`], passed in because
    /// finding it visits every vertex (the fast path keeps it).
    pub fn new(
        mesh: &TriMesh,
        radius: f64,
        p: &Vector3<f64>,
        closest: Vector3<f64>,
        inside: bool,
        triangle: usize,
    ) -> SignedDistance {
        let distance = (closest - p).norm();
        let t = mesh.triangles[triangle];
        let v = &mesh.vertices;
        let normal = if distance > 1e-12 * radius {
            if inside {
                (closest - p) / distance
            } else {
                (p - closest) / distance
            }
        } else {
            (v[t[1]] - v[t[0]]).cross(&(v[t[2]] - v[t[0]])).normalize()
        };
        SignedDistance {
            distance: if inside { -distance } else { distance },
            closest,
            normal,
            triangle,
        }
    }
}
