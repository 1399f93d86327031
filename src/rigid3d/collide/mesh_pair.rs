//! Mesh–mesh contacts: the vertices of one body against the signed distance of the other, through
//! parry3d's bounding-volume hierarchy. docs/contact.md §"Mesh contacts".

use super::closest_point::SignedDistance;
use super::pieces::ConvexPieces;
use super::sphere_tree::SphereTree;
use super::vertex_contact::{Contact, Feature};
use crate::common::broad::Aabb;
use crate::rigid3d::body::RigidBody;
use crate::rigid3d::frame::ContactFrame;
use crate::rigid3d::mesh::TriMesh;
use nalgebra::Vector3;
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{TriMesh as ParryTriMesh, TriMeshFlags, TrianglePointLocation};

/// A vertex closer to the surface than this fraction of the mesh's bounding radius is on the
/// surface, not inside: its closest feature (and so its normal) is decided by round-off, e.g. a
/// vertex lying in the plane of a face it does not touch. Such a vertex is not a contact.
pub const SURFACE_TOLERANCE: f64 = 1e-9;

/// What a kept candidate vertex knows of its nearest triangle of the other body
/// ([`MeshCollider::signed_distance_keeping`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NearestTriangle {
    /// Not looked at yet.
    Unknown,
    /// No triangle leads by more than round-off (or too deep to ask, or still moving): searched
    /// each time; after `retry_in` more searches the next also looks for a leading triangle.
    Ambiguous {
        /// Searches left before the next looks for a lead.
        retry_in: u8,
    },
    /// This triangle, nearer than every other by more than the gap when it was found.
    Kept(u32),
    /// This triangle, nearer than every other by `lead` (m, at most the gap) when the search
    /// found it at `at` (the vertex in the other body's frame, m): it stays the nearest, and the
    /// search's answer, while the vertex is within (`lead` − [`LEAD_ROUND_OFF`] ρ) / 2 of `at`
    /// (docs/contact.md §"Temporal coherence", "Leading triangles").
    Leading {
        /// The nearest triangle.
        triangle: u32,
        /// How much nearer than every other triangle it was at `at`, m.
        lead: f64,
        /// Where the vertex was (the other body's frame), m.
        at: [f64; 3],
        /// Whether it has answered a query since (one that fails at once moved too fast for
        /// its lead, and the vertex waits [`LEAD_RETRY`] searches before the next look).
        served: bool,
    },
    /// Ambiguous, and its last search found the vertex on the surface: within
    /// [`ON_SURFACE_FRACTION`] of the mesh's bounding radius of this triangle. While it still is,
    /// it is no contact, and the search is skipped ([`vertex_contact`]).
    OnSurface(u32),
}

/// Round-off allowance of a lead, as a fraction of the mesh's bounding radius: a triangle is
/// leading only when it is nearer than every other by more than this, and kept while twice the
/// vertex's motion stays below its lead less this (distances are computed to about 1e-16 of
/// the coordinates; the same allowance as the kept triangles' gap).
pub const LEAD_ROUND_OFF: f64 = 1e-9;

/// Searches a vertex waits before it looks for a leading triangle again, after a look found
/// none or its leading triangle was given up at the next query (a moving vertex): the look
/// costs about as much as the search, so a moving vertex pays it on one search in
/// `LEAD_RETRY + 1`.
pub const LEAD_RETRY: u8 = 8;

/// A vertex within this fraction of the mesh's bounding radius of one of its triangles is on
/// the surface for [`NearestTriangle::OnSurface`]: half of [`SURFACE_TOLERANCE`], so that the
/// search's signed distance, at most this distance plus round-off in magnitude, is never below
/// −[`SURFACE_TOLERANCE`] of the radius, the contact threshold.
pub const ON_SURFACE_FRACTION: f64 = 0.5 * SURFACE_TOLERANCE;

/// A body's mesh prepared for queries: parry's triangle mesh with its BVH and pseudo-normals
/// (for a reliable inside test), in the body frame.
#[derive(Clone)]
pub struct MeshCollider {
    shape: ParryTriMesh,
    local_box: Aabb,
    radius: f64,
    mesh: std::sync::Arc<TriMesh>,
    /// The mesh's convex pieces (`collision: complete` and the penetration measure).
    pub pieces: std::sync::Arc<ConvexPieces>,
    /// The mesh's sphere tree, with `culling: sphere_tree` ([`Self::with_sphere_tree`]); `None`
    /// culls by the bounding box alone before the BVH query.
    pub sphere_tree: Option<std::sync::Arc<SphereTree>>,
}

impl std::fmt::Debug for MeshCollider {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshCollider")
            .field("vertices", &self.mesh.vertices.len())
            .field("triangles", &self.mesh.triangles.len())
            .finish()
    }
}

fn to_parry(v: &Vector3<f64>) -> PVector {
    PVector::new(v.x, v.y, v.z)
}

fn from_parry(v: PVector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

impl MeshCollider {
    /// Prepares `mesh` (body frame, closed and outward-oriented, as scene loading checks).
    /// Fails only for a mesh parry cannot build (no triangles, or a topology it rejects).
    pub fn new(mesh: std::sync::Arc<TriMesh>) -> Result<MeshCollider, String> {
        let pieces = std::sync::Arc::new(ConvexPieces::of_mesh(&mesh)?);
        Self::with_pieces(mesh, pieces)
    }

    /// Prepares `mesh` with its convex pieces already computed (bodies sharing a mesh share
    /// them; the decomposition of a non-convex mesh takes a while).
    pub fn with_pieces(
        mesh: std::sync::Arc<TriMesh>,
        pieces: std::sync::Arc<ConvexPieces>,
    ) -> Result<MeshCollider, String> {
        let vertices = mesh.vertices.iter().map(to_parry).collect();
        let indices = mesh.triangles.iter().map(|t| t.map(|i| i as u32)).collect();
        let shape = ParryTriMesh::with_flags(vertices, indices, TriMeshFlags::ORIENTED)
            .map_err(|e| format!("cannot build the collision mesh: {e:?}"))?;
        let local_box = Aabb::around(mesh.vertices.iter().copied());
        Ok(MeshCollider {
            shape,
            local_box,
            radius: mesh.bounding_radius(),
            mesh,
            pieces,
            sphere_tree: None,
        })
    }

    /// This collider with a sphere tree for culling (bodies sharing a mesh share it).
    pub fn with_sphere_tree(mut self, tree: std::sync::Arc<SphereTree>) -> MeshCollider {
        self.sphere_tree = Some(tree);
        self
    }

    /// Builds the mesh's sphere tree to `depth` octree levels with this collider's signed
    /// distance (the BVH's). docs/contact.md §"Sphere trees".
    pub fn build_sphere_tree(&self, depth: u32) -> SphereTree {
        SphereTree::build(&self.mesh, depth, &|p| self.signed_distance(p).distance)
    }

    /// The body's world bounding box (of its transformed vertices).
    pub fn world_aabb(&self, body: &RigidBody) -> Aabb {
        Aabb::around(
            self.mesh
                .vertices
                .iter()
                .map(|v| body.x + body.rotation * v),
        )
    }

    /// The world bounding boxes of `bodies` into `out` (replaced), `colliders[i]` belonging to
    /// body i (the broad phase's input).
    pub fn world_boxes(bodies: &[RigidBody], colliders: &[MeshCollider], out: &mut Vec<Aabb>) {
        out.clear();
        out.extend(bodies.iter().zip(colliders).map(|(b, c)| c.world_aabb(b)));
    }

    /// Signed distance from `p` (body frame) to the surface, through the BVH. Same meaning as
    /// [`super::closest_point::brute_force_signed_distance`].
    pub fn signed_distance(&self, p: &Vector3<f64>) -> SignedDistance {
        let (projection, (triangle, _)) = self
            .shape
            .project_local_point_and_get_location(to_parry(p), false);
        SignedDistance::new(
            &self.mesh,
            self.radius,
            p,
            from_parry(projection.point),
            projection.is_inside,
            triangle as usize,
        )
    }

    /// The triangle nearest `p` (body frame) when every other triangle is farther from `p` by
    /// more than `gap` (m), else `None`. It then stays the nearest, and [`Self::signed_distance`]'s
    /// answer, while `p` moves by less than `gap / 2` (distances to a fixed triangle change by at
    /// most the motion). docs/contact.md §"Temporal coherence".
    pub fn unique_nearest_triangle(&self, p: &Vector3<f64>, gap: f64) -> Option<u32> {
        let q = to_parry(p);
        let (projection, (nearest, _)) = self.shape.project_local_point_and_get_location(q, false);
        let distance = (projection.point - q).length();
        self.is_unique_nearest(p, nearest, distance, gap)
            .then_some(nearest)
    }

    /// Whether `triangle`, at `distance` from `p`, is nearer than every other triangle by more
    /// than `gap`. Every triangle within `distance + gap` of `p` is compared (the BVH's boxes
    /// meeting a cube of that half-side around `p`); the others are farther anyway.
    fn is_unique_nearest(&self, p: &Vector3<f64>, triangle: u32, distance: f64, gap: f64) -> bool {
        self.lead(p, triangle, distance, gap)
            .is_some_and(|lead| lead > gap)
    }

    /// How much nearer `p` `triangle` (at `distance` from it) is than every other triangle within
    /// `distance + gap` of `p` (the BVH's boxes meeting a cube of that half-side around `p`), m:
    /// the least (other's distance − `distance`), +∞ when there is none; every triangle farther
    /// than that reach is more than `gap` farther than `triangle`. `None` when the reach is not
    /// finite. docs/contact.md §"Temporal coherence".
    fn lead(&self, p: &Vector3<f64>, triangle: u32, distance: f64, gap: f64) -> Option<f64> {
        let q = to_parry(p);
        let reach = distance + gap;
        if !reach.is_finite() {
            return None;
        }
        let around = parry3d_f64::bounding_volume::Aabb::new(
            q - PVector::splat(reach),
            q + PVector::splat(reach),
        );
        let mut lead = f64::INFINITY;
        for other in self.shape.bvh().intersect_aabb(&around) {
            if other == triangle {
                continue;
            }
            let (projection, _) =
                (self.shape.triangle(other)).project_local_point_and_get_location(q, false);
            let ahead = (projection.point - q).length() - distance;
            if ahead.is_nan() {
                return Some(0.0);
            }
            lead = lead.min(ahead);
        }
        Some(lead)
    }

    /// [`Self::signed_distance`] for a kept candidate vertex, using and settling what is known of
    /// its nearest triangle, and how it was answered: on a kept triangle without the search; on
    /// a leading triangle without the search while the vertex is within half its lead (less
    /// round-off) of where it was searched; otherwise by the search, after which (for a vertex
    /// within `gap` of the surface, so that the comparison's neighbourhood stays small) the
    /// triangle's lead over every other is measured: when unknown, a lead above `gap` keeps the
    /// triangle for the list's life; else the vertex is on the surface when it is within
    /// [`ON_SURFACE_FRACTION`] of the radius of it ([`NearestTriangle::OnSurface`]), leading
    /// where the lead is above [`LEAD_ROUND_OFF`] of the radius, else ambiguous (and the next
    /// [`LEAD_RETRY`] searches do not measure a lead). docs/contact.md §"Temporal coherence"
    /// ("Leading triangles").
    pub fn signed_distance_keeping(
        &self,
        p: &Vector3<f64>,
        nearest: &mut NearestTriangle,
        gap: f64,
    ) -> (SignedDistance, VertexQuery) {
        let on_surface = |sd: &SignedDistance| {
            (sd.distance.abs() <= ON_SURFACE_FRACTION * self.radius)
                .then_some(NearestTriangle::OnSurface(sd.triangle as u32))
        };
        let round_off = LEAD_ROUND_OFF * self.radius;
        match *nearest {
            NearestTriangle::Kept(triangle) => {
                (self.signed_distance_on(p, triangle), VertexQuery::OnKept)
            }
            NearestTriangle::Leading {
                triangle,
                lead,
                at,
                ref mut served,
            } if crate::common::faults::fault!(leading_motion_unchecked)
                || 2.0 * (p - Vector3::from(at)).norm() + round_off < lead =>
            {
                *served = true;
                (self.signed_distance_on(p, triangle), VertexQuery::OnLeading)
            }
            NearestTriangle::Ambiguous { .. }
            | NearestTriangle::OnSurface(_)
            | NearestTriangle::Leading { .. }
            | NearestTriangle::Unknown => {
                let unknown = *nearest == NearestTriangle::Unknown;
                let retry_in = match *nearest {
                    NearestTriangle::Ambiguous { retry_in } => retry_in,
                    NearestTriangle::Leading { served: false, .. } => LEAD_RETRY,
                    _ => 0,
                };
                let look = retry_in == 0;
                let sd = self.signed_distance(p);
                let depth = sd.distance.abs();
                let lead = (look && depth < gap)
                    .then(|| self.lead(p, sd.triangle as u32, depth, gap))
                    .flatten()
                    .unwrap_or(0.0);
                let triangle = sd.triangle as u32;
                *nearest = if unknown && lead > gap {
                    NearestTriangle::Kept(triangle)
                } else if let Some(on) = on_surface(&sd) {
                    on
                } else if lead > round_off {
                    NearestTriangle::Leading {
                        triangle,
                        lead: lead.min(gap),
                        at: [p.x, p.y, p.z],
                        served: false,
                    }
                } else {
                    NearestTriangle::Ambiguous {
                        retry_in: if look { LEAD_RETRY } else { retry_in - 1 },
                    }
                };
                (sd, VertexQuery::Searched)
            }
        }
    }

    /// Whether `p` (body frame) is within [`ON_SURFACE_FRACTION`] of the bounding radius of
    /// `triangle` (its distance to a point parry's projection puts on the triangle): then the
    /// surface is at most that far, and [`Self::signed_distance`]'s answer, a nearest point's
    /// distance, is no contact ([`vertex_contact`]). False when it is NaN.
    /// docs/contact.md §"Temporal coherence" ("Vertices on the surface").
    pub fn still_on_surface(&self, p: &Vector3<f64>, triangle: u32) -> bool {
        let q = to_parry(p);
        let (projection, _) =
            (self.shape.triangle(triangle)).project_local_point_and_get_location(q, false);
        (projection.point - q).length() <= ON_SURFACE_FRACTION * self.radius
    }

    /// [`Self::signed_distance`] when `triangle` is known to be `p`'s unique nearest triangle
    /// ([`Self::unique_nearest_triangle`]): the same steps as parry's query after its search
    /// (the triangle's projection, then the inside test by the pseudo-normal of the feature the
    /// projection lies on, as `TriMesh::project_local_point_and_get_location_with_max_dist`
    /// does), so the same bits, without the search.
    pub fn signed_distance_on(&self, p: &Vector3<f64>, triangle: u32) -> SignedDistance {
        let q = to_parry(p);
        let (mut projection, location) =
            (self.shape.triangle(triangle)).project_local_point_and_get_location(q, false);
        if let Some(pseudo_normals) = self.shape.pseudo_normals_if_oriented() {
            let pseudo_normal = match location {
                TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => {
                    Some(self.shape.triangle(triangle).scaled_normal())
                }
                TrianglePointLocation::OnEdge(e, _) => (pseudo_normals.edges_pseudo_normal)
                    .get(triangle as usize)
                    .map(|normals| normals[e as usize]),
                TrianglePointLocation::OnVertex(v) => {
                    let index = self.shape.indices()[triangle as usize][v as usize];
                    (pseudo_normals.vertices_pseudo_normal)
                        .get(index as usize)
                        .copied()
                }
            };
            if let Some(pseudo_normal) = pseudo_normal {
                projection.is_inside = (q - projection.point).dot(pseudo_normal) <= 0.0;
            }
        }
        SignedDistance::new(
            &self.mesh,
            self.radius,
            p,
            from_parry(projection.point),
            projection.is_inside,
            triangle as usize,
        )
    }

    /// Bytes parry's bounding-volume hierarchy takes (its nodes; for the culling comparison).
    pub fn bvh_memory_bytes(&self) -> usize {
        self.shape.bvh().total_memory_size()
    }

    /// The mesh's bounding radius (largest vertex distance from the body origin), m.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The body's size: the smallest side of the mesh's bounding box in its own frame, m.
    pub fn size(&self) -> f64 {
        self.local_box.smallest_side()
    }

    /// Whether a body-frame point is inside this mesh's bounding box and bounding sphere (two
    /// cheap first tests). Both are exact culls: every point of the solid is a convex combination
    /// of vertices, so it lies in the vertices' box and within the largest vertex distance of the
    /// origin.
    pub fn may_contain(&self, p: &Vector3<f64>) -> bool {
        self.local_box.contains(p) && p.norm_squared() <= self.radius * self.radius
    }

    /// [`Self::may_contain`] with the box and the sphere grown by `margin` (m): a point that
    /// fails this is farther than `margin` from passing it.
    pub fn may_come_within(&self, p: &Vector3<f64>, margin: f64) -> bool {
        let grown = Aabb {
            min: self.local_box.min.add_scalar(-margin),
            max: self.local_box.max.add_scalar(margin),
        };
        grown.contains(p) && p.norm() <= self.radius + margin
    }
}

/// How [`vertex_contact`] answered a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexQuery {
    /// Outside j's box or sphere (or sphere tree): no signed distance.
    Culled,
    /// Still on j's surface where its last search found it ([`NearestTriangle::OnSurface`]):
    /// no contact, without the search.
    OnSurface,
    /// By its signed distance, found by the BVH search.
    Searched,
    /// By its signed distance on its kept triangle ([`NearestTriangle::Kept`]), without the
    /// search.
    OnKept,
    /// By its signed distance on its leading triangle ([`NearestTriangle::Leading`]), without
    /// the search.
    OnLeading,
}

/// Appends a contact for every vertex of body `i` inside body `j` by more than
/// [`SURFACE_TOLERANCE`] of j's bounding radius: point the vertex,
/// depth its distance to j's surface, normal the outward direction of j's surface there
/// (rotated to the world frame). Body i is body 1, body j is body 2.
pub fn vertex_contacts(
    i: usize,
    body_i: &RigidBody,
    j: usize,
    body_j: &RigidBody,
    collider_j: &MeshCollider,
    out: &mut Vec<Contact>,
) {
    // Against an analytic ellipsoid, its exact implicit surface instead of its mesh.
    if let Some(shape) = &body_j.ellipsoid {
        super::ellipsoid::vertices_in_ellipsoid(i, body_i, j, body_j, shape, out);
        return;
    }
    for vertex in 0..body_i.mesh.vertices.len() {
        let mut nearest = NearestTriangle::Ambiguous { retry_in: 0 };
        vertex_contact(
            i,
            body_i,
            vertex,
            j,
            body_j,
            collider_j,
            (&mut nearest, 0.0),
            out,
        );
    }
}

/// [`vertex_contacts`] for one vertex of body i (body j without an analytic ellipsoid): appends
/// its contact if it is inside body j. `nearest`: what is known of the vertex's nearest triangle
/// of j and the gap that keeps it ([`MeshCollider::signed_distance_keeping`]; `Ambiguous` for
/// the plain search); a kept triangle spares the BVH search and gives the same contact. Returns
/// how the vertex was answered ([`VertexQuery`]).
#[allow(clippy::too_many_arguments)]
pub fn vertex_contact(
    i: usize,
    body_i: &RigidBody,
    vertex: usize,
    j: usize,
    body_j: &RigidBody,
    collider_j: &MeshCollider,
    (nearest, gap): (&mut NearestTriangle, f64),
    out: &mut Vec<Contact>,
) -> VertexQuery {
    let local = &body_i.mesh.vertices[vertex];
    let point = body_i.x + body_i.rotation * local;
    let in_j = body_j.rotation.transpose() * (point - body_j.x);
    if !collider_j.may_contain(&in_j) {
        return VertexQuery::Culled;
    }
    // In no leaf sphere: outside j's solid, so no contact (docs/contact.md §"Sphere trees").
    if let Some(tree) = &collider_j.sphere_tree
        && !tree.may_contain(&in_j)
    {
        return VertexQuery::Culled;
    }
    // Found on j's surface by its last search and still within half the surface tolerance of
    // the same triangle: the search's distance would be at most that (plus round-off) in
    // magnitude, above the contact threshold −SURFACE_TOLERANCE ρ_j, so no contact
    // (docs/contact.md §"Temporal coherence", "Vertices on the surface").
    if let NearestTriangle::OnSurface(triangle) = *nearest
        && (crate::common::faults::fault!(surface_skip_unchecked)
            || collider_j.still_on_surface(&in_j, triangle))
    {
        return VertexQuery::OnSurface;
    }
    let (sd, answer) = collider_j.signed_distance_keeping(&in_j, nearest, gap);
    if sd.distance < -SURFACE_TOLERANCE * collider_j.radius
        && sd.normal.iter().all(|x| x.is_finite())
    {
        let normal = (body_j.rotation * sd.normal).normalize();
        out.push(Contact {
            body1: i,
            body2: Some(j),
            feature: Feature::Vertex(vertex),
            point,
            frame: ContactFrame::from_normal(&normal),
            depth: -sd.distance,
        });
    }
    answer
}
