//! `rigidref run IMAGE.png` (or a 2D scene file): the 2D image-block system's trace, reports and
//! summary. docs/blocks2d.md.

use super::progress::{Progress, Stopped};
use super::run_args::RunArgs;
use anyhow::bail;
use rigidref::blocks2d::params::MAX_ADAPTIVE_SUBSTEPS;
use rigidref::blocks2d::scene::{Scene2, load_2d};
use rigidref::blocks2d::trace::{Record2, TraceHeader2};
use rigidref::blocks2d::world::World2;
use rigidref::rigid3d::trace::TraceFormat;
use rigidref::sim::{Flow, RunTotals, SolveTotals, drive, is_recorded};
use rigidref::tools::nuts::{RISEN, nut_statistics, outside_bag, plot, time_to_rise};
use std::io::Write;
use std::path::Path;

/// A 2D scene with the command line's 2D options and `--set` overrides, its warnings printed.
pub fn load_scene(
    path: &Path,
    options: &super::args::Blocks2dOptions,
    sets: &super::args::SceneSets,
) -> anyhow::Result<Scene2> {
    let scene = load_2d(path, &options.command_line(sets)?)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
}

/// Runs a 2D scene and writes its trace (and the reports asked for).
pub fn run(image: &Path, args: &RunArgs) -> anyhow::Result<()> {
    // 2D traces are JSON lines only, and a 2D run always collides: refuse rather than ignore.
    if args.output.format() == TraceFormat::Csv {
        bail!(
            "{}: 2D traces are written as JSON lines only (--format jsonl; docs/trace-format.md)",
            image.display()
        );
    }
    if args.no_collisions {
        bail!(
            "{}: --no-collisions applies to 3D scenes only",
            image.display()
        );
    }
    let rest_threshold = args.rest.value()?;
    let all_contacts = args.reports.all_contacts;
    let scene = load_scene(image, &args.blocks, &args.sets)?;
    let mut world = scene.world;
    world
        .check_finite()
        .map_err(|e| anyhow::anyhow!("{}: {e}", image.display()))?;
    let steps = args.length.steps(world.params.dt, "")?;
    args.output.prepare()?;
    let out_path = args.output.path();
    let mut out = std::io::BufWriter::new(super::common::create_trace_output(&out_path)?);
    let name = image
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let write_err =
        |e: std::io::Error| anyhow::anyhow!("{}: cannot write trace: {e}", out_path.display());
    let mut header = TraceHeader2::for_world(&world, &name, &image.display().to_string());
    header.overrides = scene.overrides.clone();
    write_json_line(&mut out, &header).map_err(write_err)?;
    write_json_line(&mut out, &Record2::of_world(&world, all_contacts)).map_err(write_err)?;
    let mut reports = Reports2::open(&args.reports)?;
    reports.nuts(&world)?;
    let mut progress = Progress::steps(steps, args.quiet);
    let start_energy = world.energy().total;
    let (mut run_totals, mut last_done, mut most_contacts) = (RunTotals::default(), 0, 0);
    let ran = drive(&mut world, steps, |w, k| -> Result<Flow, Stopped> {
        last_done = k;
        let totals = SolveTotals::of(&w.solves);
        run_totals.add(
            &w.solves,
            k,
            w.params.gravity * w.params.dt / f64::from(w.substeps_in_step),
        );
        most_contacts = most_contacts.max(w.most_contacts_in_step);
        if let Some(dir) = &args.output.dump_problems {
            for solve in &w.solves {
                super::common::dump_problem(
                    dir,
                    &name,
                    k,
                    w.params.dt / f64::from(w.substeps_in_step),
                    solve,
                )?;
            }
        }
        reports.scaling(w, k, &totals)?;
        if is_recorded(k, steps, args.output.every) {
            write_json_line(&mut out, &Record2::of_world(w, all_contacts))?;
            reports.nuts(w)?;
        }
        progress.tick(k);
        Ok(Flow::Continue)
    });
    out.flush().map_err(write_err)?;
    let nut_finding = reports.flush()?;
    progress.finish();
    Stopped::outcome(ran, |e| {
        format!(
            "{}: the run stopped: {e}; the trace so far (to step {last_done}) is kept in {}",
            image.display(),
            out_path.display()
        )
    })?;
    if let Some(warning) = run_totals.unresolved_warning("blocks per time unit") {
        eprintln!("{}: {warning}", image.display());
    }
    if let Some(first) = world.impulses.iter().map(|i| i.time).reduce(f64::min) {
        eprintln!(
            "warning: {}: {} scripted impulse(s) from t = {first} were never applied: the run ended at t = {}",
            image.display(),
            world.impulses.len(),
            world.time()
        );
    }
    if !args.quiet {
        let summary = Summary2 {
            image,
            steps,
            wall: progress.elapsed(),
            rest_threshold,
            totals: run_totals,
            most_contacts,
            overrides: &scene.overrides,
            start_energy,
        };
        summary.print(&world);
        if let Some(finding) = nut_finding {
            eprintln!("nuts           {finding}");
        }
        eprintln!("trace          {}", out_path.display());
    }
    Ok(())
}

/// The reports a 2D run writes beside its trace: the scaling CSV (every step) and the nut
/// report (every recorded step).
struct Reports2 {
    scaling: Option<std::io::BufWriter<std::fs::File>>,
    nuts: Option<std::io::BufWriter<std::fs::File>>,
    /// The nut report's path and its (t, fraction of the heaviest fifth in the upper half)
    /// points, for the plot beside it.
    nut_points: Option<(std::path::PathBuf, Vec<(f64, f64)>)>,
}

impl Reports2 {
    /// Creates the files asked for, with their header lines.
    fn open(asked: &super::run_args::Run2dReports) -> anyhow::Result<Reports2> {
        let mut reports = Reports2 {
            scaling: None,
            nuts: None,
            nut_points: None,
        };
        if let Some(p) = &asked.scaling_csv {
            let mut f = super::common::create_file(p)?;
            writeln!(f, "step,bodies,contacts,pgs_seconds")?;
            reports.scaling = Some(f);
        }
        if let Some(p) = &asked.nut_report {
            let mut f = super::common::create_file(p)?;
            writeln!(
                f,
                "t,mean_height_heaviest_fifth,mean_height_others,heaviest_fraction_in_upper_half,outside_bag"
            )?;
            reports.nuts = Some(f);
            reports.nut_points = Some((p.with_extension("svg"), Vec::new()));
        }
        Ok(reports)
    }

    /// Step `k`'s line of the scaling CSV: contacts detected and PGS seconds, summed over its
    /// substeps.
    fn scaling(&mut self, w: &World2, k: u64, totals: &SolveTotals) -> std::io::Result<()> {
        match &mut self.scaling {
            Some(f) => writeln!(
                f,
                "{k},{},{},{:.9}",
                w.bodies.len(),
                w.contacts_in_step,
                totals.solve_seconds
            ),
            None => Ok(()),
        }
    }

    /// A line of the nut report: where the heaviest fifth of the moving bodies is now.
    fn nuts(&mut self, w: &World2) -> std::io::Result<()> {
        let Some(f) = &mut self.nuts else {
            return Ok(());
        };
        let s = nut_statistics(w);
        if let Some((_, points)) = &mut self.nut_points {
            points.push((w.time(), s.heaviest_fraction_in_upper_half));
        }
        writeln!(
            f,
            "{},{},{},{},{}",
            w.time(),
            s.heaviest_mean_height,
            s.others_mean_height,
            s.heaviest_fraction_in_upper_half,
            outside_bag(w)
        )
    }

    /// Flushes the files and draws the nut report's plot (NAME.svg beside NAME.csv), with the
    /// time the largest nuts took to rise, if they did; returns that finding for the summary.
    fn flush(&mut self) -> anyhow::Result<Option<String>> {
        for f in [&mut self.nuts, &mut self.scaling].into_iter().flatten() {
            f.flush()?;
        }
        if let Some((path, points)) = &self.nut_points {
            let risen = match time_to_rise(points) {
                Some(t) => format!("reached {RISEN} at t = {t}"),
                None => format!("did not reach {RISEN}"),
            };
            let title = format!("heaviest fifth of the nuts in the upper half ({risen})");
            plot(points, path, &title).map_err(anyhow::Error::msg)?;
            let last = points.last().map_or(f64::NAN, |p| p.1);
            return Ok(Some(format!(
                "heaviest fifth in the upper half: {:.2} at the start, {last:.2} at the end; {risen}; plot {}",
                points.first().map_or(f64::NAN, |p| p.1),
                path.display()
            )));
        }
        Ok(None)
    }
}

/// Writes `value` as one line of JSON.
fn write_json_line(out: &mut impl Write, value: &impl serde::Serialize) -> std::io::Result<()> {
    serde_json::to_writer(&mut *out, value)?;
    out.write_all(b"\n")
}

/// What the 2D summary reports beside the world's own state.
struct Summary2<'a> {
    image: &'a Path,
    steps: u64,
    wall: f64,
    rest_threshold: f64,
    totals: RunTotals,
    most_contacts: usize,
    overrides: &'a [String],
    /// Total energy at the start (kinetic + potential + elastic), mass · blocks² / time².
    start_energy: f64,
}

impl Summary2<'_> {
    fn print(&self, world: &World2) {
        let e = world.energy();
        let p = &world.params;
        let moving = world.bodies.iter().filter(|b| !b.pinned).count();
        let resting = world
            .bodies
            .iter()
            .filter(|b| !b.pinned && b.kinetic_energy() < self.rest_threshold)
            .count();
        let mut joined = String::new();
        if !world.pins.is_empty() || !world.springs.is_empty() {
            joined = format!(
                "; {} pins, {} springs",
                world.pins.len(),
                world.springs.len()
            );
        }
        eprintln!(
            "image          {} ({} bodies, {} pinned{joined})",
            self.image.display(),
            world.bodies.len(),
            world.bodies.len() - moving
        );
        eprintln!(
            "steps          {} × {} substeps, h = {}, t = {}; gravity {} at {}°",
            self.steps,
            p.substeps,
            p.h(),
            world.time(),
            p.gravity,
            p.gravity_angle
        );
        if let Some(travel) = p.max_travel {
            eprintln!(
                "adaptive       at most {travel} blocks per substep: up to {} substeps in a step{}",
                world.most_substeps,
                match world.capped_steps {
                    0 => String::new(),
                    n => format!(
                        "; warning: {n} steps at the cap of {MAX_ADAPTIVE_SUBSTEPS} substeps moved further"
                    ),
                }
            );
        }
        let solver = match p.solver {
            rigidref::solve::Solver::Newton => "by newton (exact)".to_string(),
            rigidref::solve::Solver::Pgs => format!(
                "by pgs, {} iterations{}, order {:?} (seed {})",
                p.iterations,
                p.tolerance
                    .map_or(String::new(), |t| format!(" (tolerance {t})")),
                p.order,
                p.seed
            ),
        };
        eprintln!(
            "solver         {:?} contacts {solver}, μ {}, restitution {}, warm start {}, post-stabilisation {} (slop {}){}",
            p.contact_model,
            p.mu,
            p.restitution,
            p.warm_start,
            p.post_stabilization,
            p.slop,
            if p.shock_propagation {
                ", shock propagation"
            } else {
                ""
            }
        );
        if !self.overrides.is_empty() {
            eprintln!("overrides      {}", self.overrides.join(", "));
        }
        eprintln!("wall time      {:.3} s", self.wall);
        // The total and its change first: in a pile the potential energy dominates and the
        // kinetic energy alone says little about what the run gained or lost.
        eprintln!(
            "energy         {:.6e} → {:.6e}, change {:+.3e} (now kinetic {:.6e}, potential {:.6e})",
            self.start_energy,
            e.total,
            e.total - self.start_energy,
            e.kinetic,
            e.potential
        );
        if p.post_stabilization {
            eprintln!(
                "post-stab.     worst residual {:.3e} blocks per time unit (the position solve's, {} iterations)",
                world.post_stabilization_residual, p.iterations
            );
        }
        eprintln!(
            "at rest        {resting} of {moving} bodies below kinetic energy {}",
            self.rest_threshold
        );
        eprintln!(
            "contacts       {} now, at most {}; solves: {}",
            world.contacts.len(),
            self.most_contacts,
            self.totals
                .describe("blocks per time unit", "blocks (disc overlap)")
        );
        if let Some(line) =
            self.totals
                .describe_criteria("mass·blocks/time", "blocks/time", "mass·blocks²/time²")
        {
            eprintln!("criteria       {line}");
        }
    }
}
