//! Detection of every contact of a world, in a fixed order: the ground, then the body pairs the
//! broad phase finds. docs/contact.md §"Collision detection".

use super::coherence::{Anchor, Candidate, cached_pair_contacts};
use super::ground::ground_contacts;
use super::manifold::{ManifoldBuffers, manifold_contacts};
use super::mesh_pair::{MeshCollider, vertex_contacts};
use super::penetration::Penetration;
use super::persistent::KeepRule;
use super::vertex_contact::Contact;
use crate::common::broad::{Aabb, BroadGrid, KeptPairs};
use crate::common::pair_cache::{CacheStats, PairCache};
use crate::rigid3d::body::RigidBody;
use nalgebra::{Matrix3, Vector3};

/// How body pairs are tested (the scene's `collision`). docs/contact.md §"Complete collision
/// detection".
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum CollisionMethod {
    /// The assignment's rule: each vertex of one mesh inside the other (default).
    #[default]
    Vertices,
    /// The vertex rule plus the contact manifolds of the bodies' convex pieces, which find
    /// edge–edge crossings and face contacts the vertex rule misses.
    Complete,
    /// The 3D Python starter's `collision.py`, rule for rule ([`super::starter`]): per pair
    /// one direction only, contacts at the closest surface point, body by body.
    Starter,
}

impl CollisionMethod {
    /// The scene-file value.
    pub fn name(self) -> &'static str {
        match self {
            CollisionMethod::Vertices => "vertices",
            CollisionMethod::Complete => "complete",
            CollisionMethod::Starter => "starter",
        }
    }
}

/// How the vertices of one mesh are culled before the signed-distance query against another
/// (the scene's `culling`). Both find exactly the same contacts. docs/contact.md §"Sphere trees".
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum Culling {
    /// The other mesh's bounding box, then parry's bounding-volume hierarchy (default).
    #[default]
    Bvh,
    /// The bounding box, then the other mesh's sphere tree ([`super::sphere_tree`]): a vertex in
    /// none of its leaf spheres is outside it and is not queried.
    SphereTree,
}

impl Culling {
    /// The scene-file value.
    pub fn name(self) -> &'static str {
        match self {
            Culling::Bvh => "bvh",
            Culling::SphereTree => "sphere_tree",
        }
    }
}

/// Collision detection's reusable buffers: the bodies' world boxes and the manifold queries'
/// buffers, kept from call to call so that detection allocates nothing once warmed up; and, when
/// made with [`Detector::cached`], each body pair's candidates kept from step to step
/// (docs/contact.md §"Temporal coherence").
#[derive(Clone, Debug, Default)]
pub struct Detector {
    boxes: Vec<Aabb>,
    manifold: ManifoldBuffers,
    /// Keep candidate lists (`detection_cache`).
    use_cache: bool,
    /// Compare with fresh detection on every call (`check_detection`).
    check: bool,
    /// Keep each piece pair's separating-axis features (`persistent_manifolds`).
    persistent: bool,
    /// Each piece pair's last separating-axis search, per body pair, one per piece candidate in
    /// order (with the cache and `collision: complete`: a leading axis, or persistent manifolds).
    features: PairCache<(), super::persistent::KeptFeatures>,
    /// The check's oracle, for contacts that differ as kept manifolds may.
    oracle: super::sat::OracleBuffers,
    /// The check's first disagreement with persistent manifolds, said.
    check_example: Option<String>,
    cache: PairCache<Anchor, Candidate>,
    fresh: Vec<Contact>,
    /// The broad phase's grown pairs and each body's pose then (with the cache).
    kept_pairs: KeptPairs<(Vector3<f64>, Matrix3<f64>)>,
    /// The broad phase's grid (without the cache).
    grid: BroadGrid,
    pairs: Vec<(usize, usize)>,
    placed: super::penetration::PlacedBuffers,
}

impl Detector {
    /// A detector that keeps each pair's candidates between calls; with `check`, every call also
    /// runs fresh detection and counts a difference in [`CacheStats::mismatches`].
    pub fn cached(check: bool) -> Detector {
        Detector {
            use_cache: true,
            check,
            ..Detector::default()
        }
    }

    /// This detector with persistent manifolds (`persistent_manifolds`, with the cache and
    /// `collision: complete`): each piece pair's manifold from its kept features where they serve
    /// (docs/contact.md §"Persistent manifolds").
    pub fn with_persistent_manifolds(mut self, on: bool) -> Detector {
        self.persistent = on;
        self
    }

    /// The debug check's first difference that is not allowed, said (`None` when none).
    pub fn check_example(&self) -> Option<&str> {
        self.check_example.as_deref()
    }

    /// How often the kept candidates served a pair, and the debug check's counts.
    pub fn stats(&self) -> CacheStats {
        CacheStats {
            manifolds_kept: self.manifold.kept.served,
            manifolds_searched: self.manifold.kept.searched,
            ..self.cache.stats
        }
    }

    /// Finds all contacts of `bodies` (with the ground and with each other), replacing `out`, in
    /// a fixed order: ground contacts body by body, then body pairs in the broad phase's order;
    /// per pair the vertex rule's contacts in both directions (vertices in mesh order) and, with
    /// [`CollisionMethod::Complete`], then the manifold contacts they do not already hold
    /// (pieces in order, points in parry's order). `colliders[i]` belongs to body i. With
    /// [`CollisionMethod::Starter`], the starter's rules and order instead
    /// ([`super::starter::starter_contacts`]; no broad phase, no cache).
    pub fn detect(
        &mut self,
        bodies: &[RigidBody],
        colliders: &[MeshCollider],
        method: CollisionMethod,
        out: &mut Vec<Contact>,
    ) {
        if method == CollisionMethod::Starter {
            super::starter::starter_contacts(bodies, out);
            return;
        }
        out.clear();
        self.manifold.piece_boxes.begin();
        for (i, body) in bodies.iter().enumerate() {
            // `complete` takes vertices within the speculative margin above the plane too (a body
            // written exactly on the ground is held from the first step); the vertex rule only
            // vertices below it.
            let touching = match method {
                CollisionMethod::Vertices | CollisionMethod::Starter => 0.0,
                CollisionMethod::Complete => {
                    super::manifold::speculative_margin(colliders[i].radius())
                }
            };
            ground_contacts(i, body, touching, out);
        }
        MeshCollider::world_boxes(bodies, colliders, &mut self.boxes);
        if method == CollisionMethod::Complete {
            // Bodies within the speculative margin have contacts: their boxes must pair (0.3
            // written as 0.1 + 0.2 lifts a box 4e-17 m off the one below).
            for (b, collider) in self.boxes.iter_mut().zip(colliders) {
                let grow = super::manifold::speculative_margin(collider.radius());
                b.min = b.min.add_scalar(-grow);
                b.max = b.max.add_scalar(grow);
            }
        }
        self.find_pairs(bodies, colliders);
        if self.use_cache {
            self.cache.begin();
            self.features.begin();
        }
        for &(i, j) in &self.pairs {
            let analytic = bodies[i].ellipsoid.is_some() || bodies[j].ellipsoid.is_some();
            if self.use_cache && !analytic {
                cached_pair_contacts(
                    (i, j),
                    bodies,
                    colliders,
                    method == CollisionMethod::Complete,
                    // Each piece pair's last search kept: served exactly (its leading axis),
                    // or within the preferences' bound with persistent manifolds.
                    Some((
                        &mut self.features,
                        if self.persistent {
                            KeepRule::WithinPreferences
                        } else {
                            KeepRule::Exact
                        },
                    )),
                    &mut self.cache,
                    &mut self.manifold,
                    out,
                );
                continue;
            }
            let pair_start = out.len();
            vertex_contacts(i, &bodies[i], j, &bodies[j], &colliders[j], out);
            vertex_contacts(j, &bodies[j], i, &bodies[i], &colliders[i], out);
            if method == CollisionMethod::Complete {
                manifold_contacts(
                    (i, j),
                    bodies,
                    colliders,
                    pair_start,
                    &mut self.manifold,
                    out,
                );
            }
        }
        if self.use_cache {
            self.cache.end();
            self.features.end();
            if self.check {
                let mut fresh = std::mem::take(&mut self.fresh);
                detect_contacts(bodies, colliders, method, &mut fresh);
                self.cache.stats.checked += 1;
                if fresh != *out {
                    // Kept manifolds may differ from fresh ones, within the bound the oracle
                    // checks; anything else is a bug.
                    let agree = if self.persistent {
                        super::audit::kept_manifolds_agree(
                            bodies,
                            colliders,
                            out,
                            &fresh,
                            &mut self.oracle,
                        )
                    } else {
                        Err("the contacts differ".to_string())
                    };
                    if let Err(e) = &agree {
                        self.check_example.get_or_insert_with(|| e.clone());
                    }
                    if agree.is_ok() {
                        self.cache.stats.kept_differs += 1;
                    } else {
                        self.cache.stats.mismatches += 1;
                    }
                }
                self.fresh = fresh;
            }
        }
    }

    /// Every interpenetrating pair ([`super::penetration::penetrations`]), with this detector's
    /// box buffer.
    pub fn penetrations(
        &mut self,
        bodies: &[RigidBody],
        colliders: &[MeshCollider],
        out: &mut Vec<Penetration>,
    ) {
        MeshCollider::world_boxes(bodies, colliders, &mut self.boxes);
        self.find_pairs(bodies, colliders);
        super::penetration::penetrations_in(
            bodies,
            colliders,
            (&self.boxes, &self.pairs),
            &mut self.placed,
            out,
        );
    }

    /// The broad phase on `self.boxes` into `self.pairs`: with the cache, from the kept grown
    /// pairs (margin [`super::coherence::MARGIN_FRACTION`] of each body's bounding radius; a
    /// body's points have moved by at most |Δx| + ‖ΔR‖ ρ); the same pairs either way.
    fn find_pairs(&mut self, bodies: &[RigidBody], colliders: &[MeshCollider]) {
        if !self.use_cache {
            self.grid.pairs_into(&self.boxes, &mut self.pairs);
            return;
        }
        let margin = |k: usize| super::coherence::MARGIN_FRACTION * colliders[k].radius();
        self.kept_pairs.overlapping(
            &self.boxes,
            margin,
            |k| (bodies[k].x, bodies[k].rotation),
            |k, (x, r)| {
                (bodies[k].x - x).norm() + (bodies[k].rotation - r).norm() * colliders[k].radius()
            },
            &mut self.pairs,
        );
    }
}

/// [`Detector::detect`] with fresh buffers (for one-off queries and tests).
pub fn detect_contacts(
    bodies: &[RigidBody],
    colliders: &[MeshCollider],
    method: CollisionMethod,
    out: &mut Vec<Contact>,
) {
    Detector::default().detect(bodies, colliders, method, out);
}
