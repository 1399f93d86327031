//! The contact frame, the contact Jacobian and the Delassus operator, checked against their
//! definitions (docs/contact.md §"Contact frame", §"Contact Jacobian", §"Delassus operator").

use crate::common;

use nalgebra::{Matrix3, SVector, Vector3};
use proptest::prelude::*;
use rigidref::problem::FrictionModel;
use rigidref::rigid3d::assemble::{ProblemSettings, assemble_problem};
use rigidref::rigid3d::collide::Contact;
use rigidref::rigid3d::contact::jacobian_block;
use rigidref::rigid3d::frame::ContactFrame;
use rigidref::rigid3d::rotation::exp_so3;
use rigidref::rigid3d::warm_start::WarmStart;

fn unit_vector() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_filter("not too short", |(x, y, z)| x * x + y * y + z * z > 1e-4)
        .prop_map(|(x, y, z)| Vector3::new(x, y, z).normalize())
}

fn vector(scale: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-scale..scale, -scale..scale, -scale..scale).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

fn rotation() -> impl Strategy<Value = Matrix3<f64>> {
    vector(3.0).prop_map(|w| exp_so3(&w))
}

/// The six signed world axes and the diagonals: the normals a frame construction with an
/// operator-precedence slip gets wrong.
fn special_normals() -> Vec<Vector3<f64>> {
    let mut normals = Vec::new();
    for k in 0..3 {
        for s in [1.0, -1.0] {
            let mut n = Vector3::zeros();
            n[k] = s;
            normals.push(n);
        }
    }
    for x in [1.0, -1.0] {
        for y in [1.0, -1.0] {
            for z in [1.0, -1.0] {
                normals.push(Vector3::new(x, y, z).normalize());
            }
        }
    }
    normals.push(Vector3::new(1.0, 1.0, 0.0).normalize());
    normals.push(Vector3::new(0.0, -1.0, 1e-9).normalize());
    normals
}

fn assert_frame(n: &Vector3<f64>) {
    let f = ContactFrame::from_normal(n);
    let m = Matrix3::from_columns(&[f.n, f.t1, f.t2]);
    // Orthonormal to round-off: a few ulps of 1.
    assert!(
        (m.transpose() * m - Matrix3::identity()).amax() < 1e-14,
        "frame for {n:?} is not orthonormal: {m}"
    );
    assert!(
        (m.determinant() - 1.0).abs() < 1e-14,
        "frame for {n:?} is not right-handed"
    );
    assert_eq!(f.n, *n);
}

#[test]
fn contact_frame_is_orthonormal_and_right_handed_for_every_normal() {
    for n in special_normals() {
        assert_frame(&n);
    }
    // The ground's frame is (y, −z, −x): docs/contact.md §"Contact frame".
    let ground = ContactFrame::from_normal(&Vector3::y());
    assert_eq!(ground.t1, -Vector3::z());
    assert_eq!(ground.t2, -Vector3::x());
    proptest!(common::seeded(2000), |(n in unit_vector())| {
        assert_frame(&n);
    });
}

/// The separation s(t) = p₁(t) − p₂(t) of the material points of body 1 and body 2 that coincide
/// with p at t = 0, each body moving with constant v and ω: x(t) = x + t v, R(t) = exp(t[ω]) R.
fn separation(
    t: f64,
    p: &Vector3<f64>,
    bodies: &[(Vector3<f64>, Vector3<f64>, Vector3<f64>); 2],
) -> Vector3<f64> {
    let point = |(x, v, w): &(Vector3<f64>, Vector3<f64>, Vector3<f64>)| {
        x + t * v + exp_so3(&(w * t)) * (p - x)
    };
    point(&bodies[0]) - point(&bodies[1])
}

#[test]
fn jacobian_rows_are_the_time_derivative_of_the_separation() {
    proptest!(common::seeded(500), |(
        n in unit_vector(),
        p in vector(2.0),
        x1 in vector(2.0), v1 in vector(3.0), w1 in vector(5.0),
        x2 in vector(2.0), v2 in vector(3.0), w2 in vector(5.0),
    )| {
        let frame = ContactFrame::from_normal(&n);
        let j1 = jacobian_block(&frame, &(p - x1));
        let j2 = -jacobian_block(&frame, &(p - x2));
        let u1 = SVector::<f64, 6>::from_iterator(v1.iter().chain(w1.iter()).copied());
        let u2 = SVector::<f64, 6>::from_iterator(v2.iter().chain(w2.iter()).copied());
        let ju = j1 * u1 + j2 * u2;
        // Central difference: truncation error ~ ε² |ω|³ |r| ≈ 1e-10, round-off ~ 1e-16/ε ≈
        // 1e-10, both far below the 1e-6 relative the issue asks for.
        let eps = 1e-6;
        let bodies = [(x1, v1, w1), (x2, v2, w2)];
        let ds = (separation(eps, &p, &bodies) - separation(-eps, &p, &bodies)) / (2.0 * eps);
        let scale = ds.norm().max(ju.norm()).max(1e-3);
        for (row, d) in [frame.n, frame.t1, frame.t2].iter().enumerate() {
            let fd = d.dot(&ds);
            prop_assert!((ju[row] - fd).abs() <= 1e-6 * scale,
                "row {row}: J u = {}, finite difference {fd}", ju[row]);
        }
    });
}

#[test]
fn delassus_block_is_symmetric_psd_and_equals_the_dense_product() {
    proptest!(common::seeded(300), |(
        masses in proptest::collection::vec(0.1..1000.0f64, 3),
        moments in proptest::collection::vec((0.01..100.0f64, 0.01..100.0f64, 0.01..100.0f64), 3),
        frames in proptest::collection::vec(rotation(), 3),
        positions in proptest::collection::vec(vector(2.0), 3),
        contact_data in proptest::collection::vec((0usize..3, 0usize..4, vector(2.0), unit_vector(), 0.0..0.1f64), 1..8),
    )| {
        let bodies: Vec<_> = (0..3).map(|i| {
            let (a, b, c) = moments[i];
            // Principal moments must satisfy the triangle inequality to be a body's; sort and
            // lift the largest below the sum of the others.
            let mut m = [a, b, c];
            m.sort_by(f64::total_cmp);
            m[2] = m[2].min(0.99 * (m[0] + m[1]));
            let mut body = common::body(masses[i], m, frames[i]);
            body.x = positions[i];
            body.rotation = frames[i];
            body.update_world_inertia();
            body
        }).collect();
        let contacts: Vec<Contact> = contact_data.iter().map(|&(b1, b2, p, n, depth)| {
            // b2 == 3 or b2 == b1 is the ground.
            let body2 = if b2 < 3 && b2 != b1 { Some(b2) } else { None };
            Contact { body1: b1, body2, feature: rigidref::rigid3d::collide::Feature::Vertex(0), point: p, frame: ContactFrame::from_normal(&n), depth }
        }).collect();
        let settings = ProblemSettings { h: 0.01, mu: 0.5, friction: FrictionModel::Box, compliance: 0.0, stabilization: 0.2, slop: 0.0, max_push_speed: f64::INFINITY, };
        let problem = assemble_problem(&bodies, &contacts, &settings, &WarmStart::new(false));
        let dense = problem.dense_delassus();
        let scale = dense.amax();
        for k in 0..problem.contacts.len() {
            let block = problem.delassus_block(k);
            let from_dense = dense.view((3 * k, 3 * k), (3, 3));
            prop_assert!((block - from_dense).amax() <= 1e-12 * scale,
                "contact {k}: block {block} differs from the dense {from_dense}");
            prop_assert!((block - block.transpose()).amax() <= 1e-14 * scale);
            let eigenvalues = block.symmetric_eigenvalues();
            prop_assert!(eigenvalues.min() >= -1e-12 * scale, "eigenvalues {eigenvalues}");
        }
        // The whole operator too: symmetric and positive semidefinite.
        prop_assert!((&dense - dense.transpose()).amax() <= 1e-12 * scale);
        let eigenvalues = dense.clone().symmetric_eigenvalues();
        prop_assert!(eigenvalues.min() >= -1e-10 * scale, "eigenvalues {eigenvalues}");
    });
}
