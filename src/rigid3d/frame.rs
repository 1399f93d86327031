//! The contact frame: a unit normal and two tangents, pure geometry shared by detection (which
//! finds each contact's normal) and assembly (which builds the Jacobian rows from it).
//! docs/contact.md §"Contact frame".
//!
//! Sign convention: the normal n points from body 2 into body 1 (docs/contact.md, and
//! [`crate::rigid3d::contact`]'s module documentation).

use nalgebra::{Matrix3, Vector3};

/// An orthonormal, right-handed contact frame: t2 = n × t1, so det[n t1 t2] = +1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFrame {
    /// Unit normal, from body 2 into body 1.
    pub n: Vector3<f64>,
    /// First unit tangent.
    pub t1: Vector3<f64>,
    /// Second unit tangent, n × t1.
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

    /// The rows n, t1, t2 as a matrix.
    pub fn rows(&self) -> Matrix3<f64> {
        Matrix3::from_rows(&[self.n.transpose(), self.t1.transpose(), self.t2.transpose()])
    }
}
