//! Analytic shapes a body may carry beside its mesh: the ellipsoid (the rattleback's smooth
//! bottom). Pure geometry, below the body ([`crate::rigid3d::body::RigidBody::ellipsoid`]) and
//! the detection that uses it ([`crate::rigid3d::collide::ellipsoid`]). docs/contact.md
//! §"Ellipsoid contact".

use nalgebra::Vector3;

/// An ellipsoid fixed in a body: centre and semi-axes along the body frame's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Centre in the body frame (relative to the centre of mass), m.
    pub centre: Vector3<f64>,
    /// Semi-axes (a, b, c) along the body x, y, z axes, m, > 0.
    pub semi_axes: Vector3<f64>,
}

impl Ellipsoid {
    /// The body-frame surface point farthest along the body-frame direction `u` (‖u‖ > 0): with
    /// A = diag(a, b, c), c + A² u / ‖A u‖ (maximising u·q over qᵀA⁻²q = 1 by a Lagrange
    /// multiplier).
    pub fn support(&self, u: &Vector3<f64>) -> Vector3<f64> {
        let a = self.semi_axes;
        let au = a.component_mul(u);
        self.centre + a.component_mul(&au) / au.norm()
    }

    /// For a body-frame point `p` strictly inside: its depth (the distance to the nearest surface
    /// point q, m) and the outward unit normal at q. `None` outside or at the centre.
    /// docs/contact.md §"Ellipsoid contact".
    ///
    /// With y = p − c, the nearest point minimises ‖x − y‖² over Σ (x_k/a_k)² = 1 (x = q − c); a
    /// Lagrange multiplier t gives x_k = a_k² y_k / (a_k² + t), and for an inside point t is the
    /// root in (−a_min², 0) of F(t) = Σ (a_k y_k / (a_k² + t))² − 1, which decreases in t there
    /// (found by bisection). Then q − p = −t A⁻²x lies along the outward normal, so the depth is
    /// ‖q − p‖ and the normal is A⁻²x normalised. When y has no component along the smallest
    /// axes and F stays below 0 on the whole interval, the nearest points lie on the ridge
    /// t = −a_min²: the other components as above, the rest of the unit norm along a smallest axis.
    pub fn inside(&self, p: &Vector3<f64>) -> Option<(f64, Vector3<f64>)> {
        let y = p - self.centre;
        let a = self.semi_axes;
        let f = y.component_div(&a).norm_squared();
        if f >= 1.0 || f == 0.0 || f.is_nan() {
            return None;
        }
        let a2 = a.component_mul(&a);
        let a_min2 = a2.min();
        let smallest = |k: usize| a2[k] == a_min2;
        let at = |t: f64| Vector3::from_fn(|k, _| a2[k] * y[k] / (a2[k] + t));
        let excess = |t: f64| at(t).component_div(&a).norm_squared() - 1.0;
        let unbounded = (0..3).any(|k| smallest(k) && y[k] != 0.0);
        let x = if !unbounded && {
            // On the ridge t = −a_min²: the terms of the smallest axes vanish (y_k = 0 there).
            let ridge = Vector3::from_fn(|k, _| {
                if smallest(k) {
                    0.0
                } else {
                    a2[k] * y[k] / (a2[k] - a_min2)
                }
            });
            ridge.component_div(&a).norm_squared() < 1.0
        } {
            let mut x = Vector3::from_fn(|k, _| {
                if smallest(k) {
                    0.0
                } else {
                    a2[k] * y[k] / (a2[k] - a_min2)
                }
            });
            let rest = 1.0 - x.component_div(&a).norm_squared();
            let k = (0..3).find(|&k| smallest(k)).unwrap_or(0);
            x[k] = a[k] * rest.sqrt();
            x
        } else {
            let (mut lo, mut hi) = (-a_min2, 0.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if excess(mid) > 0.0 {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            at(0.5 * (lo + hi))
        };
        let n = x.component_div(&a2).normalize();
        Some(((x - y).norm(), n))
    }
}
