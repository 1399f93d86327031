//! Trajectory mode: every quantity of a trace against the reference's over time
//! (docs/grading.md §"Trajectory mode").

use super::refusal::{check_traces, motion_check};
use super::*;

/// Trajectory mode: every quantity of `other` against `reference` at the record times of the
/// sparser of the two within the common span, the other interpolated (x, v, ω, energies and
/// momenta linearly, R by slerp).
pub fn compare_trajectories(
    reference: &Trace,
    other: &Trace,
    tol: &TrajectoryTolerances,
) -> Result<Comparison, String> {
    let prepared = match check_traces(reference, other)? {
        Ok(prepared) => prepared,
        Err(refusal) => return Ok(Comparison::refused("trajectory", refusal)),
    };
    let (span, map, matched_by) = (prepared.span, prepared.map, prepared.matched_by);
    // Sample at the record times of the sparser trace (within the common span) and interpolate
    // the denser one, so that a trace recorded every K frames is compared where it has data.
    let in_span = |t: &Trace| -> Vec<f64> {
        t.records
            .iter()
            .map(|r| r.t)
            .filter(|&t| t >= span.0 && t <= span.1)
            .collect()
    };
    let (from_reference, from_other) = (in_span(reference), in_span(other));
    let times = if from_other.len() < from_reference.len() {
        from_other
    } else {
        from_reference
    };
    // Both traces at each sample time, interpolated once: every body's state, and the 13
    // system values (energy terms, momenta).
    struct Sample {
        t: f64,
        bodies: Vec<(State, State)>,
        system: ([f64; 13], [f64; 13]),
    }
    let samples: Vec<Sample> = times
        .iter()
        .map(|&t| Sample {
            t,
            bodies: map
                .iter()
                .enumerate()
                .map(|(i, &j)| {
                    (
                        body_at(&reference.records, i, t),
                        body_at(&other.records, j, t),
                    )
                })
                .collect(),
            system: (
                system_at(&reference.records, t),
                system_at(&other.records, t),
            ),
        })
        .collect();
    let mut errors = Vec::new();
    let mut track =
        |quantity: String, unit: &'static str, tolerance: f64, f: &dyn Fn(&Sample) -> f64| {
            let each = samples.iter().map(|sample| (sample.t, f(sample)));
            errors.push(quantity_error(quantity, unit, tolerance, span.0, each));
        };
    for i in 0..map.len() {
        let label = body_label(reference, i);
        track(format!("{label} position"), "m", tol.position, &|s| {
            let (a, b) = &s.bodies[i];
            (a.x - b.x).norm()
        });
        track(format!("{label} orientation"), "rad", tol.angle, &|s| {
            let (a, b) = &s.bodies[i];
            angle_between(&a.rotation, &b.rotation)
        });
        track(format!("{label} velocity"), "m/s", tol.velocity, &|s| {
            let (a, b) = &s.bodies[i];
            (a.v - b.v).norm()
        });
        track(
            format!("{label} angular velocity"),
            "rad/s",
            tol.omega,
            &|s| {
                let (a, b) = &s.bodies[i];
                (a.omega - b.omega).norm()
            },
        );
    }
    let names = [
        "energy.kinetic_linear",
        "energy.kinetic_angular",
        "energy.potential",
        "energy.total",
    ];
    let energy_scale = energy_scale(reference);
    for (k, name) in names.iter().enumerate() {
        track(name.to_string(), "J", tol.energy * energy_scale, &|s| {
            (s.system.0[k] - s.system.1[k]).abs()
        });
    }
    // Relative to the reference's largest momentum, but never less than that of the whole mass
    // moving at 1 m/s (at 1 m for angular momentum): a system at rest has zero momentum, and
    // round-off must not fail it.
    let total_mass: f64 = reference.header.bodies.iter().map(|b| b.mass).sum();
    for (k, name) in [
        "momentum.linear",
        "momentum.angular",
        "momentum.angular_com",
    ]
    .iter()
    .enumerate()
    {
        let part = |v: &[f64; 13]| Vector3::new(v[4 + 3 * k], v[5 + 3 * k], v[6 + 3 * k]);
        let of_record = |r: &TraceRecord| {
            let m = &r.momentum;
            v3([&m.linear, &m.angular, &m.angular_com][k]).norm()
        };
        let scale = reference
            .records
            .iter()
            .map(of_record)
            .fold(total_mass.max(f64::MIN_POSITIVE), f64::max);
        let unit = if k == 0 { "kg·m/s" } else { "kg·m²/s" };
        track(name.to_string(), unit, tol.momentum * scale, &|s| {
            (part(&s.system.0) - part(&s.system.1)).norm()
        });
    }
    let checks = vec![motion_check(reference, other, &map)];
    let agree =
        errors.iter().all(|e| e.first_exceeded.is_none()) && checks.iter().all(|c| c.passed);
    Ok(Comparison {
        mode: "trajectory",
        span,
        matched_by,
        matching: map,
        errors,
        outcomes: Vec::new(),
        checks,
        agree,
        refused: None,
    })
}
