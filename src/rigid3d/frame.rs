//! The contact frame: a unit normal and two tangents, pure geometry shared by detection (which
//! finds each contact's normal) and assembly (which builds the Jacobian rows from it).
//! docs/contact.md §"Contact frame".
//!
//! Sign convention: the normal n points from body 2 into body 1 (docs/contact.md, and
//! [`crate::rigid3d::contact`]'s module documentation).

use nalgebra::{Matrix3, Vector3};

/// How a contact's tangents are made from its normal (the scene's `tangents`).
/// docs/contact.md §"Contact frame".
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
pub enum Tangents {
    /// Unit tangents: [`ContactFrame::from_normal`] (default).
    #[default]
    Orthonormal,
    /// The 3D Python starter's (`contact.py`): [`ContactFrame::starter`], not normalised.
    Starter,
}

impl Tangents {
    /// The scene-file value.
    pub fn name(self) -> &'static str {
        match self {
            Tangents::Orthonormal => "orthonormal",
            Tangents::Starter => "starter",
        }
    }

    /// The frame for a unit normal `n` by this rule.
    pub fn frame(self, n: &Vector3<f64>) -> ContactFrame {
        match self {
            Tangents::Orthonormal => ContactFrame::from_normal(n),
            Tangents::Starter => ContactFrame::starter(n),
        }
    }
}

/// A right-handed contact frame: t2 = n × t1, so det[n t1 t2] > 0; orthonormal except with the
/// starter's tangents ([`ContactFrame::starter`]), which are orthogonal but not of unit length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFrame {
    /// Unit normal, from body 2 into body 1.
    pub n: Vector3<f64>,
    /// First tangent (unit, except with the starter's tangents).
    pub t1: Vector3<f64>,
    /// Second tangent, n × t1.
    pub t2: Vector3<f64>,
}

impl ContactFrame {
    /// The frame for a unit normal `n`. t1 is n crossed with the world axis least aligned with n,
    /// normalised, so |n × e| ≥ √(2/3) and the construction never divides by a small number; for
    /// the ground normal +y this gives t1 = −z, t2 = −x. docs/contact.md §"Contact frame".
    /// (The starter's version has an operator-precedence slip in its axis choice; this one picks
    /// the axis by comparing absolute components explicitly.)
    pub fn from_normal(n: &Vector3<f64>) -> ContactFrame {
        let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
        let axis = if ax <= ay && ax <= az {
            Vector3::x()
        } else if ay <= az {
            Vector3::y()
        } else {
            Vector3::z()
        };
        let t1 = n.cross(&axis).normalize();
        let t2 = n.cross(&t1);
        ContactFrame { n: *n, t1, t2 }
    }

    /// The 3D Python starter's frame, as its `contact.py` builds it from the normal, to the bit:
    /// an axis e is chosen, t2 = n × e and t1 = t2 × n, not normalised (both of length |n × e|,
    /// so friction rows scaled by it and box bounds ±μλn on the scaled rows). Its axis test is
    /// `abs(n[0]) < abs(n[1] and abs(n[0]) < abs(n[2]))`, where Python's `and` yields n[1]
    /// when n[1] is 0 and otherwise the truth of |n₀| < |n₂| (as 1 or 0): so e = x when n₁ ≠ 0,
    /// |n₀| < |n₂| and |n₀| < 1; else e = y when |n₁| < |n₂|; else e = z. For the ground's
    /// normal +y this gives t1 = z, t2 = x; for axis-aligned normals the tangents are unit.
    /// docs/contact.md §"Contact frame".
    pub fn starter(n: &Vector3<f64>) -> ContactFrame {
        let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
        // `n[1] and …` is falsy (n[1] itself, 0) only when n[1] == 0 (±0; NaN is truthy).
        let inner = if n.y == 0.0 {
            0.0
        } else if ax < az {
            1.0
        } else {
            0.0
        };
        let axis = if ax < inner {
            Vector3::x()
        } else if ay < az {
            Vector3::y()
        } else {
            Vector3::z()
        };
        let t2 = n.cross(&axis);
        let t1 = t2.cross(n);
        ContactFrame { n: *n, t1, t2 }
    }

    /// The rows n, t1, t2 as a matrix.
    pub fn rows(&self) -> Matrix3<f64> {
        Matrix3::from_rows(&[self.n.transpose(), self.t1.transpose(), self.t2.transpose()])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The starter's axis choice, slip and all: each case is what `contact.py`'s expression
    /// gives (python/tests/test_starter3d.py evaluates the expression itself).
    #[test]
    fn the_starter_frame_follows_contact_py_including_its_precedence_slip() {
        let ground = ContactFrame::starter(&Vector3::y());
        assert_eq!((ground.t1, ground.t2), (Vector3::z(), Vector3::x()));
        // n₁ = 0: the first test is false whatever n₀ and n₂ are; then |n₁| < |n₂| picks y.
        let side = ContactFrame::starter(&Vector3::new(0.0, 0.0, 1.0));
        assert_eq!(side.t2, Vector3::new(0.0, 0.0, 1.0).cross(&Vector3::y()));
        // n₁ ≠ 0, |n₀| < |n₂|: e = x.
        let n = Vector3::new(0.1, 0.5, 0.86).normalize();
        let f = ContactFrame::starter(&n);
        assert_eq!(f.t2, n.cross(&Vector3::x()));
        assert_eq!(f.t1, f.t2.cross(&n));
        // Not unit: |t1| = |t2| = |n × x| < 1; orthogonal to n and to each other.
        assert!((f.t2.norm() - n.cross(&Vector3::x()).norm()).abs() < 1e-15);
        assert!(f.t2.norm() < 0.999);
        assert!(
            f.t1.dot(&n).abs() < 1e-15
                && f.t2.dot(&n).abs() < 1e-15
                && f.t1.dot(&f.t2).abs() < 1e-15
        );
        assert!((n.cross(&f.t1) - f.t2).norm() < 1e-15);
        // n₁ ≠ 0, |n₀| ≥ |n₂|: the first test compares |n₀| < 0 (false); then |n₁| < |n₂|.
        // The slip: the starter never asks whether |n₀| < |n₁|, so for (0.3, 0.1, 0.9) it picks
        // x where the intended test (|n₀| least) picks y.
        let n = Vector3::new(0.3, 0.1, 0.9).normalize();
        assert_eq!(ContactFrame::starter(&n).t2, n.cross(&Vector3::x()));
        let n = Vector3::new(0.8, 0.2, 0.3).normalize();
        assert_eq!(ContactFrame::starter(&n).t2, n.cross(&Vector3::y()));
        let n = Vector3::new(0.8, 0.4, 0.3).normalize();
        assert_eq!(ContactFrame::starter(&n).t2, n.cross(&Vector3::z()));
    }
}
