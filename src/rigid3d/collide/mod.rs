//! Collision detection for 3D mesh bodies: which vertices are inside the ground or another body,
//! how deep, and which way out. docs/contact.md §"Collision detection".
//!
//! - [`ground`]: every vertex below the plane y = 0 is a contact with normal +y;
//! - [`broad`]: sweep-and-prune on world bounding boxes picks the body pairs worth testing;
//! - [`mesh`]: the vertices of each body of a pair against the other body's surface (signed
//!   distance through parry3d's bounding-volume hierarchy), both directions;
//! - [`closest_point`]: the brute-force oracle that tests hold [`mesh`] against.
//!
//! A contact always has the vertex owner as body 1 and the body it penetrates (or the ground) as
//! body 2, so the normal (out of body 2) is the direction body 1 must move to separate.

pub mod closest_point;
pub mod ground;
pub mod mesh;

pub use mesh::MeshCollider;

use crate::rigid3d::body::RigidBody;
use crate::rigid3d::contact::ContactFrame;
use nalgebra::Vector3;

/// One contact found by collision detection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The body whose vertex penetrates (body 1).
    pub body1: usize,
    /// The body it penetrates, or `None` for the ground (body 2).
    pub body2: Option<usize>,
    /// Index of the penetrating vertex in body 1's mesh; with the bodies it identifies the contact
    /// from step to step (warm start).
    pub vertex: usize,
    /// Contact point: the penetrating vertex, world frame, m.
    pub point: Vector3<f64>,
    /// Contact frame; `frame.n` points from body 2 into body 1.
    pub frame: ContactFrame,
    /// Penetration depth, m, ≥ 0.
    pub depth: f64,
}

/// Finds all contacts of `bodies` (with the ground and with each other), appending them to `out`
/// in a fixed order: ground contacts body by body, then body pairs in the broad phase's order,
/// each pair's two directions in turn, vertices in mesh order. `colliders[i]` belongs to body i.
pub fn detect_contacts(bodies: &[RigidBody], colliders: &[MeshCollider], out: &mut Vec<Contact>) {
    out.clear();
    for (i, body) in bodies.iter().enumerate() {
        ground::ground_contacts(i, body, out);
    }
    let boxes: Vec<crate::common::broad::Aabb> = bodies
        .iter()
        .zip(colliders)
        .map(|(b, c)| c.world_aabb(b))
        .collect();
    for (i, j) in crate::common::broad::overlapping_pairs(&boxes) {
        mesh::vertex_contacts(i, &bodies[i], j, &bodies[j], &colliders[j], out);
        mesh::vertex_contacts(j, &bodies[j], i, &bodies[i], &colliders[i], out);
    }
}
