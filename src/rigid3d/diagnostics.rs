//! Energy and momentum, per body and for the whole system. docs/dynamics.md §"Energy and momentum".
//!
//! Potential energy is measured from the world origin: U = −m g·x, so with g = (0, −9.8, 0) it is
//! m·9.8·y and is zero on the ground plane.

use crate::rigid3d::body::RigidBody;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Energies in J.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// ½ m v·v, J.
    pub kinetic_linear: f64,
    /// ½ ωᵀ J ω, J.
    pub kinetic_angular: f64,
    /// −m g·x, J.
    pub potential: f64,
    /// The sum of the three, J.
    pub total: f64,
}

/// Momenta in SI units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Momentum {
    /// p = Σ m v, kg·m/s.
    pub linear: Vector3<f64>,
    /// Angular momentum about the world origin, Σ (x × m v + J ω), kg·m²/s.
    pub angular: Vector3<f64>,
    /// Angular momentum about the centre of mass (of the body, or of the system),
    /// Σ ((x − c) × m v + J ω), kg·m²/s.
    pub angular_com: Vector3<f64>,
}

impl std::ops::Add for Energy {
    type Output = Energy;
    fn add(self, o: Energy) -> Energy {
        Energy {
            kinetic_linear: self.kinetic_linear + o.kinetic_linear,
            kinetic_angular: self.kinetic_angular + o.kinetic_angular,
            potential: self.potential + o.potential,
            total: self.total + o.total,
        }
    }
}

/// Energy of one body under gravity `gravity` (m/s²).
pub fn body_energy(body: &RigidBody, gravity: &Vector3<f64>) -> Energy {
    let kinetic_linear = 0.5 * body.mass * body.v.norm_squared();
    let kinetic_angular = 0.5 * body.omega.dot(&(body.inertia_world * body.omega));
    let potential = -body.mass * gravity.dot(&body.x);
    Energy {
        kinetic_linear,
        kinetic_angular,
        potential,
        total: kinetic_linear + kinetic_angular + potential,
    }
}

/// Momentum of one body; `angular_com` is about the body's own centre of mass (J ω).
pub fn body_momentum(body: &RigidBody) -> Momentum {
    let linear = body.v * body.mass;
    let spin = body.inertia_world * body.omega;
    Momentum {
        linear,
        angular: body.x.cross(&linear) + spin,
        angular_com: spin,
    }
}

/// Total energy of the system, J.
pub fn system_energy(bodies: &[RigidBody], gravity: &Vector3<f64>) -> Energy {
    bodies
        .iter()
        .map(|b| body_energy(b, gravity))
        .fold(Energy::default(), |a, e| a + e)
}

/// Total momentum; `angular_com` is about the system's centre of mass c = Σ m x / Σ m.
pub fn system_momentum(bodies: &[RigidBody]) -> Momentum {
    let total_mass: f64 = bodies.iter().map(|b| b.mass).sum();
    let com = if total_mass > 0.0 {
        bodies.iter().map(|b| b.x * b.mass).sum::<Vector3<f64>>() / total_mass
    } else {
        Vector3::zeros()
    };
    let mut total = Momentum::default();
    for body in bodies {
        let m = body_momentum(body);
        total.linear += m.linear;
        total.angular += m.angular;
        total.angular_com += (body.x - com).cross(&m.linear) + m.angular_com;
    }
    total
}

/// Times (s) at which a sampled signal changes sign, by linear interpolation between samples.
/// Used for the Dzhanibekov flip: the body-frame spin about the intermediate axis reverses sign
/// at each flip. docs/dynamics.md §"The Dzhanibekov flip period".
pub fn sign_changes(samples: &[(f64, f64)]) -> Vec<f64> {
    samples
        .windows(2)
        .filter(|w| (w[0].1 < 0.0) != (w[1].1 < 0.0))
        .map(|w| {
            let ((t0, y0), (t1, y1)) = (w[0], w[1]);
            t0 + (t1 - t0) * y0 / (y0 - y1)
        })
        .collect()
}

/// The flip period, s: the full period of the intermediate-axis spin (two flips, + → − → +),
/// estimated as twice the mean spacing of its sign changes. None with fewer than two changes.
pub fn flip_period(sign_change_times: &[f64]) -> Option<f64> {
    let n = sign_change_times.len();
    (n >= 2).then(|| 2.0 * (sign_change_times[n - 1] - sign_change_times[0]) / (n - 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid3d::mesh::TriMesh;
    use nalgebra::Matrix3;
    use std::sync::Arc;

    #[test]
    fn energy_and_momentum_of_one_body_by_hand() {
        let mesh = Arc::new(TriMesh::cuboid(Vector3::repeat(-0.5), Vector3::repeat(0.5)));
        let mut b = RigidBody::new(
            "b",
            2.0,
            Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)),
            mesh,
        );
        b.x = Vector3::new(1.0, 3.0, 0.0);
        b.v = Vector3::new(0.0, 0.0, 4.0);
        b.omega = Vector3::new(0.0, 1.0, 0.0);
        let g = Vector3::new(0.0, -9.8, 0.0);
        let e = body_energy(&b, &g);
        assert_eq!(e.kinetic_linear, 16.0);
        assert_eq!(e.kinetic_angular, 1.0);
        assert!((e.potential - 2.0 * 9.8 * 3.0).abs() < 1e-12);
        let p = body_momentum(&b);
        assert_eq!(p.linear, Vector3::new(0.0, 0.0, 8.0));
        // x × p = (1,3,0) × (0,0,8) = (24, −8, 0); plus J ω = (0, 2, 0).
        assert_eq!(p.angular, Vector3::new(24.0, -6.0, 0.0));
        let system = system_momentum(std::slice::from_ref(&b));
        assert_eq!(system.angular_com, Vector3::new(0.0, 2.0, 0.0));
    }

    #[test]
    fn flip_period_of_a_sine_is_its_period() {
        let samples: Vec<(f64, f64)> = (0..2000)
            .map(|i| {
                let t = i as f64 * 0.01;
                (t, (t * std::f64::consts::TAU / 3.0 + 0.1).sin())
            })
            .collect();
        let changes = sign_changes(&samples);
        assert_eq!(changes.len(), 13);
        // Linear interpolation of a sine sampled 300 times a period errs by ~1e-6 s at a zero.
        assert!((flip_period(&changes).unwrap() - 3.0).abs() < 1e-5);
    }
}
