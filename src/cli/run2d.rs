//! `rigidref run IMAGE.png`: the 2D image-block system. docs/blocks2d.md.

use super::run::RunArgs;
use anyhow::{Context, bail};
use nalgebra::Vector2;
use rigidref::blocks::image::{ImageSettings, load_image};
use rigidref::blocks::trace::{Record2, TraceHeader2};
use rigidref::blocks::world::{Params2, ScriptedImpulse, World2};
use rigidref::trace::TraceFormat;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// Parses `T:BODY:JX,JY` or `T:BODY:JX,JY:PX,PY`.
pub fn parse_impulse(text: &str) -> Result<ScriptedImpulse, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let pair = |s: &str| -> Result<Vector2<f64>, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{s:?}: {e}"))?;
        match v.as_slice() {
            [x, y] if x.is_finite() && y.is_finite() => Ok(Vector2::new(*x, *y)),
            _ => Err(format!("{s:?} is not two finite numbers X,Y")),
        }
    };
    if !(parts.len() == 3 || parts.len() == 4) {
        return Err(format!(
            "--impulse {text:?}: expected TIME:BODY:JX,JY[:PX,PY]"
        ));
    }
    let time: f64 = parts[0]
        .parse()
        .map_err(|e| format!("--impulse {text:?}: time: {e}"))?;
    let body: usize = parts[1]
        .parse()
        .map_err(|e| format!("--impulse {text:?}: body: {e}"))?;
    if !(time.is_finite() && time >= 0.0) {
        return Err(format!("--impulse {text:?}: time must be ≥ 0"));
    }
    Ok(ScriptedImpulse {
        time,
        body,
        impulse: pair(parts[2]).map_err(|e| format!("--impulse {text:?}: impulse {e}"))?,
        point: if parts.len() == 4 {
            Some(pair(parts[3]).map_err(|e| format!("--impulse {text:?}: point {e}"))?)
        } else {
            None
        },
    })
}

/// Parses `BODY:VX,VY:OMEGA:FREQ`.
pub fn parse_shake(text: &str) -> Result<rigidref::blocks::world::Shake, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let bad = || format!("--shake {text:?}: expected BODY:VX,VY:OMEGA:FREQ");
    if parts.len() != 4 {
        return Err(bad());
    }
    let body: usize = parts[0].parse().map_err(|_| bad())?;
    let v: Vec<f64> = parts[1]
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let angular: f64 = parts[2].parse().map_err(|_| bad())?;
    let frequency: f64 = parts[3].parse().map_err(|_| bad())?;
    if v.len() != 2
        || !v
            .iter()
            .chain([angular, frequency].iter())
            .all(|x| x.is_finite())
        || frequency < 0.0
    {
        return Err(bad());
    }
    Ok(rigidref::blocks::world::Shake {
        body,
        velocity: Vector2::new(v[0], v[1]),
        angular,
        frequency,
    })
}

/// Where the heaviest fifth of the moving bodies is: (mean height of the heaviest, mean height of
/// the rest, fraction of the heaviest in the upper half of the moving bodies), height = −y.
pub fn nut_statistics(world: &World2) -> (f64, f64, f64) {
    let mut moving: Vec<&rigidref::blocks::body::Body2> =
        world.bodies.iter().filter(|b| !b.pinned).collect();
    if moving.len() < 2 {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    moving.sort_by(|a, b| b.mass.total_cmp(&a.mass));
    let heavy = (moving.len() / 5).max(1);
    let mean = |s: &[&rigidref::blocks::body::Body2]| {
        s.iter().map(|b| -b.x.y).sum::<f64>() / s.len() as f64
    };
    let mut heights: Vec<f64> = moving.iter().map(|b| -b.x.y).collect();
    heights.sort_by(f64::total_cmp);
    let median = heights[heights.len() / 2];
    let upper = moving[..heavy].iter().filter(|b| -b.x.y >= median).count() as f64 / heavy as f64;
    (mean(&moving[..heavy]), mean(&moving[heavy..]), upper)
}

/// The parameters from the command line, checked.
pub fn params_from_args(args: &RunArgs) -> anyhow::Result<Params2> {
    let d = Params2::default();
    let p = Params2 {
        step: args.step.unwrap_or(d.step),
        substeps: args.substeps.unwrap_or(d.substeps),
        gravity: args.gravity.unwrap_or(d.gravity),
        gravity_angle: args.gravity_angle.unwrap_or(d.gravity_angle),
        mu: args.mu.unwrap_or(d.mu),
        restitution: args.restitution.unwrap_or(d.restitution),
        iterations: args.iterations.unwrap_or(d.iterations),
        tolerance: args.pgs_tolerance,
        order: args.order.unwrap_or(d.order),
        seed: args.seed.unwrap_or(d.seed),
        warm_start: !args.no_warm_start,
        post_stabilization: !args.no_post_stabilization,
        slop: args.slop.unwrap_or(d.slop),
        contact_model: args.contact_model.unwrap_or(d.contact_model),
        ..d
    };
    let positive = |name: &str, x: f64| -> anyhow::Result<()> {
        if !(x.is_finite() && x > 0.0) {
            bail!("--{name} must be a positive number, got {x}");
        }
        Ok(())
    };
    let non_negative = |name: &str, x: f64| -> anyhow::Result<()> {
        if !(x.is_finite() && x >= 0.0) {
            bail!("--{name} must be a number ≥ 0, got {x}");
        }
        Ok(())
    };
    positive("step", p.step)?;
    if p.substeps == 0 {
        bail!("--substeps must be at least 1");
    }
    if p.iterations == 0 {
        bail!("--iterations must be at least 1");
    }
    non_negative("gravity", p.gravity)?;
    if !p.gravity_angle.is_finite() {
        bail!("--gravity-angle must be finite");
    }
    non_negative("mu", p.mu)?;
    non_negative("restitution", p.restitution)?;
    if p.restitution > 1.0 {
        bail!("--restitution must be in [0, 1], got {}", p.restitution);
    }
    non_negative("slop", p.slop)?;
    if let Some(t) = p.tolerance {
        positive("pgs-tolerance", t)?;
    }
    Ok(p)
}

/// Whether `path` is a 2D scene: a .png image, or a JSON file with an `image` key.
pub fn is_2d(path: &Path) -> bool {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return true;
    }
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        && std::fs::read_to_string(path).is_ok_and(|t| rigidref::blocks::scene::is_scene2(&t))
}

/// The world of a 2D scene: an image with the command line's options, or a 2D scene file (whose
/// parameters, impulses and shakes come from the file; giving 2D physics options as well is an
/// error rather than a silent choice between the two).
pub fn world_from_args(path: &Path, args: &RunArgs) -> anyhow::Result<World2> {
    if !(args.rest_threshold().is_finite() && args.rest_threshold() >= 0.0) {
        bail!(
            "--rest-threshold must be a number ≥ 0, got {}",
            args.rest_threshold()
        );
    }
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        let given = args.physics_2d_given();
        if !given.is_empty() {
            bail!(
                "{}: a 2D scene file sets its own parameters; {} on the command line apply to .png scenes only",
                path.display(),
                given.join(", ")
            );
        }
        return world_of_scene_file(path);
    }
    world_from_image(path, args)
}

/// The world of a 2D scene file, its warnings printed.
fn world_of_scene_file(path: &Path) -> anyhow::Result<World2> {
    let scene = rigidref::blocks::scene::load_scene2(path)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene.world)
}

/// The world of a 2D scene as it stands: a 2D scene file with its parameters, or an image with
/// the default parameters (for commands without the 2D options, such as `crosscheck`).
pub fn world_of_scene(path: &Path) -> anyhow::Result<World2> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return world_of_scene_file(path);
    }
    let groups = load_image(path, &ImageSettings::default()).map_err(|e| anyhow::anyhow!(e))?;
    Ok(World2::new(&groups, Params2::default()))
}

/// Loads the image and builds the world, with the scripted impulses.
pub fn world_from_image(image: &Path, args: &RunArgs) -> anyhow::Result<World2> {
    let threshold = args
        .white_threshold
        .unwrap_or(ImageSettings::default().white_threshold);
    if !(0.0..1.0).contains(&threshold) {
        bail!("--white-threshold must be in [0, 1), got {threshold}");
    }
    let groups = load_image(
        image,
        &ImageSettings {
            white_threshold: threshold,
        },
    )
    .map_err(|e| anyhow::anyhow!(e))?;
    let params = params_from_args(args)?;
    let mut world = World2::new(&groups, params);
    for text in &args.impulse {
        let i = parse_impulse(text).map_err(|e| anyhow::anyhow!(e))?;
        if i.body >= world.bodies.len() {
            bail!(
                "--impulse {text:?}: body {} does not exist ({} bodies in {})",
                i.body,
                world.bodies.len(),
                image.display()
            );
        }
        world.impulses.push(i);
    }
    for text in &args.shake {
        let s = parse_shake(text).map_err(|e| anyhow::anyhow!(e))?;
        if s.body >= world.bodies.len() {
            bail!(
                "--shake {text:?}: body {} does not exist ({} bodies in {})",
                s.body,
                world.bodies.len(),
                image.display()
            );
        }
        world.shakes.push(s);
    }
    Ok(world)
}

/// Runs an image scene and writes its 2D trace.
pub fn run(image: &Path, args: &RunArgs) -> anyhow::Result<()> {
    // 2D traces are JSON lines only, and a 2D run always collides: refuse rather than ignore.
    let csv_out = args
        .out
        .as_ref()
        .is_some_and(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")));
    if args.format == Some(TraceFormat::Csv) || (args.format.is_none() && csv_out) {
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
    let mut world = world_from_args(image, args)?;
    world
        .check_finite()
        .map_err(|e| anyhow::anyhow!("{}: {e}", image.display()))?;
    let steps = super::steps_of(args, world.params.step, "")?;
    let out_path = args.out.clone().unwrap_or_else(|| "trace.jsonl".into());
    let out = super::create_trace_output(&out_path)?;
    let mut out = std::io::BufWriter::new(out);
    let name = image
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let header = TraceHeader2::for_world(&world, &name, &image.display().to_string());
    let write_err =
        |e: std::io::Error| anyhow::anyhow!("{}: cannot write trace: {e}", out_path.display());
    serde_json::to_writer(&mut out, &header)?;
    out.write_all(b"\n").map_err(write_err)?;
    serde_json::to_writer(&mut out, &Record2::of_world(&world))?;
    out.write_all(b"\n").map_err(write_err)?;
    let mut scaling = match &args.scaling_csv {
        Some(p) => {
            let mut f = std::io::BufWriter::new(
                std::fs::File::create(p)
                    .with_context(|| format!("{}: cannot create", p.display()))?,
            );
            writeln!(f, "step,bodies,contacts,pgs_seconds").map_err(write_err)?;
            Some(f)
        }
        None => None,
    };
    let mut nuts = match &args.nut_report {
        Some(p) => {
            let mut f = std::io::BufWriter::new(
                std::fs::File::create(p)
                    .with_context(|| format!("{}: cannot create", p.display()))?,
            );
            writeln!(
                f,
                "t,mean_height_heaviest_fifth,mean_height_others,heaviest_fraction_in_upper_half"
            )
            .map_err(write_err)?;
            Some(f)
        }
        None => None,
    };
    if let Some(dir) = &args.dump_problems {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the problem directory", dir.display()))?;
        world.record_problems = true;
    }
    let started = Instant::now();
    let progress = super::progress_bar(steps, super::STEPS_TEMPLATE);
    let mut shown = false;
    let mut most_contacts = 0;
    for k in 1..=steps {
        world.step();
        if let Err(e) = world.check_finite() {
            out.flush().map_err(write_err)?;
            bail!(
                "{}: the run stopped: {e}; the trace so far (to step {}) is kept in {}",
                image.display(),
                k - 1,
                out_path.display()
            );
        }
        most_contacts = most_contacts.max(world.frame.most_contacts);
        if let Some(dir) = &args.dump_problems {
            for solve in &world.frame_solves {
                let path = dir.join(format!("step-{k:06}-{:02}.json", solve.substep));
                let file = solve.problem_file(&name, k, world.params.h());
                let text = serde_json::to_string(&file).context("serialising a contact problem")?;
                std::fs::write(&path, text + "\n")
                    .with_context(|| format!("{}: cannot write", path.display()))?;
            }
        }
        if let Some(f) = &mut scaling {
            writeln!(
                f,
                "{k},{},{},{:.9}",
                world.bodies.len(),
                world.frame.contacts,
                world.frame.solve_seconds
            )
            .map_err(write_err)?;
        }
        if k % args.every == 0 || k == steps {
            serde_json::to_writer(&mut out, &Record2::of_world(&world))?;
            out.write_all(b"\n").map_err(write_err)?;
            if let Some(f) = &mut nuts {
                let (heavy, others, upper) = nut_statistics(&world);
                writeln!(f, "{},{heavy},{others},{upper}", world.time()).map_err(write_err)?;
            }
        }
        super::show_progress_after_a_second(&progress, started, args.quiet, &mut shown);
        if k % 16 == 0 {
            progress.set_position(k);
        }
    }
    out.flush().map_err(write_err)?;
    if let Some(f) = &mut nuts {
        f.flush().map_err(write_err)?;
    }
    if let Some(f) = &mut scaling {
        f.flush().map_err(write_err)?;
    }
    progress.finish_and_clear();
    if !args.quiet {
        let (kinetic, potential) = world.energy();
        let p = &world.params;
        let resting = world
            .bodies
            .iter()
            .filter(|b| !b.pinned && b.kinetic_energy() < args.rest_threshold())
            .count();
        let moving = world.bodies.iter().filter(|b| !b.pinned).count();
        eprintln!(
            "image          {} ({} bodies, {} pinned)",
            image.display(),
            world.bodies.len(),
            world.bodies.len() - moving
        );
        eprintln!(
            "steps          {steps} × {} substeps, h = {}, t = {}",
            p.substeps,
            p.h(),
            world.time()
        );
        eprintln!(
            "solver         {:?}, {} iterations, order {:?}, μ {}, restitution {}, post-stabilisation {}",
            p.contact_model, p.iterations, p.order, p.mu, p.restitution, p.post_stabilization
        );
        eprintln!("wall time      {:.3} s", started.elapsed().as_secs_f64());
        eprintln!("energy         kinetic {kinetic:.6e}, potential {potential:.6e}");
        eprintln!(
            "at rest        {resting} of {moving} bodies below kinetic energy {}",
            args.rest_threshold()
        );
        eprintln!(
            "contacts       {} now, at most {most_contacts}",
            world.last.contacts.len()
        );
        eprintln!("trace          {}", out_path.display());
    }
    Ok(())
}
