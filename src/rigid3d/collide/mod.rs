//! Collision detection for 3D mesh bodies: which vertices are inside the ground or another body,
//! how deep, and which way out. docs/contact.md §"Collision detection".
//!
//! - [`detect`]: every contact of a world, in a fixed order ([`detect_contacts`]);
//! - [`vertex_contact`]: what a contact is ([`Contact`]);
//! - [`ground`]: every vertex below the plane y = 0 is a contact with normal +y;
//! - [`ellipsoid`]: a body's analytic ellipsoid (the rattleback): its lowest point on the
//!   ground, other meshes' vertices against its implicit surface;
//! - [`crate::common::broad`]: sweep-and-prune on world bounding boxes picks the body pairs
//!   worth testing;
//! - [`mesh_pair`]: the vertices of each body of a pair against the other body's surface (signed
//!   distance through parry3d's bounding-volume hierarchy), both directions;
//! - [`coherence`]: each pair's candidates kept from step to step (the same contacts);
//! - [`sphere_tree`]: with `culling: sphere_tree`, a tree of spheres covering each mesh's solid
//!   culls the vertices that cannot be inside it before the BVH query;
//! - [`closest_point`]: the brute-force oracle that tests hold [`mesh_pair`] against;
//! - [`pieces`]: each mesh as convex pieces (itself when convex, else a convex decomposition);
//! - [`polytope`]: a convex piece's faces, planes and edges;
//! - [`separating_axes`]: two convex pieces' contact by separating axes (exact where faces touch
//!   exactly, edges are parallel or the overlap is deep) and its contact points by clipping;
//! - [`manifold`]: with `collision: complete`, the contact manifolds of the pieces add what the
//!   vertex rule misses (edge–edge crossings, faces on faces);
//! - [`starter`]: with `collision: starter`, the 3D Python starter's detection rule for rule (one
//!   direction per pair, the closest surface point, its body-by-body order);
//! - [`sat`]: the oracle, separating axes by brute force (sharing no code with detection);
//! - [`audit`]: a pair's contacts held against the oracle (the campaign, crosscheck, the watch);
//! - [`penetration`]: how deep bodies interpenetrate, whatever contacts were found, by the
//!   oracle.
//!
//! A contact has the vertex owner as body 1 and the body it penetrates (or the ground) as body 2,
//! so the normal (out of body 2) is the direction body 1 must move to separate; the starter's
//! pair contacts name the two the other way round, as the starter does, with the normal into the
//! penetrated body (body 1), still the direction body 1 must move.

pub mod audit;
pub mod closest_point;
pub mod coherence;
pub mod detect;
pub mod ellipsoid;
pub mod gjk;
pub mod ground;
pub mod manifold;
pub mod mesh_pair;
pub mod penetration;
pub mod persistent;
pub mod pieces;
pub mod polytope;
pub mod sat;
pub mod separating_axes;
pub mod sphere_tree;
pub mod starter;
pub mod vertex_contact;

pub use detect::{CollisionMethod, Culling, detect_contacts};
pub use mesh_pair::MeshCollider;
pub use vertex_contact::{Contact, Feature};
