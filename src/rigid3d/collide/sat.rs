//! The oracle of 3D detection and the penetration measure: the penetration depth of two convex
//! pieces by the separating axis theorem over every candidate axis, sharing no code with the
//! detection it checks (which merges faces and prunes edge pairs by their Gauss-map arcs,
//! [`super::separating_axes`]). docs/contact.md §"Penetration measure", §"The oracle campaign".
//!
//! Two convex polyhedra overlap exactly when their projections overlap on every hull-triangle
//! normal of either and every cross product of a hull-triangle edge of one with one of the other;
//! the smallest overlap among those axes is the distance one must move to separate them (the
//! minimum translation distance, MTD). Plainly that is O(edges₁ · edges₂ · vertices) per pair;
//! [`OracleBuffers::depth`] may skip candidates by a sound distance argument (below), which keeps
//! the measure cheap for round pieces that barely touch.
//!
//! **The prune.** The MTD d is the distance from the origin to the boundary of A ⊖ B, reached on
//! a face of A ⊖ B: a face of A minus a vertex of B, a vertex of A minus a face of B, or an edge
//! of A minus an edge of B. In each case there are points p ∈ (that feature of A) and q ∈ (that
//! feature of B) with p − q = ±d n, so the feature of A comes within d of B and the feature of B
//! within d of A. Any axis's overlap is at least d. So with u an upper bound on d (the overlap
//! along any axis), a triangle or edge of A farther than u from B's bounding sphere (the sphere
//! about B's vertex mean through its farthest vertex) cannot carry the MTD, and its axes can be
//! skipped; the same for B. The bound is tightened as axes are tried.
//!
//! The argument needs the pieces to overlap: for pieces that are apart, the features of a
//! separating axis need not come within the bound. So the pruned oracle first asks GJK
//! ([`super::gjk`]) for a certificate. Apart: the depth is 0 at once. Undecided (rare:
//! [`super::gjk::Verdict::Undecided`]): every axis is tried. Overlapping: the argument holds,
//! and p − q = ±d n gives finer tests besides, each skipping what cannot carry the MTD:
//! - a triangle of A pairs with a vertex q of B that lies within d of the triangle's plane and of
//!   its bounding sphere (q is itself within d of A's bounding sphere);
//! - an edge pair's two edges come within d of each other (their bounding spheres), and along the
//!   pair's own axis n the edges' lines are exactly d apart, |(m_a − m_b)·n| = d for their
//!   midpoints, at closest points of the lines that lie on the edges (p and q themselves); the
//!   last two are tested where the edges' angle has a sine of at least 1e-3, so that round-off in
//!   n stays far below the slack.

use super::gjk;
use super::pieces::Piece;
use nalgebra::{Matrix3, Vector3};

/// Slack added to the prune's distance comparisons, as a fraction of the larger piece radius:
/// round-off in the bounds, never geometry.
pub const PRUNE_SLACK: f64 = 1e-9;

/// A piece placed in the world: its vertices, hull-triangle normals and corners, hull-triangle
/// edges, and its bounding sphere.
#[derive(Clone, Debug, Default)]
struct Placed {
    vertices: Vec<Vector3<f64>>,
    /// Per hull triangle: unit normal, centroid, radius of the sphere about the centroid through
    /// its corners.
    triangles: Vec<(Vector3<f64>, Vector3<f64>, f64)>,
    /// Per hull-triangle edge: direction (end − start), midpoint, half length.
    edges: Vec<(Vector3<f64>, Vector3<f64>, f64)>,
    centre: Vector3<f64>,
    radius: f64,
}

impl Placed {
    /// Places the vertices and the bounding sphere (all that the first tests read).
    fn place_vertices(&mut self, piece: &Piece, rotation: &Matrix3<f64>, x: &Vector3<f64>) {
        self.vertices.clear();
        self.vertices
            .extend(piece.vertices.iter().map(|v| rotation * v + x));
        self.centre = self.vertices.iter().sum::<Vector3<f64>>() / self.vertices.len() as f64;
        self.radius = self
            .vertices
            .iter()
            .map(|v| (v - self.centre).norm())
            .fold(0.0, f64::max);
    }

    /// Places the triangles and edges, after [`Placed::place_vertices`].
    fn place_features(&mut self, piece: &Piece, rotation: &Matrix3<f64>) {
        self.triangles.clear();
        for (t, n) in piece.triangles.iter().zip(&piece.normals) {
            let [a, b, c] = t.map(|i| self.vertices[i]);
            let centroid = (a + b + c) / 3.0;
            let reach = [a, b, c]
                .iter()
                .map(|p| (p - centroid).norm())
                .fold(0.0, f64::max);
            self.triangles.push((rotation * n, centroid, reach));
        }
        self.edges.clear();
        for [i, j] in &piece.edges {
            let (p, q) = (self.vertices[*i], self.vertices[*j]);
            self.edges
                .push((q - p, (p + q) / 2.0, (q - p).norm() / 2.0));
        }
    }
}

/// The extent [min, max] of `points` along `axis`.
fn extent(points: &[Vector3<f64>], axis: &Vector3<f64>) -> (f64, f64) {
    // Plain comparisons (the points are finite): f64::min and max would also handle NaN, at
    // a cost in this, the oracle's innermost loop.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in points {
        let s = p.dot(axis);
        if s < lo {
            lo = s;
        }
        if s > hi {
            hi = s;
        }
    }
    (lo, hi)
}

/// The overlap of two point sets' projections on a unit axis, m (≤ 0: the axis separates them).
fn overlap(a: &[Vector3<f64>], b: &[Vector3<f64>], axis: &Vector3<f64>) -> f64 {
    let (a_lo, a_hi) = extent(a, axis);
    let (b_lo, b_hi) = extent(b, axis);
    (a_hi - b_lo).min(b_hi - a_lo)
}

/// Whether the closest points of two edges' lines (direction d, midpoint m; not parallel) lie on
/// the edges themselves, to a millionth of their lengths: the points p, q with p − q along the
/// pair's axis, which an edge pair carrying the MTD has there (module docs). The line
/// parameters s, t (p = m_a + s d_a, q = m_b + t d_b, each edge at |·| ≤ 1/2) solve the two
/// conditions that p − q is perpendicular to both edges.
fn lines_meet_within(
    (da, ma): (&Vector3<f64>, &Vector3<f64>),
    (db, mb): (&Vector3<f64>, &Vector3<f64>),
) -> bool {
    let w = ma - mb;
    let (a, b, c) = (da.dot(da), da.dot(db), db.dot(db));
    let (d, e) = (da.dot(&w), db.dot(&w));
    let den = a * c - b * b;
    let (s, t) = ((b * e - c * d) / den, (a * e - b * d) / den);
    const WITHIN: f64 = 0.5 + 1e-6;
    s.abs() <= WITHIN && t.abs() <= WITHIN
}

/// The oracle's working memory, kept between calls so that the per-step measure allocates
/// nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct OracleBuffers {
    a: Placed,
    b: Placed,
    /// With the prune: b's edges that may come near a (under the first bound).
    near_b: Vec<usize>,
    /// With the prune: a's vertices that may come near b, and b's near a.
    near_va: Vec<Vector3<f64>>,
    near_vb: Vec<Vector3<f64>>,
}

impl OracleBuffers {
    /// The penetration depth (MTD) of piece `a` at (rotation, x) and piece `b`, m; 0 when some
    /// axis separates them. `prune`: skip the candidates the module docs' distance argument
    /// rules out (the same answer up to round-off; `false` tries every axis).
    pub fn depth(
        &mut self,
        (a, rotation_a, x_a): (&Piece, &Matrix3<f64>, &Vector3<f64>),
        (b, rotation_b, x_b): (&Piece, &Matrix3<f64>, &Vector3<f64>),
        prune: bool,
    ) -> f64 {
        self.a.place_vertices(a, rotation_a, x_a);
        self.b.place_vertices(b, rotation_b, x_b);
        let (pa, pb) = (&self.a, &self.b);
        let slack = PRUNE_SLACK * pa.radius.max(pb.radius);
        // An upper bound to start from: the overlap along the line of the centres (any axis).
        let between = pb.centre - pa.centre;
        let first = between.try_normalize(0.0).unwrap_or_else(Vector3::y);
        let mut depth = overlap(&pa.vertices, &pb.vertices, &first);
        if depth <= 0.0 {
            return 0.0;
        }
        // The prune's argument holds for overlapping pieces only (module docs).
        let prune = prune
            && match gjk::hulls_overlap(&pa.vertices, &pb.vertices, &-between) {
                gjk::Verdict::Apart => return 0.0,
                gjk::Verdict::Overlap => true,
                gjk::Verdict::Undecided => false,
            };
        // The triangles and edges, needed from here on only.
        self.a.place_features(a, rotation_a);
        self.b.place_features(b, rotation_b);
        let (pa, pb) = (&self.a, &self.b);
        // Whether a feature (centre c, reach r) of one piece may come within `depth` of the
        // other piece (its bounding sphere).
        let near = |c: &Vector3<f64>, r: f64, other: &Placed, depth: f64| {
            !prune || (c - other.centre).norm() - r - other.radius <= depth + slack
        };
        // With the prune: each piece's vertices near the other (a triangle's MTD partner is one).
        for (near_vertices, this, other) in
            [(&mut self.near_va, pa, pb), (&mut self.near_vb, pb, pa)]
        {
            near_vertices.clear();
            if prune {
                near_vertices.extend(this.vertices.iter().filter(|q| near(q, 0.0, other, depth)));
            }
        }
        for (this, other, partners) in [(pa, pb, &self.near_vb), (pb, pa, &self.near_va)] {
            for (n, centroid, reach) in &this.triangles {
                if !near(centroid, *reach, other, depth) {
                    continue;
                }
                // With the prune: a face of one piece carries the MTD with a vertex q of the other
                // (p − q = ±d n, p on the face), so q lies within d of the face's plane and of its
                // bounding sphere.
                let bound = depth + slack;
                if prune
                    && !partners.iter().any(|q| {
                        let r = q - centroid;
                        r.dot(n).abs() <= bound && r.norm() - reach <= bound
                    })
                {
                    continue;
                }
                let o = overlap(&pa.vertices, &pb.vertices, n);
                if o <= 0.0 {
                    return 0.0;
                }
                depth = depth.min(o);
            }
        }
        // b's edges near a under the bound as it stands (it only falls: each pair below is
        // held to the bound as it is then).
        self.near_b.clear();
        self.near_b.extend(
            (0..pb.edges.len()).filter(|&k| near(&pb.edges[k].1, pb.edges[k].2, pa, depth)),
        );
        for (da, ma, ha) in &pa.edges {
            if !near(ma, *ha, pb, depth) {
                continue;
            }
            for &k in &self.near_b {
                let (db, mb, hb) = &pb.edges[k];
                // Each edge near the other piece, and (with the prune) near each other.
                if !near(mb, *hb, pa, depth)
                    || (prune && (ma - mb).norm() - ha - hb > depth + slack)
                {
                    continue;
                }
                let c = da.cross(db);
                // Parallel edges give no axis of their own (their cross product is round-off).
                if c.norm() <= 1e-9 * da.norm() * db.norm() {
                    continue;
                }
                let axis = c.normalize();
                // With the prune: the pair carries the MTD only along its own axis, where p − q
                // = ±d n makes the distance of the edges' lines, |(ma − mb)·n|, exactly d (module
                // docs). Only where the axis is well conditioned: the line distance's relative
                // round-off is roughly 1e-16 over the sine of the edges' angle (an estimate).
                if prune
                    && c.norm() >= 1e-3 * da.norm() * db.norm()
                    && ((ma - mb).dot(&axis).abs() > depth + slack
                        || !lines_meet_within((da, ma), (db, mb)))
                {
                    continue;
                }
                let o = overlap(&pa.vertices, &pb.vertices, &axis);
                if o <= 0.0 {
                    return 0.0;
                }
                depth = depth.min(o);
            }
        }
        depth
    }

    /// The overlap of piece `a` at (rotation, x) and piece `b` along the unit `axis`, m: how far
    /// one must move along it to separate them (≤ 0 when it separates them). A contact normal n
    /// is an axis of least penetration when this is the [`OracleBuffers::depth`].
    pub fn overlap_along(
        &mut self,
        (a, rotation_a, x_a): (&Piece, &Matrix3<f64>, &Vector3<f64>),
        (b, rotation_b, x_b): (&Piece, &Matrix3<f64>, &Vector3<f64>),
        axis: &Vector3<f64>,
    ) -> f64 {
        self.a.place_vertices(a, rotation_a, x_a);
        self.b.place_vertices(b, rotation_b, x_b);
        overlap(&self.a.vertices, &self.b.vertices, axis)
    }
}

/// The penetration depth of piece `a` of `body_a` and piece `b` of `body_b` by every axis (no
/// prune), m: for tests.
pub fn sat_depth(
    a: &Piece,
    body_a: &crate::rigid3d::body::RigidBody,
    b: &Piece,
    body_b: &crate::rigid3d::body::RigidBody,
) -> f64 {
    OracleBuffers::default().depth(
        (a, &body_a.rotation, &body_a.x),
        (b, &body_b.rotation, &body_b.x),
        false,
    )
}
