//! The detection campaign: `collision: complete`'s contacts between two convex bodies held
//! against the separating-axis oracle ([`crate::rigid3d::collide::sat`], which shares no code
//! with detection) over random poses and the degenerate ones users write: faces exactly
//! touching, edges and corners aligned, rotations by multiples of 90° (exact and computed),
//! faces turned on faces, parallel edges on edges, identical footprints, deep overlaps, each
//! nudged by a few ulps. docs/contact.md §"The oracle campaign"; docs/verification.md.

use crate::rigid3d::body::RigidBody;
pub use crate::rigid3d::collide::audit::{
    AUDIT_TOLERANCE, PairCheck, check_pair, preferred_depth_bound,
};
use crate::rigid3d::collide::sat::OracleBuffers;
use crate::rigid3d::collide::{CollisionMethod, Contact, MeshCollider, detect_contacts};
use crate::rigid3d::mesh::TriMesh;
use nalgebra::{Matrix3, Rotation3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// How a campaign pose was made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoseKind {
    /// Random rotations, the bodies within reach of each other.
    Random,
    /// Faces exactly touching (or within a few ulps, or overlapping a little or deeply), the
    /// bodies turned by multiples of 90° and one of them about the contact axis, sides centred,
    /// aligned, corner on corner or random.
    FaceOnFace,
    /// Both bodies turned 45° about one horizontal axis, resting edge on edge.
    EdgeOnEdge,
    /// The same orientation, one above the other, overlapping by up to most of a body.
    SameFootprint,
}

/// The kinds, in the order the campaign cycles through them.
pub const POSE_KINDS: [PoseKind; 4] = [
    PoseKind::Random,
    PoseKind::FaceOnFace,
    PoseKind::EdgeOnEdge,
    PoseKind::SameFootprint,
];

/// The 24 rotations that map the axes onto the axes, as exact matrices (entries 0 and ±1).
pub fn axis_rotations() -> Vec<Matrix3<f64>> {
    let mut out = Vec::new();
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    for i in 0..3 {
        for si in [1.0, -1.0] {
            for j in 0..3 {
                if j == i {
                    continue;
                }
                for sj in [1.0, -1.0] {
                    let (u, v) = (axes[i] * si, axes[j] * sj);
                    out.push(Matrix3::from_columns(&[u, v, u.cross(&v)]));
                }
            }
        }
    }
    out
}

/// A campaign: meshes (each convex) and their colliders.
pub struct DetectionCampaign {
    meshes: Vec<Arc<TriMesh>>,
    colliders: Vec<MeshCollider>,
    rotations: Vec<Matrix3<f64>>,
    oracle: OracleBuffers,
    contacts: Vec<Contact>,
}

/// What a campaign found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CampaignReport {
    /// Pairs tried.
    pub pairs: u64,
    /// Pairs the oracle found overlapping beyond the tolerance.
    pub overlapping: u64,
    /// Pairs within the tolerance of touching (|depth| below it and the bounding boxes meeting).
    pub touching: u64,
    /// Contacts checked.
    pub contacts: u64,
    /// Pairs with a disagreement.
    pub disagreements: u64,
    /// The first few disagreements, with the pose that gave them.
    pub examples: Vec<String>,
    /// The largest deepest-contact / oracle depth over pairs overlapping by more than 1e-6 of
    /// the radius.
    pub worst_depth_ratio: f64,
    /// The smallest, over the same pairs.
    pub least_depth_ratio: f64,
}

impl DetectionCampaign {
    /// A campaign over `meshes` (each must be convex: one piece).
    pub fn new(meshes: Vec<Arc<TriMesh>>) -> Result<DetectionCampaign, String> {
        let colliders = meshes
            .iter()
            .map(|m| MeshCollider::new(m.clone()))
            .collect::<Result<Vec<_>, _>>()?;
        if colliders.iter().any(|c| !c.pieces.convex) {
            return Err("the detection campaign takes convex meshes only".into());
        }
        Ok(DetectionCampaign {
            meshes,
            colliders,
            rotations: axis_rotations(),
            oracle: OracleBuffers::default(),
            contacts: Vec::new(),
        })
    }

    /// Boxes of the shapes the project's scenes use, made here so that the campaign needs no
    /// files: a 0.2 m cube with the off-centre coordinates `rigidref massprops` writes
    /// (−0.10000000000000009 … 0.09999999999999987), a 0.5 m cube, a 0.8 × 0.4 × 1.2 m brick, a
    /// 0.2 × 0.6 × 1.0 m slab, and an octahedron (faces at no right angle).
    pub fn built_in_meshes() -> Vec<Arc<TriMesh>> {
        let cube20 = TriMesh::cuboid(
            Vector3::new(-0.10000000000000009, -0.1, -0.10000000000000009),
            Vector3::new(0.09999999999999987, 0.1, 0.09999999999999987),
        );
        let half = |x: f64, y: f64, z: f64| {
            TriMesh::cuboid(Vector3::new(-x, -y, -z), Vector3::new(x, y, z))
        };
        let octahedron = TriMesh {
            vertices: vec![
                Vector3::new(0.3, 0.0, 0.0),
                Vector3::new(-0.3, 0.0, 0.0),
                Vector3::new(0.0, 0.3, 0.0),
                Vector3::new(0.0, -0.3, 0.0),
                Vector3::new(0.0, 0.0, 0.3),
                Vector3::new(0.0, 0.0, -0.3),
            ],
            triangles: vec![
                [0, 2, 4],
                [2, 1, 4],
                [1, 3, 4],
                [3, 0, 4],
                [2, 0, 5],
                [1, 2, 5],
                [3, 1, 5],
                [0, 3, 5],
            ],
            file_numbers: Vec::new(),
            file_vertex_count: 0,
        };
        [
            cube20,
            half(0.25, 0.25, 0.25),
            half(0.4, 0.2, 0.6),
            half(0.1, 0.3, 0.5),
            octahedron,
        ]
        .into_iter()
        .map(Arc::new)
        .collect()
    }

    /// Runs `pairs` poses from `seed`, cycling through [`POSE_KINDS`].
    pub fn run(&mut self, pairs: u64, seed: u64) -> CampaignReport {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut report = CampaignReport {
            least_depth_ratio: f64::INFINITY,
            ..CampaignReport::default()
        };
        for k in 0..pairs {
            let kind = POSE_KINDS[(k % POSE_KINDS.len() as u64) as usize];
            let case_seed: u64 = rng.random();
            self.check_case(kind, case_seed, &mut report);
        }
        report
    }

    /// Meshes in the campaign.
    pub fn mesh_count(&self) -> usize {
        self.meshes.len()
    }

    /// Mesh `a` at (x_a, R_a) and mesh `b` at (x_b, R_b) as bodies.
    pub fn bodies(
        &self,
        (a, x_a, r_a): (usize, Vector3<f64>, Matrix3<f64>),
        (b, x_b, r_b): (usize, Vector3<f64>, Matrix3<f64>),
    ) -> [RigidBody; 2] {
        let body = |mesh: usize, x: Vector3<f64>, r: Matrix3<f64>| {
            let mut body = RigidBody::new(
                "campaign",
                1.0,
                Matrix3::identity(),
                self.meshes[mesh].clone(),
            );
            body.x = x;
            body.rotation = r;
            body
        };
        [body(a, x_a, r_a), body(b, x_b, r_b)]
    }

    /// `collision: complete`'s contacts between two bodies of meshes `a` and `b`, checked
    /// against the oracle.
    pub fn check_bodies(&mut self, (a, b): (usize, usize), bodies: &[RigidBody; 2]) -> PairCheck {
        detect_contacts(
            bodies,
            &[self.colliders[a].clone(), self.colliders[b].clone()],
            CollisionMethod::Complete,
            &mut self.contacts,
        );
        self.contacts.retain(|c| c.body2.is_some());
        check_pair(
            [&bodies[0], &bodies[1]],
            [&self.colliders[a], &self.colliders[b]],
            &self.contacts,
            true,
            &mut self.oracle,
        )
    }

    /// One pose of `kind` from `seed`, checked, its counts added to `report`.
    pub fn check_case(&mut self, kind: PoseKind, seed: u64, report: &mut CampaignReport) {
        let (a, b, bodies) = self.pose(kind, seed);
        let check = self.check_bodies((a, b), &bodies);
        let radius = self.colliders[a].radius().max(self.colliders[b].radius());
        report.pairs += 1;
        report.contacts += check.contacts as u64;
        if check.depth > AUDIT_TOLERANCE * radius {
            report.overlapping += 1;
            // The ratio says something only where the depth is above round-off.
            if check.depth > 1e-6 * radius {
                report.worst_depth_ratio =
                    report.worst_depth_ratio.max(check.deepest / check.depth);
                report.least_depth_ratio =
                    report.least_depth_ratio.min(check.deepest / check.depth);
            }
        } else {
            let boxes = [
                self.colliders[a].world_aabb(&bodies[0]),
                self.colliders[b].world_aabb(&bodies[1]),
            ];
            if boxes[0].overlaps(&boxes[1]) {
                report.touching += 1;
            }
        }
        if !check.disagreements.is_empty() {
            report.disagreements += 1;
            if report.examples.len() < 5 {
                report.examples.push(format!(
                    "{kind:?} seed {seed}: meshes {a} and {b} at x {:?}, {:?}, R {:?}, {:?}: {}",
                    bodies[0].x.as_slice(),
                    bodies[1].x.as_slice(),
                    bodies[0].rotation.as_slice(),
                    bodies[1].rotation.as_slice(),
                    check.disagreements.join("; ")
                ));
            }
        }
    }

    /// The two bodies of one pose: mesh indices and the bodies.
    pub fn pose(&self, kind: PoseKind, seed: u64) -> (usize, usize, [RigidBody; 2]) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let n = self.meshes.len();
        let (a, b) = (rng.random_range(0..n), rng.random_range(0..n));
        // Sometimes far from the origin, where coordinates carry more round-off.
        let base = match rng.random_range(0..4) {
            0 => Vector3::new(0.0, 0.1, 0.0),
            1 => Vector3::new(0.5, 0.25, 0.0),
            2 => Vector3::new(
                rng.random_range(-10.0..10.0),
                10.0,
                rng.random_range(-10.0..10.0),
            ),
            _ => Vector3::new(1000.0, 0.3, -1000.0),
        };
        let body = |mesh: usize, x: Vector3<f64>, r: Matrix3<f64>| {
            let [body, _] = self.bodies((mesh, x, r), (mesh, x, r));
            body
        };
        let random_rotation = |rng: &mut ChaCha8Rng| {
            let v = Vector3::new(
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
            );
            *Rotation3::new(v).matrix()
        };
        match kind {
            PoseKind::Random => {
                let (ra, rb) = (random_rotation(&mut rng), random_rotation(&mut rng));
                let reach = self.colliders[a].radius() + self.colliders[b].radius();
                let direction = random_rotation(&mut rng) * Vector3::x();
                let distance = reach * rng.random_range(0.3..1.05);
                (
                    a,
                    b,
                    [body(a, base, ra), body(b, base + direction * distance, rb)],
                )
            }
            PoseKind::FaceOnFace | PoseKind::EdgeOnEdge | PoseKind::SameFootprint => {
                let k = rng.random_range(0..3usize); // the contact axis
                let (ra, rb) = match kind {
                    PoseKind::FaceOnFace => {
                        let ra = self.rotations[rng.random_range(0..24)];
                        let s = if rng.random_bool(0.2) {
                            // A multiple of 90° as users compute it: cos(π/2) ≈ 6e-17.
                            let axis = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()]
                                [rng.random_range(0..3)];
                            let quarter = rng.random_range(1..4) as f64;
                            *Rotation3::from_axis_angle(
                                &axis,
                                quarter * std::f64::consts::FRAC_PI_2,
                            )
                            .matrix()
                        } else {
                            self.rotations[rng.random_range(0..24)]
                        };
                        let degrees: [f64; 6] =
                            [0.0, 10.0, 30.0, 45.0, 90.0, rng.random_range(0.0..360.0)];
                        let turn = degrees[rng.random_range(0..6)].to_radians();
                        let axis = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()][k];
                        (ra, *Rotation3::from_axis_angle(&axis, turn).matrix() * s)
                    }
                    PoseKind::EdgeOnEdge => {
                        let about = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()]
                            [(k + 1 + rng.random_range(0..2)) % 3];
                        let diamond =
                            *Rotation3::from_axis_angle(&about, std::f64::consts::FRAC_PI_4)
                                .matrix();
                        (diamond, diamond)
                    }
                    _ => {
                        let r = if rng.random_bool(0.5) {
                            self.rotations[rng.random_range(0..24)]
                        } else {
                            random_rotation(&mut rng)
                        };
                        (r, r)
                    }
                };
                let extent = |mesh: usize, r: &Matrix3<f64>, axis: usize| {
                    self.meshes[mesh]
                        .vertices
                        .iter()
                        .map(|v| (r * v)[axis])
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                            (lo.min(s), hi.max(s))
                        })
                };
                let mut xb = base;
                // Along the contact axis: touching, as written or computed.
                let (_, a_hi) = extent(a, &ra, k);
                let (b_lo, b_hi) = extent(b, &rb, k);
                xb[k] = base[k] + a_hi - b_lo;
                let thickness = (b_hi - b_lo).min(extent(a, &ra, k).1 - extent(a, &ra, k).0);
                match rng.random_range(0..6) {
                    0 => {}
                    1 => {
                        for _ in 0..rng.random_range(1..3) {
                            xb[k] = if rng.random_bool(0.5) {
                                xb[k].next_up()
                            } else {
                                xb[k].next_down()
                            };
                        }
                    }
                    2 => xb[k] -= thickness * 10f64.powf(rng.random_range(-12.0..-2.0)),
                    3 => xb[k] -= thickness * rng.random_range(0.01..0.95),
                    // Touching as a sum: 0.1 + 0.2 is not 0.3.
                    4 => xb[k] = (base[k] + a_hi) + (-b_lo),
                    _ => xb[k] += thickness * 10f64.powf(rng.random_range(-12.0..-3.0)),
                }
                if kind == PoseKind::SameFootprint {
                    xb[k] = base[k] + (a_hi - b_lo) - thickness * rng.random_range(1e-4..0.95);
                }
                // Across it: centred, sides aligned, corner on corner, or anywhere.
                for j in (0..3).filter(|&j| j != k) {
                    let (alo, ahi) = extent(a, &ra, j);
                    let (blo, bhi) = extent(b, &rb, j);
                    xb[j] = base[j]
                        + match rng.random_range(0..5) {
                            0 => 0.0,
                            1 => ahi - bhi,
                            2 => alo - blo,
                            3 => ahi - blo,
                            _ => rng.random_range(alo - bhi..ahi - blo),
                        };
                }
                (a, b, [body(a, base, ra), body(b, xb, rb)])
            }
        }
    }
}
