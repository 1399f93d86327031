//! The scene `rigidref run` uses when given none: the project's own Dzhanibekov scene, compiled
//! into the binary from scenes/ so that a fresh clone runs without any files.

use super::{BodyFileTexts, BodyFiles, Overrides, Scene, parse_scene};
use crate::common::scene_json::SceneError;

/// The project file the embedded scene is a copy of.
pub const DEFAULT_SCENE_NAME: &str = "scenes/dzhanibekov.json";

/// Where a run of the embedded scene says it came from (summary and trace header): it runs the
/// copy compiled into the binary, whether or not the file exists where it is run.
pub const BUILT_IN_SOURCE: &str = "built-in (compiled-in copy of scenes/dzhanibekov.json)";

const SCENE: &str = include_str!("../../../scenes/dzhanibekov.json");
/// (file_root, body JSON, OBJ) of every body file the embedded scene may name.
const BODY_FILES: &[(&str, &str, &str)] = &[(
    "data/slab",
    include_str!("../../../scenes/data/slab.json"),
    include_str!("../../../scenes/data/slab.obj"),
)];

struct Embedded;

impl BodyFiles for Embedded {
    fn find(&self, file_root: &str) -> Result<BodyFileTexts, SceneError> {
        BODY_FILES
            .iter()
            .find(|(root, _, _)| *root == file_root)
            .map(|(root, json, obj)| BodyFileTexts {
                json: (json.to_string(), format!("<embedded>/scenes/{root}.json")),
                obj: (obj.to_string(), format!("<embedded>/scenes/{root}.obj")),
            })
            .ok_or_else(|| SceneError(format!("{file_root}: not among the embedded body files")))
    }
}

/// The embedded default scene.
/// (It cannot fail in a released binary: tests/suite/cli/commands.rs runs it.)
pub fn default_scene() -> Result<Scene, SceneError> {
    default_scene_with(&Overrides::default())
}

/// The embedded default scene with `overrides` of its parameters (`--set KEY=VALUE`).
pub fn default_scene_with(overrides: &Overrides) -> Result<Scene, SceneError> {
    parse_scene(
        SCENE,
        &format!("<embedded>/{DEFAULT_SCENE_NAME}"),
        "dzhanibekov",
        &Embedded,
        overrides,
    )
}
