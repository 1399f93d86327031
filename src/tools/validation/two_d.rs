//! The 2D part of `rigidref validate` (docs/validation.md §"2D: pymunk"): the 2D known-answer
//! scenes (scenes/blocks/block_slide.json, bar_topple.json, stack_rest.json), their mirror
//! description for pymunk (python/mirrors/pymunk_mirror.py), rigidref's exact (Newton) run, and
//! the observables measured on every run's 2D trace by rigidref's own code (the penetration by
//! rigidref's own disc detection on the run's poses).
//!
//! rigidref's 2D bodies collide as one disc of radius √2/2 per block (docs/blocks2d.md
//! §"Collision"), so a body sliding on a pinned row of blocks rides over the discs' bumps: the flat
//! Coulomb slide's v₀²/(2μg) is not this model's answer. The slide and the topple are therefore
//! judged against rigidref's exact run (which has no tuning: an exact solve of each step's
//! problem), and the stack's rest (no drift, overlap within the slop) is judged absolutely.

use super::engines::{Engine, Settings};
use super::judge::Expected;
use super::observe::Measured;
use super::{RunResult, RunStatus, SceneResult};
use crate::blocks2d::collide::{Contact2, detect_contacts};
use crate::blocks2d::disc_tree::BLOCK_RADIUS;
use crate::blocks2d::trace::{Contact2Record, Record2, TraceHeader2};
use crate::blocks2d::world::World2;
use crate::sim::{Flow, drive};
use crate::solve::criteria::contact_criteria;
use crate::tools::viewing::plot::PlottedRun;
use crate::tools::viewing::series::{Plot, Series};
use nalgebra::{SVector, Vector2};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Speed below which a 2D body counts as stopped, blocks per time unit (a thousandth of the
/// slide's start).
pub const STOP_SPEED_2D: f64 = 1e-3;

/// What a 2D scene's answer is known to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Known2 {
    /// Body 0 settles on the ground, is pushed along it (the scene's impulse) and slides to rest.
    Slide,
    /// Body 0, a bar standing on the ground, is pushed at its top and topples onto its side.
    Topple,
    /// The bodies settle into a stack that then stays at rest.
    Rest,
}

/// One 2D scene of the set.
#[derive(Clone, Copy, Debug)]
pub struct KnownScene2 {
    /// The file in the scene folder (under `blocks/`).
    pub file: &'static str,
    /// How long it runs, time units.
    pub time: f64,
    /// What is known about it.
    pub known: Known2,
}

/// The 2D set, in report order.
pub const SCENES_2D: [KnownScene2; 3] = [
    KnownScene2 {
        file: "blocks/block_slide.json",
        time: 10.0,
        known: Known2::Slide,
    },
    KnownScene2 {
        file: "blocks/bar_topple.json",
        time: 12.0,
        known: Known2::Topple,
    },
    KnownScene2 {
        file: "blocks/stack_rest.json",
        time: 8.0,
        known: Known2::Rest,
    },
];

/// Time from which the stack is judged at rest, time units (the bodies fall 0.586 blocks onto
/// one another first: under g = 1 that takes about 1.1 time units per level, and rigidref's run is
/// settled to round-off by 2).
pub const REST_FROM: f64 = 3.0;

/// The stem of a 2D scene file (`block_slide`).
pub fn stem(file: &str) -> &str {
    file.rsplit('/')
        .next()
        .unwrap_or(file)
        .trim_end_matches(".json")
}

/// The 2D scene named `name` (its stem, with or without `.json`).
pub fn known_scene2(name: &str) -> Option<KnownScene2> {
    let name = name.strip_suffix(".json").unwrap_or(name);
    SCENES_2D.iter().find(|s| stem(s.file) == name).copied()
}

/// A body of the 2D mirror description.
#[derive(Clone, Debug, Serialize)]
pub struct MirrorBody2 {
    /// `body{i}`, as in rigidref's trace.
    pub name: String,
    /// Mass (a black block is 1).
    pub mass: f64,
    /// Moment of inertia about the centre of mass, mass · blocks².
    pub inertia: f64,
    /// Pinned (static): infinite mass.
    pub pinned: bool,
    /// Initial centre of mass, blocks.
    pub x0: [f64; 2],
    /// Initial angle, rad.
    pub theta0: f64,
    /// Initial velocity, blocks per time unit.
    pub v0: [f64; 2],
    /// Initial angular velocity, rad per time unit.
    pub omega0: f64,
    /// Each block's centre in the body frame (relative to the centre of mass), blocks.
    pub blocks: Vec<[f64; 2]>,
}

/// A scripted impulse of the description.
#[derive(Clone, Debug, Serialize)]
pub struct MirrorImpulse2 {
    /// Applied at the start of the first step at or after this time.
    pub time: f64,
    /// The body.
    pub body: usize,
    /// The impulse, mass · blocks per time unit.
    pub impulse: [f64; 2],
    /// The world point, blocks (`None`: the centre of mass).
    pub point: Option<[f64; 2]>,
}

/// What the pymunk mirror needs of a 2D scene (docs/validation.md §"2D: pymunk").
#[derive(Clone, Debug, Serialize)]
pub struct MirrorScene2 {
    /// [`super::mirror::MIRROR_FORMAT`].
    pub format: &'static str,
    /// [`super::mirror::MIRROR_VERSION`].
    pub version: u32,
    /// 2.
    pub dimension: u32,
    /// The scene's name (the file's stem).
    pub scene: String,
    /// The same.
    pub scene_file: String,
    /// The scene file.
    pub source: String,
    /// Step, time units.
    pub dt: f64,
    /// Substeps per step.
    pub substeps: u32,
    /// The engine's step dt / substeps, time units.
    pub h: f64,
    /// Steps to run.
    pub frames: u64,
    /// Gravity, blocks per time unit².
    pub gravity: [f64; 2],
    /// Friction coefficient of every pair.
    pub mu: f64,
    /// Restitution of every pair.
    pub restitution: f64,
    /// rigidref's post-stabilisation slop (the overlap it lets stand), blocks.
    pub slop: f64,
    /// Every block's contact disc radius, √2/2 blocks.
    pub block_radius: f64,
    /// The bodies, in rigidref's order.
    pub bodies: Vec<MirrorBody2>,
    /// The scripted impulses.
    pub impulses: Vec<MirrorImpulse2>,
}

impl MirrorScene2 {
    /// The description of `world` (as loaded) run for `frames` steps. A scene with what the mirror
    /// cannot reproduce (shakes, pins, springs, penalty contact, adaptive substeps) is refused.
    pub fn of_world(
        world: &World2,
        source: &str,
        name: &str,
        frames: u64,
    ) -> Result<MirrorScene2, String> {
        let p = &world.params;
        let refuse = |what: &str| {
            Err(format!(
                "{source}: {what}: the pymunk mirror does not reproduce it"
            ))
        };
        if !world.shakes.is_empty() {
            return refuse("shakes");
        }
        if !world.pins.is_empty() || !world.springs.is_empty() {
            return refuse("pins or springs");
        }
        if p.contact_model != crate::blocks2d::params::ContactModel::Pgs {
            return refuse("penalty contact");
        }
        if p.max_travel.is_some() {
            return refuse("adaptive substeps");
        }
        let g = p.gravity_vector();
        Ok(MirrorScene2 {
            format: super::mirror::MIRROR_FORMAT,
            version: super::mirror::MIRROR_VERSION,
            dimension: 2,
            scene: name.to_string(),
            scene_file: name.to_string(),
            source: source.to_string(),
            dt: p.dt,
            substeps: p.substeps,
            h: p.h(),
            frames,
            gravity: [g.x, g.y],
            mu: p.mu,
            restitution: p.restitution,
            slop: p.slop,
            block_radius: BLOCK_RADIUS,
            bodies: world
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| MirrorBody2 {
                    name: format!("body{i}"),
                    mass: b.mass,
                    inertia: b.inertia,
                    pinned: b.pinned,
                    x0: [b.x.x, b.x.y],
                    theta0: b.theta,
                    v0: [b.v.x, b.v.y],
                    omega0: b.omega,
                    blocks: b.blocks.iter().map(|k| [k.local.x, k.local.y]).collect(),
                })
                .collect(),
            impulses: world
                .impulses
                .iter()
                .map(|i| MirrorImpulse2 {
                    time: i.time,
                    body: i.body,
                    impulse: [i.impulse.x, i.impulse.y],
                    point: i.point.map(|q| [q.x, q.y]),
                })
                .collect(),
        })
    }
}

/// A loaded 2D scene of the set.
pub struct Loaded2 {
    /// Which one.
    pub known: KnownScene2,
    /// The scene file.
    pub path: PathBuf,
    /// Its world as loaded (the initial state).
    pub world: World2,
    /// Steps to run.
    pub frames: u64,
    /// The description written for the mirrors.
    pub description: PathBuf,
}

/// Loads `known` from `scene_dir` and writes its description into `descriptions`.
pub fn load(known: KnownScene2, scene_dir: &Path, descriptions: &Path) -> Result<Loaded2, String> {
    let path = scene_dir.join(known.file);
    if !path.is_file() {
        return Err(format!(
            "{}: not found (give the folder of rigidref's scenes with --scene-dir)",
            path.display()
        ));
    }
    let scene = crate::blocks2d::scene::load_scene2(&path).map_err(|e| e.to_string())?;
    let frames = crate::sim::steps_in(known.time, scene.world.params.dt, "")?;
    let name = stem(known.file);
    let description =
        MirrorScene2::of_world(&scene.world, &path.display().to_string(), name, frames)?;
    let dpath = descriptions.join(format!("{name}.mirror.json"));
    let text = serde_json::to_string_pretty(&description).map_err(|e| e.to_string())?;
    std::fs::write(&dpath, text + "\n")
        .map_err(|e| format!("{}: cannot write: {e}", dpath.display()))?;
    Ok(Loaded2 {
        known,
        path,
        world: scene.world,
        frames,
        description: dpath,
    })
}

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
/// `super::observe::criteria`) of every contact of `records` that carries its contact velocity
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

fn push_time(world: &World2) -> f64 {
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

/// The angle at which the toppling bar counts as having hit the ground, rad (80°: lying on its
/// side is 90°, and its top block's disc meets the ground's before that).
pub const HIT_ANGLE: f64 = 80.0 * std::f64::consts::PI / 180.0;

fn x(
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

/// The expectations of a 2D scene: closed forms where the disc model has them, else rigidref's
/// exact run (`reference`, its own observables).
pub fn expectations_2d(loaded: &Loaded2, reference: &[Measured]) -> Vec<Expected> {
    let p = &loaded.world.params;
    let theirs = |key: &str| {
        reference
            .iter()
            .find(|m| m.key == key)
            .and_then(|m| m.value)
    };
    let slop = p.slop;
    let pen = |from: &str| {
        x(
            "penetration",
            "deepest disc overlap",
            "blocks",
            Some(0.0),
            Some(2.0 * slop),
            format!(
                "rigidref's disc overlap on the run's poses{from}; within twice rigidref's slop {slop} (the overlap its post-stabilisation lets stand)"
            ),
        )
    };
    let mut out = match loaded.known.known {
        Known2::Slide => {
            let b = &loaded.world.bodies[0];
            let v0 = loaded
                .world
                .impulses
                .first()
                .map_or(0.0, |i| i.impulse.norm() / b.mass);
            let g = p.gravity;
            let flat = v0 * v0 / (2.0 * p.mu * g);
            let (t, d) = (theirs("stop_time"), theirs("stop_distance"));
            vec![
                x(
                    "stop_time",
                    "stop time after the push",
                    "time",
                    t,
                    t.map(|t| 2.0 * p.dt + 0.05 * t),
                    format!(
                        "rigidref's exact run (a flat Coulomb slide would stop after v₀/(μg) = {:.4}; the discs' bumps stop it sooner); within 2 steps + 5 %",
                        v0 / (p.mu * g)
                    ),
                ),
                x(
                    "stop_distance",
                    "slide distance",
                    "blocks",
                    d,
                    d.map(|d| 0.05 * d.abs()),
                    format!(
                        "rigidref's exact run (a flat Coulomb slide would go v₀²/(2μg) = {flat:.4}; over the ground's discs it climbs bumps 0.09 high); within 5 %"
                    ),
                ),
                pen(""),
            ]
        }
        Known2::Topple => {
            let t = theirs("hit_time");
            vec![
                x(
                    "hit_time",
                    "time from the push to 80°",
                    "time",
                    t,
                    t.map(|t| 2.0 * p.dt + 0.05 * t),
                    "rigidref's exact run; within 2 steps + 5 %".to_string(),
                ),
                x(
                    "final_angle",
                    "final |θ|",
                    "rad",
                    Some(std::f64::consts::FRAC_PI_2),
                    Some(0.05),
                    "lying on its side, π/2; within 0.05 rad (its ends rest on the ground's discs)"
                        .to_string(),
                ),
                pen(""),
            ]
        }
        Known2::Rest => vec![
            x(
                "rest_drift",
                "largest displacement after settling",
                "blocks",
                Some(0.0),
                Some(0.01),
                format!("0 from t = {REST_FROM} on (a stack at rest stays); within 0.01 block"),
            ),
            pen(&format!(" from t = {REST_FROM} on")),
        ],
    };
    out.push(x("criterion_primal", "primal criterion (max)", "mass·block/time", None, None,
        "reported: 0 for Coulomb's law (ContactBench), on each step's last substep's contacts and impulses".to_string()));
    out.push(x(
        "criterion_dual",
        "dual criterion (max)",
        "block/time",
        None,
        None,
        "reported: 0 for Coulomb's law".to_string(),
    ));
    out.push(x(
        "criterion_complementarity",
        "complementarity (max)",
        "mass·block²/time²",
        None,
        None,
        "reported: 0 for Coulomb's law".to_string(),
    ));
    out
}

/// rigidref's exact run of a 2D scene, measured and judged: the scene's result with that one run
/// (the engines' rows are added to it by [`engine_run`]).
pub fn reference(l: &Loaded2, out: &Path) -> Result<SceneResult, String> {
    let name = stem(l.known.file);
    let dir = out.join("traces").join("rigidref");
    super::create(&dir)?;
    let path = dir.join(format!("{name}.jsonl"));
    run_rigidref_2d(l, &path)?;
    let records = read_trace_2d(&path, l.world.bodies.len())?;
    let reference = observe_2d(l, &records);
    let expected = expectations_2d(l, &reference);
    let run = RunResult {
        engine: Engine::Rigidref,
        settings: None,
        status: RunStatus::Ran,
        trace: Some(super::relative(out, &path)),
        model: None,
        measured: super::judged(&expected, &reference, &reference),
        plotted: Some(plotted_2d(
            format!("{} (Newton)", Engine::Rigidref.name()),
            &records,
            l,
        )),
    };
    Ok(SceneResult {
        file: format!("{name}.json"),
        name: name.to_string(),
        source: l.path.display().to_string(),
        dimension: 2,
        frames: l.frames,
        dt: l.world.params.dt,
        expected,
        runs: vec![run],
    })
}

/// A 2D engine's run of `settings` on `l` (its trace already written by the Python mirror under
/// `out/traces/ENGINE-SETTINGS/`), measured and judged against `scene`'s expectations and
/// rigidref's run; `failure`: the engine's process failed as a whole.
pub fn engine_run(
    l: &Loaded2,
    scene: &SceneResult,
    engine: Engine,
    settings: Settings,
    failure: Option<&str>,
    out: &Path,
) -> RunResult {
    let name = stem(l.known.file);
    let mut run = RunResult {
        engine,
        settings: Some(settings),
        status: RunStatus::Ran,
        trace: None,
        model: None,
        measured: Vec::new(),
        plotted: None,
    };
    let dir = out
        .join("traces")
        .join(format!("{}-{}", engine.name(), settings.name()));
    let path = dir.join(format!("{name}.jsonl"));
    let model_path = dir.join(format!("{name}.model.json"));
    let outcome = match failure {
        Some(e) => Err(e.to_string()),
        None => super::read_model(&model_path),
    };
    match outcome.and_then(|model| read_trace_2d(&path, l.world.bodies.len()).map(|r| (model, r))) {
        Ok((model, records)) => {
            run.model = model;
            run.trace = Some(super::relative(out, &path));
            run.measured = super::judged(
                &scene.expected,
                &observe_2d(l, &records),
                &super::reference_of(scene),
            );
            run.plotted = Some(plotted_2d(run.label(), &records, l));
        }
        Err(e) => run.status = RunStatus::Failed(e),
    }
    run
}

/// The panels of a 2D scene's plot: what its observables are measured from.
pub const PANELS_2D: [(&str, &str, &str); 5] = [
    (
        "position",
        "largest displacement of a body from its start",
        "blocks",
    ),
    ("speed", "largest speed of a body", "blocks/time"),
    ("angle", "largest |θ| of a body", "rad"),
    (
        "penetration",
        "deepest disc overlap (rigidref's detection)",
        "blocks",
    ),
    ("energy", "total energy", "mass·block²/time²"),
];

/// A 2D run's series for the scene's plot ([`PANELS_2D`], bodies that are not pinned), each
/// against time: the quantities its observables are measured from. docs/validation.md
/// §"The report".
pub fn plotted_2d(label: String, records: &[Record2], l: &Loaded2) -> PlottedRun {
    let moving: Vec<usize> = (0..l.world.bodies.len())
        .filter(|&i| !l.world.bodies[i].pinned)
        .collect();
    let Some(first) = records.first() else {
        return PlottedRun {
            label,
            t: Vec::new(),
            plots: Vec::new(),
        };
    };
    let largest = |r: &Record2, f: &dyn Fn(&Record2, usize) -> f64| {
        moving.iter().map(|&i| f(r, i)).fold(0.0, f64::max)
    };
    let mut world = l.world.clone();
    let mut contacts = Vec::new();
    let values: [Vec<Option<f64>>; 5] = [
        records
            .iter()
            .map(|r| {
                Some(largest(r, &|r, i| {
                    let (a, b) = (r.bodies[i].x, first.bodies[i].x);
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
                }))
            })
            .collect(),
        records
            .iter()
            .map(|r| {
                Some(largest(r, &|r, i| {
                    (r.bodies[i].v[0].powi(2) + r.bodies[i].v[1].powi(2)).sqrt()
                }))
            })
            .collect(),
        records
            .iter()
            .map(|r| Some(largest(r, &|r, i| r.bodies[i].theta.abs())))
            .collect(),
        records
            .iter()
            .map(|r| Some(overlap_at(&mut world, r, &mut contacts)))
            .collect(),
        records.iter().map(|r| Some(r.energy.total)).collect(),
    ];
    let plots = PANELS_2D
        .iter()
        .zip(values)
        .map(|(&(key, title, unit), values)| Plot {
            key,
            title: title.into(),
            unit: unit.into(),
            log: false,
            series: vec![Series {
                name: String::new(),
                values,
            }],
        })
        .collect();
    PlottedRun {
        label,
        t: records.iter().map(|r| r.t).collect(),
        plots,
    }
}
