//! Observables of a run, measured on its trace alone (rigidref's, rapier's and every Python
//! mirror's alike): the quantities each known-answer scene's closed form speaks of, and what every
//! contact scene is judged by (penetration, energy, the physical criteria on the engine's own
//! contact impulses). docs/validation.md §"Observables".

use super::scenes::{Known, KnownScene};
use crate::rigid3d::diagnostics::{flip_period, sign_changes};
use crate::rigid3d::frame::ContactFrame;
use crate::rigid3d::scene::Scene;
use crate::rigid3d::trace::{Trace, TraceRecord};
use crate::rigid3d::world::World;
use crate::solve::criteria::contact_criteria;
use nalgebra::{Matrix3, SVector, Vector3};

/// Speed below which a body counts as stopped, m/s (a thousandth of the slowest start here).
pub const STOP_SPEED: f64 = 1e-3;

/// One measured quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// Its key in the JSON report.
    pub key: &'static str,
    /// Its value (`None`: the run never showed it, e.g. a body that never stopped).
    pub value: Option<f64>,
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn rotation(r: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| r[i][j])
}

/// Time of the first record at which `f` holds, s.
fn first_time(records: &[TraceRecord], f: impl Fn(&TraceRecord) -> bool) -> Option<f64> {
    records.iter().find(|r| f(r)).map(|r| r.t)
}

/// The record nearest time `t`.
fn at(records: &[TraceRecord], t: f64) -> &TraceRecord {
    records
        .iter()
        .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
        .expect("a trace has records")
}

/// The penetration measure of each record, m: rigidref's (src/rigid3d/collide/penetration.rs)
/// on the record's body poses, whatever engine wrote them.
pub fn penetrations(scene: &Scene, records: &[TraceRecord]) -> Result<Vec<f64>, String> {
    let mut world = World::new(scene)?;
    Ok(records
        .iter()
        .map(|r| {
            for (b, s) in world.bodies.iter_mut().zip(&r.bodies) {
                b.x = v3(s.x);
                b.rotation = rotation(&s.rotation);
            }
            world.measure_penetration();
            world.deepest_penetration()
        })
        .collect())
}

/// The largest energy rise above the lowest energy seen so far, J: a contact model that adds
/// energy shows here (gravity and friction only take it away).
fn energy_rise(records: &[TraceRecord]) -> f64 {
    let mut lowest = f64::INFINITY;
    let mut rise: f64 = 0.0;
    for r in records {
        lowest = lowest.min(r.energy.total);
        rise = rise.max(r.energy.total - lowest);
    }
    rise
}

/// The physical criteria (ContactBench; src/solve/criteria.rs) of every contact of every record,
/// their largest values: the impulse λ the engine reported and the contact velocity c after the
/// step, v + ω × (p − x) of each body with x where the body was at the step's start (the previous
/// record) and v, ω at its end. `None` when the trace has no contacts with impulses.
pub fn criteria(mu: f64, records: &[TraceRecord]) -> Option<[f64; 3]> {
    let mut worst = [0.0f64; 3];
    let mut any = false;
    for pair in records.windows(2) {
        let (before, after) = (&pair[0], &pair[1]);
        for c in &after.contacts {
            let point = v3(c.p);
            let velocity = |i: i64| -> Vector3<f64> {
                if i < 0 {
                    return Vector3::zeros();
                }
                let (s0, s) = (&before.bodies[i as usize], &after.bodies[i as usize]);
                v3(s.v) + v3(s.omega).cross(&(point - v3(s0.x)))
            };
            let relative = velocity(c.bodies[0]) - velocity(c.bodies[1]);
            let frame = ContactFrame::from_normal(&v3(c.n));
            let cv = SVector::<f64, 3>::new(
                relative.dot(&frame.n),
                relative.dot(&frame.t1),
                relative.dot(&frame.t2),
            );
            let lambda = SVector::<f64, 3>::from(c.lambda);
            let k = contact_criteria(mu, &lambda, &cv);
            worst = [
                worst[0].max(k.primal),
                worst[1].max(k.dual),
                worst[2].max(k.complementarity),
            ];
            any = true;
        }
    }
    any.then_some(worst)
}

/// Σλn of the last `window` records' contacts between `bodies` (either order; −1 the ground),
/// divided by `weight` (N·s per step), averaged over those records.
fn layer_ratio(records: &[TraceRecord], bodies: [i64; 2], weight: f64, window: usize) -> f64 {
    let tail = &records[records.len().saturating_sub(window)..];
    let sum: f64 = tail
        .iter()
        .map(|r| {
            r.contacts
                .iter()
                .filter(|c| c.bodies == bodies || c.bodies == [bodies[1], bodies[0]])
                .map(|c| c.lambda[0])
                .sum::<f64>()
        })
        .sum();
    sum / (weight * tail.len() as f64)
}

/// The intermediate principal axis of body 0, body frame.
fn intermediate_axis(scene: &Scene) -> Vector3<f64> {
    let eigen = scene.bodies[0].inertia.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    eigen.eigenvectors.column(order[1]).into_owned()
}

/// Sign-change times of body 0's spin about its intermediate axis (body frame), s.
pub fn flips(scene: &Scene, records: &[TraceRecord]) -> Vec<f64> {
    let axis = intermediate_axis(scene);
    let samples: Vec<(f64, f64)> = records
        .iter()
        .map(|r| {
            let s = &r.bodies[0];
            (
                r.t,
                (rotation(&s.rotation).transpose() * v3(s.omega)).dot(&axis),
            )
        })
        .collect();
    sign_changes(&samples)
}

/// Every observable of `known` measured on `trace` of `scene`.
pub fn observe(scene: &Scene, known: &KnownScene, trace: &Trace) -> Result<Vec<Measured>, String> {
    let r = &trace.records;
    if r.len() < 2 {
        return Err(format!("{}: fewer than two records", trace.header.source));
    }
    let last = &r[r.len() - 1];
    let (first, end) = (&r[0], last.t);
    let p = &scene.params;
    let m = |key, value| Measured { key, value };
    let speed = |rec: &TraceRecord, i: usize| v3(rec.bodies[i].v).norm();
    let mut out = Vec::new();
    match known.known {
        Known::Slide => {
            out.push(m(
                "stop_time",
                first_time(&r[1..], |rec| speed(rec, 0) < STOP_SPEED),
            ));
            let d = v3(last.bodies[0].x) - v3(first.bodies[0].x);
            out.push(m("stop_distance", Some((d.x * d.x + d.z * d.z).sqrt())));
        }
        Known::Drag => {
            out.push(m(
                "slip_time",
                first_time(r, |rec| rec.bodies[0].v[0] > STOP_SPEED),
            ));
            out.push(m("final_speed", Some(last.bodies[0].v[0])));
        }
        Known::Rolls | Known::Slides => {
            let half = at(r, end / 2.0);
            let a = (last.bodies[0].v[0] - half.bodies[0].v[0]) / (last.t - half.t);
            out.push(m("acceleration", Some(a)));
            let radius = scene.bodies[0].ellipsoid.map_or(0.0, |e| e.semi_axes.x);
            // The contact point is r below the centre (the ground is y = 0; gravity is tilted).
            let lever = Vector3::new(0.0, -radius, 0.0);
            let contact_velocity =
                |rec: &TraceRecord| v3(rec.bodies[0].v) + v3(rec.bodies[0].omega).cross(&lever);
            if known.known == Known::Rolls {
                out.push(m("slip_speed", Some(contact_velocity(last).norm())));
            } else {
                let alpha =
                    -(last.bodies[0].omega[2] - half.bodies[0].omega[2]) / (last.t - half.t);
                out.push(m("spin_up", Some(alpha)));
            }
        }
        Known::Flip => {
            let changes = flips(scene, r);
            out.push(m("first_flip", changes.first().copied()));
            out.push(m("flip_period", flip_period(&changes)));
            out.push(m(
                "energy_drift",
                Some(last.energy.total / first.energy.total - 1.0),
            ));
        }
        Known::Projectile => {
            let b = &scene.bodies[0];
            let exact = b.x0 + b.v0 * end + p.gravity * (end * end / 2.0);
            out.push(m(
                "position_error",
                Some((v3(last.bodies[0].x) - exact).norm()),
            ));
            let spin = |rec: &TraceRecord| {
                let s = &rec.bodies[0];
                let rot = rotation(&s.rotation);
                (rot * b.inertia * rot.transpose() * v3(s.omega)).norm()
            };
            out.push(m(
                "angular_momentum_drift",
                Some(spin(last) / spin(first) - 1.0),
            ));
        }
        Known::HeavyOnLight => {
            let drop = first.bodies[1].x[1] - last.bodies[1].x[1];
            let slide = (v3(last.bodies[0].x) - v3(first.bodies[0].x)).xz().norm();
            let holds = drop.abs() < 1e-3 && slide < 1e-3;
            out.push(m("holds", Some(if holds { 1.0 } else { 0.0 })));
            out.push(m("heavy_drop", Some(drop)));
            let g = p.gravity.norm() * p.h();
            let (light, heavy) = (scene.bodies[0].mass, scene.bodies[1].mass);
            out.push(m(
                "lower_layer",
                Some(layer_ratio(r, [0, -1], (light + heavy) * g, 100)),
            ));
            out.push(m(
                "upper_layer",
                Some(layer_ratio(r, [1, 0], heavy * g, 100)),
            ));
        }
        Known::Rest => {
            out.push(m("rest_height", Some(last.bodies[0].x[1])));
            out.push(m("rest_speed", Some(speed(last, 0))));
            let weight = scene.bodies[0].mass * p.gravity.norm() * p.h();
            out.push(m(
                "carried_weight",
                Some(layer_ratio(r, [0, -1], weight, 20)),
            ));
        }
        Known::Stack => {
            let drift = (0..scene.bodies.len())
                .map(|i| (v3(last.bodies[i].x) - v3(first.bodies[i].x)).norm())
                .fold(0.0, f64::max);
            out.push(m("holds", Some(if drift < 0.01 { 1.0 } else { 0.0 })));
            out.push(m("largest_drift", Some(drift)));
        }
    }
    if p.check_collisions {
        let depth = penetrations(scene, r)?;
        out.push(m(
            "deepest_penetration",
            Some(depth.iter().copied().fold(0.0, f64::max)),
        ));
        out.push(m("energy_rise", Some(energy_rise(r))));
        if let Some([primal, dual, complementarity]) = criteria(p.mu, r) {
            out.push(m("criterion_primal", Some(primal)));
            out.push(m("criterion_dual", Some(dual)));
            out.push(m("criterion_complementarity", Some(complementarity)));
        }
    }
    Ok(out)
}
