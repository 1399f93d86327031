//! An analytic ellipsoid as a body's contact shape (the rattleback's smooth bottom): one contact
//! with the ground at the exact lowest point, and a mesh's vertices against the exact implicit
//! surface. docs/contact.md §"Ellipsoid contact".

use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::contact::ContactFrame;
use nalgebra::Vector3;

/// An ellipsoid fixed in a body: centre and semi-axes along the body frame's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Centre in the body frame (relative to the centre of mass), m.
    pub centre: Vector3<f64>,
    /// Semi-axes (a, b, c) along the body x, y, z axes, m, > 0.
    pub semi_axes: Vector3<f64>,
}

impl Ellipsoid {
    /// The body-frame surface point farthest along the body-frame direction `u` (‖u‖ > 0): with
    /// A = diag(a, b, c), c + A² u / ‖A u‖ (maximising u·q over qᵀA⁻²q = 1 by a Lagrange
    /// multiplier).
    pub fn support(&self, u: &Vector3<f64>) -> Vector3<f64> {
        let a = self.semi_axes;
        let au = a.component_mul(u);
        self.centre + a.component_mul(&au) / au.norm()
    }

    /// The outward unit normal at body-frame surface point `q`: the gradient of
    /// Σ ((q − c)_k / a_k)², normalised.
    pub fn normal(&self, q: &Vector3<f64>) -> Vector3<f64> {
        let a2 = self.semi_axes.component_mul(&self.semi_axes);
        (q - self.centre).component_div(&a2).normalize()
    }

    /// For a body-frame point `p` strictly inside: its depth and the outward normal there, from
    /// the nearest surface point along the ray from the centre scaled by the implicit function,
    /// q = c + (p − c)/√f, f = Σ ((p − c)_k / a_k)² < 1: depth = |q − p|·|n·(q − p)/|q − p||,
    /// the distance to the tangent plane at q (exact on a sphere, and for the shallow depths of a
    /// contact the first-order distance to the surface). `None` outside or at the centre.
    pub fn inside(&self, p: &Vector3<f64>) -> Option<(f64, Vector3<f64>)> {
        let r = p - self.centre;
        let f = r.component_div(&self.semi_axes).norm_squared();
        if f >= 1.0 || f == 0.0 || f.is_nan() {
            return None;
        }
        let q = self.centre + r / f.sqrt();
        let n = self.normal(&q);
        Some((n.dot(&(q - p)), n))
    }
}

/// Appends the ellipsoid body's one ground contact, when its lowest point is below y = 0: the
/// support point along R⁻¹(−y), normal +y, depth −y. Body `index` is body 1.
pub fn ellipsoid_ground_contact(
    index: usize,
    body: &RigidBody,
    shape: &Ellipsoid,
    out: &mut Vec<Contact>,
) {
    let down = body.rotation.transpose() * -Vector3::y();
    let point = body.x + body.rotation * shape.support(&down);
    if point.y < 0.0 {
        out.push(Contact {
            body1: index,
            body2: None,
            feature: Feature::Surface,
            point,
            frame: ContactFrame::from_normal(&Vector3::y()),
            depth: -point.y,
        });
    }
}

/// Appends a contact for every vertex of body `i` strictly inside body `j`'s ellipsoid: point the
/// vertex, depth and normal from [`Ellipsoid::inside`] (the normal rotated to the world frame).
/// Body i is body 1.
pub fn vertices_in_ellipsoid(
    i: usize,
    body_i: &RigidBody,
    j: usize,
    body_j: &RigidBody,
    shape: &Ellipsoid,
    out: &mut Vec<Contact>,
) {
    for (vertex, local) in body_i.mesh.vertices.iter().enumerate() {
        let point = body_i.x + body_i.rotation * local;
        let in_j = body_j.rotation.transpose() * (point - body_j.x);
        if let Some((depth, n)) = shape.inside(&in_j)
            && depth > 0.0
        {
            out.push(Contact {
                body1: i,
                body2: Some(j),
                feature: Feature::Vertex(vertex),
                point,
                frame: ContactFrame::from_normal(&(body_j.rotation * n).normalize()),
                depth,
            });
        }
    }
}
