//! `collision: complete`: the contacts the vertex rule misses, from contact manifolds between the
//! two bodies' convex pieces (the axis of least penetration by separating axes, then the
//! reference face clipped against the incident face, or the closest points of two edges:
//! [`super::separating_axes`]). docs/contact.md §"Complete collision detection".

use super::mesh_pair::MeshCollider;
use super::persistent::{KeepRule, KeptCounts, KeptFeatures, kept_contact};
use super::pieces::{ConvexPieces, pose};
use super::separating_axes::{Placement, SatBuffers};
use super::vertex_contact::{Contact, Feature};
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;

/// A manifold point whose witness lies within this fraction of the smaller body's bounding radius
/// of a contact already found (a vertex contact, or an earlier manifold point) is that contact.
pub const SAME_POINT_TOLERANCE: f64 = 1e-9;

/// Manifold points (and, with `collision: complete`, ground vertices) apart by at most this
/// fraction of the smaller body's bounding radius are speculative contacts: their depth is minus
/// the gap, and the problem lets the bodies close the gap in the step but no more
/// (docs/contact.md §"Speculative contacts"). A resting stack written exactly touching then
/// keeps its contacts while round-off rocks a corner up by micrometres.
pub const SPECULATIVE_FRACTION: f64 = 0.01;

/// The speculative margin of a body of bounding radius `radius`, m.
pub fn speculative_margin(radius: f64) -> f64 {
    SPECULATIVE_FRACTION * radius
}

/// The manifold queries' working memory (the separating-axis query's placed vertices, clip
/// polygons and points), kept from call to call so that they allocate nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct ManifoldBuffers {
    /// The separating-axis query's buffers.
    pub sat: SatBuffers,
    /// How often kept features served (persistent manifolds).
    pub kept: KeptCounts,
    /// Each body's pieces' world boxes, formed once per detection.
    pub piece_boxes: PieceBoxes,
}

/// Each body's convex pieces' world boxes ([`super::pieces::Piece::world_aabb`] at the body's
/// pose), formed at the first piece pair of the body that a detection asks for and kept for the
/// rest of that detection: a body meets several neighbours, and forming a box places every
/// vertex of its piece. The boxes are the same numbers as formed afresh (the same function of
/// the same pose); they are kept while the detection ([`PieceBoxes::begin`]) and the pose's
/// bits are the same. docs/performance.md §"Issue 49: the set-up in problem order".
#[derive(Clone, Debug, Default)]
pub struct PieceBoxes {
    detection: u64,
    bodies: Vec<BodyPieceBoxes>,
}

#[derive(Clone, Debug, Default)]
struct BodyPieceBoxes {
    detection: u64,
    /// The bits of the body's position and rotation the boxes were formed at.
    pose: [u64; 12],
    boxes: Vec<crate::common::broad::Aabb>,
}

impl PieceBoxes {
    /// A new detection: every kept box is formed again when next asked for.
    pub fn begin(&mut self) {
        self.detection += 1;
    }

    /// Forms body `i`'s pieces' world boxes unless this detection already did at this pose.
    pub(super) fn ensure(&mut self, i: usize, body: &RigidBody, pieces: &ConvexPieces) {
        if self.bodies.len() <= i {
            self.bodies.resize_with(i + 1, BodyPieceBoxes::default);
        }
        // The position's and the rotation's bits, read from their contiguous storage.
        let (x, rotation) = (body.x.as_slice(), body.rotation.as_slice());
        let bits: [u64; 12] =
            std::array::from_fn(|k| if k < 3 { x[k] } else { rotation[k - 3] }.to_bits());
        let kept = &mut self.bodies[i];
        if kept.detection == self.detection
            && kept.pose == bits
            && kept.boxes.len() == pieces.pieces.len()
            && self.detection != 0
        {
            return;
        }
        let pose = pose(body);
        kept.boxes.clear();
        kept.boxes
            .extend(pieces.pieces.iter().map(|p| p.world_aabb(&pose)));
        (kept.detection, kept.pose) = (self.detection, bits);
    }

    /// Piece `a`'s world box of body `i` (after [`Self::ensure`]).
    pub(super) fn get(&self, i: usize, a: usize) -> crate::common::broad::Aabb {
        self.bodies[i].boxes[a]
    }
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
    let boxes = &mut buffers.piece_boxes;
    boxes.ensure(i, &bodies[i], pair.pieces_i);
    boxes.ensure(j, &bodies[j], pair.pieces_j);
    for a in 0..pair.pieces_i.pieces.len() {
        for b in 0..pair.pieces_j.pieces.len() {
            let boxes = &buffers.piece_boxes;
            if within(&boxes.get(i, a), &boxes.get(j, b), pair.margin) {
                piece_pair_contacts(&pair, (a, b), pair_start, buffers, None, out);
            }
        }
    }
}

/// [`manifold_contacts`] over the piece pairs `candidates` only (in their order, ascending),
/// each tested by its world boxes as there: the same contacts when `candidates` holds every
/// piece pair whose boxes overlap (docs/contact.md §"Temporal coherence"). A piece pair given
/// its kept features (persistent manifolds) has its manifold from them where they serve
/// ([`kept_contact`]; docs/contact.md §"Persistent manifolds"), and forgets them when its boxes
/// are apart.
#[allow(clippy::too_many_arguments)]
pub fn manifold_contacts_among<'k>(
    (i, j): (usize, usize),
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    candidates: impl Iterator<Item = (usize, usize, Option<&'k mut KeptFeatures>)>,
    rule: KeepRule,
    pair_start: usize,
    buffers: &mut ManifoldBuffers,
    out: &mut Vec<Contact>,
) {
    let pair = PairPoses::new((i, j), bodies, colliders);
    let boxes = &mut buffers.piece_boxes;
    boxes.ensure(i, &bodies[i], pair.pieces_i);
    boxes.ensure(j, &bodies[j], pair.pieces_j);
    for (a, b, kept) in candidates {
        let boxes = &buffers.piece_boxes;
        if within(&boxes.get(i, a), &boxes.get(j, b), pair.margin) {
            let kept = kept.map(|kept| (kept, rule));
            piece_pair_contacts(&pair, (a, b), pair_start, buffers, kept, out);
        } else if let Some(kept) = kept {
            *kept = KeptFeatures::Unknown;
        }
    }
}

/// Whether two boxes overlap or are apart by at most `gap` (m) along every axis: pieces that may
/// come within the speculative margin.
fn within(a: &crate::common::broad::Aabb, b: &crate::common::broad::Aabb, gap: f64) -> bool {
    (0..3).all(|k| a.min[k] - gap <= b.max[k] && b.min[k] - gap <= a.max[k])
}

/// A body pair placed for the manifold queries.
struct PairPoses<'a> {
    i: usize,
    j: usize,
    pieces_i: &'a ConvexPieces,
    pieces_j: &'a ConvexPieces,
    /// Body i's rotation and position (the pieces' frame is the body's).
    rotation_i: nalgebra::Matrix3<f64>,
    x_i: nalgebra::Vector3<f64>,
    /// Body j's frame seen from body i's.
    placement: Placement,
    tolerance: f64,
    /// The speculative margin, m.
    margin: f64,
    /// The larger bounding radius of the two bodies, m.
    radius: f64,
}

impl<'a> PairPoses<'a> {
    fn new(
        (i, j): (usize, usize),
        bodies: &[RigidBody],
        colliders: &'a [MeshCollider],
    ) -> PairPoses<'a> {
        let (bi, bj) = (&bodies[i], &bodies[j]);
        PairPoses {
            i,
            j,
            pieces_i: &colliders[i].pieces,
            pieces_j: &colliders[j].pieces,
            rotation_i: bi.rotation,
            x_i: bi.x,
            placement: Placement::between((&bi.rotation, &bi.x), (&bj.rotation, &bj.x)),
            tolerance: SAME_POINT_TOLERANCE * colliders[i].radius().min(colliders[j].radius()),
            margin: speculative_margin(colliders[i].radius().min(colliders[j].radius())),
            radius: colliders[i].radius().max(colliders[j].radius()),
        }
    }
}

/// The contacts of piece a of body i with piece b of body j that `out[pair_start..]` does not
/// already hold; with `kept` (the piece pair's kept features), from them where they serve.
fn piece_pair_contacts(
    pair: &PairPoses,
    (a, b): (usize, usize),
    pair_start: usize,
    buffers: &mut ManifoldBuffers,
    kept: Option<(&mut KeptFeatures, KeepRule)>,
    out: &mut Vec<Contact>,
) {
    let (i, j, tolerance, margin) = (pair.i, pair.j, pair.tolerance, pair.margin);
    let (piece_a, piece_b) = (&pair.pieces_i.pieces[a], &pair.pieces_j.pieces[b]);
    // Without kept features, afresh each time (the buffers reused): no history, so detection
    // depends on the state only. Pieces apart by more than the margin have no contact, so such
    // a gap stops it.
    let polytopes = (&piece_a.polytope, &piece_b.polytope);
    let found = match kept {
        Some((kept, rule)) => kept_contact(
            &mut buffers.sat,
            polytopes,
            &pair.placement,
            margin,
            pair.radius,
            rule,
            kept,
            &mut buffers.kept,
        ),
        None => buffers
            .sat
            .contact(polytopes.0, polytopes.1, &pair.placement, margin)
            .map(|found| found.normal),
    };
    let Some(normal) = found else {
        return;
    };
    // n₁ points out of piece a toward piece b (body i's frame); ours points from j into i.
    let n = -(pair.rotation_i * normal);
    let world = |p: &nalgebra::Vector3<f64>| pair.x_i + pair.rotation_i * p;
    for point in &buffers.sat.points {
        // Apart by more than the margin (or NaN): not a contact. Within it, a speculative
        // contact of negative depth (a stack written exactly touching is held from its first
        // step, and keeps its corners while round-off rocks it).
        if point.distance.is_nan() || point.distance > margin {
            continue;
        }
        let on_i = world(&point.on_a);
        let on_j = world(&point.on_b);
        let depth = -point.distance;
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
                feature1: point.feature_a,
                feature2: point.feature_b,
            },
            point: on_i,
            frame: ContactFrame::from_normal(&n),
            depth,
        });
    }
}
