//! Detection held against the oracle: a body pair's contacts against the separating-axis depth
//! of the two bodies ([`super::sat`], which shares no code with detection), for the detection
//! campaign, `rigidref crosscheck` and the run's watch. docs/contact.md §"The oracle campaign".

use super::manifold::speculative_margin;
use super::mesh_pair::MeshCollider;
use super::sat::OracleBuffers;
use super::separating_axes::{AXIS_TIE_TOLERANCE, EDGE_PREFERENCE, FACE_B_PREFERENCE};
use super::vertex_contact::{Contact, Feature};
use crate::common::broad::{Aabb, overlapping_pairs};
use crate::rigid3d::body::RigidBody;

/// The comparison's round-off allowance, as a fraction of the larger body's bounding radius:
/// detection works in one body's frame and the oracle in the world's, so their projections
/// differ by round-off of the coordinates (about 1e-16 of the farthest coordinate; the campaign
/// places bodies up to 1 km from the origin, where that is 1e-13 m against radii of 0.1 m).
pub const AUDIT_TOLERANCE: f64 = 1e-9;

/// The largest depth a manifold contact may report for an exact penetration depth `depth` of
/// bodies whose larger radius is `radius`, m: the face preferences' bound (docs/contact.md
/// §"Exact convex contact") plus round-off.
pub fn preferred_depth_bound(depth: f64, radius: f64) -> f64 {
    let tie = AXIS_TIE_TOLERANCE * radius;
    (depth + 2.0 * tie) / (EDGE_PREFERENCE * FACE_B_PREFERENCE) + AUDIT_TOLERANCE * radius
}

/// What one pair's check found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairCheck {
    /// The oracle's penetration depth (minimum translation distance), m.
    pub depth: f64,
    /// Contacts detection found between the pair.
    pub contacts: usize,
    /// The deepest of them, m (−∞ when there are none).
    pub deepest: f64,
    /// The largest overlap of the pair along a manifold contact's normal, m.
    pub normal_overlap: f64,
    /// What disagrees with the oracle beyond the stated bounds (empty when all agree).
    pub disagreements: Vec<String>,
}

/// Checks `found`, the contacts between bodies 0 and 1 (each one convex piece), against the
/// oracle:
///
/// - none missed (with `complete`; the assignment's vertex rule misses edge crossings by
///   design): an overlap d beyond the tolerance has a contact at least d − (1 − 0.9) d − τ deep
///   (the face preference's allowance);
/// - none too deep: no manifold contact deeper than [`preferred_depth_bound`], no vertex-rule
///   contact deeper than d itself (a vertex inside a convex body is at most d from its surface);
/// - along the right axis: along every manifold contact's normal the bodies overlap by at most
///   the bound, so a normal in the contact plane, deep by a body's width, disagrees.
pub fn check_pair(
    bodies: [&RigidBody; 2],
    colliders: [&MeshCollider; 2],
    found: &[Contact],
    complete: bool,
    oracle: &mut OracleBuffers,
) -> PairCheck {
    let pieces = [
        &colliders[0].pieces.pieces[0],
        &colliders[1].pieces.pieces[0],
    ];
    let placed = |k: usize| (pieces[k], &bodies[k].rotation, &bodies[k].x);
    let radius = colliders[0].radius().max(colliders[1].radius());
    let tolerance = AUDIT_TOLERANCE * radius;
    let depth = oracle.depth(placed(0), placed(1), false);
    let bound = preferred_depth_bound(depth, radius);
    let mut check = PairCheck {
        depth,
        deepest: f64::NEG_INFINITY,
        ..PairCheck::default()
    };
    for c in found {
        check.contacts += 1;
        check.deepest = check.deepest.max(c.depth);
        let manifold = matches!(c.feature, Feature::Manifold { .. });
        let limit = if manifold { bound } else { depth + tolerance };
        if c.depth > limit {
            check.disagreements.push(format!(
                "a contact ({:?} at {:?}) is {:.3e} m deep where the bodies overlap by {depth:.3e} m (allowed {limit:.3e} m)",
                c.feature,
                c.point.as_slice(),
                c.depth
            ));
        }
        if manifold {
            let along = oracle.overlap_along(placed(0), placed(1), &c.frame.n);
            check.normal_overlap = check.normal_overlap.max(along);
            if along > bound {
                check.disagreements.push(format!(
                    "a contact's normal {:?} is not an axis of least penetration: the bodies overlap by {along:.3e} m along it, by {depth:.3e} m along the best (allowed {bound:.3e} m)",
                    c.frame.n.as_slice()
                ));
            }
        }
    }
    let shortfall = (1.0 - EDGE_PREFERENCE) * depth + AXIS_TIE_TOLERANCE * radius + tolerance;
    if complete && depth > tolerance && check.deepest < depth - shortfall {
        check.disagreements.push(if check.contacts == 0 {
            format!("the bodies overlap by {depth:.3e} m and no contact between them was found")
        } else {
            format!(
                "the bodies overlap by {depth:.3e} m but the deepest of the {} contacts between them is {:.3e} m",
                check.contacts, check.deepest
            )
        });
    }
    check
}

/// Running totals of a world's detection audited against the oracle on every substep
/// (`rigidref crosscheck` on a 3D scene).
#[derive(Clone, Debug, Default)]
pub struct DetectionAudit {
    /// Substeps audited.
    pub substeps: u64,
    /// Body pairs checked (both bodies convex, their boxes meeting).
    pub pairs: u64,
    /// Of those, pairs the oracle found overlapping beyond the tolerance.
    pub overlapping: u64,
    /// Contacts between bodies checked.
    pub contacts: u64,
    /// Pairs whose boxes meet but one body is not convex (the oracle's depth is then per piece
    /// and the vertex rule's depths may exceed it): not checked.
    pub skipped: u64,
    /// Pairs with a disagreement.
    pub disagreements: u64,
    /// With the vertex rule: overlapping pairs whose contacts do not reach the overlap (the
    /// rule's known misses: edges crossing, faces on faces), not disagreements.
    pub vertex_rule_short: u64,
    /// The first few disagreements, naming the bodies, step and substep.
    pub examples: Vec<String>,
    oracle: OracleBuffers,
    boxes: Vec<Aabb>,
    pair_contacts: Vec<Contact>,
}

impl DetectionAudit {
    /// Checks one substep's `contacts` of `bodies` (detection's output at that state): every
    /// pair of convex bodies whose boxes, grown by the speculative margin, meet.
    pub fn check(
        &mut self,
        bodies: &[RigidBody],
        colliders: &[MeshCollider],
        contacts: &[Contact],
        complete: bool,
        (step, substep): (u64, u32),
    ) {
        self.substeps += 1;
        MeshCollider::world_boxes(bodies, colliders, &mut self.boxes);
        for (b, c) in self.boxes.iter_mut().zip(colliders) {
            let grow = speculative_margin(c.radius());
            b.min = b.min.add_scalar(-grow);
            b.max = b.max.add_scalar(grow);
        }
        for (i, j) in overlapping_pairs(&self.boxes) {
            if !(colliders[i].pieces.convex && colliders[j].pieces.convex)
                || bodies[i].ellipsoid.is_some()
                || bodies[j].ellipsoid.is_some()
            {
                self.skipped += 1;
                continue;
            }
            self.pair_contacts.clear();
            self.pair_contacts.extend(contacts.iter().filter(|c| {
                (c.body1 == i && c.body2 == Some(j)) || (c.body1 == j && c.body2 == Some(i))
            }));
            let check = check_pair(
                [&bodies[i], &bodies[j]],
                [&colliders[i], &colliders[j]],
                &self.pair_contacts,
                complete,
                &mut self.oracle,
            );
            self.pairs += 1;
            self.contacts += check.contacts as u64;
            let radius = colliders[i].radius().max(colliders[j].radius());
            if check.depth > AUDIT_TOLERANCE * radius {
                self.overlapping += 1;
                if !complete && check.deepest < check.depth - AUDIT_TOLERANCE * radius {
                    self.vertex_rule_short += 1;
                }
            }
            if !check.disagreements.is_empty() {
                self.disagreements += 1;
                if self.examples.len() < 5 {
                    self.examples.push(format!(
                        "step {step} substep {substep}: body {i} ({:?}) and body {j} ({:?}): {}",
                        bodies[i].name,
                        bodies[j].name,
                        check.disagreements.join("; ")
                    ));
                }
            }
        }
    }
}

/// With persistent manifolds (docs/contact.md §"Persistent manifolds"): whether cached
/// detection's contacts `cached` differ from fresh detection's `fresh` only as kept manifolds
/// may. The ground and vertex-rule contacts must be the same, bit for bit, in the same order; a
/// body pair whose manifold contacts differ must meet the bounds fresh detection meets: for two
/// convex bodies every check of [`check_pair`] (none missed, none too deep, along an axis of
/// least penetration within the preferences' bound), otherwise each manifold contact no deeper
/// than [`preferred_depth_bound`] of its piece pair's oracle depth, nor its pieces overlapping
/// by more along its normal. `Err` names the first difference that is not allowed.
pub fn kept_manifolds_agree(
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    cached: &[Contact],
    fresh: &[Contact],
    oracle: &mut OracleBuffers,
) -> Result<(), String> {
    let manifold = |c: &&Contact| matches!(c.feature, Feature::Manifold { .. });
    if !cached
        .iter()
        .filter(|c| !manifold(c))
        .eq(fresh.iter().filter(|c| !manifold(c)))
    {
        return Err("the ground or vertex-rule contacts differ from fresh detection's".into());
    }
    let pair_of = |c: &Contact| {
        let other = c.body2.unwrap_or(usize::MAX);
        (c.body1.min(other), c.body1.max(other))
    };
    let mut pairs: Vec<(usize, usize)> = cached
        .iter()
        .chain(fresh)
        .filter(manifold)
        .map(pair_of)
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    for (i, j) in pairs {
        let of_pair = |contacts: &[Contact]| -> Vec<Contact> {
            contacts
                .iter()
                .filter(|c| pair_of(c) == (i, j))
                .copied()
                .collect()
        };
        let (ours, theirs) = (of_pair(cached), of_pair(fresh));
        if ours == theirs {
            continue;
        }
        let radius = colliders[i].radius().max(colliders[j].radius());
        let convex = colliders[i].pieces.convex
            && colliders[j].pieces.convex
            && bodies[i].ellipsoid.is_none()
            && bodies[j].ellipsoid.is_none();
        if convex {
            let check = check_pair(
                [&bodies[i], &bodies[j]],
                [&colliders[i], &colliders[j]],
                &ours,
                true,
                oracle,
            );
            if !check.disagreements.is_empty() {
                return Err(format!(
                    "bodies {i} and {j}: {}",
                    check.disagreements.join("; ")
                ));
            }
            continue;
        }
        for c in ours.iter() {
            let Feature::Manifold { piece1, piece2, .. } = c.feature else {
                continue;
            };
            let Some(body2) = c.body2 else { continue };
            let placed = |body: usize, piece: u32| {
                (
                    &colliders[body].pieces.pieces[piece as usize],
                    &bodies[body].rotation,
                    &bodies[body].x,
                )
            };
            let (a, b) = (placed(c.body1, piece1), placed(body2, piece2));
            let depth = oracle.depth(a, b, true);
            let bound = preferred_depth_bound(depth, radius);
            let along = oracle.overlap_along(a, b, &c.frame.n);
            if c.depth > bound || along > bound {
                return Err(format!(
                    "bodies {i} and {j}: a kept manifold contact {:.3e} m deep, its pieces overlapping by {along:.3e} m along its normal, where they overlap by {depth:.3e} m (allowed {bound:.3e} m)",
                    c.depth
                ));
            }
        }
    }
    Ok(())
}
