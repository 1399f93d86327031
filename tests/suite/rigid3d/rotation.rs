//! Rotations (src/rigid3d/rotation.rs; docs/dynamics.md §"Rotation update"): the exponential map
//! near and far from zero, and the projections that keep R a rotation.

use nalgebra::{Matrix3, Unit, Vector3};
use rigidref::rigid3d::rotation::{
    exp_so3, nearest_rotation, orthonormality_error, reorthonormalize,
};

#[test]
fn exp_so3_matches_axis_angle_and_is_continuous_at_the_series_switch() {
    let axis = Vector3::new(1.0, 2.0, -0.5).normalize();
    for &angle in &[0.0, 1e-9, 0.99e-4, 1.01e-4, 0.3, 2.0, 3.1] {
        let expected = nalgebra::Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle);
        let got = exp_so3(&(axis * angle));
        // Both are computed in f64 from the same axis and angle; 1e-15 allows a few ulps.
        assert!((got - expected.matrix()).norm() < 1e-15, "angle {angle}");
    }
}

#[test]
fn exp_so3_of_a_tiny_rotation_is_exact_to_a_few_ulps_in_every_entry() {
    // Below |θ|² = 1e-8 the coefficients a = sin x / x and b = (1 − cos x)/x² come from their
    // Taylor series. Each entry of R = I + a[θ]× + b[θ]×² must be right to a few ulps of its own
    // size, not merely of 1: an off-diagonal entry is about |θ| (1e-4 here), and b's error shows
    // in it at 1e-16, far below 1e-15 absolute. The reference evaluates the same formula with
    // a = sin x / x and b = 2 sin²(x/2)/x², both accurate to an ulp at small x (no cancellation).
    for &angle in &[1e-9, 3e-7, 2e-5, 0.99e-4] {
        for axis in [
            Vector3::new(1.0, 2.0, -0.5),
            Vector3::new(-0.3, 0.1, 0.9),
            Vector3::new(0.0, 0.0, 1.0),
        ] {
            let theta: Vector3<f64> = axis.normalize() * angle;
            let x: f64 = theta.norm();
            let (a, b) = (x.sin() / x, 2.0 * (x / 2.0).sin().powi(2) / (x * x));
            let k = rigidref::rigid3d::rotation::skew(&theta);
            let expected = Matrix3::identity() + k * a + k * k * b;
            let got = exp_so3(&theta);
            for (g, e) in got.iter().zip(expected.iter()) {
                // 4 ulps of the entry (and of 1e-300 for an exact zero).
                assert!(
                    (g - e).abs() <= 4.0 * f64::EPSILON * e.abs().max(1e-300),
                    "angle {angle}: {g:e} against {e:e}"
                );
            }
        }
    }
}

#[test]
fn reorthonormalize_squares_the_error() {
    let mut r = exp_so3(&Vector3::new(0.3, -0.2, 0.9));
    r[(0, 1)] += 1e-6;
    let before = orthonormality_error(&r);
    let after = orthonormality_error(&reorthonormalize(&r));
    assert!(before > 5e-7);
    assert!(after < 1e-11, "after {after}");
}

#[test]
fn orthonormality_error_is_the_frobenius_norm_of_rt_r_minus_i() {
    // For s R with R a rotation, RᵀR − I = (s² − 1) I, whose Frobenius norm is √3 |s² − 1|.
    let r = exp_so3(&Vector3::new(0.7, 0.1, -0.4));
    assert!(orthonormality_error(&r) < 1e-15);
    let s: f64 = 1.001;
    let expected = 3f64.sqrt() * (s * s - 1.0);
    assert!((orthonormality_error(&(r * s)) - expected).abs() < 1e-12 * expected);
}

#[test]
fn nearest_rotation_makes_a_nearly_orthonormal_r0_a_rotation_to_round_off() {
    // A scene's R0 written with a few digits is off by up to ~1e-3; the projection (iterated
    // Newton–Schulz) must return a rotation to round-off (1e-15), near the input (to the size of
    // the perturbation), with determinant +1.
    let r = exp_so3(&Vector3::new(-0.2, 1.3, 0.5));
    for (i, j, e) in [(0, 0, 1e-3), (1, 2, -7e-4), (2, 1, 3e-4), (0, 2, 1e-6)] {
        let mut m = r;
        m[(i, j)] += e;
        let q = nearest_rotation(&m);
        assert!(
            orthonormality_error(&q) < 1e-15,
            "error {}",
            orthonormality_error(&q)
        );
        assert!((q.determinant() - 1.0).abs() < 1e-15);
        assert!(
            (q - r).norm() < 2.0 * e.abs(),
            "moved {} for a perturbation of {e}",
            (q - r).norm()
        );
    }
}
