//! Contacts with the ground plane y = 0. docs/contact.md §"Ground contacts".

use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use nalgebra::Vector3;

/// Appends a contact for every vertex of `body` strictly below y = 0: normal +y, point the
/// vertex, depth −y (for a body with an analytic ellipsoid, its lowest point instead). Body
/// `index` is body 1; the ground is body 2.
pub fn ground_contacts(index: usize, body: &RigidBody, out: &mut Vec<Contact>) {
    // A body with an analytic ellipsoid touches the ground at its one lowest point.
    if let Some(shape) = &body.ellipsoid {
        super::ellipsoid::ellipsoid_ground_contact(index, body, shape, out);
        return;
    }
    let frame = ContactFrame::from_normal(&Vector3::y());
    for (vertex, local) in body.mesh.vertices.iter().enumerate() {
        let point = body.x + body.rotation * local;
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
