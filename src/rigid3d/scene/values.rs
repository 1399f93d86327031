//! Validated values of the 3D scene and body files (vectors, orientations, inertia, the
//! starter's damping key). Like [`crate::common::values`], each checks itself while it is read.

use nalgebra::{Matrix3, Vector3};
use serde::de::Error;
use serde::{Deserialize, Deserializer};

/// A finite 3-vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3(pub Vector3<f64>);

impl<'de> Deserialize<'de> for Vec3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let a = <[f64; 3]>::deserialize(d)?;
        if a.iter().any(|c| !c.is_finite()) {
            return Err(D::Error::custom("vector components must be finite"));
        }
        Ok(Vec3(Vector3::from(a)))
    }
}

/// A finite 3×3 matrix given as a list of three rows.
fn matrix3<'de, D: Deserializer<'de>>(d: D) -> Result<Matrix3<f64>, D::Error> {
    let rows = <[[f64; 3]; 3]>::deserialize(d)?;
    if rows.iter().flatten().any(|c| !c.is_finite()) {
        return Err(D::Error::custom("matrix entries must be finite"));
    }
    Ok(Matrix3::from_fn(|i, j| rows[i][j]))
}

/// The starter's `damping` key. The assignment defines no damping model, so only 0 is accepted:
/// ignoring any other value would silently change the physics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZeroDamping;

impl<'de> Deserialize<'de> for ZeroDamping {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if x != 0.0 {
            return Err(D::Error::custom(format!(
                "damping {x} is not supported: the assignment defines no damping model (only 0 is accepted)"
            )));
        }
        Ok(ZeroDamping)
    }
}

/// An orthonormal matrix (‖RᵀR − I‖ ≤ [`Orientation::TOLERANCE`]) with determinant +1 (a rotation)
/// or −1 (a reflection; the assignment's scene2, scene5 and scene6 use one, see
/// docs/scene-format.md §"R0 and reflections"). The matrix is projected to exact orthonormality.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orientation {
    /// The orthonormal matrix.
    pub matrix: Matrix3<f64>,
    /// True when det = +1.
    pub proper: bool,
}

impl Orientation {
    /// How far from orthonormal a scene's `R0` may be (‖RᵀR − I‖_F, and |det| − 1).
    pub const TOLERANCE: f64 = 1e-6;
}

impl<'de> Deserialize<'de> for Orientation {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let r = matrix3(d)?;
        let err = crate::rigid3d::rotation::orthonormality_error(&r);
        if err > Orientation::TOLERANCE {
            return Err(D::Error::custom(format!(
                "not a rotation: ‖RᵀR − I‖ = {err:.3e} (at most {:e} allowed)",
                Orientation::TOLERANCE
            )));
        }
        let det = r.determinant();
        if (det.abs() - 1.0).abs() > Orientation::TOLERANCE {
            return Err(D::Error::custom(format!("not a rotation: det = {det}")));
        }
        Ok(Orientation {
            matrix: crate::rigid3d::rotation::nearest_rotation(&r),
            proper: det > 0.0,
        })
    }
}

/// A symmetric positive definite inertia matrix, kg·m².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia(pub Matrix3<f64>);

impl Inertia {
    /// Relative asymmetry |Jij − Jji| / max|J| allowed; body files written with 16 digits are
    /// symmetric to ~1e-16.
    pub const SYMMETRY_TOLERANCE: f64 = 1e-9;
}

impl<'de> Deserialize<'de> for Inertia {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let j = matrix3(d)?;
        check_inertia(&j).map_err(D::Error::custom)?;
        Ok(Inertia((j + j.transpose()) * 0.5))
    }
}

/// Checks that `j` is symmetric and positive definite; the error says which and by how much.
pub fn check_inertia(j: &Matrix3<f64>) -> Result<(), String> {
    let scale = j.amax();
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        if (j[(a, b)] - j[(b, a)]).abs() > Inertia::SYMMETRY_TOLERANCE * scale {
            return Err(format!(
                "not symmetric: J[{a}][{b}] = {} but J[{b}][{a}] = {}",
                j[(a, b)],
                j[(b, a)]
            ));
        }
    }
    let eigen = ((j + j.transpose()) * 0.5).symmetric_eigenvalues();
    let min = eigen.min();
    if min.is_nan() || min <= 1e-12 * scale {
        return Err(format!(
            "not positive definite: principal moments {:.6e}, {:.6e}, {:.6e}",
            eigen[0], eigen[1], eigen[2]
        ));
    }
    Ok(())
}
