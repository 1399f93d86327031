//! Observables of a run, and their comparison between rigidref and the rapier3d mirror.
//! docs/verification.md §"rapier3d" lists each observable, why the two may differ, and the
//! tolerance used.

use super::rapier::{RapierMirror, Snapshot};
use crate::rigid3d::diagnostics::{flip_period, sign_changes};
use crate::rigid3d::scene::Scene;
use crate::rigid3d::world::World;
use crate::sim::{Flow, drive};
use serde::Serialize;

/// A run as a sequence of states, one per frame (index 0 is the initial state).
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// Frame step, s.
    pub dt: f64,
    /// States per frame.
    pub states: Vec<Vec<Snapshot>>,
    /// Whether the frame had contacts.
    pub contact: Vec<bool>,
}

/// Runs rigidref on `scene` for `steps` frames.
pub fn record_rigidref(scene: &Scene, steps: u64) -> Result<Trajectory, String> {
    let mut world = World::new(scene)?;
    let snap = |w: &World| -> Vec<Snapshot> {
        w.bodies
            .iter()
            .map(|b| Snapshot {
                x: b.x,
                rotation: b.rotation,
                v: b.v,
                omega: b.omega,
            })
            .collect()
    };
    let mut t = Trajectory {
        dt: scene.params.dt,
        states: vec![snap(&world)],
        contact: vec![false],
    };
    drive(&mut world, steps, |w, _| {
        t.states.push(snap(w));
        t.contact.push(!w.solves.is_empty());
        Ok::<_, String>(Flow::Continue)
    })?;
    Ok(t)
}

/// Runs the rapier mirror of `scene` for `steps` frames.
pub fn record_rapier(scene: &Scene, steps: u64) -> Result<Trajectory, String> {
    let mut mirror = RapierMirror::new(scene)?;
    let mut t = Trajectory {
        dt: scene.params.dt,
        states: vec![mirror.snapshots()],
        contact: vec![false],
    };
    for _ in 0..steps {
        mirror.step();
        t.states.push(mirror.snapshots());
        t.contact.push(mirror.has_contacts());
    }
    Ok(t)
}

/// One observable measured on both runs.
#[derive(Clone, Debug, Serialize)]
pub struct Observable {
    /// What is measured.
    pub name: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// rigidref's value.
    pub rigidref: f64,
    /// rapier's value.
    pub rapier: f64,
    /// An analytic value both should be near, when there is one.
    pub reference: Option<f64>,
    /// Largest accepted difference (absolute, in `unit`), or `None` for an observable that is
    /// reported only.
    pub tolerance: Option<f64>,
    /// Why the two may differ and where the tolerance comes from.
    pub note: &'static str,
    /// Whether every difference (rigidref − rapier, and each against the reference) is within
    /// the tolerance.
    pub passed: bool,
}

fn observable(
    name: &'static str,
    unit: &'static str,
    (a, b): (f64, f64),
    reference: Option<f64>,
    tolerance: Option<f64>,
    note: &'static str,
) -> Observable {
    let passed = match tolerance {
        None => true,
        Some(tol) => {
            (a - b).abs() <= tol
                && reference.is_none_or(|r| (a - r).abs() <= tol && (b - r).abs() <= tol)
        }
    };
    Observable {
        name,
        unit,
        rigidref: a,
        rapier: b,
        reference,
        tolerance,
        note,
        passed,
    }
}

/// Total energy of the bodies of `scene` in `states`, J.
fn energy(scene: &Scene, states: &[Snapshot]) -> f64 {
    scene
        .bodies
        .iter()
        .zip(states)
        .map(|(d, s)| {
            let inertia = s.rotation * d.inertia * s.rotation.transpose();
            0.5 * d.mass * s.v.norm_squared() + 0.5 * s.omega.dot(&(inertia * s.omega))
                - d.mass * scene.params.gravity.dot(&s.x)
        })
        .sum()
}

/// The flip period of body 0 (s): sign changes of its angular velocity about its intermediate
/// principal axis, in its body frame.
fn flip(scene: &Scene, t: &Trajectory) -> Option<f64> {
    let eigen = scene.bodies[0].inertia.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let axis = eigen.eigenvectors.column(order[1]).into_owned();
    let samples: Vec<(f64, f64)> = t
        .states
        .iter()
        .enumerate()
        .map(|(k, s)| {
            (
                k as f64 * t.dt,
                (s[0].rotation.transpose() * s[0].omega).dot(&axis),
            )
        })
        .collect();
    flip_period(&sign_changes(&samples))
}

/// The observables that apply to `scene`, measured on both trajectories (same scene, same
/// number of frames).
pub fn compare(scene: &Scene, ours: &Trajectory, theirs: &Trajectory) -> Vec<Observable> {
    let p = &scene.params;
    let g = p.gravity.norm();
    let last = ours.states.len() - 1;
    let mut out = Vec::new();
    let first_contact = |t: &Trajectory| t.contact.iter().position(|&c| c).map(|k| k as f64 * t.dt);
    if let (Some(a), Some(b)) = (first_contact(ours), first_contact(theirs)) {
        out.push(observable(
            "time of first contact",
            "s",
            (a, b),
            None,
            Some(p.dt * (1.0 + 1e-9)),
            "within one frame: rigidref detects a contact once a vertex is below the surface, rapier predicts it (speculative contacts) and may touch a frame earlier",
        ));
    }
    let body0_rest =
        |t: &Trajectory| t.states[last][0].v.norm() < 0.05 && t.states[last][0].omega.norm() < 0.1;
    // Where bodies are resting is compared only when every body rests in both runs: a scene that
    // is still moving (or chaotic, like a brick sliding off a ball) may end anywhere.
    let all_rest = |t: &Trajectory| {
        t.states[last]
            .iter()
            .all(|s| s.v.norm() < 0.05 && s.omega.norm() < 0.1)
    };
    if g > 0.0 && p.check_collisions && all_rest(ours) && all_rest(theirs) {
        let radius = scene.bodies[0].mesh.bounding_radius();
        out.push(observable(
            "rest height of body 0",
            "m",
            (ours.states[last][0].x.y, theirs.states[last][0].x.y),
            None,
            Some(0.02 * radius),
            "within 2% of the body's radius: rigidref rests up to the stabilisation slop (5 mm) deep, rapier on its contact skin",
        ));
        let r = ours.states[last][0].rotation.transpose() * theirs.states[last][0].rotation;
        let angle = ((r.trace() - 1.0) / 2.0)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        out.push(observable(
            "rest orientation difference of body 0",
            "°",
            (angle, 0.0),
            None,
            None,
            "reported only: a symmetric body rests in any of several equivalent orientations",
        ));
    }
    let v0 = scene.bodies[0].v0;
    let horizontal = (v0.x * v0.x + v0.z * v0.z).sqrt();
    if g > 0.0
        && p.mu > 0.0
        && horizontal > 0.5
        && v0.y.abs() < 1e-9
        && body0_rest(ours)
        && body0_rest(theirs)
    {
        let slide = |t: &Trajectory| {
            let d = t.states[last][0].x - t.states[0][0].x;
            (d.x * d.x + d.z * d.z).sqrt()
        };
        let expected = horizontal * horizontal / (2.0 * p.mu * g);
        out.push(observable(
            "sliding distance of body 0",
            "m",
            (slide(ours), slide(theirs)),
            Some(expected),
            Some(0.05 * expected),
            "within 5% of each other and of v0²/(2μg): rigidref's symplectic Euler stops short by v0 h/2, rapier's substepped solver by less",
        ));
    }
    let at_rest_start = scene
        .bodies
        .iter()
        .all(|b| b.v0 == nalgebra::Vector3::zeros() && b.omega0 == nalgebra::Vector3::zeros());
    if g > 0.0 && p.check_collisions && scene.bodies.len() >= 2 && at_rest_start {
        let standing = |t: &Trajectory| {
            let ok = scene.bodies.iter().enumerate().all(|(i, d)| {
                let s0 = &t.states[0][i];
                let s = &t.states[last][i];
                let drift = ((s.x.x - s0.x.x).powi(2) + (s.x.z - s0.x.z).powi(2)).sqrt();
                drift < 0.25 * d.mesh.bounding_radius()
                    && (s.x.y - s0.x.y).abs() < 0.25 * d.mesh.bounding_radius()
            });
            if ok { 1.0 } else { 0.0 }
        };
        if all_rest(ours) && all_rest(theirs) {
            let size = scene
                .bodies
                .iter()
                .map(|d| crate::rigid3d::collide::penetration::mesh_size(&d.mesh))
                .fold(f64::INFINITY, f64::min);
            let height = |t: &Trajectory, i: usize| t.states[last][i].x.y;
            let worst = (0..scene.bodies.len())
                .max_by(|&i, &j| {
                    let d = |k| (height(ours, k) - height(theirs, k)).abs();
                    d(i).total_cmp(&d(j))
                })
                .unwrap_or(0);
            out.push(observable(
                "rest height, the body differing most",
                "m",
                (height(ours, worst), height(theirs, worst)),
                None,
                Some(0.02 * size),
                "within 2% of the smallest body's size: rigidref rests each contact up to the stabilisation slop (5 mm) deep, rapier on its contact skin, and a stack adds the differences up",
            ));
        }
        out.push(observable(
            "stack standing at the end (1 = yes)",
            "",
            (standing(ours), standing(theirs)),
            None,
            Some(0.0),
            "both must agree: every body within a quarter of its radius of where it started",
        ));
    }
    if g == 0.0 && scene.bodies.len() == 1 {
        // Present when either run flips at least twice; a run that does not flip counts as NaN,
        // which no tolerance accepts.
        let (a, b) = (flip(scene, ours), flip(scene, theirs));
        if a.is_some() || b.is_some() {
            let (a, b) = (a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN));
            out.push(observable(
                "Dzhanibekov flip period of body 0",
                "s",
                (a, b),
                None,
                Some(0.05 * if a.is_nan() { b } else { a }),
                "within 5%: both integrate the gyroscopic term, rigidref explicitly, rapier with its own gyroscopic correction",
            ));
        }
    }
    let e0 = energy(scene, &ours.states[0]);
    out.push(observable(
        "total energy at the end / at the start",
        "",
        (energy(scene, &ours.states[last]) / e0, energy(scene, &theirs.states[last]) / e0),
        None,
        None,
        "reported only: the two solvers dissipate differently in impacts (rigidref's are perfectly inelastic with Baumgarte push-out; rapier's soft contacts absorb)",
    ));
    out
}
