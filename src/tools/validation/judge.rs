//! What each observable should be: its closed form (or exact statement) for the scene, the
//! tolerance a run is judged by, and why that tolerance (docs/validation.md §"Observables"). Every
//! run, rigidref's own included, is judged by the same code.

use super::observe::STOP_SPEED;
use super::scenes::{Known, KnownScene};
use crate::rigid3d::diagnostics::{flip_period, sign_changes};
use crate::rigid3d::scene::Scene;
use crate::verify::references::euler::torque_free_rk4;
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

/// The expectation for one observable.
#[derive(Clone, Debug, Serialize)]
pub struct Expected {
    /// The observable's key ([`super::observe::Measured::key`]).
    pub key: &'static str,
    /// What it is, for the report.
    pub name: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// The closed form's value, when there is one (`None`: reported, compared with rigidref only).
    pub exact: Option<f64>,
    /// The largest accepted |value − exact| (absolute, in `unit`).
    pub tolerance: Option<f64>,
    /// The closed form and where the tolerance comes from.
    pub note: String,
}

fn e(
    key: &'static str,
    name: &'static str,
    unit: &'static str,
    exact: Option<f64>,
    tolerance: Option<f64>,
    note: String,
) -> Expected {
    Expected {
        key,
        name,
        unit,
        exact,
        tolerance,
        note,
    }
}

/// The expectations of every observable [`super::observe::observe`] measures on `scene`.
pub fn expectations(scene: &Scene, known: &KnownScene) -> Vec<Expected> {
    let p = &scene.params;
    let (g, h, mu) = (p.gravity.norm(), p.h(), p.mu);
    let mut out = Vec::new();
    match known.known {
        Known::Slide => {
            let v0 = scene.bodies[0].v0.norm();
            let time = v0 / (mu * g);
            let distance = v0 * v0 / (2.0 * mu * g);
            out.push(e("stop_time", "stop time", "s", Some(time), Some(2.0 * h + 0.01 * time),
                format!("v₀/(μg) = {time:.4} s; within 2 h + 1 %: a step-based run stops within a step or two of it")));
            out.push(e("stop_distance", "stop distance", "m", Some(distance), Some(0.02 * distance),
                format!("v₀²/(2μg) = {distance:.5} m; within 2 %: symplectic Euler stops v₀h/2 = {:.2} % short (first order in h)", 100.0 * v0 * h / 2.0 / distance)));
        }
        Known::Drag => {
            let b = &scene.bodies[0];
            let rate = b.force_rate.norm();
            let t0 = mu * b.mass * g / rate;
            // v = Ḟ (t − t₀)² / (2m) reaches STOP_SPEED at t₀ + √(2 m v / Ḟ).
            let onset = t0 + (2.0 * b.mass * STOP_SPEED / rate).sqrt();
            let t = known.seconds;
            let v = rate * (t - t0).powi(2) / (2.0 * b.mass);
            out.push(e("slip_time", "slip onset (v > 1 mm/s)", "s", Some(onset), Some(0.005),
                format!("sticks until μmg/Ḟ = {t0:.4} s, then v = Ḟ(t − t₀)²/(2m) passes 1 mm/s at {onset:.4} s; within 5 ms: the load acts at each step's start and a step's impulse is O(h)")));
            out.push(e(
                "final_speed",
                "speed at the end",
                "m/s",
                Some(v),
                Some(0.02 * v),
                format!(
                    "Ḟ(t − t₀)²/(2m) = {v:.4} m/s at t = {t} s; within 2 % (an O(h) shift of t₀)"
                ),
            ));
        }
        Known::Rolls | Known::Slides => {
            let sin = p.gravity.x / g;
            let cos = (1.0 - sin * sin).sqrt();
            let b = &scene.bodies[0];
            if known.known == Known::Rolls {
                let a = 5.0 / 7.0 * g * sin;
                out.push(e("acceleration", "acceleration down the incline", "m/s²", Some(a), Some(0.01 * a),
                    format!("(5/7) g sin θ = {a:.4} m/s² (rolling without slipping, μ ≥ (2/7) tan θ); within 1 %")));
                out.push(e(
                    "slip_speed",
                    "slip speed at the contact",
                    "m/s",
                    Some(0.0),
                    Some(1e-3),
                    "0 (rolling); within 1 mm/s".to_string(),
                ));
            } else {
                let a = g * (sin - mu * cos);
                let r = b.ellipsoid.map_or(0.0, |e| e.semi_axes.x);
                let alpha = mu * b.mass * g * cos * r / b.inertia[(2, 2)];
                out.push(e(
                    "acceleration",
                    "acceleration down the incline",
                    "m/s²",
                    Some(a),
                    Some(0.01 * a),
                    format!("g (sin θ − μ cos θ) = {a:.4} m/s² (sliding); within 1 %"),
                ));
                out.push(e(
                    "spin_up",
                    "angular acceleration",
                    "rad/s²",
                    Some(alpha),
                    Some(0.01 * alpha),
                    format!("μ m g cos θ r / J = {alpha:.4} rad/s²; within 1 %"),
                ));
            }
        }
        Known::Flip => {
            let body = &scene.bodies[0];
            let eigen = body.inertia.symmetric_eigen();
            let mut order = [0usize, 1, 2];
            order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
            let axis = eigen.eigenvectors.column(order[1]).into_owned();
            let h_ref = h / 100.0;
            let steps = (known.seconds / h_ref).round() as usize;
            let samples: Vec<(f64, f64)> = torque_free_rk4(
                &body.inertia,
                &(body.r0.transpose() * body.omega0),
                h_ref,
                steps,
            )
            .into_iter()
            .step_by(100)
            .map(|(t, w)| (t, w.dot(&axis)))
            .collect();
            let changes = sign_changes(&samples);
            let first = changes.first().copied();
            let period = flip_period(&changes);
            out.push(e("first_flip", "first flip", "s", first, first.map(|f| 0.05 * f),
                format!("RK4 at h/100 (src/verify/references/euler.rs): {:.4} s; within 5 % (first-order integrators shift the flips by O(h))", first.unwrap_or(f64::NAN))));
            out.push(e(
                "flip_period",
                "flip period",
                "s",
                period,
                period.map(|f| 0.05 * f),
                format!(
                    "RK4 at h/100: {:.4} s; within 5 %",
                    period.unwrap_or(f64::NAN)
                ),
            ));
            let (energy_gain, _) = explicit_gains(
                &body.inertia,
                &(body.r0.transpose() * body.omega0),
                h,
                known.seconds,
            );
            let bound = GAIN_MARGIN * energy_gain + ROUND_OFF;
            out.push(e("energy_drift", "energy drift (end/start − 1)", "", Some(0.0), Some(bound),
                format!("0 (torque-free); within {GAIN_MARGIN} × {energy_gain:.3e}, the explicit step's documented gain Σ ½h²gᵀJ⁻¹g / E₀ along the RK4 solution (docs/dynamics.md §\"Why the explicit gyroscopic term gains energy\"; first order in h)")));
        }
        Known::Projectile => {
            let t = known.seconds;
            let bound = g * h * t / 2.0;
            out.push(e("position_error", "distance from x₀ + v₀t + gt²/2 at the end", "m", Some(0.0), Some(1.01 * bound),
                format!("0; within g h t/2 = {bound:.4} m, symplectic Euler's first-order error (x_n = x₀ + v₀t + g t²/2 + g h t/2)")));
            let b = &scene.bodies[0];
            let (_, momentum_gain) =
                explicit_gains(&b.inertia, &(b.r0.transpose() * b.omega0), h, t);
            let bound = GAIN_MARGIN * momentum_gain + ROUND_OFF;
            out.push(e("angular_momentum_drift", "|L_c| end/start − 1", "", Some(0.0), Some(bound),
                format!("0 (torque-free about the centre of mass); within {GAIN_MARGIN} × {momentum_gain:.3e}, the explicit step's documented gain (|L|² gains h²|ω × L|² a step, docs/dynamics.md) along the RK4 solution (first order in h)")));
        }
        Known::HeavyOnLight => {
            out.push(e("holds", "stack holds (1 = yes)", "", Some(1.0), Some(0.0),
                "1: the heavy body sinks less than 1 mm and the light one moves less than 1 mm sideways".to_string()));
            out.push(e(
                "heavy_drop",
                "heavy body's drop",
                "m",
                None,
                None,
                "reported".to_string(),
            ));
            out.push(e(
                "lower_layer",
                "light–ground Σλn / ((m₁+m₂) g h)",
                "",
                Some(1.0),
                Some(0.01),
                "1: the lower layer carries both weights (mean of the last 100 steps); within 1 %"
                    .to_string(),
            ));
            out.push(e(
                "upper_layer",
                "heavy–light Σλn / (m₂ g h)",
                "",
                Some(1.0),
                Some(0.01),
                "1: the upper layer carries the heavy weight; within 1 %".to_string(),
            ));
        }
        Known::Rest => {
            out.push(e(
                "rest_height",
                "height of the centre at rest",
                "m",
                None,
                None,
                "reported: the icosphere rests on a vertex, on the contact model's own depth"
                    .to_string(),
            ));
            out.push(e(
                "rest_speed",
                "speed at the end",
                "m/s",
                Some(0.0),
                Some(STOP_SPEED),
                "0; within 1 mm/s".to_string(),
            ));
            out.push(e(
                "carried_weight",
                "ball–ground Σλn / (m g h)",
                "",
                Some(1.0),
                Some(0.01),
                "1: the contact carries the weight (mean of the last 20 steps); within 1 %"
                    .to_string(),
            ));
        }
        Known::Stack => {
            out.push(e(
                "holds",
                "stack stands (1 = yes)",
                "",
                Some(1.0),
                Some(0.0),
                "1: no body moves more than 1 cm".to_string(),
            ));
            out.push(e(
                "largest_drift",
                "largest body displacement",
                "m",
                None,
                None,
                "reported".to_string(),
            ));
        }
    }
    if p.check_collisions {
        let size = scene
            .bodies
            .iter()
            .map(|b| crate::rigid3d::collide::penetration::mesh_size(&b.mesh))
            .fold(f64::INFINITY, f64::min);
        let resting = (0.01 * size).max(2.0 * p.stabilization_slop);
        // A body that falls onto the ground crosses it between two steps: the first step that
        // sees the contact finds it up to (impact speed) × h deep, whatever the contact model
        // (speculative contacts, as rapier's, see it a step early).
        let impact = if known.known == Known::Rest {
            impact_speed(scene) * h
        } else {
            0.0
        };
        let bound = resting.max(impact);
        out.push(e("deepest_penetration", "deepest penetration", "m", Some(0.0), Some(bound),
            if impact > resting {
                format!("0; within {bound:.4} m, the impact speed √(2g·fall) times h: a step-based run finds the ground up to a step's travel deep on the step it first touches it")
            } else {
                format!("0; within {bound:.4} m, the larger of 1 % of the smallest body and twice rigidref's slop (its resting depth)")
            }));
        out.push(e("energy_rise", "largest energy rise", "J", None, None,
            "reported: contact with friction only takes energy away; a rise is energy a contact model adds".to_string()));
        out.push(e(
            "criterion_primal",
            "primal criterion (max)",
            "N·s",
            None,
            None,
            "reported: 0 for Coulomb's law (ContactBench)".to_string(),
        ));
        out.push(e(
            "criterion_dual",
            "dual criterion (max)",
            "m/s",
            None,
            None,
            "reported: 0 for Coulomb's law".to_string(),
        ));
        out.push(e(
            "criterion_complementarity",
            "complementarity (max)",
            "J",
            None,
            None,
            "reported: 0 for Coulomb's law".to_string(),
        ));
    }
    out
}

/// The slack on the explicit step's gains: they are summed along the exact (RK4) solution, while
/// a first-order run's own trajectory drifts from it by O(h) (its flips come early or late).
pub const GAIN_MARGIN: f64 = 1.5;

/// Round-off allowance on a drift that is exactly zero for a conserving integrator (relative).
pub const ROUND_OFF: f64 = 1e-9;

/// What the explicit (spatial) step gains over `seconds` at step `h` on a torque-free body of
/// inertia `inertia` (body frame, kg·m²) starting at `omega_b` (body frame, rad/s): (relative
/// energy gain Σ ½h² gᵀJ⁻¹g / E₀, relative |L| gain √(1 + Σ h²|g|²/|L₀|²) − 1) with
/// g = ω × Jω, summed along the RK4 solution sampled at h (docs/dynamics.md §"Why the explicit
/// gyroscopic term gains energy"). Both are O(h).
pub fn explicit_gains(
    inertia: &Matrix3<f64>,
    omega_b: &Vector3<f64>,
    h: f64,
    seconds: f64,
) -> (f64, f64) {
    let steps = (seconds / h).round() as usize;
    let inverse = inertia.try_inverse().unwrap_or_else(Matrix3::zeros);
    let samples = torque_free_rk4(inertia, omega_b, h / 100.0, steps * 100);
    let (mut energy, mut momentum) = (0.0, 0.0);
    for (_, w) in samples.iter().step_by(100).take(steps) {
        let g = w.cross(&(inertia * w));
        energy += 0.5 * h * h * g.dot(&(inverse * g));
        momentum += h * h * g.norm_squared();
    }
    let e0 = 0.5 * omega_b.dot(&(inertia * omega_b));
    let l0 = (inertia * omega_b).norm_squared();
    (energy / e0, (1.0 + momentum / l0).sqrt() - 1.0)
}

/// The speed at which body 0 of a drop scene reaches the ground: √(v₀ᵧ² + 2 g (y₀ − r)) with r
/// its lowest point's depth below its centre, m/s.
fn impact_speed(scene: &Scene) -> f64 {
    let b = &scene.bodies[0];
    let g = scene.params.gravity.norm();
    let below = b
        .mesh
        .vertices
        .iter()
        .map(|v| -(b.r0 * v).y)
        .fold(0.0, f64::max);
    let fall = (b.x0.y - below).max(0.0);
    (b.v0.y * b.v0.y + 2.0 * g * fall).sqrt()
}
