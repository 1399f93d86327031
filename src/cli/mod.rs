//! Command-line interface: argument definitions and dispatch. Each subcommand lives in its own
//! file and returns `anyhow::Result`; `main` prints an error as one line and exits with 1.

mod contacts;
mod crosscheck;
mod factory;
mod golden;
mod massprops;
mod rapier;
mod render;
mod run;
mod run2d;
mod scene;

use clap::{Parser, Subcommand};

/// rigidref: a reference simulator of rigid bodies with frictional contact, for checking other
/// simulators against. Every run is deterministic and writes a trace of every quantity.
#[derive(Parser)]
#[command(name = "rigidref", version, about, long_about = None, args_conflicts_with_subcommands = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Arguments for `run` when no subcommand is given.
    #[command(flatten)]
    run: run::RunArgs,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene (or the built-in default) and write a trace.
    Run(run::RunArgs),
    /// Compute the mass properties of a closed triangle mesh and write a centred body file.
    Massprops(massprops::MasspropsArgs),
    /// Load and check a scene, and print it with every default filled in.
    Scene(scene::SceneArgs),
    /// Print one step's contacts: point, frame, depth, Jacobian, Delassus block, b and λ.
    Contacts(contacts::ContactsArgs),
    /// Solve every contact problem of a run (or problem files) with PGS and clarabel and compare;
    /// or, with --rapier, compare the run with a rapier3d mirror.
    Crosscheck(crosscheck::CrosscheckArgs),
    /// Compare fresh runs of the canonical scenes with golden/ (or regenerate it with --update).
    Golden(golden::GoldenArgs),
    /// Run a 2D image scene and write PNG frames and an animated GIF.
    Render(render::RenderArgs),
    /// Drop random bodies into a container (2D stress test), with the scaling report.
    Factory(factory::FactoryArgs),
}

/// Runs the chosen subcommand; no subcommand means `run` (so `cargo run --release` runs the
/// default scene).
pub fn dispatch(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Some(Command::Run(args)) => run::run(args),
        Some(Command::Massprops(args)) => massprops::massprops(args),
        Some(Command::Scene(args)) => scene::scene(args),
        Some(Command::Contacts(args)) => contacts::contacts(args),
        Some(Command::Crosscheck(args)) => crosscheck::crosscheck(args),
        Some(Command::Golden(args)) => golden::golden(args),
        Some(Command::Render(args)) => render::render_command(args),
        Some(Command::Factory(args)) => factory::factory(args).map(|_| ()),
        None => run::run(cli.run),
    }
}

/// Loads the scene at `path`, or the embedded default, and prints its warnings to stderr.
fn load_scene_or_default(path: Option<&std::path::Path>) -> anyhow::Result<rigidref::scene::Scene> {
    let scene = match path {
        Some(p) => {
            // A JSON object with neither a 3D scene's parameters nor a 2D scene's image: say
            // both, rather than only the 3D reader's "missing field `sim_parameters`".
            if let Ok(text) = std::fs::read_to_string(p)
                && let Ok(serde_json::Value::Object(map)) = serde_json::from_str(&text)
                && !map.contains_key("sim_parameters")
                && !map.contains_key("image")
            {
                anyhow::bail!(
                    "{}: neither a 3D scene (no \"sim_parameters\") nor a 2D scene (no \"image\")",
                    p.display()
                );
            }
            rigidref::scene::load_scene(p)?
        }
        None => rigidref::scene::default_scene()?,
    };
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
}

/// The number of steps of `run`: `--steps`, else `--time` (default 10) over the step size `dt`,
/// rounded to the nearest whole step (the 1e-9 guards 0.3/0.1 = 2.9999999999999996), at least 1.
/// Also checks `--every`. `unit` names the time unit in the error ("seconds" in 3D).
fn steps_of(args: &run::RunArgs, dt: f64, unit: &str) -> anyhow::Result<u64> {
    if args.every == 0 {
        anyhow::bail!("--every must be at least 1");
    }
    match args.steps {
        Some(n) => {
            check_step_count(n as f64, dt)?;
            Ok(n)
        }
        None => steps_in(args.time.unwrap_or(10.0), dt, unit),
    }
}

/// The whole steps of size `dt` in `time` (the 1e-9 guards 0.3/0.1 = 2.9999999999999996), at
/// least 1, after checking `time` is positive (`unit` names its unit in the error) and the count
/// within [`MAX_STEPS`].
fn steps_in(time: f64, dt: f64, unit: &str) -> anyhow::Result<u64> {
    if !(time.is_finite() && time > 0.0) {
        anyhow::bail!("--time must be a positive number{unit}, got {time}");
    }
    let steps = (time / dt + 1e-9).floor().max(1.0);
    check_step_count(steps, dt)?;
    Ok(steps as u64)
}

/// Fails, naming the file, when a scene path cannot be read (checked before options are
/// judged against the kind of scene, so that a typo is reported as a missing file).
pub(crate) fn check_readable(path: Option<&std::path::Path>) -> anyhow::Result<()> {
    if let Some(p) = path
        && let Err(e) = std::fs::File::open(p)
    {
        anyhow::bail!("{}: cannot open: {e}", p.display());
    }
    Ok(())
}

/// The most steps one run may take: far beyond any useful run (a day at a microsecond a step),
/// so that a step size like 1e-300 is an error rather than a run that never ends.
pub(crate) const MAX_STEPS: f64 = 1e11;

/// Refuses a run of more than [`MAX_STEPS`] steps of size `dt`.
pub(crate) fn check_step_count(steps: f64, dt: f64) -> anyhow::Result<()> {
    if steps > MAX_STEPS {
        anyhow::bail!(
            "{steps:.3e} steps of {dt:.3e} is more than the limit of {MAX_STEPS:.0e}; ask for fewer steps (a larger step size or a shorter time)"
        );
    }
    Ok(())
}

/// The trace's destination: `-` is standard output, anything else a file created (or truncated)
/// now, so that an unwritable path fails before the run starts.
fn create_trace_output(path: &std::path::Path) -> anyhow::Result<Box<dyn std::io::Write>> {
    use anyhow::Context;
    Ok(if path.as_os_str() == "-" {
        Box::new(std::io::stdout().lock())
    } else {
        Box::new(
            std::fs::File::create(path)
                .with_context(|| format!("{}: cannot create trace file", path.display()))?,
        )
    })
}

/// A progress bar over `steps` steps, hidden until [`show_progress_after_a_second`] reveals it
/// (runs shorter than about a second get none; indicatif hides it when stderr is not a terminal).
fn progress_bar(steps: u64, template: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(steps),
        indicatif::ProgressDrawTarget::hidden(),
    );
    bar.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// The progress template of a run.
const STEPS_TEMPLATE: &str =
    "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps (eta {eta})";

/// Shows `bar` once a run has taken more than a second (unless `quiet`); `shown` remembers it.
fn show_progress_after_a_second(
    bar: &indicatif::ProgressBar,
    started: std::time::Instant,
    quiet: bool,
    shown: &mut bool,
) {
    if !quiet && !*shown && started.elapsed() > std::time::Duration::from_secs(1) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        *shown = true;
    }
}
