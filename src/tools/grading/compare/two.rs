//! 2D traces (the image-block system) in trajectory mode: the 3D comparison's rules with 2D
//! states (docs/grading.md §"2D traces"). Units are the 2D system's: blocks, time units, the
//! mass unit of a block (docs/blocks2d.md §"World frame and units").
//!
//! Bodies are matched by what the image gives, not by the order a simulator lists them in: each
//! body's block count and mass, and its centre at the first record (the component's pixels fix
//! it); a reference body takes the other trace's unmatched body of the same blocks and mass
//! whose first centre is nearest, within half a block.

use super::*;
use crate::blocks2d::trace::{Record2, TraceHeader2};

/// A 2D trace: its header and complete records.
#[derive(Clone, Debug)]
pub struct Trace2 {
    /// The header line.
    pub header: TraceHeader2,
    /// The records, in file order.
    pub records: Vec<Record2>,
}

/// Why a 2D trace cannot be compared with the reference, in the order of the 3D checks
/// (docs/grading.md §"Refused traces"): records at all, the reference's number of bodies, finite
/// numbers, strictly increasing times, the reference's span covered to one step at each end,
/// records at most max(the reference's spacing, [`MAX_GAP_STEPS`] steps) apart.
fn defect(reference: &Trace2, other: &Trace2) -> Option<Refusal> {
    let refuse = |kind: &'static str, message: String| Some(Refusal { kind, message });
    let masses: Vec<(usize, f64)> = (other.header.bodies.iter().enumerate())
        .filter(|(_, b)| !b.pinned)
        .map(|(i, b)| (i, b.mass))
        .collect();
    if let Some(r) = super::refusal::header_defect(other.header.dt, &masses, "") {
        return Some(r);
    }
    if other.records.is_empty() {
        return refuse("empty", "the trace has no records".into());
    }
    let bodies = reference.header.bodies.len();
    if other.header.bodies.len() != bodies {
        return refuse(
            "wrong bodies",
            format!(
                "the trace has {} bodies, the reference {bodies}",
                other.header.bodies.len()
            ),
        );
    }
    for r in &other.records {
        if r.bodies.len() != bodies {
            return refuse(
                "wrong bodies",
                format!(
                    "the record at step {} has {} bodies, the header {bodies}",
                    r.step,
                    r.bodies.len()
                ),
            );
        }
        if !r.t.is_finite() {
            return refuse(
                "not finite",
                format!("the time of the record at step {} is not finite", r.step),
            );
        }
        for (i, b) in r.bodies.iter().enumerate() {
            let numbers = [b.x[0], b.x[1], b.theta, b.v[0], b.v[1], b.omega];
            if !numbers.iter().all(|x| x.is_finite()) {
                return refuse(
                    "not finite",
                    format!("body {i} is not finite at step {} (t = {})", r.step, r.t),
                );
            }
        }
    }
    let times =
        |t: &Trace2| -> Vec<(u64, f64)> { t.records.iter().map(|r| (r.step, r.t)).collect() };
    super::refusal::time_defect(&times(reference), reference.header.dt, &times(other), "")
}

/// `map[i]`: the other trace's body that is the reference's body `i`, matched by block count,
/// mass and first centre (module documentation); an error names a body with no partner (a
/// refusal, `wrong bodies`, in the comparisons).
pub fn match_bodies_2d(reference: &Trace2, other: &Trace2) -> Result<Vec<usize>, String> {
    let (r, o) = (&reference.header.bodies, &other.header.bodies);
    let (r0, o0) = (&reference.records[0], &other.records[0]);
    let mut taken = vec![false; o.len()];
    let mut map = Vec::with_capacity(r.len());
    for (i, body) in r.iter().enumerate() {
        let centre = r0.bodies[i].x;
        let same = |j: usize| {
            o[j].blocks == body.blocks
                && (o[j].mass - body.mass).abs() <= 1e-6 * body.mass.abs().max(o[j].mass.abs())
        };
        let distance = |j: usize| {
            let c = o0.bodies[j].x;
            ((c[0] - centre[0]).powi(2) + (c[1] - centre[1]).powi(2)).sqrt()
        };
        let best = (0..o.len())
            .filter(|&j| !taken[j] && same(j))
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
            .filter(|&j| distance(j) <= 0.5);
        let Some(j) = best else {
            return Err(format!(
                "reference body {i} ({} blocks, mass {}, first at ({}, {})) has no body of the \
                 other trace with its blocks and mass within half a block: not the same image",
                body.blocks, body.mass, centre[0], centre[1]
            ));
        };
        taken[j] = true;
        map.push(j);
    }
    Ok(map)
}

/// Body `i`'s (x, y, θ, vx, vy, ω) at `t`, interpolated linearly.
fn body2_at(records: &[Record2], i: usize, t: f64) -> [f64; 6] {
    let (a, b, s) = bracket(records, |r: &Record2| r.t, t);
    let of = |r: &Record2| {
        let b = &r.bodies[i];
        [b.x[0], b.x[1], b.theta, b.v[0], b.v[1], b.omega]
    };
    let (p, q) = (of(&records[a]), of(&records[b]));
    std::array::from_fn(|k| lerp(p[k], q[k], s))
}

/// (kinetic, potential, total energy, px, py, angular momentum) at `t`, interpolated linearly.
fn system2_at(records: &[Record2], t: f64) -> [f64; 6] {
    let (a, b, s) = bracket(records, |r: &Record2| r.t, t);
    let of = |r: &Record2| {
        let (e, m) = (&r.energy, &r.momentum);
        [
            e.kinetic,
            e.potential,
            e.total,
            m.linear[0],
            m.linear[1],
            m.angular,
        ]
    };
    let (p, q) = (of(&records[a]), of(&records[b]));
    std::array::from_fn(|k| lerp(p[k], q[k], s))
}

/// The difference of two angles, rad, wrapped into [0, π].
pub(super) fn angle_difference(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// The matching (other body of each reference body) and the span both traces cover.
pub(super) type Prepared = (Vec<usize>, f64, f64);

/// What both 2D modes do first: the reference must be a trace that would pass its own checks
/// (else an error), the other is refused for the first defect it has (`Ok(Err(refusal))`),
/// then the bodies are matched by the image. Returns the matching and the span both traces
/// cover, (start, end).
pub(super) fn prepare(
    reference: &Trace2,
    other: &Trace2,
) -> Result<Result<Prepared, Refusal>, String> {
    if reference.records.is_empty() {
        return Err("the reference trace has no records".into());
    }
    if let Some(r) = defect(reference, reference) {
        return Err(format!("the reference trace: {}", r.message));
    }
    if let Some(r) = defect(reference, other) {
        return Ok(Err(r));
    }
    let map = match match_bodies_2d(reference, other) {
        Ok(map) => map,
        Err(message) => {
            return Ok(Err(Refusal {
                kind: "wrong bodies",
                message,
            }));
        }
    };
    let start = reference.records[0].t.max(other.records[0].t);
    let end = (reference.records.last().map(|r| r.t))
        .unwrap_or(start)
        .min(other.records.last().map_or(start, |r| r.t));
    Ok(Ok((map, start, end)))
}

/// Trajectory mode for 2D traces: every body's position (blocks), angle (rad), velocity and
/// angular velocity, the energies and momenta, at the record times of the sparser trace within
/// the common span, the other interpolated linearly. Tolerances as in 3D, in the 2D units.
pub fn compare_trajectories_2d(
    reference: &Trace2,
    other: &Trace2,
    tol: &TrajectoryTolerances,
) -> Result<Comparison, String> {
    let (map, start, end) = match prepare(reference, other)? {
        Ok(prepared) => prepared,
        Err(refusal) => return Ok(Comparison::refused("trajectory", refusal)),
    };
    let in_span = |t: &Trace2| -> Vec<f64> {
        t.records
            .iter()
            .map(|r| r.t)
            .filter(|&t| t >= start && t <= end)
            .collect()
    };
    let (a, b) = (in_span(reference), in_span(other));
    let times = if b.len() < a.len() { b } else { a };
    let mut errors = Vec::new();
    let mut track =
        |quantity: String, unit: &'static str, tolerance: f64, f: &dyn Fn(f64) -> f64| {
            let each = times.iter().map(|&t| (t, f(t)));
            errors.push(quantity_error(quantity, unit, tolerance, start, each));
        };
    for (i, &j) in map.iter().enumerate() {
        let label = format!("body {i} ({:?})", reference.header.bodies[i].name);
        let states = |t: f64| {
            (
                body2_at(&reference.records, i, t),
                body2_at(&other.records, j, t),
            )
        };
        track(format!("{label} position"), "block", tol.position, &|t| {
            let (p, q) = states(t);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
        });
        track(format!("{label} angle"), "rad", tol.angle, &|t| {
            let (p, q) = states(t);
            angle_difference(p[2], q[2])
        });
        track(format!("{label} velocity"), "block/t", tol.velocity, &|t| {
            let (p, q) = states(t);
            ((p[3] - q[3]).powi(2) + (p[4] - q[4]).powi(2)).sqrt()
        });
        track(
            format!("{label} angular velocity"),
            "rad/t",
            tol.omega,
            &|t| {
                let (p, q) = states(t);
                (p[5] - q[5]).abs()
            },
        );
    }
    // Energies against the reference's energy scale; momenta against the whole mass at
    // 1 block/t or the largest momentum.
    let total_mass: f64 = reference
        .header
        .bodies
        .iter()
        .filter(|b| !b.pinned)
        .map(|b| b.mass)
        .sum();
    let energy_scale = energy_scale_2d(reference);
    let systems = |t: f64| {
        (
            system2_at(&reference.records, t),
            system2_at(&other.records, t),
        )
    };
    for (k, name) in ["energy.kinetic", "energy.potential", "energy.total"]
        .iter()
        .enumerate()
    {
        track(
            name.to_string(),
            "mass·block²/t²",
            tol.energy * energy_scale,
            &|t| {
                let (p, q) = systems(t);
                (p[k] - q[k]).abs()
            },
        );
    }
    let momentum_scale = reference
        .records
        .iter()
        .map(|r| {
            r.momentum.linear[0]
                .hypot(r.momentum.linear[1])
                .max(r.momentum.angular.abs())
        })
        .fold(total_mass.max(f64::MIN_POSITIVE), f64::max);
    track(
        "momentum.linear".into(),
        "mass·block/t",
        tol.momentum * momentum_scale,
        &|t| {
            let (p, q) = systems(t);
            (p[3] - q[3]).hypot(p[4] - q[4])
        },
    );
    track(
        "momentum.angular".into(),
        "mass·block²/t",
        tol.momentum * momentum_scale,
        &|t| {
            let (p, q) = systems(t);
            (p[5] - q[5]).abs()
        },
    );
    let checks = vec![motion_check_2d(reference, other, &map)];
    let agree =
        errors.iter().all(|e| e.first_exceeded.is_none()) && checks.iter().all(|c| c.passed);
    Ok(Comparison {
        mode: "trajectory",
        span: (start, end),
        matched_by: "image",
        matching: map,
        errors,
        outcomes: Vec::new(),
        checks,
        agree,
        refused: None,
    })
}

/// The reference's energy scale, as in 3D: the largest of its largest kinetic energy, the range
/// of its potential energy and the energy of lifting every body that is not pinned by 0.01 block
/// (with |g| at least 1 block/t²), mass·block²/t².
pub(super) fn energy_scale_2d(reference: &Trace2) -> f64 {
    let g = reference.header.gravity;
    let g = (g[0] * g[0] + g[1] * g[1]).sqrt().max(1.0);
    let total_mass: f64 = (reference.header.bodies.iter())
        .filter(|b| !b.pinned)
        .map(|b| b.mass)
        .sum();
    let kinetic = (reference.records.iter())
        .map(|r| r.energy.kinetic)
        .fold(0.0, f64::max);
    let (low, high) = (reference.records.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
            (l.min(r.energy.potential), h.max(r.energy.potential))
        });
    kinetic
        .max(high - low)
        .max(total_mass * g * 0.01)
        .max(f64::MIN_POSITIVE)
}

/// The candidate's positions and angles against its own velocities, record by record
/// ([`super::motion`]), for the bodies that are not pinned, with the reference's step and top
/// speed; bodies named by the reference's numbers (`map[i]`: the other's body of reference
/// body i).
pub(super) fn motion_check_2d(reference: &Trace2, other: &Trace2, map: &[usize]) -> Outcome {
    let g = reference.header.gravity;
    let pinned: Vec<bool> = reference.header.bodies.iter().map(|b| b.pinned).collect();
    let scale = super::motion::speed_scale(
        reference.records.iter().flat_map(|r| {
            (r.bodies.iter().zip(&pinned))
                .filter(|(_, p)| !**p)
                .map(|(b, _)| (b.v[0].hypot(b.v[1]), b.omega.abs()))
        }),
        g[0].hypot(g[1]),
        reference.header.dt,
    );
    let times: Vec<f64> = other.records.iter().map(|r| r.t).collect();
    let bodies: Vec<usize> = (0..other.header.bodies.len())
        .filter(|&j| !other.header.bodies[j].pinned)
        .collect();
    let state = |k: usize, j: usize| {
        let b = &other.records[k].bodies[j];
        super::motion::Moving {
            x: [b.x[0], b.x[1], 0.0],
            v: [b.v[0], b.v[1], 0.0],
            omega: [b.omega, 0.0, 0.0],
        }
    };
    let turned = |k: usize, j: usize| {
        let d = other.records[k].bodies[j].theta - other.records[k - 1].bodies[j].theta;
        [d, 0.0, 0.0]
    };
    let label = |j: usize| match map.iter().position(|&m| m == j) {
        Some(i) => format!("body {i} ({:?})", reference.header.bodies[i].name),
        None => format!("the trace's body {j}"),
    };
    super::motion::motion_row(
        &times,
        &bodies,
        &state,
        &turned,
        &label,
        super::motion::Scale {
            unit: "block",
            speed_unit: "block/t",
            dt: reference.header.dt,
            speed: scale,
        },
    )
}
