//! Contacts of an analytic ellipsoid ([`crate::rigid3d::shape::Ellipsoid`], the rattleback's
//! smooth bottom): one contact with the ground at the exact lowest point, and a mesh's vertices
//! against the exact implicit surface. docs/contact.md §"Ellipsoid contact".

use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use crate::rigid3d::shape::Ellipsoid;
use nalgebra::Vector3;

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
