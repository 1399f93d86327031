//! `rigidref run SCENE.json` for a 3D scene: the trace, the problem dumps and the summary.

use super::progress::{Progress, Stopped};
use super::run_args::RunArgs;
use anyhow::Context;
use rigidref::rigid3d::diagnostics::{Energy, Momentum};
use rigidref::rigid3d::penetration_watch::InterpenetrationWatch;
use rigidref::rigid3d::scene::embedded::BUILT_IN_SOURCE;
use rigidref::rigid3d::trace::{TraceHeader, TraceRecord, TraceWriter};
use rigidref::rigid3d::world::World;
use rigidref::sim::{Flow, RunTotals, drive, is_recorded};

/// Runs a 3D scene. A run that fails midway keeps the trace written so far, flushed and valid.
pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let mut scene = super::common::load_scene_or_default(args.scene.as_deref(), &args.sets)?;
    if args.no_collisions {
        scene.params.check_collisions = false;
    }
    let steps = args.length.steps(scene.params.dt, " of seconds")?;
    args.output.prepare()?;
    let (format, out_path) = (args.output.format(), args.output.path());
    let out = super::common::create_trace_output(&out_path)?;
    let source = if args.scene.is_some() {
        scene.source.clone()
    } else {
        BUILT_IN_SOURCE.to_string()
    };

    let mut world = World::new(&scene).map_err(anyhow::Error::msg)?;
    let mut header = TraceHeader::for_world(&world, &source);
    header.overrides = scene.overrides.clone();
    let mut writer = TraceWriter::new(out, format, &header)
        .with_context(|| format!("{}: cannot write", out_path.display()))?;
    let write_err =
        |e: std::io::Error| anyhow::anyhow!("{}: cannot write trace: {e}", out_path.display());
    writer
        .write(TraceRecord::of_world(&world))
        .map_err(write_err)?;
    let (mut records, mut last_recorded) = (1u64, 0u64);
    let start = (world.energy(), world.momentum());
    let mut progress = Progress::steps(steps, args.quiet);
    let mut stats = RunTotals::default();
    let mut watch = InterpenetrationWatch::default();
    for warning in watch.observe(&world) {
        eprintln!("{warning}");
    }
    let mut stopped_at_contact = None;

    let ran = drive(&mut world, steps, |w, k| -> Result<Flow, Stopped> {
        stats.add(&w.solves, k, w.params.gravity.norm() * w.params.h());
        for warning in watch.observe(w) {
            progress.println(&warning);
        }
        if let Some(dir) = &args.output.dump_problems {
            for solve in &w.solves {
                super::common::dump_problem(dir, &w.params.name, k, w.params.h(), solve)?;
            }
        }
        let stop_here = w.params.stop_on_contact && !w.solves.is_empty();
        if is_recorded(k, steps, args.output.every) || stop_here {
            writer.write(TraceRecord::of_world(w)).map_err(write_err)?;
            records += 1;
            last_recorded = k;
        }
        progress.tick(k);
        if stop_here {
            stopped_at_contact = Some(k);
            return Ok(Flow::Stop);
        }
        Ok(Flow::Continue)
    });
    writer.flush().map_err(write_err)?;
    progress.finish();
    let ran = Stopped::outcome(ran, |failure| {
        format!(
            "{}: the run stopped: {failure}; the trace up to step {last_recorded} is in {}",
            scene.source,
            out_path.display()
        )
    })?;
    stats.measured = Some(watch.deepest);
    let check = super::common::detection_check(
        world.params.check_detection,
        world.detection_stats(),
        &scene.source,
    )?;
    if let Some(warning) = stats.unresolved_warning("m/s") {
        eprintln!("{}: {warning}", scene.source);
    }
    let wall = progress.elapsed();
    if !args.quiet {
        eprintln!("scene          {} ({source})", world.params.name);
        if world.params.preset == rigidref::common::preset::Preset::Starter {
            let p = &world.params;
            eprintln!(
                "preset         starter (the Python starter's, docs/scene-format.md §\"The starter preset\"; keys given override it): warm_start {}, stabilization {}, collision {}, tangents {}, pgs_iterations {}, pgs_order {:?}",
                p.warm_start,
                p.stabilization,
                p.collision.name(),
                p.tangents.name(),
                p.pgs_iterations,
                p.pgs_order
            );
        }
        if !scene.overrides.is_empty() {
            eprintln!("overrides      {}", scene.overrides.join(", "));
        }
        print_summary(&world, ran, wall, start, &stats);
        if watch.warnings > 0 {
            eprintln!(
                "watch          {} warnings about interpenetration or detection, printed above as they happened (docs/contact.md §\"Never silent\")",
                watch.warnings
            );
        }
        if let Some(line) = check {
            eprintln!("{line}");
        }
        eprintln!(
            "trace          {} ({records} records, {format:?})",
            out_path.display()
        );
    }
    if let Some(k) = stopped_at_contact {
        let n = world.solves.last().map_or(0, |s| s.contacts.len());
        eprintln!(
            "stop_on_contact: stopped at the first frame with contacts, step {k} (t = {} s), {n} contacts; inspect them with `rigidref contacts {}`",
            world.time(),
            args.scene
                .as_ref()
                .map_or(String::new(), |p| p.display().to_string())
        );
    }
    Ok(())
}

/// The summary's physics lines: steps, wall time, energy and momentum drift, contacts.
fn print_summary(
    world: &World,
    steps: u64,
    wall: f64,
    (start_energy, start_momentum): (Energy, Momentum),
    c: &RunTotals,
) {
    let (end_energy, end_momentum) = (world.energy(), world.momentum());
    let total_mass: f64 = world.bodies.iter().map(|b| b.mass).sum();
    // Gravity's impulse over the run is exactly M g t; what is left is drift.
    let momentum_drift = (end_momentum.linear
        - start_momentum.linear
        - world.params.gravity * (total_mass * world.time()))
    .norm();
    // Uniform gravity exerts no torque about the system's centre of mass.
    let angular_drift = (end_momentum.angular_com - start_momentum.angular_com).norm();
    let de = end_energy.total - start_energy.total;
    let relative = |d: f64, scale: f64| {
        if scale > 0.0 {
            format!(" ({:+.3e} relative)", d / scale)
        } else {
            String::new()
        }
    };
    let p = &world.params;
    eprintln!("bodies         {}", world.bodies.len());
    eprintln!(
        "steps          {steps} × {} substeps, h = {} s, t = {} s, integrator {}",
        p.substeps,
        p.h(),
        world.time(),
        p.integrator.name()
    );
    eprintln!(
        "wall time      {wall:.3} s ({:.0} steps/s)",
        steps as f64 / wall.max(1e-9)
    );
    eprintln!(
        "energy         {:.6e} J → {:.6e} J, drift {de:+.3e} J{}",
        start_energy.total,
        end_energy.total,
        relative(de, start_energy.total.abs())
    );
    if c.solves == 0 {
        eprintln!(
            "momentum drift |Δp − M g t| = {momentum_drift:.3e} kg·m/s, |ΔL_com| = {angular_drift:.3e} kg·m²/s{}",
            relative(angular_drift, start_momentum.angular_com.norm())
        );
    } else {
        // The ground's contact impulses are external (the bodies' impulses on each other cancel
        // in the sums): with ground contact, what is left is the ground's impulse, not a drift.
        eprintln!(
            "momentum       |Δp − M g t| = {momentum_drift:.3e} kg·m/s, |ΔL_com| = {angular_drift:.3e} kg·m²/s (the ground's contact impulses included: a drift only without ground contact)"
        );
    }
    if !p.check_collisions {
        return;
    }
    eprintln!("contacts       {}", c.describe("m/s", "m"));
    if let Some(line) = c.describe_criteria("N·s", "m/s", "J") {
        eprintln!("criteria       {line}");
    }
}
