//! Two convex pieces' contact by GJK then EPA, and their contact manifold, with one EPA kept from
//! call to call: parry3d's own steps (`contact_support_map_support_map_with_params` and
//! `contact_manifold_pfm_pfm`, parry3d-f64 0.31) in the same order on the same numbers, so the
//! results are the same bits, but without the fresh EPA those functions make on every call, whose
//! buffers were most of what a step of `collision: complete` allocated. docs/contact.md
//! §"Complete collision detection".

use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::epa::EPA;
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::query::{ContactManifold, TrackedContact};
use parry3d_f64::shape::{PackedFeatureId, PolygonalFeature, PolygonalFeatureMap, SupportMap};

/// GJK/EPA's working memory, kept between queries so that a query allocates nothing once its
/// buffers have grown. Cloning gives empty buffers (they hold nothing between queries).
#[derive(Default)]
pub struct ConvexQuery {
    epa: EPA,
}

impl Clone for ConvexQuery {
    fn clone(&self) -> ConvexQuery {
        ConvexQuery::default()
    }
}

impl std::fmt::Debug for ConvexQuery {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ConvexQuery")
    }
}

impl ConvexQuery {
    /// The deepest-point contact of two touching or overlapping convex shapes, g1 at the origin
    /// and g2 at `pos12` in g1's frame: `ClosestPoints(p1, p2 in g1's frame, n1)` with n1 out of
    /// g1, or `NoIntersection` when they are apart. GJK starts from the direction between the
    /// shapes' origins (+x if they coincide); EPA runs when GJK finds the origin inside the
    /// Minkowski difference.
    pub fn contact<G1, G2>(&mut self, pos12: &Pose, g1: &G1, g2: &G2) -> GJKResult
    where
        G1: ?Sized + SupportMap,
        G2: ?Sized + SupportMap,
    {
        let (closest, simplex) = gjk_from_origins(pos12, g1, g2, 0.0, true);
        if closest != GJKResult::Intersection {
            return closest;
        }
        match self.epa.closest_points(pos12, g1, g2, &simplex) {
            Some((p1, p2, n)) => GJKResult::ClosestPoints(p1, p2, n),
            None => GJKResult::NoIntersection(Vector::X),
        }
    }

    /// The contact manifold of two convex polyhedra, replacing `manifold`'s points and normals:
    /// the [`ConvexQuery::contact`] direction n1, each piece's supporting feature (face, edge or
    /// vertex) toward the other, the two features clipped against each other, and the deepest
    /// point itself. `manifold.local_n1` is n1 (zero when the query failed, the GJK direction
    /// when apart, with no points then). History is not used: every call starts afresh.
    pub fn manifold<S1, S2>(
        &mut self,
        pos12: &Pose,
        pfm1: &S1,
        pfm2: &S2,
        manifold: &mut ContactManifold<(), ()>,
    ) where
        S1: ?Sized + PolygonalFeatureMap,
        S2: ?Sized + PolygonalFeatureMap,
    {
        manifold.points.clear();
        manifold.local_n2 = Vector::ZERO;
        match self.contact(pos12, pfm1, pfm2) {
            GJKResult::ClosestPoints(p1, p2_1, n1) => {
                let n2 = pos12.rotation.inverse() * -n1;
                let p2 = pos12.inverse_transform_point(p2_1);
                let (mut feature1, mut feature2) =
                    (PolygonalFeature::default(), PolygonalFeature::default());
                pfm1.local_support_feature_toward(n1, p1, &mut feature1);
                pfm2.local_support_feature_toward(n2, p2, &mut feature2);
                PolygonalFeature::contacts(
                    pos12,
                    &pos12.inverse(),
                    n1,
                    n2,
                    &feature1,
                    &feature2,
                    manifold,
                    false,
                );
                // The deepest point, whatever the clipping found (its features unknown).
                manifold.points.push(TrackedContact::new(
                    p1,
                    p2,
                    PackedFeatureId::UNKNOWN,
                    PackedFeatureId::UNKNOWN,
                    (p2_1 - p1).dot(n1),
                ));
                manifold.local_n1 = n1;
                manifold.local_n2 = n2;
            }
            GJKResult::NoIntersection(dir) => manifold.local_n1 = dir,
            _ => manifold.local_n1 = Vector::ZERO,
        }
    }
}

/// Whether two convex shapes (g2 at `pos12` in g1's frame) are certainly further apart than
/// `distance`: GJK stops as soon as a direction's support points are more than `distance` apart
/// along it (a separating axis with that gap), and says nothing otherwise (false).
pub fn apart_by_more_than<G1, G2>(pos12: &Pose, g1: &G1, g2: &G2, distance: f64) -> bool
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    matches!(
        gjk_from_origins(pos12, g1, g2, distance, false).0,
        GJKResult::NoIntersection(_)
    )
}

/// parry's GJK (`gjk::closest_points` with `max_dist` and `exact_dist`) started, as parry's
/// contact query starts it, from the direction between the shapes' origins (+x if they
/// coincide); also returns its final simplex (for EPA).
fn gjk_from_origins<G1, G2>(
    pos12: &Pose,
    g1: &G1,
    g2: &G2,
    max_dist: f64,
    exact_dist: bool,
) -> (GJKResult, VoronoiSimplex)
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(pos12, g1, g2, dir));
    let result = gjk::closest_points(pos12, g1, g2, max_dist, exact_dist, &mut simplex);
    (result, simplex)
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::query::details::{contact_manifold_pfm_pfm, contact_support_map_support_map};
    use parry3d_f64::shape::{ConvexPolyhedron, Cuboid};

    /// A tetrahedron-ish hull and a box, overlapping, touching and apart in several poses.
    fn poses() -> Vec<Pose> {
        let mut out = Vec::new();
        for k in 0..40 {
            let t = k as f64 * 0.173;
            let translation =
                Vector::new(0.9 * t.cos(), 0.35 + 0.6 * (1.3 * t).sin(), 0.4 * t.sin());
            let axis = Vector::new(t.sin(), 1.0, (2.0 * t).cos()).normalize();
            out.push(Pose::from_parts(
                translation,
                parry3d_f64::math::Rotation::from_axis_angle(axis, 0.7 * t),
            ));
        }
        out
    }

    fn hull() -> ConvexPolyhedron {
        let points = [
            Vector::new(-0.5, -0.3, -0.4),
            Vector::new(0.6, -0.2, -0.3),
            Vector::new(0.0, 0.5, 0.1),
            Vector::new(0.1, -0.1, 0.6),
            Vector::new(-0.2, 0.2, -0.5),
        ];
        ConvexPolyhedron::from_convex_hull(&points).unwrap()
    }

    /// The bits of a vector (so that 0.0 and −0.0 differ).
    fn bits(v: Vector) -> [u64; 3] {
        [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
    }

    /// Our contact and manifold against parry's for `a` and `b` over [`poses`]; returns how many
    /// poses overlap.
    fn compare_with_parry<S: PolygonalFeatureMap + SupportMap>(
        a: &ConvexPolyhedron,
        b: &S,
    ) -> usize {
        let mut query = ConvexQuery::default();
        let mut ours = ContactManifold::<(), ()>::new();
        let mut theirs = ContactManifold::<(), ()>::new();
        let mut overlapping = 0;
        for pos12 in poses() {
            let parry = contact_support_map_support_map(&pos12, a, b, 0.0);
            match (query.contact(&pos12, a, b), parry) {
                (GJKResult::ClosestPoints(p1, p2_1, n1), Some(c)) => {
                    overlapping += 1;
                    let p2 = pos12.inverse_transform_point(p2_1);
                    assert_eq!(
                        (bits(p1), bits(p2), bits(n1), (p2_1 - p1).dot(n1).to_bits()),
                        (
                            bits(c.point1),
                            bits(c.point2),
                            bits(c.normal1),
                            c.dist.to_bits()
                        )
                    );
                }
                (GJKResult::NoIntersection(_), None) => {}
                (ours, theirs) => panic!("{pos12:?}: ours {ours:?}, parry {theirs:?}"),
            }
            query.manifold(&pos12, a, b, &mut ours);
            theirs.points.clear();
            theirs.local_n1 = Vector::ZERO;
            theirs.local_n2 = Vector::ZERO;
            contact_manifold_pfm_pfm(&pos12, a, 0.0, None, b, 0.0, None, 0.0, &mut theirs);
            assert_eq!(bits(ours.local_n1), bits(theirs.local_n1), "{pos12:?}");
            assert_eq!(bits(ours.local_n2), bits(theirs.local_n2), "{pos12:?}");
            assert_eq!(ours.points.len(), theirs.points.len(), "{pos12:?}");
            for (p, q) in ours.points.iter().zip(&theirs.points) {
                assert_eq!(
                    (
                        bits(p.local_p1),
                        bits(p.local_p2),
                        p.dist.to_bits(),
                        p.fid1,
                        p.fid2
                    ),
                    (
                        bits(q.local_p1),
                        bits(q.local_p2),
                        q.dist.to_bits(),
                        q.fid1,
                        q.fid2
                    )
                );
            }
        }
        overlapping
    }

    #[test]
    fn kept_epa_gives_parrys_contacts_and_manifolds_bit_for_bit() {
        // A hull against a box and against another hull (the pieces of a decomposed mesh are
        // hulls), each with one query object over all the poses, so that its EPA is reused.
        let box_overlaps = compare_with_parry(&hull(), &Cuboid::new(Vector::new(0.4, 0.25, 0.3)));
        let other = ConvexPolyhedron::from_convex_hull(&[
            Vector::new(-0.4, -0.2, -0.3),
            Vector::new(0.5, -0.3, 0.1),
            Vector::new(0.1, 0.4, -0.2),
            Vector::new(-0.1, 0.1, 0.5),
            Vector::new(0.3, 0.3, 0.3),
            Vector::new(-0.3, -0.4, 0.2),
        ])
        .unwrap();
        let hull_overlaps = compare_with_parry(&hull(), &other);
        // The poses must exercise EPA (overlap) as well as GJK alone (apart).
        for overlapping in [box_overlaps, hull_overlaps] {
            assert!(
                (5..35).contains(&overlapping),
                "{overlapping} of 40 overlap"
            );
        }
    }

    #[test]
    fn apart_by_more_than_certifies_a_gap_and_nothing_less() {
        // Two unit cubes side by side along x, their faces 0.1 apart (then turned a little, which
        // only narrows the gap between corners).
        let cube = Cuboid::new(Vector::new(0.5, 0.5, 0.5));
        let at = |gap: f64, angle: f64| {
            Pose::from_parts(
                Vector::new(1.0 + gap, 0.0, 0.0),
                parry3d_f64::math::Rotation::from_axis_angle(Vector::Y, angle),
            )
        };
        assert!(apart_by_more_than(&at(0.1, 0.0), &cube, &cube, 0.09));
        assert!(!apart_by_more_than(&at(0.1, 0.0), &cube, &cube, 0.11));
        assert!(!apart_by_more_than(&at(-0.01, 0.0), &cube, &cube, 0.0));
        // Turned by 0.2 rad the nearest corner is 0.5 (cos 0.2 + sin 0.2) − 0.5 ≈ 0.089 closer.
        let narrowed = 0.1 - 0.5 * (0.2_f64.cos() + 0.2_f64.sin() - 1.0);
        assert!(apart_by_more_than(
            &at(0.1, 0.2),
            &cube,
            &cube,
            narrowed - 1e-6
        ));
        assert!(!apart_by_more_than(
            &at(0.1, 0.2),
            &cube,
            &cube,
            narrowed + 1e-6
        ));
    }
}
