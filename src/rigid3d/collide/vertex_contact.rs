//! A contact as 3D collision detection finds it: a point of body 1 inside the ground or body 2.

use crate::rigid3d::frame::ContactFrame;
use nalgebra::Vector3;

/// Which features of the two bodies a contact comes from; with the bodies it identifies the
/// contact from substep to substep (warm start).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Feature {
    /// A vertex of body 1's mesh inside body 2 or the ground (the assignment's rule).
    Vertex(usize),
    /// A vertex of body 2's mesh inside body 1 (`collision: starter`, which lists a pair
    /// contact with the penetrated body as body 1, as the starter's contacts do;
    /// [`super::starter`]).
    StarterVertex(usize),
    /// The lowest point of body 1's analytic ellipsoid on the ground (one per body;
    /// [`super::ellipsoid`]).
    Surface,
    /// A point of a convex pieces' contact manifold (`collision: complete` only): piece indices
    /// of body 1 and body 2 and parry's packed feature ids on each (0 for the manifold's deepest
    /// point, whose features parry does not name).
    Manifold {
        /// Body 1's piece.
        piece1: u32,
        /// Body 2's piece.
        piece2: u32,
        /// Feature of piece 1 (parry's `PackedFeatureId`).
        feature1: u32,
        /// Feature of piece 2.
        feature2: u32,
    },
}

/// One contact found by collision detection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The body whose point penetrates (body 1).
    pub body1: usize,
    /// The body it penetrates, or `None` for the ground (body 2).
    pub body2: Option<usize>,
    /// The features the contact comes from: for the vertex rule, the penetrating vertex of body
    /// 1's mesh.
    pub feature: Feature,
    /// Contact point: the penetrating vertex (vertex rule) or the manifold point on body 1's
    /// surface (complete), inside body 2; with `collision: starter`, a pair contact's point is
    /// the closest point of body 1's surface to body 2's penetrating vertex; world frame, m.
    pub point: Vector3<f64>,
    /// Contact frame; `frame.n` points from body 2 into body 1.
    pub frame: ContactFrame,
    /// Penetration depth along n, m: > 0 for the vertex rule; with `collision: complete` it may
    /// be ≤ 0, a speculative contact whose gap is −depth (docs/contact.md §"Speculative contacts").
    pub depth: f64,
}

impl Contact {
    /// The penetrating vertex of body 1, for a vertex-rule contact.
    pub fn vertex(&self) -> Option<usize> {
        match self.feature {
            Feature::Vertex(v) => Some(v),
            Feature::Manifold { .. } | Feature::Surface | Feature::StarterVertex(_) => None,
        }
    }
}
