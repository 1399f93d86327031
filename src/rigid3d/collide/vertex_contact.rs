//! A contact as 3D collision detection finds it: a vertex of body 1 inside the ground or body 2.

use crate::rigid3d::contact::ContactFrame;
use nalgebra::Vector3;

/// One contact found by collision detection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The body whose vertex penetrates (body 1).
    pub body1: usize,
    /// The body it penetrates, or `None` for the ground (body 2).
    pub body2: Option<usize>,
    /// Index of the penetrating vertex in body 1's mesh; with the bodies it identifies the contact
    /// from step to step (warm start).
    pub vertex: usize,
    /// Contact point: the penetrating vertex, world frame, m.
    pub point: Vector3<f64>,
    /// Contact frame; `frame.n` points from body 2 into body 1.
    pub frame: ContactFrame,
    /// Penetration depth, m, ≥ 0.
    pub depth: f64,
}
