//! Rotation matrices: the skew-symmetric cross-product matrix, the exponential map used by the
//! position update, and the checks and projections that keep `R` a rotation.
//!
//! Derivation: docs/dynamics.md §"Rotation update".

use nalgebra::{Matrix3, Vector3};

/// The cross-product matrix `[a]×`, so that `skew(a) * b == a.cross(&b)`.
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// The rotation `exp([θ]×)` for a rotation vector `θ` (radians), by Rodrigues' formula.
///
/// Near θ = 0 the coefficients sin|θ|/|θ| and (1 − cos|θ|)/|θ|² are taken from their Taylor
/// series, so that a tiny rotation is still exact to round-off rather than 0/0.
/// docs/dynamics.md §"Rotation update".
pub fn exp_so3(theta: &Vector3<f64>) -> Matrix3<f64> {
    let angle_sq = theta.norm_squared();
    let (a, b) = if angle_sq < 1e-8 {
        // sin x / x = 1 − x²/6 + x⁴/120 − …, (1 − cos x)/x² = 1/2 − x²/24 + x⁴/720 − …; for
        // x² < 1e-8 the x⁴ terms (below 1e-18) are under half an ulp of a ≈ 1 and b ≈ ½, so
        // adding them could not change a bit of either: two terms are exact in f64.
        (1.0 - angle_sq / 6.0, 0.5 - angle_sq / 24.0)
    } else {
        let angle = angle_sq.sqrt();
        (angle.sin() / angle, (1.0 - angle.cos()) / angle_sq)
    };
    let k = skew(theta);
    Matrix3::identity() + k * a + k * k * b
}

/// One step of the Newton–Schulz iteration (Björck and Bowie's first-order orthogonalisation)
/// towards the nearest rotation: `R ← R (3I − RᵀR) / 2`. It removes the first-order part of the orthonormality error, so a
/// matrix that is orthonormal to ε comes back orthonormal to O(ε²) — applied every step it holds
/// `RᵀR = I` at round-off level indefinitely. docs/dynamics.md §"Rotation update".
pub fn reorthonormalize(r: &Matrix3<f64>) -> Matrix3<f64> {
    r * (Matrix3::identity() * 3.0 - r.transpose() * r) * 0.5
}

/// `‖RᵀR − I‖` in the Frobenius norm: how far `R` is from orthonormal.
pub fn orthonormality_error(r: &Matrix3<f64>) -> f64 {
    (r.transpose() * r - Matrix3::identity()).norm()
}

/// The nearest rotation to a matrix that is already close to one (within about 1e-3), by
/// iterating [`reorthonormalize`] until it stops improving. Used once on the scene's `R0`.
pub fn nearest_rotation(r: &Matrix3<f64>) -> Matrix3<f64> {
    let mut q = *r;
    for _ in 0..8 {
        q = reorthonormalize(&q);
        if orthonormality_error(&q) < 1e-15 {
            break;
        }
    }
    q
}
