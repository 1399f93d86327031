//! Temporal coherence in 3D detection: per body pair, the vertices of each body that were within
//! a margin of the other's bounding box and sphere (with what each learns of its nearest triangle
//! of the other body: kept where it is nearer than every other by more than twice the margin),
//! and (with `collision: complete`) the convex piece pairs whose world boxes were within the
//! margin of each other and which were not apart by more than the margin along a separating
//! axis, kept while the pair has moved less than half the margin. Everything kept gives exactly what fresh detection finds, so
//! the contacts are the same, bit for bit. docs/contact.md §"Temporal coherence".

use super::manifold::{ManifoldBuffers, manifold_contacts_among};
use super::mesh_pair::{MeshCollider, NearestTriangle, VertexQuery, vertex_contact};
use super::persistent::{KeepRule, KeptFeatures};
use super::separating_axes::Placement;
use super::vertex_contact::Contact;
use crate::common::pair_cache::PairCache;
use crate::rigid3d::body::RigidBody;
use nalgebra::{Matrix3, Vector3};

/// A pair's margin as a fraction of the smaller body's bounding radius (for 0.5 m cubes, 0.022 m):
/// far above a resting body's motion per substep, far below a falling one's (a body falling
/// 1 m/s moves 0.01 m per substep of 0.01 s, so it keeps its lists for about a substep).
pub const MARGIN_FRACTION: f64 = 0.05;

/// A candidate of a pair (i, j), i < j.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Candidate {
    /// A vertex of body i, against body j, and what is known of its nearest triangle of j.
    VertexOfFirst(u32, NearestTriangle),
    /// A vertex of body j, against body i, and what is known of its nearest triangle of i.
    VertexOfSecond(u32, NearestTriangle),
    /// Piece a of body i with piece b of body j (with persistent manifolds, what it keeps of its
    /// last separating-axis search is in a list of its own, [`KeptFeatures`], in the same order).
    Pieces(u32, u32),
}

/// The poses a pair's list was found at, and its margin.
#[derive(Clone, Copy, Debug)]
pub struct Anchor {
    /// j's frame from i's: in_j = r_rel p + t_rel for p in i's frame.
    r_rel: Matrix3<f64>,
    t_rel: Vector3<f64>,
    /// World poses (for the pieces' world boxes).
    x: [Vector3<f64>; 2],
    r: [Matrix3<f64>; 2],
    margin: f64,
}

/// The pose of body j seen from body i: (R_jᵀ R_i, R_jᵀ (x_i − x_j)).
fn relative(bi: &RigidBody, bj: &RigidBody) -> (Matrix3<f64>, Vector3<f64>) {
    let rt = bj.rotation.transpose();
    (rt * bi.rotation, rt * (bi.x - bj.x))
}

impl Anchor {
    /// The pair's relative motion since the anchor, m: a bound on how far any vertex of either
    /// body has moved in the other's frame, ‖ΔR‖ (max(ρ_i, ρ_j) + |t₀|) + |Δt| ([`Self::holds`]);
    /// exactly 0 at the anchor's poses.
    fn motion(&self, bi: &RigidBody, bj: &RigidBody, radii: (f64, f64)) -> f64 {
        let (r_rel, t_rel) = relative(bi, bj);
        (r_rel - self.r_rel).norm() * (radii.0.max(radii.1) + self.t_rel.norm())
            + (t_rel - self.t_rel).norm()
    }

    fn of(bi: &RigidBody, bj: &RigidBody, margin: f64) -> Anchor {
        let (r_rel, t_rel) = relative(bi, bj);
        Anchor {
            r_rel,
            t_rel,
            x: [bi.x, bj.x],
            r: [bi.rotation, bj.rotation],
            margin,
        }
    }

    /// Whether every point the pair's tests place has moved by at most half the margin since the
    /// anchor. A vertex p of i (|p| ≤ ρ_i) is tested at in_j = R p + t in j's frame, and moved
    /// there by at most ‖ΔR‖ ρ_i + |Δt|; a vertex q of j is tested at Rᵀ (q − t) in i's frame, moved
    /// by at most ‖ΔR‖ (ρ_j + |t₀|) + |Δt|; the pieces' world boxes (vertices within ρ of the body
    /// origin) by at most |Δx| + ‖ΔR_world‖ ρ each (Frobenius norms bound the spectral ones).
    /// False when any of it is NaN.
    fn holds(&self, bi: &RigidBody, bj: &RigidBody, radii: (f64, f64), pieces: bool) -> bool {
        let relative_motion = self.motion(bi, bj, radii);
        let world_motion = |b: &RigidBody, k: usize, radius: f64| {
            (b.x - self.x[k]).norm() + (b.rotation - self.r[k]).norm() * radius
        };
        let half = self.margin / 2.0;
        relative_motion <= half
            && (!pieces || world_motion(bi, 0, radii.0) + world_motion(bj, 1, radii.1) <= half)
    }
}

/// A pair's margin m, m ([`MARGIN_FRACTION`] of the smaller bounding radius).
fn pair_margin(ci: &MeshCollider, cj: &MeshCollider) -> f64 {
    MARGIN_FRACTION * ci.radius().min(cj.radius())
}

/// The candidates of pair (i, j) at the bodies' present poses, into `out`, in fresh detection's
/// order (i's vertices, j's vertices, then piece pairs, each ascending), and their anchor.
fn find_candidates(
    (i, j): (usize, usize),
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    pieces: bool,
    manifold: &mut ManifoldBuffers,
    out: &mut Vec<Candidate>,
) -> Anchor {
    let (bi, bj) = (&bodies[i], &bodies[j]);
    let (ci, cj) = (&colliders[i], &colliders[j]);
    let margin = pair_margin(ci, cj);
    for (v, local) in bi.mesh.vertices.iter().enumerate() {
        let in_j = bj.rotation.transpose() * (bi.x + bi.rotation * local - bj.x);
        if cj.may_come_within(&in_j, margin) {
            out.push(Candidate::VertexOfFirst(v as u32, NearestTriangle::Unknown));
        }
    }
    for (v, local) in bj.mesh.vertices.iter().enumerate() {
        let in_i = bi.rotation.transpose() * (bj.x + bj.rotation * local - bi.x);
        if ci.may_come_within(&in_i, margin) {
            out.push(Candidate::VertexOfSecond(
                v as u32,
                NearestTriangle::Unknown,
            ));
        }
    }
    if pieces {
        let placement = Placement::between((&bi.rotation, &bi.x), (&bj.rotation, &bj.x));
        // The pieces' world boxes of this detection (formed once for each body).
        manifold.piece_boxes.ensure(i, bi, &ci.pieces);
        manifold.piece_boxes.ensure(j, bj, &cj.pieces);
        for (a, piece_a) in ci.pieces.pieces.iter().enumerate() {
            let box_a = manifold.piece_boxes.get(i, a);
            for (b, piece_b) in cj.pieces.pieces.iter().enumerate() {
                let box_b = manifold.piece_boxes.get(j, b);
                let near = (0..3).all(|k| {
                    box_a.min[k] - margin <= box_b.max[k] && box_b.min[k] - margin <= box_a.max[k]
                });
                // Pieces further apart than the margin stay apart while the list holds (each
                // point moves by at most half the margin relative to the other body): no
                // manifold of theirs can have a point, so they are not candidates. The
                // separating-axis query decides it once per list.
                if near
                    && !manifold.sat.apart_by_more_than(
                        &piece_a.polytope,
                        &piece_b.polytope,
                        &placement,
                        margin,
                    )
                {
                    out.push(Candidate::Pieces(a as u32, b as u32));
                }
            }
        }
    }
    Anchor::of(bi, bj, margin)
}

/// The contacts of pair (i, j) (neither with an analytic ellipsoid) from its kept candidates,
/// or from fresh ones when the pair has moved too far: exactly fresh detection's contacts for the
/// pair, appended to `out`. `pieces`: with the convex pieces' manifolds (`collision: complete`);
/// `kept`: with persistent manifolds, each pair's piece-pair features (one per piece candidate,
/// in order; found anew with the candidates), each piece pair's manifold from them where they
/// serve (docs/contact.md §"Persistent manifolds": then not always fresh detection's manifold).
#[allow(clippy::too_many_arguments)]
pub fn cached_pair_contacts(
    (i, j): (usize, usize),
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    pieces: bool,
    kept: Option<(&mut PairCache<(), KeptFeatures>, KeepRule)>,
    cache: &mut PairCache<Anchor, Candidate>,
    manifold: &mut ManifoldBuffers,
    out: &mut Vec<Contact>,
) {
    let (bi, bj) = (&bodies[i], &bodies[j]);
    let radii = (colliders[i].radius(), colliders[j].radius());
    let found = std::cell::Cell::new(false);
    let candidates = cache.candidates(
        (i, j),
        |a| crate::common::faults::fault!(stale_detection_cache) || a.holds(bi, bj, radii, pieces),
        |_, list| {
            found.set(true);
            find_candidates((i, j), bodies, colliders, pieces, manifold, list)
        },
    );
    let pair_start = out.len();
    // A triangle kept at any step of the list's life keeps for the rest of it: the vertex is
    // then within m / 2 of where it was when the list was found, and stays within m / 2 of it,
    // so it moves by less than m from where the triangle was found; a gap of 2m (plus round-off)
    // covers that.
    let margin = pair_margin(&colliders[i], &colliders[j]);
    let gap = |other: usize| 2.0 * margin + 1e-9 * colliders[other].radius();
    let gaps = (gap(j), gap(i));
    let (mut queries, mut nearest_kept, mut nearest_leading, mut on_surface) = (0, 0, 0, 0);
    for c in candidates.iter_mut() {
        let (vertex, (own, other), (body, against), nearest, gap) = match c {
            Candidate::VertexOfFirst(v, nearest) => (*v, (i, j), (bi, bj), nearest, gaps.0),
            Candidate::VertexOfSecond(v, nearest) => (*v, (j, i), (bj, bi), nearest, gaps.1),
            Candidate::Pieces(..) => continue,
        };
        let answer = vertex_contact(
            own,
            body,
            vertex as usize,
            other,
            against,
            &colliders[other],
            (nearest, gap),
            out,
        );
        queries += (answer != VertexQuery::Culled) as u64;
        nearest_kept += matches!(answer, VertexQuery::OnKept | VertexQuery::OnLeading) as u64;
        nearest_leading += (answer == VertexQuery::OnLeading) as u64;
        on_surface += (answer == VertexQuery::OnSurface) as u64;
    }
    if pieces {
        let count = candidates
            .iter()
            .filter(|c| matches!(c, Candidate::Pieces(..)))
            .count();
        // The features are kept while the candidates are (a fresh list starts unknown).
        let rule = kept.as_ref().map_or(KeepRule::Exact, |(_, rule)| *rule);
        let features = kept.map(|(kept, _)| {
            kept.candidates(
                (i, j),
                |_| !found.get(),
                |_, list| list.extend(std::iter::repeat_n(KeptFeatures::Unknown, count)),
            )
        });
        let mut features = features.filter(|f| f.len() == count).map(|f| f.iter_mut());
        let piece_pairs = candidates.iter().filter_map(move |c| match *c {
            Candidate::Pieces(a, b) => Some((
                a as usize,
                b as usize,
                features.as_mut().and_then(|f| f.next()),
            )),
            _ => None,
        });
        manifold_contacts_among(
            (i, j),
            bodies,
            colliders,
            piece_pairs,
            rule,
            pair_start,
            manifold,
            out,
        );
    }
    cache.stats.queries += queries;
    cache.stats.nearest_kept += nearest_kept;
    cache.stats.nearest_leading += nearest_leading;
    cache.stats.on_surface += on_surface;
}
