//! Command-line interface: argument definitions and dispatch. Each subcommand lives in its own
//! file and returns `anyhow::Result`; `main` prints an error as one line and exits with 1 (2 for
//! an unreadable input to `compare` or `compare-problem`, 3 for problems `crosscheck` could not
//! check).

mod args;
mod args2d;
mod bench;
mod common;
mod compare;
mod compare_problem;
mod contacts;
mod contacts2d;
mod contacts3d;
mod converge;
mod convert_problem;
mod crosscheck;
mod factory;
mod golden;
mod grade;
mod massprops;
mod plot;
mod progress;
mod rapier;
mod render;
mod run;
mod run2d;
mod run3d;
mod run_args;
mod scene;
mod solve_problems;
mod validate;
mod view;

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
    run: run_args::RunArgs,
    /// The largest input file read (scene, body file, mesh, image, problem file, trace), MB; a
    /// larger one is a one-line error (docs/scene-format.md §"Input limits").
    #[arg(
        long,
        global = true,
        value_name = "MB",
        default_value_t = 1024,
        help_heading = "Input limits (every command)"
    )]
    max_input_mb: u64,
    /// The largest image read by the 2D system, pixels (its blocks grow with them).
    #[arg(long, global = true, value_name = "PIXELS", default_value_t = rigidref::common::input::DEFAULT_MAX_IMAGE_PIXELS, help_heading = "Input limits (every command)")]
    max_image_pixels: u64,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene (or the built-in default) and write a trace.
    Run(run_args::RunArgs),
    /// Compute the mass properties of a closed triangle mesh and write a centred body file.
    Massprops(massprops::MasspropsArgs),
    /// Load and check a scene, and print it with every default filled in.
    Scene(scene::SceneArgs),
    /// Print one step's contacts: point, frame, depth, Jacobian, Delassus block, b and λ.
    Contacts(contacts::ContactsArgs),
    /// Solve every contact problem of a run (or problem files) with PGS and clarabel and compare;
    /// or, with --rapier, compare the run with a rapier3d mirror.
    Crosscheck(crosscheck::CrosscheckArgs),
    /// Run a 3D scene at several step sizes and report each observable's observed order of
    /// convergence against a closed form, an independent integration or Richardson extrapolation.
    Converge(converge::ConvergeArgs),
    /// Compare fresh runs of the canonical scenes with golden/ (or regenerate it with --update).
    Golden(golden::GoldenArgs),
    /// Time rigidref against the rapier3d mirror on the same scenes, side by side.
    Bench(bench::BenchArgs),
    /// Draw a run as PNG frames, a GIF and an MP4 video: a 2D image scene, a 3D scene or trace.
    Render(render::RenderArgs),
    /// Drop random bodies into a container (2D stress test), with the scaling report.
    Factory(factory::FactoryArgs),
    /// Compare a trace with the reference's (3D or 2D), trajectory by trajectory or by outcome.
    Compare(compare::CompareArgs),
    /// Compare two contact-problem files (3D or 2D) for the same state, up to the tangent basis.
    CompareProblem(compare_problem::CompareProblemArgs),
    /// Write one HTML page that shows a run in a browser, offline: the bodies, contacts, plots.
    View(view::ViewArgs),
    /// Plot quantities over time from one or more traces, to an SVG file.
    Plot(plot::PlotArgs),
    /// Grade a folder of submissions (traces and problem files per scene) against the reference.
    Grade(grade::GradeArgs),
    /// Solve a library of contact problems (Siconos .dat, FCLIB .hdf5, rigidref problem files)
    /// with several solvers: a table per problem and a performance profile.
    SolveProblems(solve_problems::SolveProblemsArgs),
    /// Convert a contact problem between file formats (rigidref JSON, Siconos .dat, FCLIB HDF5).
    ConvertProblem(convert_problem::ConvertProblemArgs),
    /// Run the known-answer scenes in other engines (rapier, MuJoCo, PyBullet, Drake) and judge
    /// them against the closed forms and rigidref's exact run: a Markdown, JSON and SVG report.
    Validate(validate::ValidateArgs),
}

pub use compare::Unreadable;
pub use crosscheck::Unverified;

/// Runs the chosen subcommand; no subcommand means `run` (so `cargo run --release` runs the
/// default scene).
pub fn dispatch(cli: Cli) -> anyhow::Result<()> {
    rigidref::common::input::set_max_input_bytes(cli.max_input_mb.saturating_mul(1 << 20));
    rigidref::common::input::set_max_image_pixels(cli.max_image_pixels);
    match cli.command {
        Some(Command::Run(args)) => run::run(args),
        Some(Command::Massprops(args)) => massprops::massprops(args),
        Some(Command::Scene(args)) => scene::scene(args),
        Some(Command::Contacts(args)) => match &args.scene {
            Some(path) if rigidref::blocks2d::scene::is_2d_scene(path) => {
                contacts2d::contacts(path, &args)
            }
            _ => contacts3d::contacts(&args),
        },
        Some(Command::Crosscheck(args)) => crosscheck::crosscheck(args),
        Some(Command::SolveProblems(args)) => solve_problems::solve_problems(args),
        Some(Command::ConvertProblem(args)) => convert_problem::convert_problem(args),
        Some(Command::Converge(args)) => converge::converge_command(args),
        Some(Command::Golden(args)) => golden::golden(args),
        Some(Command::Bench(args)) => bench::bench(args),
        Some(Command::Render(args)) => render::render_command(args),
        Some(Command::Factory(args)) => factory::factory(args).map(|_| ()),
        Some(Command::Compare(args)) => compare::compare(args),
        Some(Command::CompareProblem(args)) => compare_problem::compare_problem(args),
        Some(Command::Grade(args)) => grade::grade(args),
        Some(Command::Validate(args)) => validate::validate(args),
        Some(Command::View(args)) => view::view(args),
        Some(Command::Plot(args)) => plot::plot(args),
        None => run::run(cli.run),
    }
}
