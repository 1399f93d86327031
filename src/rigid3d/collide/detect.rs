//! Detection of every contact of a world, in a fixed order: the ground, then the body pairs the
//! broad phase finds. docs/contact.md §"Collision detection".

use super::ground::ground_contacts;
use super::mesh::{MeshCollider, vertex_contacts};
use super::vertex_contact::Contact;
use crate::common::broad::{Aabb, overlapping_pairs};
use crate::rigid3d::body::RigidBody;

/// Finds all contacts of `bodies` (with the ground and with each other), appending them to `out`
/// in a fixed order: ground contacts body by body, then body pairs in the broad phase's order,
/// each pair's two directions in turn, vertices in mesh order. `colliders[i]` belongs to body i.
pub fn detect_contacts(bodies: &[RigidBody], colliders: &[MeshCollider], out: &mut Vec<Contact>) {
    out.clear();
    for (i, body) in bodies.iter().enumerate() {
        ground_contacts(i, body, out);
    }
    let boxes: Vec<Aabb> = bodies
        .iter()
        .zip(colliders)
        .map(|(b, c)| c.world_aabb(b))
        .collect();
    for (i, j) in overlapping_pairs(&boxes) {
        vertex_contacts(i, &bodies[i], j, &bodies[j], &colliders[j], out);
        vertex_contacts(j, &bodies[j], i, &bodies[i], &colliders[i], out);
    }
}
