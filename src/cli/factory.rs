//! `rigidref factory`: random bodies dropped into a container, the stress test and scaling
//! report of the 2D system (and, with a container image and --pieces tetris, the Tetris tube).
//! docs/blocks2d.md §"Challenges", §"Scaling".

use anyhow::{Context, bail};
use clap::Args;
use rigidref::blocks::factory::{DropZone, Factory, Pieces, container, container_size};
use rigidref::blocks::image::{ImageSettings, load_image};
use rigidref::blocks::scaling::{LinearFit, linear_fit, plot, retime};
use rigidref::blocks::world::{ContactProblem2, Params2, World2};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Drops in a row that place nothing before the container counts as full.
const FULL_AFTER: u32 = 20;

/// Contact problems kept during the run for re-timing (spread evenly over the planned steps).
const RETIMED_PROBLEMS: u64 = 100;

/// Rounds of re-timing: each problem's time is the median of this many solves.
const RETIME_ROUNDS: usize = 5;

/// Arguments of `rigidref factory`.
#[derive(Args)]
#[command(after_long_help = "\
Drops --batch bodies every --interval time units into a container until --bodies have been
dropped, then lets them settle for --settle. Bodies are placed a few blocks above the top of the
pile, not at the rim, so that they land slowly however deep the container; a body is never
placed where it would overlap another (the drop waits instead). When the pile reaches the rim,
or 20 drops in a row find no free place, the container is full and dropping stops, with a note.

The scaling report: the run keeps 100 of its contact problems, spread over the run, and at the
end re-times PGS on them side by side (5 rounds, each in a fresh random order; the median
thread CPU time per problem). That is the fitted measurement: timing each step as the run reaches
it would tie the machine's slow and fast spells to the contact count of the moment, because in
a factory the contact count grows with time. The in-run times are kept too, and fitted for
comparison.

Writes DIR/scaling.csv (per step: step, t, bodies, contacts, PGS wall and thread CPU seconds),
DIR/retimed.csv (contacts, median CPU seconds per re-timed problem), DIR/scaling.svg (re-timed
points in blue with the least-squares line and R², in-run points in grey) and DIR/report.json.
Timing figures are measurements of this machine; the report states them, no test asserts them.

The scaling demonstration (at least 2 000 bodies and 10 000 contacts; docs/blocks2d.md):
  rigidref factory --pieces bricks --bodies 3000 --out factory/")]
pub struct FactoryArgs {
    /// Bodies to drop.
    #[arg(long, default_value_t = 2000)]
    pub bodies: usize,
    /// Bodies per batch.
    #[arg(long, default_value_t = 10)]
    pub batch: usize,
    /// Time between batches.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub interval: f64,
    /// Downward speed of a dropped body, blocks per time unit (so that a batch has left the drop
    /// zone when the next comes: under the default gravity a body at rest falls only ½ block in
    /// the first time unit).
    #[arg(long, default_value_t = 5.0, allow_negative_numbers = true)]
    pub drop_speed: f64,
    /// Time to run after the last drop.
    #[arg(long, default_value_t = 20.0, allow_negative_numbers = true)]
    pub settle: f64,
    /// Width of the generated container, blocks [default: sized for --bodies, with the depth].
    #[arg(long)]
    pub width: Option<usize>,
    /// Depth of the generated container, blocks [default: room for --bodies pieces, twice their
    /// blocks' area, five wide for three deep].
    #[arg(long)]
    pub depth: Option<usize>,
    /// Use the pinned bodies of this image as the container instead (e.g. tetrisTube.png).
    #[arg(long, conflicts_with_all = ["width", "depth"])]
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
    /// Bodies at the end (dropped plus the container's image's bodies).
    pub bodies: usize,
    /// Bodies dropped.
    pub dropped: usize,
    /// Dropping stopped early because the container was full: the pile reached its rim, or 20
    /// drops in a row found no free place.
    pub container_full: bool,
    /// The generated container's width and depth, blocks (none with --container).
    pub container: Option<[usize; 2]>,
    /// Most contacts in one step.
    pub max_contacts: usize,
    /// The deepest disc overlap among the last step's contacts, blocks (the pile's health: the
    /// post-stabilisation slop is 0.01; a block disc's diameter is √2).
    pub deepest_overlap_at_end: f64,
    /// Total kinetic energy at the end.
    pub kinetic_energy_at_end: f64,
    /// Moving bodies outside the container at the end (escaped through its floor or walls, or
    /// spilled over): 0 in a sound run.
    pub outside_container_at_end: usize,
    /// Steps run.
    pub steps: u64,
    /// The scaling figure: PGS solve CPU seconds against contacts, re-timed side by side on the
    /// problems kept during the run (median of `retime_rounds` rounds each).
    pub fit: Option<LinearFit>,
    /// Problems re-timed.
    pub retimed_problems: usize,
    /// Rounds of re-timing.
    pub retime_rounds: usize,
    /// For comparison: the same fitted to the thread CPU time each step's solve took in the run.
    pub fit_in_run: Option<LinearFit>,
    /// For comparison: the same fitted to the wall time each step's solve took in the run.
    pub fit_in_run_wall: Option<LinearFit>,
    /// Total PGS wall seconds in the run.
    pub pgs_seconds: f64,
    /// Total PGS thread CPU seconds in the run.
    pub pgs_cpu_seconds: f64,
    /// Wall seconds of the whole command.
    pub wall_seconds: f64,
}

fn check_args(args: &FactoryArgs) -> anyhow::Result<()> {
    if args.bodies == 0
        || args.batch == 0
        || args.iterations == 0
        || args.substeps == 0
        || args.piece_scale == 0
    {
        bail!("--bodies, --batch, --iterations, --substeps and --piece-scale must be at least 1");
    }
    if !(args.interval.is_finite() && args.interval > 0.0) {
        bail!(
            "--interval must be a positive number, got {}",
            args.interval
        );
    }
    if !(args.settle.is_finite() && args.settle >= 0.0) {
        bail!("--settle must be a number ≥ 0, got {}", args.settle);
    }
    if !(args.drop_speed.is_finite() && args.drop_speed >= 0.0) {
        bail!("--drop-speed must be a number ≥ 0, got {}", args.drop_speed);
    }
    if args.width.is_some_and(|w| w < 10) || args.depth.is_some_and(|d| d < 5) {
        bail!("the container must be at least 10 wide and 5 deep");
    }
    // Far above any useful run, so that an absurd value is an error, not a run that never ends.
    if args.bodies > 1_000_000 {
        bail!("--bodies may be at most 1000000, got {}", args.bodies);
    }
    if args.piece_scale > 16 {
        bail!("--piece-scale may be at most 16, got {}", args.piece_scale);
    }
    Ok(())
}

/// Creates `path` for writing, naming it in the error.
fn create(path: &Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    Ok(std::io::BufWriter::new(
        std::fs::File::create(path)
            .with_context(|| format!("{}: cannot create", path.display()))?,
    ))
}

/// Runs the factory.
pub fn factory(args: FactoryArgs) -> anyhow::Result<FactoryReport> {
    check_args(&args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create", args.out.display()))?;
    let (groups, size) = match &args.container {
        // The generated container's inside is `size`; its walls and floor are
        // CONTAINER_WALL blocks thick around it.
        Some(p) => {
            let g = load_image(p, &ImageSettings::default()).map_err(|e| anyhow::anyhow!(e))?;
            if !g.iter().any(|g| g.pinned) {
                bail!(
                    "{}: no pinned (blue) body to use as a container",
                    p.display()
                );
            }
            (g, None)
        }
        None => {
            let (w, d) = container_size(args.bodies, args.pieces, args.piece_scale);
            let (w, d) = (args.width.unwrap_or(w), args.depth.unwrap_or(d));
            // The container is a pixel grid before it becomes a body: an absurd size is an
            // error, not an aborted allocation.
            if (w as f64) * (d as f64) > 1e8 {
                bail!(
                    "a container of {w} × {d} blocks is more than the limit of 100 million blocks"
                );
            }
            (vec![container(w, d)], Some([w, d]))
        }
    };
    let params = Params2 {
        iterations: args.iterations,
        substeps: args.substeps,
        order: rigidref::solve::ContactOrder::Random,
        seed: args.seed,
        ..Params2::default()
    };
    let mut world = World2::new(&groups, params);
    let settings = world.pgs_settings();
    let zone = DropZone::above_pinned(&world).context("no pinned body to drop into")?;
    // The pile is full when it reaches the rim: a container must have walls to fill.
    if zone.floor - zone.rim < 5.0 {
        bail!(
            "{}: the pinned bodies rise only {} blocks above their lowest row; a container needs walls at least 5 blocks high",
            args.container
                .as_ref()
                .map_or("the container".to_string(), |p| p.display().to_string()),
            zone.floor - zone.rim
        );
    }
    let mut factory = Factory::new(args.seed, args.pieces);
    factory.scale = args.piece_scale;
    let steps_per_drop = (args.interval / world.params.step).round().max(1.0) as u64;
    let settle = (args.settle / world.params.step).round();
    let drops =
        (args.interval / world.params.step).round() * args.bodies.div_ceil(args.batch) as f64;
    super::check_step_count(settle + drops, world.params.step)?;
    let settle_steps = settle as u64;
    // The length of the run if every drop places a whole batch; drops that must wait (the drop
    // zone still occupied) lengthen it.
    let planned_steps = args.bodies.div_ceil(args.batch) as u64 * steps_per_drop + settle_steps;
    let keep_every = (planned_steps / RETIMED_PROBLEMS).max(1);
    let csv_path = args.out.join("scaling.csv");
    let mut csv = create(&csv_path)?;
    let csv_err = |e: std::io::Error| anyhow::anyhow!("{}: cannot write: {e}", csv_path.display());
    writeln!(csv, "step,t,bodies,contacts,pgs_seconds,pgs_cpu_seconds").map_err(csv_err)?;
    let (mut in_run_wall, mut in_run_cpu) = (Vec::new(), Vec::new());
    let mut kept: Vec<ContactProblem2> = Vec::new();
    let (mut dropped, mut max_contacts) = (0usize, 0usize);
    let (mut pgs_seconds, mut pgs_cpu_seconds) = (0.0, 0.0);
    // Drops in a row that placed nothing; after FULL_AFTER of them the container is full.
    let (mut fruitless, mut full) = (0u32, false);
    let mut settled = 0u64;
    let started = Instant::now();
    let progress = super::progress_bar(
        planned_steps,
        "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps, {msg}",
    );
    let mut shown = false;
    let mut k = 0u64;
    while settled < settle_steps || (dropped < args.bodies && !full) {
        let dropping = dropped < args.bodies && !full;
        if dropping && k.is_multiple_of(steps_per_drop) {
            if zone.is_full(&world) {
                full = true;
            } else {
                let n = args.batch.min(args.bodies - dropped);
                let placed = factory.drop_batch(&mut world, &zone, n, args.drop_speed);
                dropped += placed;
                fruitless = if placed == 0 { fruitless + 1 } else { 0 };
                full = fruitless >= FULL_AFTER;
            }
        }
        if !dropping {
            settled += 1;
        }
        world.step();
        k += 1;
        // Summed over the step's substeps (one solve each), so that time and contacts match.
        let contacts = world.frame.contacts;
        max_contacts = max_contacts.max(world.frame.most_contacts);
        let (wall, cpu) = (world.frame.solve_seconds, world.frame.solve_cpu_seconds);
        pgs_seconds += wall;
        pgs_cpu_seconds += cpu;
        writeln!(
            csv,
            "{},{},{},{},{wall:.9},{cpu:.9}",
            world.step,
            world.time(),
            world.bodies.len(),
            contacts,
        )
        .map_err(csv_err)?;
        if contacts > 0 {
            in_run_wall.push((contacts as f64, wall));
            in_run_cpu.push((contacts as f64, cpu));
            if k.is_multiple_of(keep_every)
                && let Some(problem) = &world.last_problem
            {
                kept.push(problem.clone());
            }
        }
        super::show_progress_after_a_second(&progress, started, args.quiet, &mut shown);
        if k.is_multiple_of(20) {
            if k > planned_steps {
                progress.set_length(k + settle_steps);
            }
            progress.set_position(k);
            progress.set_message(format!(
                "{} bodies, {contacts} contacts",
                world.bodies.len()
            ));
        }
    }
    progress.finish_and_clear();
    csv.flush().map_err(csv_err)?;
    if full {
        eprintln!(
            "note: the container is full (the pile reached its rim, or {FULL_AFTER} drops in a row found no free place): {dropped} of {} bodies were dropped",
            args.bodies
        );
    }

    let retimed = retime(&kept, &settings, RETIME_ROUNDS, args.seed);
    let retimed_path = args.out.join("retimed.csv");
    let mut retimed_csv = create(&retimed_path)?;
    let retimed_err =
        |e: std::io::Error| anyhow::anyhow!("{}: cannot write: {e}", retimed_path.display());
    writeln!(retimed_csv, "contacts,pgs_cpu_seconds_median").map_err(retimed_err)?;
    for (contacts, seconds) in &retimed {
        writeln!(retimed_csv, "{contacts},{seconds:.9}").map_err(retimed_err)?;
    }
    retimed_csv.flush().map_err(retimed_err)?;
    let fit = linear_fit(&retimed);
    let svg = args.out.join("scaling.svg");
    if fit.is_none() {
        // No line to draw: do not leave an earlier run's plot looking like this one's.
        let _ = std::fs::remove_file(&svg);
    }
    if let Some(f) = &fit {
        plot(
            &retimed,
            &in_run_cpu,
            f,
            &svg,
            "PGS solve CPU time (re-timed)",
        )
        .map_err(|e| anyhow::anyhow!(e))?;
    }
    let report = FactoryReport {
        bodies: world.bodies.len(),
        dropped,
        container_full: full,
        container: size,
        max_contacts,
        deepest_overlap_at_end: world.deepest_overlap(),
        kinetic_energy_at_end: world.energy().0,
        outside_container_at_end: world
            .bodies
            .iter()
            .filter(|b| !b.pinned && zone.is_outside(b))
            .count(),
        steps: world.step,
        fit,
        retimed_problems: retimed.len(),
        retime_rounds: RETIME_ROUNDS,
        fit_in_run: linear_fit(&in_run_cpu),
        fit_in_run_wall: linear_fit(&in_run_wall),
        pgs_seconds,
        pgs_cpu_seconds,
        wall_seconds: started.elapsed().as_secs_f64(),
    };
    let report_path = args.out.join("report.json");
    std::fs::write(&report_path, serde_json::to_string_pretty(&report)? + "\n")
        .with_context(|| format!("{}: cannot write", report_path.display()))?;
    if !args.quiet {
        print_report(&report, &args.out);
    }
    Ok(report)
}

fn print_report(report: &FactoryReport, out: &Path) {
    eprintln!(
        "bodies         {} ({} dropped){}",
        report.bodies,
        report.dropped,
        report
            .container
            .map_or(String::new(), |[w, d]| format!(", container {w} × {d}"))
    );
    eprintln!(
        "steps          {}, most contacts in a step {}",
        report.steps, report.max_contacts
    );
    eprintln!(
        "at the end     deepest overlap {:.4} blocks, kinetic energy {:.3e}, {} bodies outside the container",
        report.deepest_overlap_at_end,
        report.kinetic_energy_at_end,
        report.outside_container_at_end
    );
    let fits = [
        ("PGS re-timed ", &report.fit),
        ("in-run CPU   ", &report.fit_in_run),
        ("in-run wall  ", &report.fit_in_run_wall),
    ];
    for (what, fit) in fits {
        if let Some(f) = fit {
            eprintln!("{what}  {}, over {} points", f.describe_ms(), f.points);
        }
    }
    eprintln!(
        "wall time      {:.1} s ({:.1} s in PGS during the run)",
        report.wall_seconds, report.pgs_seconds
    );
    eprintln!(
        "report         {}/scaling.csv, retimed.csv, {}report.json",
        out.display(),
        if report.fit.is_some() {
            "scaling.svg, "
        } else {
            "(no scaling.svg: too few steps with contacts for a fit), "
        }
    );
}
