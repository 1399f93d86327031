//! `rigidref run`: simulate a scene (3D or 2D) and write its trace, with a progress bar and a
//! summary. The 3D run is in run3d.rs, the 2D run in run2d.rs; this chooses between them.

use super::args::{RestThreshold, RunLength, SceneSets, TraceOutput};
use super::args2d::Blocks2dOptions;
use super::run_args::{Run2dReports, RunArgs};
use anyhow::bail;
use rigidref::blocks2d::scene::is_2d_scene;
use std::path::Path;

/// Runs a scene: a 2D one (an image or a 2D scene file) in 2D, anything else in 3D.
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.scene
        && rigidref::blocks2d::scene::is_2d_scene(path)
    {
        return super::run2d::run(path, &args);
    }
    // `--preset` applies to a 3D scene too: as `--set preset=NAME`.
    let only_2d: Vec<String> = args
        .only_2d_given()
        .into_iter()
        .filter(|name| name != "--preset")
        .collect();
    if !only_2d.is_empty() {
        super::common::check_readable(args.scene.as_deref())?;
        let scene_name = args
            .scene
            .as_ref()
            .map_or("the built-in default scene".to_string(), |p| {
                p.display().to_string()
            });
        anyhow::bail!(
            "{scene_name}: {} {} to 2D scenes (images and 2D scene files) only; set a 3D scene's parameters with --set KEY=VALUE (e.g. --set pgs_iterations=50, docs/scene-format.md)",
            only_2d.join(", "),
            if only_2d.len() == 1 {
                "applies"
            } else {
                "apply"
            }
        );
    }
    let mut args = args;
    if let Some(preset) = args.blocks.preset {
        if args
            .sets
            .set
            .iter()
            .any(|s| s.split_once('=').is_some_and(|(k, _)| k.trim() == "preset"))
        {
            anyhow::bail!("--preset and --set preset=… both given: give one");
        }
        let name = match preset {
            rigidref::common::preset::Preset::Default => "default",
            rigidref::common::preset::Preset::Starter => "starter",
        };
        args.sets.set.insert(0, format!("preset={name}"));
    }
    super::run3d::run(&args)
}

/// Runs `input` (a 3D scene, a 2D image or scene file, or the built-in default when `None`) as
/// `rigidref run` would, recording every `every`-th frame to `trace` (2D: with all contacts).
/// `view` and `render` run scenes through this.
pub(crate) fn run_to_trace(
    input: Option<&Path>,
    length: &RunLength,
    sets: &SceneSets,
    blocks: &Blocks2dOptions,
    every: u64,
    quiet: bool,
    trace: &Path,
) -> anyhow::Result<()> {
    let two_d = input.is_some_and(is_2d_scene);
    if !two_d && !blocks.given().is_empty() {
        bail!(
            "{}: {} apply to 2D scenes only",
            input.map_or("the built-in default scene".into(), |p| p
                .display()
                .to_string()),
            blocks.given().join(", ")
        );
    }
    let run = RunArgs {
        scene: input.map(Path::to_path_buf),
        length: length.clone(),
        sets: sets.clone(),
        output: TraceOutput {
            out: Some(trace.to_path_buf()),
            every,
            format: None,
            dump_problems: None,
        },
        quiet,
        no_collisions: false,
        blocks: blocks.clone(),
        rest: RestThreshold {
            rest_threshold: None,
        },
        reports: Run2dReports {
            nut_report: None,
            scaling_csv: None,
            all_contacts: two_d,
        },
    };
    self::run(run)
}
