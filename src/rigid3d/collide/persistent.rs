//! Persistent contact manifolds (`persistent_manifolds: true` with `collision: complete` and
//! the detection cache): each piece pair keeps the axis its last full separating-axis search
//! chose (the reference face, or the edge pair; or the axis that showed it apart) and, while the
//! pair has moved little and that axis stays within the face preferences' allowance of the
//! deepest, its manifold is re-derived from that axis alone (its gap, then the same clipping at
//! the present poses) instead of searching every axis. docs/contact.md §"Persistent manifolds".

use super::polytope::Polytope;
use super::separating_axes::{
    AXIS_TIE_TOLERANCE, Axis, EDGE_PREFERENCE, FACE_B_PREFERENCE, Placement, SatBuffers,
};
use nalgebra::Vector3;

/// Kept features serve while the pair's motion since they were found (the largest displacement
/// of a vertex of either piece in the other's frame, bounded as the pair lists bound it) is at
/// most this fraction of the smaller piece's radius: the speculative margin's scale.
pub const MANIFOLD_MOTION_FRACTION: f64 = 0.01;

/// What a piece pair keeps of its last full search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KeptFeatures {
    /// Nothing yet (the pair's list was just found, or its pieces' boxes were apart).
    Unknown,
    /// The pieces were apart by more than the speculative margin along this axis.
    Apart(Axis),
    /// In contact along `axis` (after the search's own fall-back to the exact axis), found at
    /// placement `at` of B in A's frame, when the largest gap over every axis was `exact_gap`.
    Touching {
        /// The reference face (of A or B) or the edge pair.
        axis: Axis,
        /// Minus the exact penetration depth then, m.
        exact_gap: f64,
        /// B's body frame in A's then.
        at: Placement,
    },
}

/// How far a gap may fall short of the exact (largest) gap for its axis to stand: the face
/// preferences' allowance (docs/contact.md §"Exact convex contact"), (1 − P)|g| + 2τ for an
/// overlap and (1/P − 1) g + 3τ for a speculative gap, P = EDGE_PREFERENCE · FACE_B_PREFERENCE.
/// The full search's own choice always stands (up to τ-sized ties, which then search again).
pub fn preference_allowance(gap: f64, tie: f64) -> f64 {
    let p = EDGE_PREFERENCE * FACE_B_PREFERENCE;
    if gap <= 0.0 {
        (1.0 - p) * -gap + 2.0 * tie
    } else {
        (1.0 / p - 1.0) * gap + 3.0 * tie
    }
}

/// How often kept features served a piece pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KeptCounts {
    /// Piece-pair queries answered from kept features.
    pub served: u64,
    /// Piece-pair queries that ran the full search.
    pub searched: u64,
}

/// The contact of pieces A and B (B placed by `at`) into `sat.points` (replaced): from `kept`
/// when it still serves, else by the full search ([`SatBuffers::contact_or_apart`]), which
/// `kept` then records. Returns the contact normal n₁ (out of A, A's frame), or `None` when the
/// pieces are apart by more than `stop_above`. `radius`: the larger of the two bodies' bounding
/// radii (their vertices' largest distance from their origins), m.
///
/// - Apart along a kept face axis: if its gap still exceeds `stop_above`, the full search, which
///   tries that face, would stop too: apart, exactly as fresh.
/// - Touching along a kept axis found at placement (R₀, t₀), now (R, t): every vertex has moved
///   by at most δ = ‖R − R₀‖ (ρ + |t₀|) + |t − t₀| relative to the other piece since (B's vertex
///   v in A's frame R v + t; A's vertex p in B's frame Rᵀ (p − t); the Frobenius norm bounds the
///   spectral one), so no axis's gap (and not the exact gap) has grown by more than δ: the
///   exact gap now is at most U = exact_gap + δ. The kept axis
///   serves when δ ≤ [`MANIFOLD_MOTION_FRACTION`] · min(ρ_A, ρ_B), its gap g now is within
///   [`preference_allowance`] of U, and its points reach U's depth less the search's own
///   shortfall allowance; its points are then those the search would give if it chose it.
pub fn kept_contact(
    sat: &mut SatBuffers,
    (a, b): (&Polytope, &Polytope),
    at: &Placement,
    stop_above: f64,
    radius: f64,
    kept: &mut KeptFeatures,
    counts: &mut KeptCounts,
) -> Option<Vector3<f64>> {
    let tie = AXIS_TIE_TOLERANCE * a.radius.max(b.radius);
    match *kept {
        // An edge pair is one of the search's axes only while its Gauss-map arcs cross; a face
        // always is, so only a face's gap proves that the search would stop.
        KeptFeatures::Apart(axis) if !matches!(axis, Axis::Edges(..)) => {
            sat.points.clear();
            sat.place(b, at);
            if let Some((_, gap)) = sat.axis_gap(a, b, at, axis)
                && gap > stop_above
            {
                counts.served += 1;
                return None;
            }
        }
        KeptFeatures::Touching {
            axis,
            exact_gap,
            at: found_at,
        } => {
            let moved = (at.rotation - found_at.rotation).norm()
                * (radius + found_at.translation.norm())
                + (at.translation - found_at.translation).norm();
            if moved <= MANIFOLD_MOTION_FRACTION * a.radius.min(b.radius) {
                sat.points.clear();
                sat.place(b, at);
                if let Some((normal, gap)) = sat.axis_gap(a, b, at, axis) {
                    let upper = exact_gap + moved;
                    if gap > stop_above {
                        if !matches!(axis, Axis::Edges(..)) {
                            *kept = KeptFeatures::Apart(axis);
                            counts.served += 1;
                            return None;
                        }
                    } else if upper <= gap + preference_allowance(gap, tie) {
                        let reached = sat.points_along(a, b, axis, &normal);
                        // The exact depth now is at most δ − exact_gap.
                        let deepest = moved - exact_gap;
                        let short = (1.0 - EDGE_PREFERENCE) * deepest.abs() + tie;
                        if reached >= deepest - short {
                            counts.served += 1;
                            return Some(normal);
                        }
                    }
                }
            }
        }
        _ => {}
    }
    counts.searched += 1;
    match sat.contact_or_apart(a, b, at, stop_above) {
        Ok(found) => {
            *kept = KeptFeatures::Touching {
                axis: found.axis,
                exact_gap: found.exact_gap,
                at: *at,
            };
            Some(found.normal)
        }
        Err(axis) => {
            *kept = KeptFeatures::Apart(axis);
            None
        }
    }
}
