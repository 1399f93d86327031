//! Benchmark: the cost of one free-body step under each angular integrator, measured side by
//! side in one run (docs/dynamics.md §"Conservative rotation", the table of schemes).
//!
//!     cargo bench --bench integrators
//!
//! Prints ns per step (velocity half + position half, no forces) for the fast-spin body of
//! scenes/fast_spin.json at h = 0.01 s (h|ω| = 0.078) and at h = 0.1 s (h|ω| = 0.78, where the
//! implicit schemes need more Newton iterations), and each scheme's cost relative to `spatial`.
//! Ratios, not absolute times, are the result: the machine is shared.

use nalgebra::{Matrix3, Vector3};
use rigidref::rigid3d::body::{AngularIntegrator, RigidBody};
use rigidref::rigid3d::mesh::TriMesh;
use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

const SCHEMES: [AngularIntegrator; 4] = [
    AngularIntegrator::Spatial,
    AngularIntegrator::Body,
    AngularIntegrator::ImplicitGyroscopic,
    AngularIntegrator::Conservative,
];

fn main() {
    let mesh = Arc::new(TriMesh::cuboid(Vector3::repeat(-0.5), Vector3::repeat(0.5)));
    let inertia = Matrix3::from_diagonal(&Vector3::new(11.925, 10.125, 3.825));
    let rounds = 9;
    let reps = 200_000;
    println!(
        "{:>20} {:>14} {:>8} {:>14} {:>8}",
        "scheme", "ns/step h=0.01", "ratio", "ns/step h=0.1", "ratio"
    );
    let mut base = [0.0; 2];
    // Rounds interleave the schemes, so a slow patch of the shared machine hits them all.
    let mut times = vec![[Vec::new(), Vec::new()]; SCHEMES.len()];
    for _ in 0..rounds {
        for (k, &scheme) in SCHEMES.iter().enumerate() {
            for (j, h) in [0.01, 0.1].into_iter().enumerate() {
                let mut body = RigidBody::new("fast_spin", 135.0, inertia, mesh.clone());
                body.omega = Vector3::new(4.0, 3.0, 6.0);
                let start = Instant::now();
                for _ in 0..reps {
                    body.zero_forces();
                    body.step_velocity(black_box(h), scheme);
                    body.step_position(black_box(h), scheme);
                    // Keep the spin bounded for the explicit schemes (their energy grows).
                    if body.omega.norm() > 100.0 {
                        body.omega = Vector3::new(4.0, 3.0, 6.0);
                    }
                }
                black_box(&body);
                times[k][j].push(start.elapsed().as_secs_f64() * 1e9 / reps as f64);
            }
        }
    }
    for (k, scheme) in SCHEMES.iter().enumerate() {
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let t = [median(&mut times[k][0]), median(&mut times[k][1])];
        if k == 0 {
            base = t;
        }
        println!(
            "{:>20} {:>14.1} {:>8.2} {:>14.1} {:>8.2}",
            scheme.name(),
            t[0],
            t[0] / base[0],
            t[1],
            t[1] / base[1]
        );
    }
}
