//! Contacts with the ground plane y = 0. docs/contact.md §"Ground contacts".

use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::contact::ContactFrame;
use nalgebra::Vector3;

/// Appends a contact for every vertex of `body` strictly below y = 0: normal +y, point the
/// vertex, depth −y. Body `index` is body 1; the ground is body 2.
pub fn ground_contacts(index: usize, body: &RigidBody, out: &mut Vec<Contact>) {
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
