//! `collision: complete`: the contacts the vertex rule misses, from contact manifolds between the
//! two bodies' convex pieces (the penetration direction by GJK/EPA, then the two pieces'
//! supporting faces, edges or vertices clipped against each other: parry3d's steps, driven by
//! [`super::convex`]). docs/contact.md §"Complete collision detection".

use super::convex::ConvexQuery;
use super::mesh_pair::MeshCollider;
use super::pieces::{ConvexPieces, pose, world_point, world_vector};
use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use parry3d_f64::math::Pose;
use parry3d_f64::query::ContactManifold;

/// A manifold point whose witness lies within this fraction of the smaller body's bounding radius
/// of a contact already found (a vertex contact, or an earlier manifold point) is that contact.
pub const SAME_POINT_TOLERANCE: f64 = 1e-9;

/// The manifold queries' working memory (GJK/EPA's buffers and the manifold's points), kept from
/// call to call so that they allocate nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct ManifoldBuffers {
    query: ConvexQuery,
    manifold: ContactManifold<(), ()>,
}

/// Appends the manifold contacts of bodies i < j that `out[pair_start..]` (the pair's vertex
/// contacts, and then these) does not already hold. Each is
/// oriented as every contact is: body 1 = i, body 2 = j, point the witness on i's surface (inside
/// j), n from j into i, depth −(signed distance) > 0. A manifold point is already held when a
/// contact of i with j has its witness on i as point, or a contact of j with i its witness on j,
/// with the same depth and the same line of action (within round-off): the vertex rule's
/// contact, or an earlier manifold point. A vertex whose nearest face is not the manifold's
/// direction gives two contacts at one point, one per normal.
pub fn manifold_contacts(
    (i, j): (usize, usize),
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    pair_start: usize,
    buffers: &mut ManifoldBuffers,
    out: &mut Vec<Contact>,
) {
    let pair = PairPoses::new((i, j), bodies, colliders);
    for (a, piece_a) in pair.pieces_i.pieces.iter().enumerate() {
        let box_a = piece_a.world_aabb(&pair.pose_i);
        for (b, piece_b) in pair.pieces_j.pieces.iter().enumerate() {
            if box_a.overlaps(&piece_b.world_aabb(&pair.pose_j)) {
                piece_pair_contacts(&pair, (a, b), pair_start, buffers, out);
            }
        }
    }
}

/// [`manifold_contacts`] over the piece pairs `candidates` only (in their order, ascending),
/// each tested by its world boxes as there: the same contacts when `candidates` holds every
/// piece pair whose boxes overlap (docs/contact.md §"Temporal coherence").
pub fn manifold_contacts_among(
    (i, j): (usize, usize),
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    candidates: impl Iterator<Item = (usize, usize)>,
    pair_start: usize,
    buffers: &mut ManifoldBuffers,
    out: &mut Vec<Contact>,
) {
    let pair = PairPoses::new((i, j), bodies, colliders);
    for (a, b) in candidates {
        let (piece_a, piece_b) = (&pair.pieces_i.pieces[a], &pair.pieces_j.pieces[b]);
        if piece_a
            .world_aabb(&pair.pose_i)
            .overlaps(&piece_b.world_aabb(&pair.pose_j))
        {
            piece_pair_contacts(&pair, (a, b), pair_start, buffers, out);
        }
    }
}

/// A body pair placed for the manifold queries.
struct PairPoses<'a> {
    i: usize,
    j: usize,
    pieces_i: &'a ConvexPieces,
    pieces_j: &'a ConvexPieces,
    pose_i: Pose,
    pose_j: Pose,
    pos12: Pose,
    tolerance: f64,
}

impl<'a> PairPoses<'a> {
    fn new(
        (i, j): (usize, usize),
        bodies: &[RigidBody],
        colliders: &'a [MeshCollider],
    ) -> PairPoses<'a> {
        let (pose_i, pose_j) = (pose(&bodies[i]), pose(&bodies[j]));
        PairPoses {
            i,
            j,
            pieces_i: &colliders[i].pieces,
            pieces_j: &colliders[j].pieces,
            pose_i,
            pose_j,
            pos12: pose_i.inv_mul(&pose_j),
            tolerance: SAME_POINT_TOLERANCE * colliders[i].radius().min(colliders[j].radius()),
        }
    }
}

/// The contacts of piece a of body i with piece b of body j that `out[pair_start..]` does not
/// already hold.
fn piece_pair_contacts(
    pair: &PairPoses,
    (a, b): (usize, usize),
    pair_start: usize,
    buffers: &mut ManifoldBuffers,
    out: &mut Vec<Contact>,
) {
    let (i, j, tolerance) = (pair.i, pair.j, pair.tolerance);
    let (pose_i, pose_j) = (&pair.pose_i, &pair.pose_j);
    let (piece_a, piece_b) = (&pair.pieces_i.pieces[a], &pair.pieces_j.pieces[b]);
    // A fresh manifold each time (its buffers reused): GJK does not start from the previous
    // normal, which would make detection depend on history.
    let manifold = &mut buffers.manifold;
    buffers
        .query
        .manifold(&pair.pos12, &piece_a.shape, &piece_b.shape, manifold);
    // parry's n1 points out of piece a toward piece b; ours points from j into i.
    let n = -world_vector(pose_i, manifold.local_n1);
    if !(n.iter().all(|x| x.is_finite()) && (n.norm() - 1.0).abs() < 1e-6) {
        return;
    }
    let n = n.normalize();
    for point in &manifold.points {
        // Touching or apart (or NaN): not a contact.
        if point.dist.is_nan() || point.dist >= -tolerance {
            continue;
        }
        let on_i = world_point(pose_i, point.local_p1);
        let on_j = world_point(pose_j, point.local_p2);
        let depth = -point.dist;
        // The same contact: the same point, depth and line of action (a vertex of
        // j seen from i has the opposite normal).
        let same = |c: &Contact, at: &nalgebra::Vector3<f64>, normal: f64| {
            (c.point - at).norm() <= tolerance
                && (c.depth - depth).abs() <= tolerance
                && c.frame.n.dot(&n) * normal >= 1.0 - 1e-9
        };
        let held = |c: &Contact| {
            (c.body1 == i && c.body2 == Some(j) && same(c, &on_i, 1.0))
                || (c.body1 == j && c.body2 == Some(i) && same(c, &on_j, -1.0))
        };
        if out[pair_start..].iter().any(held) {
            continue;
        }
        out.push(Contact {
            body1: i,
            body2: Some(j),
            feature: Feature::Manifold {
                piece1: a as u32,
                piece2: b as u32,
                feature1: point.fid1.0,
                feature2: point.fid2.0,
            },
            point: on_i,
            frame: ContactFrame::from_normal(&n),
            depth,
        });
    }
}
