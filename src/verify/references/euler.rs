//! A high-accuracy solution of the torque-free Euler equations, J₀ ω̇ = −ω × J₀ω in the body
//! frame, by classical fourth-order Runge–Kutta. It shares no code with the simulator's
//! integrators; its error is O(h⁴), so with a small step it is a reference for the simulator's
//! first-order schemes. docs/dynamics.md §"The Dzhanibekov flip period".

use nalgebra::{Matrix3, Vector3};

/// Body-frame angular acceleration of a torque-free body, rad/s².
fn angular_acceleration(
    inertia: &Matrix3<f64>,
    inertia_inv: &Matrix3<f64>,
    omega: &Vector3<f64>,
) -> Vector3<f64> {
    -(inertia_inv * omega.cross(&(inertia * omega)))
}

/// Integrates from `omega0` (body frame, rad/s) for `steps` steps of `h` seconds and returns the
/// samples (t, ω_b) including t = 0. `inertia` must be invertible.
pub fn torque_free_rk4(
    inertia: &Matrix3<f64>,
    omega0: &Vector3<f64>,
    h: f64,
    steps: usize,
) -> Vec<(f64, Vector3<f64>)> {
    let inertia_inv = inertia.try_inverse().unwrap_or_else(Matrix3::zeros);
    let f = |w: &Vector3<f64>| angular_acceleration(inertia, &inertia_inv, w);
    let mut omega = *omega0;
    let mut samples = Vec::with_capacity(steps + 1);
    samples.push((0.0, omega));
    for k in 1..=steps {
        let k1 = f(&omega);
        let k2 = f(&(omega + k1 * (h / 2.0)));
        let k3 = f(&(omega + k2 * (h / 2.0)));
        let k4 = f(&(omega + k3 * h));
        omega += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        samples.push((k as f64 * h, omega));
    }
    samples
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk4_conserves_energy_and_momentum_magnitude_to_high_order() {
        let inertia = Matrix3::from_diagonal(&Vector3::new(13.17, 81.67, 87.09));
        let samples = torque_free_rk4(&inertia, &Vector3::new(0.0, 5.0, 0.01), 1e-4, 100_000);
        let energy = |w: &Vector3<f64>| 0.5 * w.dot(&(inertia * w));
        let (_, first) = samples[0];
        let (_, last) = samples[samples.len() - 1];
        // RK4 with h|ω| = 5e-4 has a per-step error ~ (5e-4)⁵; over 1e5 steps that is ~1e-12.
        assert!((energy(&last) / energy(&first) - 1.0).abs() < 1e-10);
        assert!(((inertia * last).norm() / (inertia * first).norm() - 1.0).abs() < 1e-10);
    }
}
