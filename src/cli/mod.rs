//! Command-line interface: argument definitions and dispatch. Each subcommand lives in its own
//! file and returns `anyhow::Result`; `main` prints an error as one line and exits with 1.

mod args;
mod contacts;
mod crosscheck;
mod factory;
mod golden;
mod massprops;
mod rapier;
mod render;
mod run;
mod run2d;
mod run3d;
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
fn load_scene_or_default(path: Option<&std::path::Path>) -> anyhow::Result<rigidref::rigid3d::scene::Scene> {
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
            rigidref::rigid3d::scene::load_scene(p)?
        }
        None => rigidref::rigid3d::scene::default_scene()?,
    };
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
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

/// Creates `path` for writing, naming it in the error.
fn create_file(path: &std::path::Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    use anyhow::Context;
    Ok(std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("{}: cannot create", path.display()))?,
    ))
}

/// Writes one contact-problem file of `--dump-problems`: DIR/step-KKKKKK-SS.json.
fn dump_problem<C: rigidref::sim::ContactGeometry, const D: usize, const R: usize>(
    dir: &std::path::Path,
    scene: &str,
    step: u64,
    h: f64,
    solve: &rigidref::sim::SubstepSolve<C, D, R>,
) -> anyhow::Result<()> {
    use anyhow::Context;
    let path = dir.join(format!("step-{step:06}-{:02}.json", solve.substep));
    let file = solve.problem_file(scene, step, h);
    let text = serde_json::to_string(&file).context("serialising a contact problem")?;
    std::fs::write(&path, text + "\n").with_context(|| format!("{}: cannot write", path.display()))
}

/// Why a run stopped early: the simulation reached a non-finite state, or writing failed.
enum Stopped {
    /// The step failed; what was written before stays written.
    Failed(rigidref::sim::NonFinite),
    /// Anything else (an output that cannot be written).
    Error(anyhow::Error),
}

impl Stopped {
    /// The outcome of a run: the steps run, or the error, a failed step explained by `failed`
    /// (which names the scene and what was kept).
    fn outcome(
        ran: Result<u64, Stopped>,
        failed: impl FnOnce(rigidref::sim::NonFinite) -> String,
    ) -> anyhow::Result<u64> {
        match ran {
            Ok(steps) => Ok(steps),
            Err(Stopped::Failed(e)) => Err(anyhow::Error::msg(failed(e))),
            Err(Stopped::Error(e)) => Err(e),
        }
    }
}

impl From<rigidref::sim::NonFinite> for Stopped {
    fn from(e: rigidref::sim::NonFinite) -> Stopped {
        Stopped::Failed(e)
    }
}

impl From<anyhow::Error> for Stopped {
    fn from(e: anyhow::Error) -> Stopped {
        Stopped::Error(e)
    }
}

impl From<std::io::Error> for Stopped {
    fn from(e: std::io::Error) -> Stopped {
        Stopped::Error(e.into())
    }
}

/// The progress template of a run.
const STEPS_TEMPLATE: &str =
    "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps (eta {eta})";

/// A progress bar over a run's steps, shown only once the run has taken more than a second
/// (unless quiet; indicatif hides it when stderr is not a terminal).
struct Progress {
    bar: indicatif::ProgressBar,
    started: std::time::Instant,
    quiet: bool,
    shown: bool,
}

impl Progress {
    /// A hidden bar over `steps` steps with `template`.
    fn new(steps: u64, template: &str, quiet: bool) -> Progress {
        let bar = indicatif::ProgressBar::with_draw_target(
            Some(steps),
            indicatif::ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            indicatif::ProgressStyle::with_template(template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Progress {
            bar,
            started: std::time::Instant::now(),
            quiet,
            shown: false,
        }
    }

    /// A bar over `steps` steps with the run template.
    fn steps(steps: u64, quiet: bool) -> Progress {
        Progress::new(steps, STEPS_TEMPLATE, quiet)
    }

    /// Step `k` is done; reveals the bar after a second.
    fn tick(&mut self, k: u64) {
        if !self.quiet && !self.shown && self.started.elapsed() > std::time::Duration::from_secs(1) {
            self.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            self.shown = true;
        }
        if self.shown && k.is_multiple_of(16) {
            self.bar.set_position(k);
        }
    }

    /// The underlying bar (to set a message or a new length).
    fn bar(&self) -> &indicatif::ProgressBar {
        &self.bar
    }

    /// Seconds since the bar was made.
    fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Removes the bar.
    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
