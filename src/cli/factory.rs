//! `rigidref factory`: random bodies dropped into a container, the stress test and scaling
//! report of the 2D system (and, with a container image and --pieces tetris, the Tetris tube).

use anyhow::{Context, bail};
use clap::Args;
use nalgebra::Vector2;
use rigidref::blocks::factory::{Factory, Pieces, container};
use rigidref::blocks::image::{ImageSettings, load_image};
use rigidref::blocks::scaling::{linear_fit, plot};
use rigidref::blocks::world::{Params2, World2};
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `rigidref factory`.
#[derive(Args)]
#[command(after_long_help = "\
Drops --batch bodies every --interval time units into a container until --bodies have been
dropped, then lets them settle for --settle. Writes DIR/scaling.csv (per step: time, bodies,
contacts, PGS solve seconds), DIR/scaling.svg (solve time against contacts with a least-squares
line and its R²) and DIR/report.json. Timing figures are measurements of this machine; the
report states them, no test asserts them.")]
pub struct FactoryArgs {
    /// Bodies to drop.
    #[arg(long, default_value_t = 2000)]
    pub bodies: usize,
    /// Bodies per batch.
    #[arg(long, default_value_t = 10)]
    pub batch: usize,
    /// Time between batches.
    #[arg(long, default_value_t = 1.0)]
    pub interval: f64,
    /// Time to run after the last drop.
    #[arg(long, default_value_t = 5.0)]
    pub settle: f64,
    /// Width of the generated container, blocks.
    #[arg(long, default_value_t = 150)]
    pub width: usize,
    /// Depth of the generated container, blocks.
    #[arg(long, default_value_t = 100)]
    pub depth: usize,
    /// Use the pinned bodies of this image as the container instead (e.g. tetrisTube.png).
    #[arg(long)]
    pub container: Option<PathBuf>,
    /// What to drop.
    #[arg(long, value_enum, default_value_t = Pieces::Random)]
    pub pieces: Pieces,
    /// Blocks per side of a piece's cell (4 for the Tetris tube's pieces).
    #[arg(long, default_value_t = 1)]
    pub piece_scale: usize,
    /// Seed of the factory (and of PGS's random order).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// PGS iterations.
    #[arg(long, default_value_t = 10)]
    pub iterations: u32,
    /// Substeps per step.
    #[arg(long, default_value_t = 1)]
    pub substeps: u32,
    /// Output folder.
    #[arg(long, default_value = "factory")]
    pub out: PathBuf,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The report written to DIR/report.json.
#[derive(serde::Serialize)]
pub struct FactoryReport {
    /// Bodies at the end (dropped plus the container).
    pub bodies: usize,
    /// Most contacts in one step.
    pub max_contacts: usize,
    /// Steps run.
    pub steps: u64,
    /// Fit of solve seconds against contacts.
    pub fit: Option<rigidref::blocks::scaling::LinearFit>,
    /// Total PGS seconds.
    pub pgs_seconds: f64,
    /// Wall seconds.
    pub wall_seconds: f64,
}

/// Runs the factory.
pub fn factory(args: FactoryArgs) -> anyhow::Result<FactoryReport> {
    if args.bodies == 0
        || args.batch == 0
        || args.iterations == 0
        || args.substeps == 0
        || args.piece_scale == 0
    {
        bail!("--bodies, --batch, --iterations, --substeps and --piece-scale must be at least 1");
    }
    if !(args.interval > 0.0 && args.settle >= 0.0) {
        bail!("--interval must be positive and --settle ≥ 0");
    }
    if args.width < 10 || args.depth < 5 {
        bail!("the container must be at least 10 wide and 5 deep");
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create", args.out.display()))?;
    let groups = match &args.container {
        Some(p) => {
            let g: Vec<_> =
                load_image(p, &ImageSettings::default()).map_err(|e| anyhow::anyhow!(e))?;
            if !g.iter().any(|g| g.pinned) {
                bail!(
                    "{}: no pinned (blue) body to use as a container",
                    p.display()
                );
            }
            g
        }
        None => vec![container(args.width, args.depth)],
    };
    let params = Params2 {
        iterations: args.iterations,
        substeps: args.substeps,
        order: rigidref::solve::ContactOrder::Random,
        seed: args.seed,
        ..Params2::default()
    };
    let mut world = World2::new(&groups, params);
    // Drop zone: across the pinned bodies' extent, above their top.
    let (mut lo, mut hi) = (
        Vector2::repeat(f64::INFINITY),
        Vector2::repeat(f64::NEG_INFINITY),
    );
    for b in world.bodies.iter().filter(|b| b.pinned) {
        for block in &b.blocks {
            let p = b.to_world(&block.local);
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    let span = (hi.x - lo.x - 8.0).max(4.0);
    let mut factory = Factory::new(args.seed, args.pieces);
    factory.scale = args.piece_scale;
    let steps_per_batch = (args.interval / world.params.step).round().max(1.0) as u64;
    let batches = args.bodies.div_ceil(args.batch);
    let total_steps =
        batches as u64 * steps_per_batch + (args.settle / world.params.step).round() as u64;
    let mut csv = std::io::BufWriter::new(std::fs::File::create(args.out.join("scaling.csv"))?);
    writeln!(csv, "step,t,bodies,contacts,pgs_seconds")?;
    let mut points = Vec::new();
    let (mut dropped, mut max_contacts, mut pgs_seconds) = (0usize, 0usize, 0.0);
    let started = Instant::now();
    let progress = super::progress_bar(
        total_steps,
        "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps, {msg}",
    );
    let mut shown = false;
    for k in 0..total_steps {
        if k % steps_per_batch == 0 && dropped < args.bodies {
            let n = args.batch.min(args.bodies - dropped);
            let slot = span / n as f64;
            for s in 0..n {
                let x = lo.x + 4.0 + slot * (s as f64 + 0.5) + factory.uniform(-0.25, 0.25) * slot;
                world.add_body(factory.make(Vector2::new(x, lo.y - 6.0)));
            }
            dropped += n;
        }
        world.step();
        let contacts = world.last.contacts.len();
        max_contacts = max_contacts.max(contacts);
        pgs_seconds += world.last.solve_seconds;
        writeln!(
            csv,
            "{},{},{},{},{:.9}",
            world.step,
            world.time(),
            world.bodies.len(),
            contacts,
            world.last.solve_seconds
        )?;
        if contacts > 0 {
            points.push((contacts as f64, world.last.solve_seconds));
        }
        super::show_progress_after_a_second(&progress, started, args.quiet, &mut shown);
        if k % 20 == 0 {
            progress.set_position(k);
            progress.set_message(format!(
                "{} bodies, {contacts} contacts",
                world.bodies.len()
            ));
        }
    }
    progress.finish_and_clear();
    csv.flush()?;
    let fit = linear_fit(&points);
    if let Some(f) = &fit {
        plot(
            &points,
            f,
            &args.out.join("scaling.svg"),
            "PGS solve time against contacts",
        )
        .map_err(|e| anyhow::anyhow!(e))?;
    }
    let report = FactoryReport {
        bodies: world.bodies.len(),
        max_contacts,
        steps: world.step,
        fit,
        pgs_seconds,
        wall_seconds: started.elapsed().as_secs_f64(),
    };
    std::fs::write(
        args.out.join("report.json"),
        serde_json::to_string_pretty(&report)? + "\n",
    )?;
    if !args.quiet {
        eprintln!("bodies         {} ({} dropped)", report.bodies, dropped);
        eprintln!(
            "steps          {}, most contacts in a step {}",
            report.steps, report.max_contacts
        );
        if let Some(f) = &report.fit {
            eprintln!(
                "PGS time       {:.3e} ms per contact + {:.3e} ms, R² = {:.3} over {} steps",
                f.slope * 1e3,
                f.intercept * 1e3,
                f.r_squared,
                f.points
            );
        }
        eprintln!(
            "wall time      {:.1} s ({:.1} s in PGS)",
            report.wall_seconds, report.pgs_seconds
        );
        eprintln!(
            "report         {}/scaling.csv, scaling.svg, report.json",
            args.out.display()
        );
    }
    Ok(report)
}
