//! 2D scene files: a JSON file naming an image and its parameters. docs/blocks2d.md §"Scene files".
//!
//! ```json
//! {"image": "stack.png",
//!  "parameters": {"substeps": 4, "iterations": 50, "order": "random"},
//!  "impulses": [{"time": 20, "body": 0, "impulse": [30, 0]}],
//!  "shakes": [{"body": 0, "velocity": [3, 0], "angular": 0, "frequency": 1}],
//!  "pins": [{"bodies": [2, null], "point": [10, 4.5]}],
//!  "springs": [{"bodies": [3, 1], "points": [[4, 2], [4, 8]], "stiffness": 5, "damping": 0.5}]}
//! ```
//!
//! `image` is relative to the scene file's folder. Pins and springs name bodies by index (`null`
//! is the world) and their anchors as world points at t = 0, blocks (pixel centres are integer
//! points, y down); a spring's `rest_length` defaults to its initial length. Every parameter is optional and defaults as on
//! the command line; unknown keys are warnings; bad values are errors naming file, line, column.

mod build;
mod json;
mod params;

pub use build::*;
use json::*;
pub use params::*;

use super::body::InertiaRule;
use super::disc_tree::DiscTreeRule;
use super::image::{ImageReader, ImageSettings, load_image};
use super::joints::{Anchor, Pin2, Spring2};
use super::params::{ContactModel, Params2, Preset};
use super::world::{ScriptedImpulse, Shake, World2};
use crate::common::scene_json::{Overrides, SceneError};
use crate::common::values::{Count, NonNegative, Positive};
use crate::solve::{ContactOrder, LocalSolve, Solver};
use nalgebra::Vector2;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A loaded 2D scene.
pub struct Scene2 {
    /// The image's path.
    pub image: PathBuf,
    /// The world, ready to run.
    pub world: World2,
    /// Warnings (unknown keys).
    pub warnings: Vec<String>,
    /// The parameters set on the command line (`--set KEY=VALUE`), as `KEY=VALUE`.
    pub overrides: Vec<String>,
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

/// Whether `path` is a 2D scene: a .png image, or a JSON file with an `image` key.
pub fn is_2d_scene(path: &Path) -> bool {
    let has = |ext: &str| {
        path.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    };
    has("png")
        || (has("json") && crate::common::input::read_text(path).is_ok_and(|t| is_scene2(&t)))
}

/// What the command line adds to a 2D scene: parameters (for images only: a scene file sets its
/// own) and scripted impulses and shakes (likewise).
#[derive(Clone, Debug, Default)]
pub struct LoadOptions2 {
    /// Parameters given as options.
    pub parameters: ParamOverrides2,
    /// `--impulse` values.
    pub impulses: Vec<ScriptedImpulse>,
    /// `--shake` values.
    pub shakes: Vec<Shake>,
    /// The option names given (`--step`, `--impulse`, …), for the message that refuses them on a
    /// scene file.
    pub given: Vec<String>,
    /// `--set KEY=VALUE`: keys of a 2D scene file's `parameters`, for images and scene files.
    pub overrides: Overrides,
}

/// A 2D scene ready to run: an image with the command line's parameters, or a scene file with
/// its own (then giving 2D physics options as well is an error rather than a silent choice
/// between the two). Warnings are returned, not printed.
pub fn load_2d(path: &Path, cli: &LoadOptions2) -> Result<Scene2, SceneError> {
    let source = path.display().to_string();
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        if !cli.given.is_empty() {
            return Err(SceneError(format!(
                "{source}: a 2D scene file sets its own parameters; {} on the command line apply to .png scenes only",
                cli.given.join(", ")
            )));
        }
        return load_scene2_with(path, &cli.overrides);
    }
    let parameters = with_overrides(&cli.parameters, &cli.overrides)?;
    let (params, settings) = parameters.resolve().map_err(|e| {
        // Name the option the value came from: `--set KEY=VALUE` or `--KEY VALUE`.
        match cli.overrides.0.iter().find(|(k, _)| k == e.key) {
            Some((k, v)) => SceneError(format!("--set {k}={v}: {k} {}", e.message)),
            None => SceneError(format!("--{} {}", e.key.replace('_', "-"), e.message)),
        }
    })?;
    let groups = load_image(path, &settings).map_err(SceneError)?;
    let mut world = World2::new(&groups, params);
    let n = world.bodies.len();
    for i in &cli.impulses {
        if i.body >= n {
            return Err(SceneError(format!(
                "--impulse: body {} does not exist ({n} bodies in {source})",
                i.body
            )));
        }
    }
    for s in &cli.shakes {
        if s.body >= n {
            return Err(SceneError(format!(
                "--shake: body {} does not exist ({n} bodies in {source})",
                s.body
            )));
        }
    }
    world.impulses.extend(cli.impulses.iter().copied());
    world.shakes.extend(cli.shakes.iter().copied());
    check_scripts(&world, "--impulse", "--shake", &source)?;
    Ok(Scene2 {
        image: path.to_path_buf(),
        world,
        warnings: Vec::new(),
        overrides: cli.overrides.describe(),
    })
}

/// The command line's parameters with `--set` overrides added, each checked as a scene file's
/// value of that key; a key given both ways is an error.
fn with_overrides(
    flags: &ParamOverrides2,
    overrides: &Overrides,
) -> Result<ParamOverrides2, SceneError> {
    if overrides.is_empty() {
        return Ok(flags.clone());
    }
    overrides.check::<ParametersFile2>("a 2D scene's parameters")?;
    let mut map = serde_json::Map::new();
    overrides.apply(&mut map);
    let set: ParametersFile2 = serde_json::from_value(serde_json::Value::Object(map))
        .map_err(|e| SceneError(format!("--set: {e}")))?;
    let set = set.plain();
    let both: Vec<&str> = set
        .given()
        .into_iter()
        .filter(|k| flags.given().contains(k))
        .collect();
    if let Some(key) = both.first() {
        return Err(SceneError(format!(
            "--set {key} and --{} both set {key}; give it once",
            key.replace('_', "-")
        )));
    }
    Ok(set.or(flags))
}

/// Loads a 2D scene file.
pub fn load_scene2(path: &Path) -> Result<Scene2, SceneError> {
    load_scene2_with(path, &Overrides::default())
}
