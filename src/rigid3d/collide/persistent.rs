//! What a piece pair keeps of its last full separating-axis search (`collision: complete` with
//! the detection cache), and when it serves instead of the search:
//!
//! - exactly, by default: a face axis while the pair has moved less than the axis's lead, where
//!   the search would choose it again (docs/contact.md §"Temporal coherence", "Leading axes");
//! - as persistent contact manifolds (`persistent_manifolds: true`): the axis the search chose
//!   (the reference face, or the edge pair; or the axis that showed it apart) while the pair has
//!   moved little and that axis stays within the face preferences' allowance of the deepest, its
//!   manifold re-derived from that axis alone (its gap, then the same clipping at the present
//!   poses). docs/contact.md §"Persistent manifolds".

use super::polytope::Polytope;
use super::separating_axes::{
    AXIS_TIE_TOLERANCE, Axis, EDGE_PREFERENCE, FACE_B_PREFERENCE, Placement, SatBuffers, SearchGaps,
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
        /// The axis's lead then, m ([`axis_lead`]; −∞ where it has none): fresh detection would
        /// choose it while the pair has moved by less than this (less τ) since.
        lead: f64,
    },
}

/// How far the search's largest gap G may lie below the true largest projection gap of two
/// overlapping pieces (minus their penetration depth), in units of τ: the search gives no axis
/// of its own to a pair of edges parallel within [`super::separating_axes::PARALLEL_SINE`] nor to
/// triangles merged into one face within 1e-9 of the radius, and each such face of the
/// Minkowski difference is a strip at most about 1e-9 × an edge length (≤ 2τ) wide next to a face
/// the search does measure, whose gap is then within that width of the strip's. Twice the sum of
/// the two: slack, not a tight bound (docs/contact.md §"Temporal coherence", "Leading axes").
pub const EXACT_GAP_SHORTFALL: f64 = 8.0;

/// Which answers kept features may give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeepRule {
    /// Fresh detection's only, bit for bit: a kept face axis serves while the pair has moved
    /// by less than its lead (the detection cache with `collision: complete`; docs/contact.md
    /// §"Temporal coherence", "Leading axes").
    Exact,
    /// Any axis within the face preferences' bound of the exact depth (`persistent_manifolds`;
    /// docs/contact.md §"Persistent manifolds").
    WithinPreferences,
}

/// The lead ℓ of the face axis a full search chose, m (docs/contact.md §"Temporal coherence",
/// "Leading axes"): if every vertex of either piece has moved by at most δ relative to the
/// other since, with δ + τ < ℓ (τ = [`AXIS_TIE_TOLERANCE`] × the larger piece radius, round-off)
/// and the exact gap G then plus ε + δ + τ still under the search's `stop_above`, the search would
/// choose the same face again. Each face's gap, and the exact gap, has changed by at most δ; ℓ
/// is the least of
///
/// - (g − g₂) / 2: the face stays the strictly largest of its piece's (g₂ the second largest);
/// - for a face of A, (g_A − g_B + 0.02 |g_A|) / 2.02: B's best face still does not beat it;
///   for a face of B, (g_B − g_A − 0.02 |g_A| − 2τ) / 2.02: it still beats A's;
/// - (g − G − ε + 0.1 |g|) / 2.1: no edge pair (whose gap is at most the true largest gap, at
///   most G + ε + δ; ε = [`EXACT_GAP_SHORTFALL`] τ) beats the faces;
///
/// (the preferences' τ left out: slack for the comparisons' own rounding). −∞ where the search
/// chose an edge pair or fell back to the exact axis (an edge pair's axis turns with the pieces:
/// no such bound), where G ≥ −τ (the pieces not clearly overlapping: the exact gap is minus the
/// penetration depth only for overlapping pieces; for pieces apart it can lie below their
/// distance), and where a gap is not finite.
pub fn axis_lead(gaps: &SearchGaps, axis: Axis, tie: f64) -> f64 {
    let (a, b, exact) = (gaps.face_a, gaps.face_b, gaps.exact);
    let finite = a.is_finite() && b.is_finite() && exact.is_finite();
    if axis != gaps.preferred || !finite || exact >= -tie {
        return f64::NEG_INFINITY;
    }
    let (b_slack, e_slack) = (1.0 - FACE_B_PREFERENCE, 1.0 - EDGE_PREFERENCE);
    let (own, second, against_other_kind) = match axis {
        Axis::FaceOfA(_) => (
            a,
            gaps.face_a_second,
            (a - b + b_slack * a.abs()) / (2.0 + b_slack),
        ),
        Axis::FaceOfB(_) => (
            b,
            gaps.face_b_second,
            (b - a - b_slack * a.abs() - 2.0 * tie) / (2.0 + b_slack),
        ),
        Axis::Edges(..) => return f64::NEG_INFINITY,
    };
    let among_own = (own - second) / 2.0;
    // The true largest gap, which bounds every edge pair's, is at most G + ε.
    let shortfall = EXACT_GAP_SHORTFALL * tie;
    let against_edges = (own - exact - shortfall + e_slack * own.abs()) / (2.0 + e_slack);
    among_own.min(against_other_kind).min(against_edges)
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

/// The motion bound δ from placement `found_at` to `at`, m: ‖R − R₀‖ (ρ + |t₀|) + |t − t₀|,
/// a bound on how far any vertex of either piece has moved in the other's frame (`radius`: ρ,
/// the larger body's bounding radius; the Frobenius norm bounds the spectral one).
fn motion_since(found_at: &Placement, at: &Placement, radius: f64) -> f64 {
    (at.rotation - found_at.rotation).norm() * (radius + found_at.translation.norm())
        + (at.translation - found_at.translation).norm()
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
///
/// With [`KeepRule::Exact`], a touching face axis serves only while δ + τ is under its lead
/// ([`axis_lead`]) and G + ε + δ + τ under `stop_above`, and its points reach the depth −g less the
/// search's shortfall allowance (so that the search's fall-back to the exact axis, whose depth is
/// at most −g, cannot happen): the search's answer, bit for bit.
#[allow(clippy::too_many_arguments)]
pub fn kept_contact(
    sat: &mut SatBuffers,
    (a, b): (&Polytope, &Polytope),
    at: &Placement,
    stop_above: f64,
    radius: f64,
    rule: KeepRule,
    kept: &mut KeptFeatures,
    counts: &mut KeptCounts,
) -> Option<Vector3<f64>> {
    let tie = AXIS_TIE_TOLERANCE * a.radius.max(b.radius);
    match *kept {
        KeptFeatures::Touching {
            axis,
            exact_gap,
            at: found_at,
            lead,
        } if rule == KeepRule::Exact => {
            let moved = motion_since(&found_at, at, radius);
            let u = moved + tie;
            // The teeth tests' deliberate bug: the lead kept however far the pair has moved.
            let within = crate::common::faults::fault!(axis_lead_motion_unchecked) || u < lead;
            if within && exact_gap + EXACT_GAP_SHORTFALL * tie + u < stop_above {
                sat.points.clear();
                sat.place(b, at);
                if let Some((normal, gap)) = sat.axis_gap(a, b, at, axis) {
                    let reached = sat.points_along(a, b, axis, &normal);
                    let depth = -gap;
                    if reached >= depth - (1.0 - EDGE_PREFERENCE) * depth.abs() {
                        counts.served += 1;
                        return Some(normal);
                    }
                }
            }
        }
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
            ..
        } => {
            let moved = motion_since(&found_at, at, radius);
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
            let lead = sat
                .last_search
                .map_or(f64::NEG_INFINITY, |gaps| axis_lead(&gaps, found.axis, tie));
            *kept = KeptFeatures::Touching {
                axis: found.axis,
                exact_gap: found.exact_gap,
                at: *at,
                lead,
            };
            Some(found.normal)
        }
        Err(axis) => {
            *kept = KeptFeatures::Apart(axis);
            None
        }
    }
}
