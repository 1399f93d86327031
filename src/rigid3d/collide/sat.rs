//! The brute-force oracle of the penetration measure: the penetration depth of two convex pieces
//! by the separating axis theorem, trying every candidate axis. docs/contact.md §"Penetration
//! measure".
//!
//! Two convex polyhedra overlap exactly when their projections overlap on every face normal of
//! either and every cross product of an edge of one with an edge of the other; the smallest
//! overlap among those axes is the distance one must move to separate them (the minimum
//! translation distance). O(edges₁ · edges₂ · vertices) per pair: slow, plain, for tests.

use super::pieces::{Piece, pose, world_point, world_vector};
use crate::rigid3d::body::RigidBody;
use nalgebra::Vector3;

/// A piece placed in the world: its vertices, face normals and edge directions.
struct Placed {
    vertices: Vec<Vector3<f64>>,
    normals: Vec<Vector3<f64>>,
    edges: Vec<Vector3<f64>>,
}

fn place(piece: &Piece, body: &RigidBody) -> Placed {
    let p = pose(body);
    let to_parry = |v: &Vector3<f64>| parry3d_f64::math::Vector::new(v.x, v.y, v.z);
    let vertices: Vec<Vector3<f64>> = piece
        .vertices
        .iter()
        .map(|v| world_point(&p, to_parry(v)))
        .collect();
    Placed {
        normals: piece
            .normals
            .iter()
            .map(|n| world_vector(&p, to_parry(n)))
            .collect(),
        edges: piece
            .edges
            .iter()
            .map(|[a, b]| vertices[*b] - vertices[*a])
            .collect(),
        vertices,
    }
}

fn extent(points: &[Vector3<f64>], axis: &Vector3<f64>) -> (f64, f64) {
    points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let s = p.dot(axis);
            (lo.min(s), hi.max(s))
        })
}

/// The penetration depth of piece `a` of `body_a` and piece `b` of `body_b`, m: the smallest
/// overlap of their projections over every candidate axis, 0 when some axis separates them.
pub fn sat_depth(a: &Piece, body_a: &RigidBody, b: &Piece, body_b: &RigidBody) -> f64 {
    let (a, b) = (place(a, body_a), place(b, body_b));
    let mut axes: Vec<Vector3<f64>> = a.normals.iter().chain(&b.normals).copied().collect();
    for ea in &a.edges {
        for eb in &b.edges {
            let c = ea.cross(eb);
            // Parallel edges give no new axis (their cross product is round-off).
            if c.norm() > 1e-9 * ea.norm() * eb.norm() {
                axes.push(c.normalize());
            }
        }
    }
    let mut depth = f64::INFINITY;
    for axis in &axes {
        let (a_lo, a_hi) = extent(&a.vertices, axis);
        let (b_lo, b_hi) = extent(&b.vertices, axis);
        let overlap = (a_hi - b_lo).min(b_hi - a_lo);
        if overlap <= 0.0 {
            return 0.0;
        }
        depth = depth.min(overlap);
    }
    depth
}
