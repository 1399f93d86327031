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
    fn place(&mut self, piece: &Piece, rotation: &Matrix3<f64>, x: &Vector3<f64>) {
        self.vertices.clear();
        self.vertices
            .extend(piece.vertices.iter().map(|v| rotation * v + x));
        self.centre = self.vertices.iter().sum::<Vector3<f64>>() / self.vertices.len() as f64;
        self.radius = self
            .vertices
            .iter()
            .map(|v| (v - self.centre).norm())
            .fold(0.0, f64::max);
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
    points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let s = p.dot(axis);
            (lo.min(s), hi.max(s))
        })
}

/// The overlap of two point sets' projections on a unit axis, m (≤ 0: the axis separates them).
fn overlap(a: &[Vector3<f64>], b: &[Vector3<f64>], axis: &Vector3<f64>) -> f64 {
    let (a_lo, a_hi) = extent(a, axis);
    let (b_lo, b_hi) = extent(b, axis);
    (a_hi - b_lo).min(b_hi - a_lo)
}

/// The oracle's working memory, kept between calls so that the per-step measure allocates
/// nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct OracleBuffers {
    a: Placed,
    b: Placed,
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
        self.a.place(a, rotation_a, x_a);
        self.b.place(b, rotation_b, x_b);
        let (pa, pb) = (&self.a, &self.b);
        let slack = PRUNE_SLACK * pa.radius.max(pb.radius);
        // An upper bound to start from: the overlap along the line of the centres (any axis).
        let between = pb.centre - pa.centre;
        let first = between.try_normalize(0.0).unwrap_or_else(Vector3::y);
        let mut depth = overlap(&pa.vertices, &pb.vertices, &first);
        if depth <= 0.0 {
            return 0.0;
        }
        // Whether a feature (centre c, reach r) of one piece may come within `depth` of the
        // other piece (its bounding sphere).
        let near = |c: &Vector3<f64>, r: f64, other: &Placed, depth: f64| {
            !prune || (c - other.centre).norm() - r - other.radius <= depth + slack
        };
        for (this, other) in [(pa, pb), (pb, pa)] {
            for (n, centroid, reach) in &this.triangles {
                if !near(centroid, *reach, other, depth) {
                    continue;
                }
                let o = overlap(&pa.vertices, &pb.vertices, n);
                if o <= 0.0 {
                    return 0.0;
                }
                depth = depth.min(o);
            }
        }
        for (da, ma, ha) in &pa.edges {
            if !near(ma, *ha, pb, depth) {
                continue;
            }
            for (db, mb, hb) in &pb.edges {
                if !near(mb, *hb, pa, depth) {
                    continue;
                }
                let c = da.cross(db);
                // Parallel edges give no axis of their own (their cross product is round-off).
                if c.norm() <= 1e-9 * da.norm() * db.norm() {
                    continue;
                }
                let o = overlap(&pa.vertices, &pb.vertices, &c.normalize());
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
        self.a.place(a, rotation_a, x_a);
        self.b.place(b, rotation_b, x_b);
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
