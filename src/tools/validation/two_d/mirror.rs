//! The 2D mirror description: the bodies, impulses and settings written for the Python mirrors
//! (python/mirrors/pymunk_mirror.py). docs/validation.md §"2D: pymunk".

use crate::blocks2d::disc_tree::BLOCK_RADIUS;
use crate::blocks2d::world::World2;
use serde::Serialize;

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
    /// [`crate::tools::validation::mirror::MIRROR_FORMAT`].
    pub format: &'static str,
    /// [`crate::tools::validation::mirror::MIRROR_VERSION`].
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
            format: crate::tools::validation::mirror::MIRROR_FORMAT,
            version: crate::tools::validation::mirror::MIRROR_VERSION,
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
