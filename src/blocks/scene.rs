//! 2D scene files: a JSON file naming an image and its parameters. docs/blocks2d.md §"Scene files".
//!
//! ```json
//! {"image": "stack.png",
//!  "parameters": {"substeps": 4, "iterations": 50, "order": "random"},
//!  "impulses": [{"time": 20, "body": 0, "impulse": [30, 0]}],
//!  "shakes": [{"body": 0, "velocity": [3, 0], "angular": 0, "frequency": 1}]}
//! ```
//!
//! `image` is relative to the scene file's folder. Every parameter is optional and defaults as on
//! the command line; unknown keys are warnings; bad values are errors naming file, line, column.

use super::image::{ImageSettings, load_image};
use super::world::{ContactModel, Params2, ScriptedImpulse, Shake, World2};
use crate::scene::SceneError;
use crate::scene::values::{Count, NonNegative, Positive};
use crate::solve::ContactOrder;
use nalgebra::Vector2;
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
struct SceneFile2 {
    image: String,
    #[serde(default)]
    parameters: ParametersFile2,
    #[serde(default)]
    impulses: Vec<ImpulseFile>,
    #[serde(default)]
    shakes: Vec<ShakeFile>,
}

#[derive(Deserialize, Default)]
struct ParametersFile2 {
    step: Option<Positive>,
    substeps: Option<Count>,
    gravity: Option<NonNegative>,
    gravity_angle: Option<f64>,
    mu: Option<NonNegative>,
    restitution: Option<NonNegative>,
    iterations: Option<Count>,
    pgs_tolerance: Option<Positive>,
    order: Option<ContactOrder>,
    seed: Option<u64>,
    warm_start: Option<bool>,
    post_stabilization: Option<bool>,
    slop: Option<NonNegative>,
    contact_model: Option<ContactModel>,
    white_threshold: Option<NonNegative>,
}

#[derive(Deserialize)]
struct ImpulseFile {
    time: NonNegative,
    body: usize,
    impulse: [f64; 2],
    point: Option<[f64; 2]>,
}

#[derive(Deserialize)]
struct ShakeFile {
    body: usize,
    velocity: [f64; 2],
    #[serde(default)]
    angular: f64,
    frequency: NonNegative,
}

/// A loaded 2D scene.
pub struct Scene2 {
    /// The image's path.
    pub image: PathBuf,
    /// The world, ready to run.
    pub world: World2,
    /// Warnings (unknown keys).
    pub warnings: Vec<String>,
}

/// Whether a JSON text is a 2D scene (has a top-level `image` key).
pub fn is_scene2(text: &str) -> bool {
    match serde_json::from_str::<serde_json::Value>(text) {
        Ok(v) => v.get("image").is_some(),
        // Unparsable (e.g. a number out of range): a 2D scene if it names an image, so that the
        // 2D reader reports what is wrong rather than the 3D one.
        Err(_) => text.contains("\"image\""),
    }
}

/// Loads a 2D scene file.
pub fn load_scene2(path: &Path) -> Result<Scene2, SceneError> {
    let source = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError(format!("{source}: cannot read scene: {e}")))?;
    let mut warnings = Vec::new();
    let file: SceneFile2 = crate::scene::json::from_str(&text, &source, &mut warnings)?;
    let p = &file.parameters;
    let d = Params2::default();
    let restitution = p.restitution.map_or(d.restitution, |x| x.0);
    if restitution > 1.0 {
        return Err(SceneError(format!(
            "{source}: parameters.restitution must be in [0, 1], got {restitution}"
        )));
    }
    if let Some(a) = p.gravity_angle
        && !a.is_finite()
    {
        return Err(SceneError(format!(
            "{source}: parameters.gravity_angle must be finite"
        )));
    }
    let params = Params2 {
        step: p.step.map_or(d.step, |x| x.0),
        substeps: p.substeps.map_or(d.substeps, |x| x.0),
        gravity: p.gravity.map_or(d.gravity, |x| x.0),
        gravity_angle: p.gravity_angle.unwrap_or(d.gravity_angle),
        mu: p.mu.map_or(d.mu, |x| x.0),
        restitution,
        iterations: p.iterations.map_or(d.iterations, |x| x.0),
        tolerance: p.pgs_tolerance.map(|x| x.0),
        order: p.order.unwrap_or(d.order),
        seed: p.seed.unwrap_or(d.seed),
        warm_start: p.warm_start.unwrap_or(d.warm_start),
        post_stabilization: p.post_stabilization.unwrap_or(d.post_stabilization),
        slop: p.slop.map_or(d.slop, |x| x.0),
        contact_model: p.contact_model.unwrap_or(d.contact_model),
        ..d
    };
    let white_threshold = p
        .white_threshold
        .map_or(ImageSettings::default().white_threshold, |x| x.0);
    if white_threshold >= 1.0 {
        return Err(SceneError(format!(
            "{source}: parameters.white_threshold must be below 1"
        )));
    }
    let image = path.parent().unwrap_or(Path::new(".")).join(&file.image);
    let groups = load_image(&image, &ImageSettings { white_threshold })
        .map_err(|e| SceneError(format!("{source}: image: {e}")))?;
    let mut world = World2::new(&groups, params);
    let n = world.bodies.len();
    for (k, i) in file.impulses.iter().enumerate() {
        if i.body >= n {
            return Err(SceneError(format!(
                "{source}: impulses[{k}]: body {} does not exist (the image has {n} bodies, 0 to {})",
                i.body,
                n - 1
            )));
        }
        if !i
            .impulse
            .iter()
            .chain(i.point.iter().flatten())
            .all(|x| x.is_finite())
        {
            return Err(SceneError(format!(
                "{source}: impulses[{k}]: the impulse and point must be finite"
            )));
        }
        world.impulses.push(ScriptedImpulse {
            time: i.time.0,
            body: i.body,
            impulse: Vector2::from(i.impulse),
            point: i.point.map(Vector2::from),
        });
    }
    for (k, s) in file.shakes.iter().enumerate() {
        if s.body >= n
            || !s
                .velocity
                .iter()
                .chain([s.angular].iter())
                .all(|x| x.is_finite())
        {
            return Err(SceneError(format!(
                "{source}: shakes[{k}]: body {} of {n}, or a non-finite value",
                s.body
            )));
        }
        world.shakes.push(Shake {
            body: s.body,
            velocity: Vector2::from(s.velocity),
            angular: s.angular,
            frequency: s.frequency.0,
        });
    }
    Ok(Scene2 {
        image,
        world,
        warnings,
    })
}
