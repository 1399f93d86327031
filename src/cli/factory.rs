//! `rigidref factory`: random bodies dropped into a container, the stress test and scaling
//! report of the 2D system (and, with a container image and --pieces tetris, the Tetris tube).
//! docs/blocks2d.md §"Challenges", §"Scaling".

use super::progress::Progress;
use clap::Args;
use rigidref::tools::experiments::factory::{
    FACTORY_ITERATIONS, FACTORY_ORDER, FactoryReport, FactorySettings, Pieces, run_factory,
};
use std::path::{Path, PathBuf};

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
points in blue with the least-squares line and R², in-run points in grey), DIR/scaling.png (the
same plot drawn one pixel per block for the 2D system: blue axes, black points, the red line;
`rigidref run DIR/scaling.png` drops the graph onto its axes) and DIR/report.json.
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
    /// PGS sweeps per solve. The factory's own default, twice the starter's 10: with 10, a pile
    /// of 10 000 bricks gives way at about 9 000; with 20 it holds (docs/blocks2d.md
    /// §"Challenges").
    #[arg(long, default_value_t = FACTORY_ITERATIONS)]
    pub iterations: u32,
    /// Substeps per step.
    #[arg(long, default_value_t = 1)]
    pub substeps: u32,
    /// PGS's contact order: random-coloured (the factory's default: a fresh seeded colouring
    /// per solve and order of the colours per sweep, the colours' contacts four at a time;
    /// docs/contact.md §"Random coloured order"), random (a fresh seeded permutation per sweep),
    /// sequential, or coloured (docs/contact.md §"Coloured order").
    #[arg(long, value_enum, default_value_t = FACTORY_ORDER)]
    pub order: rigidref::solve::ContactOrder,
    /// Threads of the coloured order's sweeps (the same bits on any number; at least 1). Two
    /// pay where the second core is free (the 10 000-brick factory: 19.8 → 22.3 steps per
    /// second at the end, docs/performance.md §"Issue 49: problem order within a colour"); on a
    /// busy machine each colour's barrier waits for the other thread, which can be slower.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub threads: u32,
    /// Shock propagation after each velocity solve: the pile solved again layer by layer from
    /// the floor up, each layer against supports held fixed (docs/blocks2d.md §"Shock
    /// propagation").
    #[arg(long)]
    pub shock_propagation: bool,
    /// Output folder.
    #[arg(long, default_value = "factory")]
    pub out: PathBuf,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
    /// Also write DIR/view.html, the viewer page of the run (docs/viewing.md), recording the
    /// bodies every K steps (bodies appear when dropped; contacts are counted, not drawn)
    /// [default: no page].
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub view_every: u64,
}

impl FactoryArgs {
    /// The run the options ask for.
    fn settings(&self) -> FactorySettings {
        FactorySettings {
            bodies: self.bodies,
            batch: self.batch,
            interval: self.interval,
            drop_speed: self.drop_speed,
            settle: self.settle,
            width: self.width,
            depth: self.depth,
            container: self.container.clone(),
            pieces: self.pieces,
            piece_scale: self.piece_scale,
            seed: self.seed,
            iterations: self.iterations,
            substeps: self.substeps,
            order: self.order,
            threads: self.threads,
            shock_propagation: self.shock_propagation,
            view_every: self.view_every,
        }
    }
}

/// Runs the factory with a progress bar, prints its report and returns it.
pub fn factory(args: FactoryArgs) -> anyhow::Result<FactoryReport> {
    let mut progress: Option<Progress> = None;
    let (report, note) = run_factory(&args.settings(), &args.out, |p| {
        let bar = progress.get_or_insert_with(|| {
            Progress::new(
                p.planned,
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps, {msg}",
                args.quiet,
            )
        });
        bar.tick(p.step);
        if p.step.is_multiple_of(20) {
            bar.bar().set_length(p.planned);
            bar.bar()
                .set_message(format!("{} bodies, {} contacts", p.bodies, p.contacts));
        }
    })
    .map_err(anyhow::Error::msg)?;
    if let Some(bar) = &progress {
        bar.finish();
    }
    if let Some(note) = note {
        eprintln!("note: {note}");
    }
    if !args.quiet {
        print_report(&report, &args.out);
    }
    let problems = report.problems();
    for p in &problems {
        eprintln!("warning: {p}");
    }
    if !problems.is_empty() {
        anyhow::bail!(
            "{}: the factory run is not sound ({}); its report is in {}",
            args.container
                .as_ref()
                .map_or("the generated container".to_string(), |p| p
                    .display()
                    .to_string()),
            problems.len(),
            args.out.display()
        );
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
        "wall time      {:.1} s ({:.1} s in PGS during the run); {:.1} steps per second at the end (the last 200 steps, {} bodies)",
        report.wall_seconds, report.pgs_seconds, report.steps_per_second_at_end, report.bodies
    );
    let p = report.phases_ms_at_end;
    eprintln!(
        "step at the end detect {:.1} ms, assemble {:.1}, PGS {:.1}, apply {:.1}, integrate {:.1}, post-stabilisation {:.1}",
        p[0], p[1], p[2], p[3], p[4], p[5]
    );
    eprintln!(
        "report         {}/scaling.csv, retimed.csv, {}report.json",
        out.display(),
        if report.fit.is_some() {
            "scaling.svg, scaling.png (the plot as a 2D scene: rigidref run it), "
        } else {
            "(no scaling.svg or .png: too few steps with contacts for a fit), "
        }
    );
}
