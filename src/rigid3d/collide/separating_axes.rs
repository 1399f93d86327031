//! The contact of two convex pieces by separating axes, exact in the degenerate cases (faces
//! exactly touching, parallel edges, coincident vertices, overlaps deeper than half a body), and
//! its contact points by clipping. docs/contact.md §"Exact convex contact".
//!
//! Everything is computed in piece A's frame (its body's frame), with piece B placed there by
//! [`Placement`]:
//!
//! 1. **face axes**: for each face of A (outward n, plane n·x = d) the gap
//!    min over B's vertices of n·v − d, and the same for each face of B against A's vertices;
//! 2. **edge axes**: for each edge of A and edge of B whose Gauss-map arcs cross (they then
//!    build a face of the Minkowski difference A ⊖ B, Gregorius 2013), the axis e_A × e_B
//!    oriented out of A at its edge (the face's outward normal; a box pair has each axis twice,
//!    once per side), and the gap of the two pieces' projections on it;
//! 3. the **axis of least penetration** is the one with the largest gap, except that faces are
//!    preferred (Gregorius 2015, "Robust contact creation for physics simulations"): an edge
//!    axis is taken only when its gap g_e exceeds the best face gap g_f by more than
//!    (1 − [`EDGE_PREFERENCE`]) |g_f| + τ, and B's best face only when its gap exceeds A's by more
//!    than (1 − [`FACE_B_PREFERENCE`]) |g_A| + τ (τ = [`AXIS_TIE_TOLERANCE`] × the larger radius,
//!    round-off; for overlaps, g_e > 0.9 g_f + τ, Gregorius's rule); within a kind the first
//!    index wins. An edge pair whose Gauss-map arcs meet only at an end (a face normal) may pass
//!    the crossing test by round-off; its axis is that face's normal and its gap that face's, so
//!    it never beats the face. Between nearly parallel faces the exact minimum often lies along an edge pair
//!    tilted by the faces' small angle, and taking it would make a resting box's patch of four
//!    corners a single edge point that jumps between steps; the preference keeps the patch, and
//!    costs at most the bound below;
//! 4. **contact points**: for a face axis with normal n, the incident face is the face of the
//!    other piece most opposed to n among those at its deepest vertex along −n; it is clipped
//!    against the reference face's side planes (Sutherland–Hodgman), and each clipped point
//!    below the reference plane is a contact point at its depth below it. For an edge axis, the
//!    closest points of the two edges. Should a preferred face's patch fall short of the exact
//!    depth d by more than (1 − [`EDGE_PREFERENCE`]) |d| + τ (its deepest incident vertex
//!    overhangs the face, as when a box tips over another's edge), the axis of least penetration
//!    is taken instead: its points do reach d.
//!
//! Every gap is a real gap between the pieces' projections on a unit axis, so the depth can
//! never come out shallower than the pieces' true overlap d (the minimum translation distance);
//! and that minimum lies along a face normal or a Minkowski-face edge cross product, so the
//! largest gap is exactly −d ([`LeastPenetration::exact_gap`]). With the preferences the chosen
//! axis's depth lies in [d, (d + 2τ) / (EDGE_PREFERENCE · FACE_B_PREFERENCE)], and the deepest
//! contact point's depth in [d − (1 − EDGE_PREFERENCE) |d| − τ, that bound].

use super::polytope::Polytope;
use nalgebra::{Matrix3, Vector3};

/// Ties between axes are decided by the rule of the module docs when the gaps differ by less
/// than this fraction of the larger piece radius: round-off, not geometry.
pub const AXIS_TIE_TOLERANCE: f64 = 1e-9;

/// An edge axis is chosen only when its gap exceeds this times the best face gap (plus τ): with
/// gaps negative, only when its penetration is under 0.9 of the face's (Gregorius's value).
pub const EDGE_PREFERENCE: f64 = 0.9;

/// A face of B is the reference only when its gap exceeds this times A's best (plus τ).
pub const FACE_B_PREFERENCE: f64 = 0.98;

/// Two edges count as parallel (their cross product is no axis of its own; the face axes cover
/// that direction) when the sine of their angle is below this.
pub const PARALLEL_SINE: f64 = 1e-9;

/// Feature ids of contact points (warm starting): the kind in the top two bits, the index below.
pub mod feature_id {
    /// A vertex of the piece.
    pub const VERTEX: u32 = 1 << 30;
    /// An edge of the piece.
    pub const EDGE: u32 = 2 << 30;
    /// A face of the piece.
    pub const FACE: u32 = 3 << 30;
}

/// Piece B's body frame seen from piece A's: x_A = rotation x_B + translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// R_Aᵀ R_B.
    pub rotation: Matrix3<f64>,
    /// R_Aᵀ (x_B − x_A), m.
    pub translation: Vector3<f64>,
}

impl Placement {
    /// B's frame in A's, from the two bodies' world rotations and positions.
    pub fn between(
        (rotation_a, x_a): (&Matrix3<f64>, &Vector3<f64>),
        (rotation_b, x_b): (&Matrix3<f64>, &Vector3<f64>),
    ) -> Placement {
        Placement {
            rotation: rotation_a.transpose() * rotation_b,
            translation: rotation_a.transpose() * (x_b - x_a),
        }
    }
}

/// The axis the query chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// A face of piece A (its normal).
    FaceOfA(usize),
    /// A face of piece B (its normal, pointing from B toward A).
    FaceOfB(usize),
    /// Edge of A × edge of B.
    Edges(usize, usize),
}

/// The axis of least penetration: which axis, its unit normal n₁ out of A toward B (A's frame),
/// and the gap along it, m (negative: the pieces overlap by −gap along n₁).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeastPenetration {
    /// The chosen axis.
    pub axis: Axis,
    /// Unit normal out of A toward B, A's frame.
    pub normal: Vector3<f64>,
    /// Gap of the two pieces' projections on it, m (< 0 when they overlap).
    pub gap: f64,
    /// The axis with the largest gap of all (faces of A, of B, then edges on exact ties).
    pub exact_axis: Axis,
    /// Its normal, as [`Self::normal`].
    pub exact_normal: Vector3<f64>,
    /// The largest gap over every axis tried, m: minus the exact penetration depth (the chosen
    /// axis's gap is within the preferences' bound of it).
    pub exact_gap: f64,
}

/// What the last full search ([`SatBuffers::contact_or_apart`]) found, beyond its answer: the
/// gaps that decided it, for the leading axis (docs/contact.md §"Temporal coherence", "Leading
/// axes"). Gaps in m; −∞ where there is no such axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchGaps {
    /// The largest gap over A's faces.
    pub face_a: f64,
    /// The second largest gap over A's faces.
    pub face_a_second: f64,
    /// The largest gap over B's faces.
    pub face_b: f64,
    /// The second largest gap over B's faces.
    pub face_b_second: f64,
    /// The largest gap over every axis tried: minus the exact penetration depth.
    pub exact: f64,
    /// The axis the preferences chose (before the fall-back to the exact axis).
    pub preferred: Axis,
}

/// One contact point of two pieces, A's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// The point on A's surface, m.
    pub on_a: Vector3<f64>,
    /// The point on B's surface, m.
    pub on_b: Vector3<f64>,
    /// (on_b − on_a)·n₁, m: negative when the point is a penetration.
    pub distance: f64,
    /// A's feature ([`feature_id`]).
    pub feature_a: u32,
    /// B's feature.
    pub feature_b: u32,
}

/// A polygon corner being clipped: its position (A's frame), its feature on the incident piece
/// and on the reference piece, and what the polygon's side from it to the next corner lies on.
#[derive(Clone, Copy, Debug)]
struct Corner {
    p: Vector3<f64>,
    incident: u32,
    reference: u32,
    side: Side,
}

/// What a clipped polygon's side lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    /// An edge of the incident piece.
    IncidentEdge(usize),
    /// The side plane of the reference face's k-th edge.
    ReferenceSide(usize),
}

/// The query's working memory, kept between calls so that it allocates nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct SatBuffers {
    /// B's vertices in A's frame.
    b_vertices: Vec<Vector3<f64>>,
    /// B's face normals in A's frame.
    b_normals: Vec<Vector3<f64>>,
    polygon: Vec<Corner>,
    clipped: Vec<Corner>,
    /// The contact points of the last [`SatBuffers::contact`].
    pub points: Vec<ContactPoint>,
    /// The Gauss-map arc tests' dot products, tabled per call ([`Self::tabulate_arcs`]).
    arcs: ArcTables,
    /// Compute every crossing edge pair's gap, none skipped by its bound (for the test that
    /// the skip changes nothing: [`Self::every_edge_gap`]).
    every_edge_gap: bool,
    /// Crossing edge pairs skipped by their bound, over this buffer's life.
    pub edge_pairs_skipped: u64,
    /// The gaps behind the last search that found the pieces touching ([`SearchGaps`]).
    pub last_search: Option<SearchGaps>,
}

/// The dot products [`arcs_cross`] takes for every edge of A against every edge of B, computed
/// once per query instead of once per edge pair: each edge's arc plane (a₂ × a₁ of its two face
/// normals; B's negated, as the test takes them), then each face normal's side of each arc plane
/// of the other piece. [`arcs_cross`]'s four sides for edges (e_A, e_B) are four entries of
/// these tables, the same expressions of the same numbers (the same bits): the query's cost
/// falls from four dot products and two cross products per edge pair to a table look-up
/// (docs/contact.md §"Exact convex contact", "The arcs tabled").
#[derive(Clone, Debug, Default)]
struct ArcTables {
    /// Per face g of B: −m_g (A's frame).
    b_negated: Vec<Vector3<f64>>,
    /// Per edge of B: (−m₂) × (−m₁), m₁, m₂ its faces' normals.
    b_planes: Vec<Vector3<f64>>,
    /// (−m_g)·(n₂ × n₁) for edge e of A (faces n₁, n₂) and face g of B, at e · faces(B) + g.
    b_sides: Vec<f64>,
    /// n_f·b_plane(e) for face f of A and edge e of B, at f · edges(B) + e.
    a_sides: Vec<f64>,
}

impl SatBuffers {
    /// Buffers whose query computes the gap of every edge pair whose arcs cross, none skipped
    /// by the bound of docs/contact.md §"Exact convex contact" ("Edge pairs bounded"): the
    /// reference the test `rigid3d::complete::edge_pairs_skipped_by_their_bound_change_nothing`
    /// holds the default query to (the same answers, bit for bit).
    pub fn every_edge_gap() -> SatBuffers {
        SatBuffers {
            every_edge_gap: true,
            ..SatBuffers::default()
        }
    }

    /// Places B's vertices and face normals in A's frame.
    pub(super) fn place(&mut self, b: &Polytope, at: &Placement) {
        self.b_vertices.clear();
        self.b_vertices
            .extend(b.vertices.iter().map(|v| at.rotation * v + at.translation));
        self.b_normals.clear();
        self.b_normals
            .extend(b.faces.iter().map(|f| at.rotation * f.normal));
    }

    /// Tables the Gauss-map arc tests of every edge of A against every edge of B ([`ArcTables`]),
    /// after [`Self::place`]. docs/contact.md §"Exact convex contact".
    fn tabulate_arcs(&mut self, a: &Polytope, b: &Polytope) {
        let t = &mut self.arcs;
        t.b_negated.clear();
        t.b_negated.extend(self.b_normals.iter().map(|m| -m));
        t.b_planes.clear();
        t.b_planes.extend(b.edges.iter().map(|e| {
            let (b1, b2) = (t.b_negated[e.faces[0]], t.b_negated[e.faces[1]]);
            b2.cross(&b1)
        }));
        t.b_sides.clear();
        for edge_a in &a.edges {
            let (a1, a2) = (
                a.faces[edge_a.faces[0]].normal,
                a.faces[edge_a.faces[1]].normal,
            );
            let a_plane = a2.cross(&a1);
            t.b_sides
                .extend(t.b_negated.iter().map(|b1| b1.dot(&a_plane)));
        }
        t.a_sides.clear();
        for face in &a.faces {
            t.a_sides
                .extend(t.b_planes.iter().map(|plane| face.normal.dot(plane)));
        }
    }

    /// The edge pairs (e_A, e_B) whose Gauss-map arcs cross with B placed by `at` (those that
    /// make a face of A ⊖ B), as the query decides it from its tables, in the query's order,
    /// into `out` (replaced): the same pairs as [`arcs_cross`] on their faces' normals (A's, and
    /// B's negated), which the test `rigid3d::complete::tabled_arc_tests_match_arcs_cross` holds
    /// it to.
    pub fn crossing_edges(
        &mut self,
        a: &Polytope,
        b: &Polytope,
        at: &Placement,
        out: &mut Vec<(usize, usize)>,
    ) {
        self.place(b, at);
        self.tabulate_arcs(a, b);
        out.clear();
        let (faces_b, edges_b) = (b.faces.len(), b.edges.len());
        let t = &self.arcs;
        for (ea, edge_a) in a.edges.iter().enumerate() {
            for (eb, edge_b) in b.edges.iter().enumerate() {
                if sides_cross(
                    t.b_sides[ea * faces_b + edge_b.faces[0]],
                    t.b_sides[ea * faces_b + edge_b.faces[1]],
                    t.a_sides[edge_a.faces[0] * edges_b + eb],
                    t.a_sides[edge_a.faces[1] * edges_b + eb],
                ) {
                    out.push((ea, eb));
                }
            }
        }
    }

    /// The axis of least penetration of A and B (B placed by `at`), or, as soon as some axis
    /// shows a gap larger than `stop_above` (m), that axis (`Err`): the pieces are then apart by
    /// more than that. Reads [`Self::place`]'s buffers.
    fn least_penetration(
        &mut self,
        a: &Polytope,
        b: &Polytope,
        at: &Placement,
        stop_above: f64,
    ) -> Result<LeastPenetration, Axis> {
        let bv = &self.b_vertices;
        // 1. Face axes of A, then of B (B's plane moved into A's frame).
        let mut face_a = (usize::MAX, f64::NEG_INFINITY);
        let (mut face_a_second, mut face_b_second) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        // The teeth tests' deliberate bug: the face of greatest penetration, as GJK/EPA gave in
        // degenerate poses (docs/verification.md §"Teeth").
        let wrong = crate::common::faults::fault!(deepest_face_axis);
        for (f, face) in a.faces.iter().enumerate() {
            let gap = lowest(bv, &face.normal) - face.offset;
            if gap > stop_above {
                return Err(Axis::FaceOfA(f));
            }
            let better = if wrong {
                face_a.0 == usize::MAX || gap < face_a.1
            } else {
                gap > face_a.1
            };
            if better {
                face_a_second = face_a.1;
                face_a = (f, gap);
            } else if gap > face_a_second {
                face_a_second = gap;
            }
        }
        if wrong {
            let (f, gap) = face_a;
            return Ok(LeastPenetration {
                axis: Axis::FaceOfA(f),
                normal: a.faces[f].normal,
                gap,
                exact_axis: Axis::FaceOfA(f),
                exact_normal: a.faces[f].normal,
                exact_gap: gap,
            });
        }
        let mut face_b = (usize::MAX, f64::NEG_INFINITY);
        for (g, face) in b.faces.iter().enumerate() {
            let n = self.b_normals[g];
            let offset = face.offset + n.dot(&at.translation);
            let gap = lowest(&a.vertices, &n) - offset;
            if gap > stop_above {
                return Err(Axis::FaceOfB(g));
            }
            if gap > face_b.1 {
                face_b_second = face_b.1;
                face_b = (g, gap);
            } else if gap > face_b_second {
                face_b_second = gap;
            }
        }
        // 2. Edge axes, for the edge pairs that make a face of the Minkowski difference
        //    (the arcs' crossing read off the tables: `arcs_cross` of the four normals).
        self.tabulate_arcs(a, b);
        let bv = &self.b_vertices;
        let mut edges = (usize::MAX, usize::MAX, f64::NEG_INFINITY, Vector3::zeros());
        let (faces_b, edges_b) = (b.faces.len(), b.edges.len());
        let best_face = face_a.1.max(face_b.1);
        for (ea, edge_a) in a.edges.iter().enumerate() {
            let da = a.vertices[edge_a.vertices[1]] - a.vertices[edge_a.vertices[0]];
            let b_sides = &self.arcs.b_sides[ea * faces_b..(ea + 1) * faces_b];
            let a1_sides = &self.arcs.a_sides[edge_a.faces[0] * edges_b..][..edges_b];
            let a2_sides = &self.arcs.a_sides[edge_a.faces[1] * edges_b..][..edges_b];
            for (eb, edge_b) in b.edges.iter().enumerate() {
                let (b1_side, b2_side) = (b_sides[edge_b.faces[0]], b_sides[edge_b.faces[1]]);
                if !sides_cross(b1_side, b2_side, a1_sides[eb], a2_sides[eb]) {
                    continue;
                }
                let db = bv[edge_b.vertices[1]] - bv[edge_b.vertices[0]];
                let cross = da.cross(&db);
                let length = cross.norm();
                if length <= PARALLEL_SINE * da.norm() * db.norm() {
                    continue;
                }
                // The Minkowski face's outward normal: out of A at its edge (the crossing lies
                // in the edge's normal cone, between n1 and n2, so it points away from A's
                // inside). Its gap is B's lowest minus A's highest projection: for this pair of
                // supporting edges, the distance between their lines along it.
                let at_edge = a.vertices[edge_a.vertices[0]] - a.centroid;
                let l = if cross.dot(&at_edge) < 0.0 {
                    -cross / length
                } else {
                    cross / length
                };
                // The computed gap is at most the two edges' own projections' difference (B's
                // lowest is at most its edge's first vertex's, A's highest at least its edge's,
                // the same products; rounding is monotone), so an edge pair whose bound does not
                // exceed the best face gap can neither stop the search nor be chosen, nor be the
                // largest gap: skipped, the same answer (docs/contact.md §"Exact convex contact",
                // "Edge pairs bounded").
                let bound = l.dot(&bv[edge_b.vertices[0]]) - l.dot(&a.vertices[edge_a.vertices[0]]);
                if bound <= best_face && !self.every_edge_gap {
                    self.edge_pairs_skipped += 1;
                    continue;
                }
                let gap = lowest(bv, &l) - highest(&a.vertices, &l);
                let normal = l;
                if gap > stop_above {
                    return Err(Axis::Edges(ea, eb));
                }
                if gap > edges.2 {
                    edges = (ea, eb, gap, normal);
                }
            }
        }
        // 3. The preferences: faces over edges, A over B, unless clearly beaten.
        let tie = AXIS_TIE_TOLERANCE * a.radius.max(b.radius);
        let face_of_a = (Axis::FaceOfA(face_a.0), a.faces[face_a.0].normal, face_a.1);
        let face_of_b = (Axis::FaceOfB(face_b.0), -self.b_normals[face_b.0], face_b.1);
        let edge_pair = (Axis::Edges(edges.0, edges.1), edges.3, edges.2);
        let mut exact = face_of_a;
        for candidate in [face_of_b, edge_pair] {
            if candidate.2 > exact.2 {
                exact = candidate;
            }
        }
        // g beats g₀ when g > g₀ + (1 − preference) |g₀| + τ: for overlaps (g₀ < 0) that is
        // g > preference · g₀ + τ, and for gaps (speculative contacts) g > g₀ / preference
        // roughly, so that the preference is for faces either way.
        let beats = |g: f64, g0: f64, preference: f64| g > g0 + (1.0 - preference) * g0.abs() + tie;
        let face = if beats(face_b.1, face_a.1, FACE_B_PREFERENCE) {
            face_of_b
        } else {
            face_of_a
        };
        let (axis, normal, gap) = if beats(edges.2, face_a.1.max(face_b.1), EDGE_PREFERENCE) {
            edge_pair
        } else {
            face
        };
        self.last_search = Some(SearchGaps {
            face_a: face_a.1,
            face_a_second,
            face_b: face_b.1,
            face_b_second,
            exact: exact.2,
            preferred: axis,
        });
        Ok(LeastPenetration {
            axis,
            normal,
            gap,
            exact_axis: exact.0,
            exact_normal: exact.1,
            exact_gap: exact.2,
        })
    }

    /// Whether pieces A and B (placed by `at`) are apart by more than `distance` (m) along some
    /// axis: then no point of one is within `distance` of the other.
    pub fn apart_by_more_than(
        &mut self,
        a: &Polytope,
        b: &Polytope,
        at: &Placement,
        distance: f64,
    ) -> bool {
        self.place(b, at);
        self.least_penetration(a, b, at, distance).is_err()
    }

    /// The contact of pieces A and B (B placed by `at`): the axis of least penetration, with
    /// its contact points in [`Self::points`] (replaced). `None`, with no points, when some axis
    /// shows a gap larger than `stop_above` (m; pass minus the depth below which points are not
    /// wanted: every point is then shallower than that).
    pub fn contact(
        &mut self,
        a: &Polytope,
        b: &Polytope,
        at: &Placement,
        stop_above: f64,
    ) -> Option<LeastPenetration> {
        self.contact_or_apart(a, b, at, stop_above).ok()
    }

    /// [`Self::contact`], naming the separating axis (`Err`) when the pieces are apart by more
    /// than `stop_above`.
    pub fn contact_or_apart(
        &mut self,
        a: &Polytope,
        b: &Polytope,
        at: &Placement,
        stop_above: f64,
    ) -> Result<LeastPenetration, Axis> {
        self.points.clear();
        self.last_search = None;
        self.place(b, at);
        let mut found = self.least_penetration(a, b, at, stop_above)?;
        let reached = self.points_along(a, b, found.axis, &found.normal);
        // A preferred face whose clipped patch falls short of the exact depth d by more than
        // the edge preference allows, (1 − 0.9)|d| (its deepest incident vertex overhangs the
        // face: a box tipping over the other's edge), is not where the bodies meet; the axis of
        // least penetration is, and its points reach d (for a face, the deepest vertex projects
        // into it; for edges, their closest points). Short by less (nearly parallel faces with a
        // corner overhanging by a hair) the face's patch stays: a stack keeps its corners.
        let tie = AXIS_TIE_TOLERANCE * a.radius.max(b.radius);
        let exact_depth = -found.exact_gap;
        let short = (1.0 - EDGE_PREFERENCE) * exact_depth.abs() + tie;
        if reached < exact_depth - short && found.exact_axis != found.axis {
            self.points.clear();
            self.points_along(a, b, found.exact_axis, &found.exact_normal);
            (found.axis, found.normal, found.gap) =
                (found.exact_axis, found.exact_normal, found.exact_gap);
        }
        Ok(found)
    }

    /// The unit normal n₁ (out of A toward B) and the gap of one axis, computed as
    /// [`Self::least_penetration`] computes it (the same bits), after [`Self::place`]; `None`
    /// for an edge pair that has become parallel (no axis of its own).
    pub(super) fn axis_gap(
        &self,
        a: &Polytope,
        b: &Polytope,
        at: &Placement,
        axis: Axis,
    ) -> Option<(Vector3<f64>, f64)> {
        let bv = &self.b_vertices;
        match axis {
            Axis::FaceOfA(f) => {
                let face = &a.faces[f];
                Some((face.normal, lowest(bv, &face.normal) - face.offset))
            }
            Axis::FaceOfB(g) => {
                let n = self.b_normals[g];
                let offset = b.faces[g].offset + n.dot(&at.translation);
                Some((-n, lowest(&a.vertices, &n) - offset))
            }
            Axis::Edges(ea, eb) => {
                let (edge_a, edge_b) = (&a.edges[ea], &b.edges[eb]);
                let da = a.vertices[edge_a.vertices[1]] - a.vertices[edge_a.vertices[0]];
                let db = bv[edge_b.vertices[1]] - bv[edge_b.vertices[0]];
                let cross = da.cross(&db);
                let length = cross.norm();
                if length <= PARALLEL_SINE * da.norm() * db.norm() {
                    return None;
                }
                let at_edge = a.vertices[edge_a.vertices[0]] - a.centroid;
                let l = if cross.dot(&at_edge) < 0.0 {
                    -cross / length
                } else {
                    cross / length
                };
                Some((l, lowest(bv, &l) - highest(&a.vertices, &l)))
            }
        }
    }

    /// The contact points along `axis` (normal n₁ out of A), into `points`; returns the deepest
    /// depth among them, m (−∞ when there are none).
    pub(super) fn points_along(
        &mut self,
        a: &Polytope,
        b: &Polytope,
        axis: Axis,
        normal: &Vector3<f64>,
    ) -> f64 {
        match axis {
            Axis::FaceOfA(f) => self.clip(a, f, b, false),
            Axis::FaceOfB(g) => self.clip(b, g, a, true),
            Axis::Edges(ea, eb) => {
                let edge_a = a.edges[ea].vertices.map(|v| a.vertices[v]);
                let edge_b = b.edges[eb].vertices.map(|v| self.b_vertices[v]);
                let (on_a, on_b) = closest_points_of_segments(edge_a, edge_b);
                self.points.push(ContactPoint {
                    on_a,
                    on_b,
                    distance: (on_b - on_a).dot(normal),
                    feature_a: feature_id::EDGE | ea as u32,
                    feature_b: feature_id::EDGE | eb as u32,
                });
            }
        }
        self.points
            .iter()
            .map(|p| -p.distance)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Contact points of reference face `f` of `reference` with the incident face of
    /// `incident`, into `points`. `reference_is_b`: the reference piece is B (its vertices and
    /// normals are the placed buffers), the incident piece A.
    fn clip(&mut self, reference: &Polytope, f: usize, incident: &Polytope, reference_is_b: bool) {
        let face = &reference.faces[f];
        // Positions and normals in A's frame, of either piece.
        let (ref_vertices, inc_vertices): (&[Vector3<f64>], &[Vector3<f64>]) = if reference_is_b {
            (&self.b_vertices, &incident.vertices)
        } else {
            (&reference.vertices, &self.b_vertices)
        };
        let n = if reference_is_b {
            self.b_normals[f]
        } else {
            face.normal
        };
        let offset = face
            .corners
            .iter()
            .map(|&c| n.dot(&ref_vertices[c]))
            .fold(f64::NEG_INFINITY, f64::max);
        // The incident piece's deepest vertex along −n, and of the faces at it the one most
        // opposed to n (first on ties): the incident face holds the deepest vertex.
        let mut deepest = (0, f64::INFINITY);
        for (v, p) in inc_vertices.iter().enumerate() {
            let height = n.dot(p);
            if height < deepest.1 {
                deepest = (v, height);
            }
        }
        let mut opposed = (0, f64::INFINITY);
        for &g in &incident.vertex_faces[deepest.0] {
            let normal = if reference_is_b {
                incident.faces[g].normal
            } else {
                self.b_normals[g]
            };
            let alignment = normal.dot(&n);
            if alignment < opposed.1 {
                opposed = (g, alignment);
            }
        }
        let incident_face = &incident.faces[opposed.0];
        let mut polygon = std::mem::take(&mut self.polygon);
        let mut clipped = std::mem::take(&mut self.clipped);
        polygon.clear();
        polygon.extend(
            incident_face
                .corners
                .iter()
                .zip(&incident_face.edges)
                .map(|(&v, &e)| Corner {
                    p: inc_vertices[v],
                    incident: feature_id::VERTEX | v as u32,
                    reference: feature_id::FACE | f as u32,
                    side: Side::IncidentEdge(e),
                }),
        );
        // Sutherland–Hodgman against each side plane s·x ≤ s·c_k, s = (c_{k+1} − c_k) × n. A
        // corner within τ of a plane counts as inside: edges parallel to a side to round-off
        // (a box on an equal box) then cross nowhere, instead of anywhere along it.
        let tie = AXIS_TIE_TOLERANCE * reference.radius.max(incident.radius);
        let corners = &face.corners;
        for k in 0..corners.len() {
            let (c0, c1) = (
                ref_vertices[corners[k]],
                ref_vertices[corners[(k + 1) % corners.len()]],
            );
            let side = (c1 - c0).cross(&n);
            let s = side / side.norm();
            let limit = s.dot(&c0);
            clipped.clear();
            for i in 0..polygon.len() {
                let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
                let (dp, dq) = (s.dot(&p.p) - limit, s.dot(&q.p) - limit);
                let (p_in, q_in) = (dp <= tie, dq <= tie);
                if p_in {
                    clipped.push(p);
                }
                if p_in != q_in {
                    // The side p → q crosses the plane: the crossing, on p's side and on side k.
                    let t = dp / (dp - dq);
                    let incident_feature = match p.side {
                        Side::IncidentEdge(e) => feature_id::EDGE | e as u32,
                        Side::ReferenceSide(_) => feature_id::FACE | opposed.0 as u32,
                    };
                    let reference_feature = match p.side {
                        // Two side planes meet at the reference face's corner.
                        Side::ReferenceSide(_) => feature_id::VERTEX | corners[k] as u32,
                        Side::IncidentEdge(_) => feature_id::EDGE | face.edges[k] as u32,
                    };
                    clipped.push(Corner {
                        p: p.p + (q.p - p.p) * t,
                        incident: incident_feature,
                        reference: reference_feature,
                        // Leaving the side plane's inside, the polygon runs along it.
                        side: if p_in { Side::ReferenceSide(k) } else { p.side },
                    });
                }
            }
            std::mem::swap(&mut polygon, &mut clipped);
            if polygon.is_empty() {
                break;
            }
        }
        for corner in &polygon {
            let depth = offset - n.dot(&corner.p);
            let on_reference = corner.p + n * depth;
            // distance = (on_b − on_a)·n₁ = −depth either way round.
            self.points.push(if reference_is_b {
                ContactPoint {
                    on_a: corner.p,
                    on_b: on_reference,
                    distance: -depth,
                    feature_a: corner.incident,
                    feature_b: corner.reference,
                }
            } else {
                ContactPoint {
                    on_a: on_reference,
                    on_b: corner.p,
                    distance: -depth,
                    feature_a: corner.reference,
                    feature_b: corner.incident,
                }
            });
        }
        self.polygon = polygon;
        self.clipped = clipped;
    }
}

/// Whether the great-circle arcs a₁a₂ and b₁b₂ of unit vectors cross (the arcs are shorter than
/// a half circle; sharing only an end point, or lying on one great circle, is no crossing).
/// b₁ and b₂ must lie on opposite sides of the plane of a₁, a₂ and vice versa, and the arcs on
/// the same half of the sphere (Gregorius 2013, "The separating axis test between convex
/// polyhedra"). For the Gauss-map arcs of an edge of A and the negated arc of an edge of B
/// this is the test that the two edges build a face of A ⊖ B.
pub fn arcs_cross(
    a1: &Vector3<f64>,
    a2: &Vector3<f64>,
    b1: &Vector3<f64>,
    b2: &Vector3<f64>,
) -> bool {
    let a_plane = a2.cross(a1);
    let b_plane = b2.cross(b1);
    let b1_side = b1.dot(&a_plane);
    let b2_side = b2.dot(&a_plane);
    let a1_side = a1.dot(&b_plane);
    let a2_side = a2.dot(&b_plane);
    sides_cross(b1_side, b2_side, a1_side, a2_side)
}

/// [`arcs_cross`]'s decision from its four sides: b₁, b₂ on either side of a's plane, a₁, a₂ on
/// either side of b's, and the arcs on the same half of the sphere.
fn sides_cross(b1_side: f64, b2_side: f64, a1_side: f64, a2_side: f64) -> bool {
    b1_side * b2_side < 0.0 && a1_side * a2_side < 0.0 && b1_side * a2_side > 0.0
}

/// The closest points of segments p₀p₁ and q₀q₁ (Ericson, Real-Time Collision Detection §5.1.9),
/// each clamped to its segment.
pub fn closest_points_of_segments(
    [p0, p1]: [Vector3<f64>; 2],
    [q0, q1]: [Vector3<f64>; 2],
) -> (Vector3<f64>, Vector3<f64>) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&r));
    let (s, t);
    if a == 0.0 && e == 0.0 {
        (s, t) = (0.0, 0.0);
    } else if a == 0.0 {
        (s, t) = (0.0, (f / e).clamp(0.0, 1.0));
    } else {
        let c = d1.dot(&r);
        if e == 0.0 {
            (s, t) = ((-c / a).clamp(0.0, 1.0), 0.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let s0 = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                (s, t) = ((-c / a).clamp(0.0, 1.0), 0.0);
            } else if t0 > 1.0 {
                (s, t) = (((b - c) / a).clamp(0.0, 1.0), 1.0);
            } else {
                (s, t) = (s0, t0);
            }
        }
    }
    (p0 + d1 * s, q0 + d2 * t)
}

/// The least of n·p over `points` (+∞ for none): a polytope's support along −n, as a height.
fn lowest(points: &[Vector3<f64>], n: &Vector3<f64>) -> f64 {
    points
        .iter()
        .map(|p| n.dot(p))
        .fold(f64::INFINITY, f64::min)
}

/// The greatest of n·p over `points` (−∞ for none): a polytope's support along n, as a height.
fn highest(points: &[Vector3<f64>], n: &Vector3<f64>) -> f64 {
    points
        .iter()
        .map(|p| n.dot(p))
        .fold(f64::NEG_INFINITY, f64::max)
}
