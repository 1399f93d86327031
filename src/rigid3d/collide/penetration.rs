//! The penetration measure: how deep bodies interpenetrate, independent of the contacts found.
//! docs/contact.md §"Penetration measure".
//!
//! For a body and the ground: the depth of its lowest vertex below y = 0 (exact: the deepest
//! point of a solid below a plane is a vertex). For two bodies whose bounding boxes overlap: the
//! largest penetration depth (minimum translation distance) of a convex piece of one with a
//! convex piece of the other, from the separating-axis oracle ([`super::sat`]; for two boxes its
//! 15 axes, [`Cuboid::depth`]), which shares no code with detection, so that a body inside
//! another cannot hide behind the contacts that were found. For convex bodies this is exactly
//! the distance one body must move to separate them.

use super::mesh_pair::MeshCollider;
use super::pieces::{Cuboid, pose};
use super::sat::OracleBuffers;
use crate::common::broad::{Aabb, overlapping_pairs};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::mesh::TriMesh;
use parry3d_f64::math::Pose;

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

/// Penetration depth of bodies `i` and `j`, m: the largest over pairs of their convex pieces of
/// the oracle's depth (0 when no pieces overlap).
pub fn pair_depth(
    body_i: &RigidBody,
    collider_i: &MeshCollider,
    body_j: &RigidBody,
    collider_j: &MeshCollider,
) -> f64 {
    let placed = |body: &RigidBody, collider: &MeshCollider| {
        let pose = pose(body);
        let boxes: Vec<Aabb> = collider
            .pieces
            .pieces
            .iter()
            .map(|p| p.world_aabb(&pose))
            .collect();
        (pose, boxes)
    };
    let (pose_i, boxes_i) = placed(body_i, collider_i);
    let (pose_j, boxes_j) = placed(body_j, collider_j);
    placed_pair_depth(
        (body_i, collider_i, &pose_i, &boxes_i),
        (body_j, collider_j, &pose_j, &boxes_j),
        &mut OracleBuffers::default(),
    )
}

/// A body placed for the measure: the body, its collider, its pose, its pieces' world boxes.
type PlacedBody<'a> = (&'a RigidBody, &'a MeshCollider, &'a Pose, &'a [Aabb]);

/// [`pair_depth`] for bodies whose pose and pieces' world boxes are already computed (once per
/// body per measure, however many pairs it is in).
fn placed_pair_depth(
    (body_i, collider_i, pose_i, boxes_i): PlacedBody,
    (body_j, collider_j, pose_j, boxes_j): PlacedBody,
    oracle: &mut OracleBuffers,
) -> f64 {
    let mut deepest = 0.0_f64;
    for (a, box_a) in collider_i.pieces.pieces.iter().zip(boxes_i) {
        for (b, box_b) in collider_j.pieces.pieces.iter().zip(boxes_j) {
            if !box_a.overlaps(box_b) {
                continue;
            }
            // Two boxes: their own 15 separating axes, a tenth of the general oracle's cost.
            let depth = if let (Some(ca), Some(cb)) = (&a.cuboid, &b.cuboid) {
                Cuboid::depth(ca, pose_i, cb, pose_j)
            } else {
                oracle.depth(
                    (a, &body_i.rotation, &body_i.x),
                    (b, &body_j.rotation, &body_j.x),
                    true,
                )
            };
            deepest = deepest.max(depth);
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
    let pairs = overlapping_pairs(&boxes);
    penetrations_in(
        bodies,
        colliders,
        (&boxes, &pairs),
        &mut PlacedBuffers::default(),
        out,
    );
}

/// The penetration measure's buffers (each body's pose and its pieces' world boxes, the
/// oracle's working memory), kept from call to call so that the measure allocates nothing once they have
/// grown.
#[derive(Clone, Debug, Default)]
pub struct PlacedBuffers {
    placed: Vec<Option<(Pose, std::ops::Range<usize>)>>,
    piece_boxes: Vec<Aabb>,
    oracle: OracleBuffers,
}

/// [`penetrations`] given the bodies' world boxes (`boxes[i]` of body i) and the pairs whose
/// boxes overlap ([`overlapping_pairs`]).
pub fn penetrations_in(
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    (boxes, pairs): (&[Aabb], &[(usize, usize)]),
    buffers: &mut PlacedBuffers,
    out: &mut Vec<Penetration>,
) {
    out.clear();
    for i in 0..bodies.len() {
        // Body and ground: the depth of the lowest vertex, the bottom of the body's world box.
        let depth = (-boxes[i].min.y).max(0.0);
        if depth > 0.0 {
            out.push(Penetration {
                body1: i,
                body2: None,
                depth,
                bound: PENETRATION_BOUND * colliders[i].size(),
            });
        }
    }
    // Each body's pose and pieces' world boxes, once (a body is in several pairs).
    let PlacedBuffers {
        placed,
        piece_boxes,
        oracle,
    } = buffers;
    placed.clear();
    placed.resize(bodies.len(), None);
    piece_boxes.clear();
    for &(i, j) in pairs {
        for k in [i, j] {
            if placed[k].is_none() {
                let pose = pose(&bodies[k]);
                let start = piece_boxes.len();
                piece_boxes.extend(
                    colliders[k]
                        .pieces
                        .pieces
                        .iter()
                        .map(|p| p.world_aabb(&pose)),
                );
                placed[k] = Some((pose, start..piece_boxes.len()));
            }
        }
    }
    for &(i, j) in pairs {
        let side = |k: usize| {
            let (pose, range) = placed[k].as_ref().expect("placed above");
            (&bodies[k], &colliders[k], pose, &piece_boxes[range.clone()])
        };
        let depth = placed_pair_depth(side(i), side(j), oracle);
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
