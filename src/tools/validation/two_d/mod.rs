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

mod judge;
mod mirror;
mod observe;
mod runs;

pub use judge::*;
pub use mirror::*;
pub use observe::*;
pub use runs::*;

use crate::blocks2d::world::World2;
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
