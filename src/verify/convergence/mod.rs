//! Observed order of convergence in the step size (docs/verification.md §"Convergence order"): a
//! 3D scene is run at several step sizes dt, one observable is measured from each run, and the
//! errors against a reference become observed orders p = ln(e₁/e₂) / ln(dt₁/dt₂). The reference is
//! a closed form, an independent integration (RK4 of the torque-free Euler equations; RK4 of the
//! no-slip rolling ellipsoid), or, where there is none, Richardson extrapolation of the runs
//! themselves, whose successive differences give the order without any reference.
//! `rigidref converge` prints the report.

mod observables;

pub use observables::*;

use crate::rigid3d::scene::Scene;
use crate::rigid3d::world::World;
use crate::sim::{Flow, drive, steps_in};
use crate::verify::references::euler::torque_free_rk4;
use crate::verify::references::noslip::NoSlipEllipsoid;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

/// A reference value and how it was obtained.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Reference {
    /// The value, in the observable's unit.
    pub value: f64,
    /// How it was obtained, in words.
    pub how: String,
    /// Its own error estimate where it is computed (the difference between the reference at its
    /// step and at twice that step), in the observable's unit; 0 for a closed form or a given value.
    pub uncertainty: f64,
}

/// One run: the step size, the steps it took and the observable's value.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Run {
    /// Step size dt, s (the scene's substeps are kept, so h = dt / substeps).
    pub dt: f64,
    /// Steps run.
    pub steps: u64,
    /// The observable's value.
    pub value: f64,
    /// value − reference, when there is a reference.
    pub error: Option<f64>,
    /// The observed order against the reference from the previous (larger) step to this one:
    /// ln(|e_prev|/|e|) / ln(dt_prev/dt); None where either error is at round-off
    /// ([`ROUND_OFF`] of the value).
    pub order: Option<f64>,
}

/// The convergence report of one observable.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Convergence {
    /// What was measured.
    pub observable: String,
    /// Its unit.
    pub unit: String,
    /// The reference, when there is one (none with `richardson`).
    pub reference: Option<Reference>,
    /// The runs, largest step first.
    pub runs: Vec<Run>,
    /// The orders from the runs alone (Richardson): for each three successive steps, the p with
    /// (Q₁ − Q₂)/(Q₂ − Q₃) = (dt₁ᵖ − dt₂ᵖ)/(dt₂ᵖ − dt₃ᵖ); None where the differences change sign
    /// (not in the asymptotic range), are at round-off ([`ROUND_OFF`]) or no p in (0, 10] fits.
    pub richardson_orders: Vec<Option<f64>>,
    /// The value extrapolated to dt → 0 from the last three runs, when their order is defined.
    pub extrapolated: Option<f64>,
}

/// Runs `scene` at each of `dts` (sorted largest first), measures `observable` of body `body`
/// within `time` seconds and compares it with the reference. Errors are one line.
pub fn converge(
    scene: &Scene,
    dts: &[f64],
    observable: Observable,
    body: usize,
    time: f64,
    reference: ReferenceChoice,
    mut progress: impl FnMut(&Run),
) -> Result<Convergence, String> {
    if body >= scene.bodies.len() {
        return Err(format!(
            "--body {body}: the scene has {} bodies (0 to {})",
            scene.bodies.len(),
            scene.bodies.len().saturating_sub(1)
        ));
    }
    if dts.is_empty() || dts.iter().any(|&dt| !(dt > 0.0 && dt.is_finite())) {
        return Err("--dt: give positive step sizes, e.g. 1e-3,5e-4,2.5e-4".into());
    }
    let mut dts = dts.to_vec();
    dts.sort_by(|a, b| b.total_cmp(a));
    dts.dedup();
    if dts.len() < 2 {
        return Err("--dt: give at least two different step sizes".into());
    }
    let reference = reference_value(scene, observable, body, time, reference, dts[dts.len() - 1])?;
    let mut runs: Vec<Run> = Vec::new();
    for &dt in &dts {
        let (value, steps) = measure(scene, dt, observable, body, time)?;
        let error = reference.as_ref().map(|r| value - r.value);
        let order = match (runs.last(), error) {
            (Some(prev), Some(e)) => prev
                .error
                .map(|pe| order_between(pe, e, prev.dt, dt, value)),
            _ => None,
        }
        .flatten();
        let run = Run {
            dt,
            steps,
            value,
            error,
            order,
        };
        progress(&run);
        runs.push(run);
    }
    let richardson_orders: Vec<Option<f64>> = runs
        .windows(3)
        .map(|w| {
            richardson_order(
                [w[0].dt, w[1].dt, w[2].dt],
                [w[0].value, w[1].value, w[2].value],
            )
        })
        .collect();
    let extrapolated = match (runs.len(), richardson_orders.last()) {
        (n, Some(Some(p))) if n >= 3 => {
            let (a, b) = (&runs[n - 2], &runs[n - 1]);
            Some(b.value - (a.value - b.value) / ((a.dt / b.dt).powf(*p) - 1.0))
        }
        _ => None,
    };
    Ok(Convergence {
        observable: observable.to_string(),
        unit: observable.unit().into(),
        reference,
        runs,
        richardson_orders,
        extrapolated,
    })
}

/// Relative size below which an error or a difference of runs is round-off (f64 carries ~16
/// digits; a run of 10⁴ steps loses a few of them): no order can be read from it.
pub const ROUND_OFF: f64 = 1e-12;

/// Whether `e` is round-off against a value of size `value`.
fn at_round_off(e: f64, value: f64) -> bool {
    e.abs() <= ROUND_OFF * value.abs().max(1.0)
}

/// ln(|e₁|/|e₂|) / ln(dt₁/dt₂); None when an error is at round-off of `value` (the scheme is
/// exact for the observable, or the runs cannot resolve its error).
fn order_between(e1: f64, e2: f64, dt1: f64, dt2: f64, value: f64) -> Option<f64> {
    (!at_round_off(e1, value) && !at_round_off(e2, value))
        .then(|| (e1.abs() / e2.abs()).ln() / (dt1 / dt2).ln())
}

/// The order p that fits Q(dt) = Q* + C dtᵖ through three runs (dt₁ > dt₂ > dt₃): the root of
/// (dt₁ᵖ − dt₂ᵖ)/(dt₂ᵖ − dt₃ᵖ) = (Q₁ − Q₂)/(Q₂ − Q₃), by bisection on (0, 10]. The left side
/// is rᵖ for a constant ratio r of step sizes, so rising in p; for unequal ratios the bisection
/// assumes it rises too (checked on 1, 0.4, 0.1 ms by the unit test), and None is returned where
/// the ends of the interval do not bracket a root.
pub fn richardson_order(dt: [f64; 3], q: [f64; 3]) -> Option<f64> {
    let (d1, d2) = (q[0] - q[1], q[1] - q[2]);
    if at_round_off(d1, q[2]) || at_round_off(d2, q[2]) || (d1 > 0.0) != (d2 > 0.0) {
        return None;
    }
    let target = d1 / d2;
    let g = |p: f64| (dt[0].powf(p) - dt[1].powf(p)) / (dt[1].powf(p) - dt[2].powf(p)) - target;
    let (mut lo, mut hi) = (1e-6, 10.0);
    if g(lo) > 0.0 || g(hi) < 0.0 {
        return None;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Runs the scene at `dt` and returns the observable's value and the steps run.
pub fn measure(
    scene: &Scene,
    dt: f64,
    observable: Observable,
    body: usize,
    time: f64,
) -> Result<(f64, u64), String> {
    let mut scene = scene.clone();
    scene.params.dt = dt;
    let steps = steps_in(time, dt, "s")?;
    let mut world = World::new(&scene)?;
    let start = world.bodies[body].x;
    let axis = intermediate_axis(&scene.bodies[body].inertia);
    let sample = |w: &World| -> f64 {
        let b = &w.bodies[body];
        match observable {
            Observable::FirstFlip => b.omega_body().dot(&axis),
            _ => b.omega.y,
        }
    };
    let mut previous = (world.time(), sample(&world));
    let mut found: Option<f64> = None;
    let mut speeds: [Option<(f64, f64)>; 2] =
        [None, Some((world.time(), world.bodies[body].v.norm()))];
    let ran = drive(&mut world, steps, |w, _| -> Result<Flow, String> {
        let b = &w.bodies[body];
        found = match observable {
            Observable::StopTime => {
                // Between samples the speed falls linearly (constant deceleration): the stop is
                // where the line through the last two moving samples reaches 0.
                let (t, speed) = (w.time(), b.v.norm());
                let stop = (speed < STOPPED).then(|| match speeds {
                    [Some((t1, s1)), Some((t2, s2))] if s1 > s2 => t2 + s2 * (t2 - t1) / (s1 - s2),
                    _ => t,
                });
                speeds = [speeds[1], Some((t, speed))];
                stop
            }
            Observable::StopDistance => (b.v.norm() < STOPPED).then(|| {
                let d = b.x - start;
                d.x.hypot(d.z)
            }),
            Observable::FirstFlip | Observable::FirstReversal => {
                let now = (w.time(), sample(w));
                let crossed = (previous.1 < 0.0) != (now.1 < 0.0);
                let at = previous.0 + (now.0 - previous.0) * previous.1 / (previous.1 - now.1);
                previous = now;
                crossed.then_some(at)
            }
            Observable::Final(_) => None,
        };
        Ok(if found.is_some() {
            Flow::Stop
        } else {
            Flow::Continue
        })
    })?;
    if let Observable::Final(field) = observable {
        let b = &world.bodies[body];
        let value = match field {
            Field::X => b.x.x,
            Field::Y => b.x.y,
            Field::Z => b.x.z,
            Field::Vx => b.v.x,
            Field::Vy => b.v.y,
            Field::Vz => b.v.z,
            Field::Wx => b.omega.x,
            Field::Wy => b.omega.y,
            Field::Wz => b.omega.z,
        };
        return Ok((value, ran));
    }
    let what = match observable {
        Observable::StopTime | Observable::StopDistance => "did not stop",
        Observable::FirstFlip => "did not flip (no sign change of the intermediate-axis spin)",
        _ => "did not reverse (no sign change of ω_y)",
    };
    found.map(|v| (v, ran)).ok_or_else(|| {
        format!(
            "body {body} ({}) {what} within {time} s at dt {dt}; give a longer --time",
            scene.bodies[body].name
        )
    })
}

/// The unit eigenvector of the middle principal moment of a body-frame inertia.
fn intermediate_axis(inertia: &Matrix3<f64>) -> Vector3<f64> {
    let eigen = SymmetricEigen::new(*inertia);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    eigen.eigenvectors.column(order[1]).into_owned()
}

/// The reference for `observable`, or None for Richardson.
fn reference_value(
    scene: &Scene,
    observable: Observable,
    body: usize,
    time: f64,
    choice: ReferenceChoice,
    finest: f64,
) -> Result<Option<Reference>, String> {
    let choice = match (choice, observable) {
        (ReferenceChoice::Auto, Observable::StopTime | Observable::StopDistance) => {
            ReferenceChoice::ClosedForm
        }
        (ReferenceChoice::Auto, Observable::FirstFlip) => ReferenceChoice::Rk4,
        (ReferenceChoice::Auto, Observable::FirstReversal) => ReferenceChoice::NoSlip,
        (ReferenceChoice::Auto, Observable::Final(_)) => ReferenceChoice::Richardson,
        (choice, _) => choice,
    };
    let b = &scene.bodies[body];
    let p = &scene.params;
    let not_for = |name: &str| format!("the {name} reference does not give {observable}");
    Ok(match choice {
        ReferenceChoice::Auto | ReferenceChoice::Richardson => None,
        ReferenceChoice::Value(value) => Some(Reference {
            value,
            how: "given".into(),
            uncertainty: 0.0,
        }),
        ReferenceChoice::ClosedForm => {
            let g = p.gravity.norm();
            let v0 = b.v0.norm();
            let mut why = Vec::new();
            if scene.bodies.len() != 1 {
                why.push("more than one body");
            }
            if p.gravity.x != 0.0 || p.gravity.z != 0.0 || p.gravity.y >= 0.0 {
                why.push("gravity not along −y");
            }
            if b.v0.y != 0.0 || v0 == 0.0 {
                why.push("the start velocity is not horizontal and non-zero");
            }
            if b.omega0 != Vector3::zeros() || b.force != Vector3::zeros() {
                why.push("a spin or a load at the start");
            }
            if p.mu <= 0.0 || !p.check_collisions {
                why.push("no friction");
            }
            if p.friction_model == crate::problem::FrictionModel::Box
                && b.v0.x != 0.0
                && b.v0.z != 0.0
            {
                why.push("box friction off a tangent axis (it veers)");
            }
            if !why.is_empty() {
                return Err(format!(
                    "no closed form for {observable} in this scene ({}); use --reference richardson",
                    why.join(", ")
                ));
            }
            let (value, how) = match observable {
                Observable::StopTime => (v0 / (p.mu * g), "v₀/(μg)"),
                Observable::StopDistance => (v0 * v0 / (2.0 * p.mu * g), "v₀²/(2μg)"),
                _ => return Err(not_for("closed-form")),
            };
            Some(Reference {
                value,
                how: format!("closed form {how}"),
                uncertainty: 0.0,
            })
        }
        ReferenceChoice::Rk4 => {
            if observable != Observable::FirstFlip {
                return Err(not_for("rk4"));
            }
            if p.check_collisions && scene.bodies.len() > 1 {
                return Err(
                    "the rk4 reference needs a body that touches nothing: one body, or \
                            check_collisions false"
                        .into(),
                );
            }
            let omega0 = b.r0.transpose() * b.omega0;
            let axis = intermediate_axis(&b.inertia);
            let flip = |h: f64| -> Result<f64, String> {
                let steps = (time / h).ceil() as usize;
                let samples: Vec<(f64, f64)> = torque_free_rk4(&b.inertia, &omega0, h, steps)
                    .into_iter()
                    .map(|(t, w)| (t, w.dot(&axis)))
                    .collect();
                crate::rigid3d::diagnostics::sign_changes(&samples)
                    .first()
                    .copied()
                    .ok_or_else(|| format!("the RK4 reference does not flip within {time} s"))
            };
            let h = (finest / 100.0).min(1e-4);
            let (value, coarse) = (flip(h)?, flip(2.0 * h)?);
            Some(Reference {
                value,
                how: format!("RK4 of the torque-free Euler equations, h = {h:.1e} s"),
                uncertainty: (value - coarse).abs(),
            })
        }
        ReferenceChoice::NoSlip => {
            if observable != Observable::FirstReversal {
                return Err(not_for("no-slip"));
            }
            let Some(e) = &b.ellipsoid else {
                return Err(format!(
                    "the no-slip reference needs a body with an `ellipsoid`; body {body} ({}) has none",
                    b.name
                ));
            };
            if p.gravity.x != 0.0 || p.gravity.z != 0.0 || p.gravity.y >= 0.0 {
                return Err("the no-slip reference needs gravity along −y".into());
            }
            let model = NoSlipEllipsoid {
                semi_axes: e.semi_axes,
                centre: e.centre,
                mass: b.mass,
                inertia: b.inertia,
                g: -p.gravity.y,
            };
            let reversal = |h: f64| -> Result<f64, String> {
                let mut s = model.start(&b.r0, &b.omega0);
                let steps = (time / h).ceil() as usize;
                for k in 1..=steps {
                    let next = model.rk4(&s, h);
                    if (s.omega.y < 0.0) != (next.omega.y < 0.0) {
                        let t0 = (k - 1) as f64 * h;
                        return Ok(t0 + h * s.omega.y / (s.omega.y - next.omega.y));
                    }
                    s = next;
                }
                Err(format!(
                    "the no-slip reference does not reverse within {time} s"
                ))
            };
            let h = 2.5e-4;
            let (value, coarse) = (reversal(h)?, reversal(2.0 * h)?);
            Some(Reference {
                value,
                how: format!("the ellipsoid rolling without slipping, RK4, h = {h:.1e} s"),
                uncertainty: (value - coarse).abs(),
            })
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Richardson's order recovers p from exact data Q = 1 + 3 (dt/1 ms)ᵖ, at unequal ratios
    /// too (the differences well above round-off at every p tried).
    #[test]
    fn richardson_order_recovers_the_order_of_exact_data() {
        for p in [0.5, 1.0, 2.0, 4.0] {
            let dt = [1e-3, 4e-4, 1e-4];
            let q = dt.map(|h: f64| 1.0 + 3.0 * (h / 1e-3).powf(p));
            let found = richardson_order(dt, q).unwrap();
            // 1e-9: bisection to 2⁻¹⁰⁰ of 10, limited by the round-off of the differences.
            assert!((found - p).abs() < 1e-9, "{p}: {found}");
        }
        assert_eq!(
            richardson_order([1e-3, 5e-4, 2.5e-4], [1.0, 2.0, 1.5]),
            None
        );
    }

    #[test]
    fn observables_read_back_their_names() {
        for name in OBSERVABLE_NAMES.split(", ") {
            let o: Observable = name.parse().unwrap();
            assert_eq!(o.to_string(), name);
        }
        assert!("final_q".parse::<Observable>().is_err());
    }
}
