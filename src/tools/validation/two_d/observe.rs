//! rigidref's exact 2D run and the observables of any engine's 2D trace, measured by rigidref's
//! own code (the penetration by its own disc detection on the run's poses). docs/validation.md
//! §"2D: pymunk".

use super::*;
use crate::blocks2d::collide::{Contact2, detect_contacts};
use crate::blocks2d::trace::{Contact2Record, Record2, TraceHeader2};
use crate::blocks2d::world::World2;
use crate::sim::{Flow, drive};
use crate::solve::criteria::contact_criteria;
use crate::tools::validation::observe::Measured;
use nalgebra::{SVector, Vector2};
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// Runs rigidref with the exact (Newton) solver on the loaded world for `frames` steps, writing
/// every step to `path` as a 2D trace.
pub fn run_rigidref_2d(loaded: &Loaded2, path: &Path) -> Result<(), String> {
    let mut world = loaded.world.clone();
    world.params.solver = crate::solve::Solver::Newton;
    let io = |e: std::io::Error| format!("{}: cannot write: {e}", path.display());
    let file = std::fs::File::create(path)
        .map_err(|e| format!("{}: cannot create: {e}", path.display()))?;
    let mut out = std::io::BufWriter::new(file);
    let mut header = TraceHeader2::for_world(
        &world,
        stem(loaded.known.file),
        &loaded.path.display().to_string(),
    );
    header.overrides = vec!["solver=newton".into()];
    fn line<T: Serialize>(out: &mut impl Write, v: &T) -> std::io::Result<()> {
        serde_json::to_writer(&mut *out, v)?;
        out.write_all(b"\n")
    }
    line(&mut out, &header).map_err(io)?;
    line(&mut out, &record_with_contacts(&world)).map_err(io)?;
    drive(&mut world, loaded.frames, |w, _| {
        line(&mut out, &record_with_contacts(w)).map_err(io)?;
        Ok::<_, String>(Flow::Continue)
    })?;
    out.flush().map_err(io)
}

/// The record of `world` with its last substep's contacts, each with its impulse λ and its
/// contact velocity after the impulses c = (A + C) λ + b of the problem that substep solved (the
/// solver's own lever arms, from the bodies' positions at the substep's start; restitution is 0
/// in the set, so c is J u⁺). docs/validation.md §"2D: pymunk".
pub fn record_with_contacts(world: &World2) -> Record2 {
    let mut record = Record2::of_world(world, false);
    let solve = world
        .solves
        .last()
        .filter(|s| s.substep + 1 == world.substeps_in_step);
    record.contacts = Some(match solve {
        None => Vec::new(),
        Some(s) => {
            let velocity = s.problem.constraint_velocity(&s.lambda);
            s.contacts
                .iter()
                .zip(&s.lambda)
                .zip(&velocity)
                .map(|((k, l), c)| Contact2Record {
                    bodies: [k.body1 as i64, k.body2 as i64],
                    p: [k.point.x, k.point.y],
                    n: [k.normal.x, k.normal.y],
                    depth: k.depth,
                    lambda: [l[0], l[1]],
                    c: Some([c[0], c[1]]),
                })
                .collect()
        }
    });
    record
}

/// The physical criteria (ContactBench; src/solve/criteria.rs::contact_criteria, as 3D's
/// `crate::tools::validation::observe::criteria`) of every contact of `records` that carries its contact velocity
/// after the step: their largest (primal, dual, complementarity). Each record holds its step's
/// last substep's contacts, so these are the last substep's. `None` when no contact carries one.
/// docs/validation.md §"2D: pymunk".
pub fn criteria_2d(mu: f64, records: &[Record2]) -> Option<[f64; 3]> {
    let mut worst = [0.0f64; 3];
    let mut any = false;
    for c in records.iter().flat_map(|r| r.contacts.iter().flatten()) {
        let Some(velocity) = c.c else { continue };
        let k = contact_criteria(
            mu,
            &SVector::<f64, 2>::from(c.lambda),
            &SVector::<f64, 2>::from(velocity),
        );
        worst = [
            worst[0].max(k.primal),
            worst[1].max(k.dual),
            worst[2].max(k.complementarity),
        ];
        any = true;
    }
    any.then_some(worst)
}

/// The records of a 2D trace file (its header checked to be a 2D trace of `bodies` bodies).
pub fn read_trace_2d(path: &Path, bodies: usize) -> Result<Vec<Record2>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, first) = lines
        .next()
        .ok_or_else(|| format!("{}: empty trace", path.display()))?;
    let header: TraceHeader2 = serde_json::from_str(first)
        .map_err(|e| format!("{}:1: not a 2D trace header: {e}", path.display()))?;
    if header.dimension != 2 || header.bodies.len() != bodies {
        return Err(format!(
            "{}: a 2D trace of {} bodies was expected",
            path.display(),
            bodies
        ));
    }
    lines
        .map(|(k, l)| {
            let r: Record2 = serde_json::from_str(l)
                .map_err(|e| format!("{}:{}: {e}", path.display(), k + 1))?;
            if r.bodies.len() != bodies {
                return Err(format!(
                    "{}:{}: {} bodies, expected {bodies}",
                    path.display(),
                    k + 1,
                    r.bodies.len()
                ));
            }
            Ok(r)
        })
        .collect()
}

/// The deepest disc overlap of `world`'s bodies placed at `record`'s poses, blocks, by
/// rigidref's own detection (`detect_contacts`): the same measure on every engine's run.
pub fn overlap_at(world: &mut World2, record: &Record2, contacts: &mut Vec<Contact2>) -> f64 {
    for (b, s) in world.bodies.iter_mut().zip(&record.bodies) {
        b.x = Vector2::new(s.x[0], s.x[1]);
        b.theta = s.theta;
    }
    detect_contacts(&world.bodies, contacts);
    contacts.iter().map(|c| c.depth).fold(0.0, f64::max)
}

pub(super) fn push_time(world: &World2) -> f64 {
    world
        .impulses
        .iter()
        .map(|i| i.time)
        .fold(f64::INFINITY, f64::min)
}

/// The observables of a 2D run's records.
pub fn observe_2d(loaded: &Loaded2, records: &[Record2]) -> Vec<Measured> {
    let mut world = loaded.world.clone();
    let mut contacts = Vec::new();
    let overlaps: Vec<f64> = records
        .iter()
        .map(|r| overlap_at(&mut world, r, &mut contacts))
        .collect();
    let deepest = |from: f64| {
        records
            .iter()
            .zip(&overlaps)
            .filter(|(r, _)| r.t >= from - 1e-9)
            .map(|(_, o)| *o)
            .fold(0.0, f64::max)
    };
    let speed = |r: &Record2| (r.bodies[0].v[0].powi(2) + r.bodies[0].v[1].powi(2)).sqrt();
    let m = |key, value| Measured { key, value };
    let push = push_time(&loaded.world);
    let mut out = match loaded.known.known {
        Known2::Slide => {
            let start = records.iter().rev().find(|r| r.t <= push + 1e-9);
            let stop = records
                .iter()
                .find(|r| r.t > push + 1e-9 && speed(r) < STOP_SPEED_2D);
            let distance = start
                .zip(records.last())
                .map(|(a, b)| b.bodies[0].x[0] - a.bodies[0].x[0]);
            vec![
                m("stop_time", stop.map(|r| r.t - push)),
                m("stop_distance", distance),
                m("penetration", Some(deepest(0.0))),
            ]
        }
        Known2::Topple => {
            let hit = records
                .iter()
                .find(|r| r.bodies[0].theta.abs() >= HIT_ANGLE)
                .map(|r| r.t - push);
            vec![
                m("hit_time", hit),
                m(
                    "final_angle",
                    records.last().map(|r| r.bodies[0].theta.abs()),
                ),
                m("penetration", Some(deepest(0.0))),
            ]
        }
        Known2::Rest => {
            let start = records.iter().find(|r| r.t >= REST_FROM - 1e-9);
            let drift = start.map(|a| {
                records
                    .iter()
                    .filter(|r| r.t >= a.t)
                    .flat_map(|r| {
                        r.bodies.iter().zip(&a.bodies).map(|(b, b0)| {
                            ((b.x[0] - b0.x[0]).powi(2) + (b.x[1] - b0.x[1]).powi(2)).sqrt()
                        })
                    })
                    .fold(0.0, f64::max)
            });
            vec![
                m("rest_drift", drift),
                m("penetration", Some(deepest(REST_FROM))),
            ]
        }
    };
    if let Some([primal, dual, complementarity]) = criteria_2d(loaded.world.params.mu, records) {
        out.push(m("criterion_primal", Some(primal)));
        out.push(m("criterion_dual", Some(dual)));
        out.push(m("criterion_complementarity", Some(complementarity)));
    }
    out
}
