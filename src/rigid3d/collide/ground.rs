//! Contacts with the ground plane y = 0. docs/contact.md §"Ground contacts".

use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use nalgebra::Vector3;

/// Appends a contact for every vertex of `body` below y = `margin` (m): normal +y, point the
/// vertex, depth −y (negative above the plane: a speculative contact; for a body with an analytic
/// ellipsoid, its lowest point below y = 0 instead). Body `index` is body 1; the ground is body
/// 2. The assignment's rule is `margin` = 0: strictly below the plane. `collision: complete`
/// passes its speculative margin, so that a body written exactly on the ground is held there from
/// its first step.
pub fn ground_contacts(index: usize, body: &RigidBody, margin: f64, out: &mut Vec<Contact>) {
    // A body with an analytic ellipsoid touches the ground at its one lowest point.
    if let Some(shape) = &body.ellipsoid {
        super::ellipsoid::ellipsoid_ground_contact(index, body, shape, out);
        return;
    }
    let frame = ContactFrame::from_normal(&Vector3::y());
    for (vertex, local) in body.mesh.vertices.iter().enumerate() {
        let point = body.x + body.rotation * local;
        if point.y < margin {
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
