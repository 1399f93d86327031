//! The penetration measure: how deep bodies interpenetrate, independent of the contacts found.
//! docs/contact.md §"Penetration measure".
//!
//! For a body and the ground: the depth of its lowest vertex below y = 0 (exact: the deepest
//! point of a solid below a plane is a vertex). For two bodies whose bounding boxes overlap: the
//! largest penetration depth (minimum translation distance) of a convex piece of one with a
//! convex piece of the other, from parry3d's GJK/EPA; [`super::sat`] is its brute-force oracle.
//! For convex bodies this is exactly the distance one body must move to separate them.

use super::mesh::MeshCollider;
use super::pieces::{Cuboid, pose};
use crate::common::broad::{Aabb, overlapping_pairs};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::mesh::TriMesh;

/// Interpenetration deeper than this fraction of the smaller body's size (the smallest side of
/// its bounding box in its own frame) means contacts were missed: a quarter.
pub const PENETRATION_BOUND: f64 = 0.25;

/// How deep one pair interpenetrates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Penetration {
    /// The first body (the lower index).
    pub body1: usize,
    /// The second body, or `None` for the ground.
    pub body2: Option<usize>,
    /// Depth, m (> 0).
    pub depth: f64,
    /// The bound for this pair, m: [`PENETRATION_BOUND`] × the smaller body's size.
    pub bound: f64,
}

impl Penetration {
    /// Whether the depth exceeds the bound.
    pub fn exceeds_bound(&self) -> bool {
        self.depth > self.bound
    }
}

/// A body's size: the smallest side of its mesh's bounding box in its own frame, m.
pub fn body_size(body: &RigidBody) -> f64 {
    mesh_size(&body.mesh)
}

/// The smallest side of a mesh's bounding box in its own frame, m.
pub fn mesh_size(mesh: &TriMesh) -> f64 {
    Aabb::around(mesh.vertices.iter().copied()).smallest_side()
}

/// Depth of `body` below the ground plane, m (0 when no vertex is below it).
pub fn ground_depth(body: &RigidBody) -> f64 {
    let lowest = body
        .mesh
        .vertices
        .iter()
        .map(|v| (body.x + body.rotation * v).y)
        .fold(f64::INFINITY, f64::min);
    (-lowest).max(0.0)
}

/// Penetration depth of bodies `i` and `j`, m: the largest over pairs of their convex pieces of
/// parry's contact depth (0 when no pieces overlap).
pub fn pair_depth(
    body_i: &RigidBody,
    collider_i: &MeshCollider,
    body_j: &RigidBody,
    collider_j: &MeshCollider,
) -> f64 {
    let (pose_i, pose_j) = (pose(body_i), pose(body_j));
    let mut deepest = 0.0_f64;
    for a in &collider_i.pieces.pieces {
        let box_a = a.world_aabb(&pose_i);
        for b in &collider_j.pieces.pieces {
            if !box_a.overlaps(&b.world_aabb(&pose_j)) {
                continue;
            }
            // Two boxes: the exact separating-axis depth, a tenth of GJK/EPA's cost.
            if let (Some(ca), Some(cb)) = (&a.cuboid, &b.cuboid) {
                deepest = deepest.max(Cuboid::depth(ca, &pose_i, cb, &pose_j));
                continue;
            }
            if let Ok(Some(contact)) =
                parry3d_f64::query::contact(&pose_i, &a.shape, &pose_j, &b.shape, 0.0)
            {
                deepest = deepest.max(-contact.dist);
            }
        }
    }
    deepest
}

/// Brute-force pair depth: [`super::sat::sat_depth`] over every pair of pieces.
pub fn brute_force_pair_depth(
    body_i: &RigidBody,
    collider_i: &MeshCollider,
    body_j: &RigidBody,
    collider_j: &MeshCollider,
) -> f64 {
    let mut deepest = 0.0_f64;
    for a in &collider_i.pieces.pieces {
        for b in &collider_j.pieces.pieces {
            deepest = deepest.max(super::sat::sat_depth(a, body_i, b, body_j));
        }
    }
    deepest
}

/// Every interpenetrating pair of the world, replacing `out`: bodies with the ground (body
/// order), then body pairs whose boxes overlap (broad-phase order); only depths > 0.
pub fn penetrations(bodies: &[RigidBody], colliders: &[MeshCollider], out: &mut Vec<Penetration>) {
    let mut boxes = Vec::new();
    MeshCollider::world_boxes(bodies, colliders, &mut boxes);
    penetrations_in(bodies, colliders, &boxes, out);
}

/// [`penetrations`] given the bodies' world boxes (`boxes[i]` of body i).
pub fn penetrations_in(
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    boxes: &[Aabb],
    out: &mut Vec<Penetration>,
) {
    out.clear();
    for (i, body) in bodies.iter().enumerate() {
        let depth = ground_depth(body);
        if depth > 0.0 {
            out.push(Penetration {
                body1: i,
                body2: None,
                depth,
                bound: PENETRATION_BOUND * colliders[i].size(),
            });
        }
    }
    for (i, j) in overlapping_pairs(boxes) {
        let depth = pair_depth(&bodies[i], &colliders[i], &bodies[j], &colliders[j]);
        if depth > 0.0 {
            out.push(Penetration {
                body1: i,
                body2: Some(j),
                depth,
                bound: PENETRATION_BOUND * colliders[i].size().min(colliders[j].size()),
            });
        }
    }
}
