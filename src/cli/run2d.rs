//! `rigidref run IMAGE.png` (or a 2D scene file): the 2D image-block system's trace, reports and
//! summary. docs/blocks2d.md.

mod reports;

use super::progress::{Progress, Stopped};
use super::run_args::RunArgs;
use anyhow::bail;
use reports::{Reports2, Summary2, write_json_line};
use rigidref::blocks2d::params::MAX_ADAPTIVE_SUBSTEPS;

use rigidref::blocks2d::trace::{Record2, TraceHeader2};
use rigidref::blocks2d::world::World2;
use rigidref::rigid3d::trace::TraceFormat;
use rigidref::sim::{Flow, RunTotals, SolveTotals, drive, is_recorded};
use rigidref::tools::experiments::nuts::{
    HOLD_CYCLES, RISEN, nut_statistics, outside_bag, plot, time_to_rise, time_to_rise_held,
};
use std::io::Write;
use std::path::Path;

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
    let scene = super::common::load_scene_2d(image, &args.blocks, &args.sets)?;
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
    // The records from here on are formatted on a thread of their own, in order.
    let mut out = rigidref::common::writer::BackgroundWriter::new(
        out,
        |out, record: &Record2| write_json_line(out, record),
        |out| out.flush(),
    );
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
            out.write(Record2::of_world(w, all_contacts))?;
            reports.nuts(w)?;
        }
        progress.tick(k);
        Ok(Flow::Continue)
    });
    out.flush().map_err(write_err)?;
    let nut_finding = reports.flush(&world)?;
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
    let check = super::common::detection_check(
        world.params.check_detection,
        world.detection_stats(),
        &image.display().to_string(),
    )?;
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
        if let Some(line) = check {
            eprintln!("{line}");
        }
        if let Some(finding) = nut_finding {
            eprintln!("nuts           {finding}");
        }
        eprintln!("trace          {}", out_path.display());
    }
    Ok(())
}
