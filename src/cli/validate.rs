//! `rigidref validate`: other engines on the known-answer scenes, judged against the closed forms
//! and rigidref's exact run (docs/validation.md). Parses, calls
//! `rigidref::tools::validation::validate`, prints the headline.

use clap::Args;
use rigidref::tools::validation::engines::{ENGINES_3D, Engine};
use rigidref::tools::validation::{RunStatus, ValidateOptions, validate as run_validation};
use std::path::PathBuf;

/// Arguments of `rigidref validate`.
#[derive(Args)]
#[command(after_long_help = "\
Each known-answer scene (sliding_cube, sliding_box, dragged_cube, ball_incline_rolls,
ball_incline_slides, dzhanibekov, projectile, heavy_on_light, sphere_drop, box_stack) is
converted into each engine's model from the scene file (boxes, spheres and convex hulls, the
ground plane, the body files' masses and inertias, mu, restitution 0, gravity, the same step) and
run twice: with the engine's documented defaults and with the settings its documentation
recommends for accuracy. rigidref runs each scene with its exact (Newton) solver. Every run
writes a rigidref trace and is judged by the same code against the closed forms and against
rigidref's run: stop distances and times, accelerations, flip times, rest drift, deepest
penetration, energy, whether the heavy-on-light stack holds, and ContactBench's criteria on the
engine's own contact impulses.

OUT gets report.md, report.json, plots/SCENE.svg, traces/ENGINE-SETTINGS/SCENE.jsonl (with each
Python engine's SCENE.model.json: its settings and its model read back), descriptions/ (what
every mirror was given) and mirrors/ (the Python code that ran). MuJoCo, PyBullet and Drake run
through --python (their PyPI packages mujoco, pybullet, drake); an engine that is not installed
is reported as such. Exit status 0 when everything ran (whatever the verdicts), 1 on an error.

pymunk (Chipmunk2D, PyPI package pymunk) runs the 2D scenes instead (scenes/blocks/block_slide,
bar_topple, stack_rest): each block a circle of radius sqrt(2)/2 (rigidref's contact disc), the
bodies' masses and moments, mu, gravity and step of the scene; the slide and the topple are
judged against rigidref's exact run, the stack's rest absolutely (docs/validation.md §\"2D:
pymunk\"). `--engines pymunk` alone runs the 2D scenes only.")]
pub struct ValidateArgs {
    /// Engines, comma-separated: rapier, mujoco, pybullet, drake (3D), pymunk (2D) (default: the four 3D engines).
    #[arg(long, value_delimiter = ',')]
    pub engines: Vec<String>,
    /// Scenes of the known-answer set, comma-separated (default: the 3D set for the 3D engines, the 2D set for pymunk).
    #[arg(long, value_delimiter = ',')]
    pub scenes: Vec<String>,
    /// The folder holding rigidref's scenes.
    #[arg(long, default_value = "scenes")]
    pub scene_dir: PathBuf,
    /// The Python interpreter with the engines installed.
    #[arg(long, default_value = "python3")]
    pub python: PathBuf,
    /// Where to write the report.
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs the validation and prints the headline table.
pub fn validate(args: ValidateArgs) -> anyhow::Result<()> {
    let engines = if args.engines.is_empty() {
        ENGINES_3D.to_vec()
    } else {
        args.engines
            .iter()
            .map(|n| Engine::parse(n.trim()))
            .collect::<Result<Vec<_>, String>>()
            .map_err(anyhow::Error::msg)?
    };
    let options = ValidateOptions {
        engines,
        scenes: args.scenes,
        scene_dir: args.scene_dir,
        out: args.out.clone(),
        python: args.python,
    };
    let v = run_validation(&options).map_err(anyhow::Error::msg)?;
    for e in &v.engines {
        match (&e.version, &e.missing) {
            (_, Some(why)) => eprintln!("{}: not installed: {why}", e.engine.name()),
            (Some(ver), None) => eprintln!("{}: {ver}", e.engine.name()),
            _ => {}
        }
    }
    for scene in &v.scenes {
        let cells: Vec<String> = scene
            .runs
            .iter()
            .map(|r| match &r.status {
                RunStatus::Ran => {
                    let (p, j) = r.score();
                    format!("{} {p}/{j}", r.label())
                }
                RunStatus::NotInstalled(_) => format!("{} not installed", r.label()),
                RunStatus::Failed(why) => format!("{} failed: {why}", r.label()),
                RunStatus::Pending => format!("{} pending", r.label()),
            })
            .collect();
        println!(
            "{}: {}",
            scene.file.trim_end_matches(".json"),
            cells.join("; ")
        );
    }
    println!("wrote {}", args.out.join("report.md").display());
    Ok(())
}
