//! `rigidref run`: simulate a scene and write its trace, with a progress bar and a summary.

use anyhow::{Context, bail};
use clap::Args;
use indicatif::ProgressDrawTarget;
use rigidref::scene::DEFAULT_SCENE_NAME;
use rigidref::trace::{TraceFormat, TraceHeader, TraceRecord, TraceWriter};
use rigidref::world::World;
use std::path::PathBuf;
use std::time::{Duration, Instant};

const SCENE_KEYS: &str = "\
SCENE FILES (the 3D assignment's JSON, read as it is; docs/scene-format.md):
  sim_parameters[0] keys and their defaults when missing (the starter code's):
    name              scene name                       (file name)
    dt                frame step, s; h = dt/substeps   0.01
    gravity           m/s², y is up                    [0, 0, 0]
    mu                friction coefficient             0
    substeps          integration steps per frame      1
    check_collisions  detect and resolve contacts      true
    stop_on_contact   stop at the first contact        false
    pgs_iterations    PGS iterations per solve         100
    damping           only 0 is accepted (the assignment defines no damping model)
    show_contacts, is_running   user-interface keys; no effect here
  Keys this project adds (docs/scene-format.md, docs/contact.md):
    integrator        angular velocity update: \"spatial\" (the assignment's explicit
                      spatial-frame scheme; default), \"body\" (the same equations in
                      the body frame), \"implicit_gyroscopic\" (implicit Euler on the
                      ω×Jω term, solved by Newton: stable at high spin)
    friction_model    \"box\" (each tangent impulse in [−μλn, μλn]; default) or
                      \"cone\" (the tangent pair in the disk of radius μλn)
    compliance        c ≥ 0 added to each normal row's diagonal, kg⁻¹ (constraint
                      force mixing: w_n = … + c λn); 0 = rigid          0
    stabilization     Baumgarte β in [0, 1]: fraction of the penetration beyond the
                      slop pushed out per step                         0.2
    stabilization_slop  penetration left alone, m                      0.005
    warm_start        start PGS from the previous substep's impulses   true
    pgs_tolerance     stop PGS when its residual ≤ this, m/s           (none: all sweeps)
    pgs_order         \"sequential\" or \"random\" (seeded shuffle each sweep)  sequential
    pgs_seed          seed of the random order                        0
  Any other key is reported as a warning and ignored.
  bodies[i]: name, file_root (ROOT.json + ROOT.obj, looked up relative to the
    assignment root = parent of the scene's folder, then the scene's folder, then the
    working directory), x0 (m), R0 (rows; default identity), v0 (m/s), omega0 (rad/s,
    world frame); missing R0 is the identity, missing v0/omega0 are zero.

TRACE (docs/trace-format.md): JSON Lines, a header line then one line per recorded step
with every body's x, R, v, ω, the energies and momenta; or a flat CSV of the same.";

/// Arguments of `rigidref run`.
#[derive(Args)]
#[command(after_long_help = SCENE_KEYS)]
pub struct RunArgs {
    /// Scene file: the 3D assignment's JSON, a 2D image (.png), or a 2D scene file (JSON naming
    /// an image; docs/blocks2d.md). Without one, the built-in default 3D scene (the project's
    /// Dzhanibekov-effect scene) runs.
    pub scene: Option<PathBuf>,
    /// Simulated time to run, s (2D: time units) [default: 10].
    #[arg(long, conflicts_with = "steps", allow_negative_numbers = true)]
    pub time: Option<f64>,
    /// Number of frames (steps of dt) to run.
    #[arg(long)]
    pub steps: Option<u64>,
    /// Trace file; "-" writes to standard output [default: trace.jsonl, or trace.csv with --format csv].
    #[arg(long, short)]
    pub out: Option<PathBuf>,
    /// Record every K-th frame (the first and the last are always recorded).
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Trace encoding [default: from the --out extension, else jsonl].
    #[arg(long, value_enum)]
    pub format: Option<TraceFormat>,
    /// Run with check_collisions = false, whatever the scene says.
    #[arg(long)]
    pub no_collisions: bool,
    /// Write each contact problem to DIR as step-KKKKKK-SS.json (frame K, substep S;
    /// docs/contact-problem-format.md), with the contacts' geometry and the PGS solution
    /// (3D and 2D: 6 or 3 degrees of freedom per body).
    #[arg(long, value_name = "DIR")]
    pub dump_problems: Option<PathBuf>,
    /// Print no progress bar and no summary.
    #[arg(long, short)]
    pub quiet: bool,

    /// 2D: step size [default: 0.05, the starter's].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub step: Option<f64>,
    /// 2D: substeps per step [default: 1].
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub substeps: Option<u32>,
    /// 2D: gravity magnitude, blocks per time² [default: 1].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub gravity: Option<f64>,
    /// 2D: gravity direction, degrees from +x (image column) toward +y (image row, down)
    /// [default: 90, toward increasing row].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub gravity_angle: Option<f64>,
    /// 2D: friction coefficient [default: 0.33].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub mu: Option<f64>,
    /// 2D: coefficient of restitution in [0, 1] [default: 0].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub restitution: Option<f64>,
    /// 2D: PGS iterations per solve [default: 10, the starter's; the demonstration images
    /// come to rest with 200, 4 substeps and random order: docs/blocks2d.md §"Demonstration
    /// settings"].
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub iterations: Option<u32>,
    /// 2D: stop PGS when its residual is below this.
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub pgs_tolerance: Option<f64>,
    /// 2D: contact order in PGS [default: sequential].
    #[arg(long, value_enum, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub order: Option<rigidref::solve::ContactOrder>,
    /// 2D: seed of the random order [default: 0].
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub seed: Option<u64>,
    /// 2D: start each solve cold.
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub no_warm_start: bool,
    /// 2D: no post-stabilisation of penetration.
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub no_post_stabilization: bool,
    /// 2D: penetration left alone by post-stabilisation, blocks [default: 0.01].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub slop: Option<f64>,
    /// 2D: contact model [default: pgs].
    #[arg(long, value_enum, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub contact_model: Option<rigidref::blocks::world::ContactModel>,
    /// 2D: near-white threshold: a pixel is empty when every channel is ≥ 1 − this [default: 0.05].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub white_threshold: Option<f64>,
    /// 2D: apply an impulse TIME:BODY:JX,JY[:PX,PY] (at the body's centre of mass unless a world
    /// point is given); repeatable.
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub impulse: Vec<String>,
    /// 2D: a body is at rest below this kinetic energy (summary; render's solid circles) [default: 1e-3].
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Image scenes (2D, SCENE is a .png)"
    )]
    pub rest_threshold: Option<f64>,
    /// 2D: prescribed motion BODY:VX,VY:OMEGA:FREQ: the body's velocity is (VX,VY)·cos(2π FREQ t)
    /// and its angular velocity OMEGA·cos(2π FREQ t) (shaking the nut bag's container).
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub shake: Vec<String>,
    /// 2D: write, per recorded step, where the heaviest fifth of the moving bodies is relative to
    /// the rest (the nut-bag challenge) to this CSV.
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub nut_report: Option<PathBuf>,
    /// 2D: write step, bodies, contacts, PGS solve seconds per step to this CSV (contacts and
    /// seconds summed over the step's substeps).
    #[arg(long, help_heading = "Image scenes (2D, SCENE is a .png)")]
    pub scaling_csv: Option<PathBuf>,
}

/// The kinetic energy below which a 2D body counts as at rest, by default (mass units ·
/// blocks² per time unit²).
pub const REST_THRESHOLD: f64 = 1e-3;

/// The names of the flags that are given.
fn given(flags: &[(&'static str, bool)]) -> Vec<&'static str> {
    flags
        .iter()
        .filter_map(|&(name, given)| given.then_some(name))
        .collect()
}

impl RunArgs {
    /// `--rest-threshold`, or its default [`REST_THRESHOLD`].
    pub fn rest_threshold(&self) -> f64 {
        self.rest_threshold.unwrap_or(REST_THRESHOLD)
    }

    /// The 2D physics options given on the command line, by flag (they apply to .png scenes).
    pub fn physics_2d_given(&self) -> Vec<&'static str> {
        given(&[
            ("--step", self.step.is_some()),
            ("--substeps", self.substeps.is_some()),
            ("--gravity", self.gravity.is_some()),
            ("--gravity-angle", self.gravity_angle.is_some()),
            ("--mu", self.mu.is_some()),
            ("--restitution", self.restitution.is_some()),
            ("--iterations", self.iterations.is_some()),
            ("--pgs-tolerance", self.pgs_tolerance.is_some()),
            ("--order", self.order.is_some()),
            ("--seed", self.seed.is_some()),
            ("--no-warm-start", self.no_warm_start),
            ("--no-post-stabilization", self.no_post_stabilization),
            ("--slop", self.slop.is_some()),
            ("--contact-model", self.contact_model.is_some()),
            ("--white-threshold", self.white_threshold.is_some()),
            ("--impulse", !self.impulse.is_empty()),
            ("--shake", !self.shake.is_empty()),
        ])
    }

    /// Every option that applies to 2D scenes only, given on the command line.
    pub fn only_2d_given(&self) -> Vec<&'static str> {
        let mut names = self.physics_2d_given();
        names.extend(given(&[
            ("--rest-threshold", self.rest_threshold.is_some()),
            ("--nut-report", self.nut_report.is_some()),
            ("--scaling-csv", self.scaling_csv.is_some()),
        ]));
        names
    }

    /// The output options of `run` given on the command line (`render` writes frames instead).
    pub fn run_outputs_given(&self) -> Vec<&'static str> {
        given(&[
            ("--out", self.out.is_some()),
            ("--format", self.format.is_some()),
            ("--every", self.every != 1),
            ("--dump-problems", self.dump_problems.is_some()),
            ("--no-collisions", self.no_collisions),
            ("--nut-report", self.nut_report.is_some()),
            ("--scaling-csv", self.scaling_csv.is_some()),
        ])
    }
}

/// Runs a scene. A run that fails midway keeps the trace written so far, flushed and valid.
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    if let Some(path) = &args.scene
        && super::run2d::is_2d(path)
    {
        return super::run2d::run(path, &args);
    }
    let scene_name = args
        .scene
        .as_ref()
        .map_or("the built-in default scene".to_string(), |p| {
            p.display().to_string()
        });
    let only_2d = args.only_2d_given();
    if !only_2d.is_empty() {
        super::check_readable(args.scene.as_deref())?;
        bail!(
            "{scene_name}: {} {} to 2D scenes (images and 2D scene files) only; a 3D scene sets its parameters in the file",
            only_2d.join(", "),
            if only_2d.len() == 1 {
                "applies"
            } else {
                "apply"
            }
        );
    }
    let mut scene = super::load_scene_or_default(args.scene.as_deref())?;
    if args.no_collisions {
        scene.params.check_collisions = false;
    }
    let dt = scene.params.dt;
    let steps = super::steps_of(&args, dt, " of seconds")?;
    if let Some(dir) = &args.dump_problems {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the problem directory", dir.display()))?;
    }
    let format = args.format.unwrap_or(match &args.out {
        Some(p) if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) => TraceFormat::Csv,
        _ => TraceFormat::Jsonl,
    });
    let out_path = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(if format == TraceFormat::Csv {
            "trace.csv"
        } else {
            "trace.jsonl"
        })
    });
    let out = super::create_trace_output(&out_path)?;
    let source = if args.scene.is_some() {
        scene.source.clone()
    } else {
        DEFAULT_SCENE_NAME.to_string()
    };

    let mut world = World::new(&scene).map_err(|e| anyhow::anyhow!(e))?;
    let header = TraceHeader::for_world(&world, &source);
    let mut writer = TraceWriter::new(out, format, &header)
        .with_context(|| format!("{}: cannot write", out_path.display()))?;
    let write_err =
        |e: std::io::Error| anyhow::anyhow!("{}: cannot write trace: {e}", out_path.display());
    writer
        .write(&TraceRecord::of_world(&world))
        .map_err(write_err)?;
    let mut records = 1u64;
    let mut last_recorded = 0u64;

    let start_energy = world.energy();
    let start_momentum = world.momentum();
    let started = Instant::now();
    let progress = super::progress_bar(steps, super::STEPS_TEMPLATE);
    let mut progress_shown = false;
    let mut contact_stats = ContactStats::default();
    let mut stopped_at_contact = None;

    for k in 1..=steps {
        if let Err(failure) = world.step() {
            writer.flush().map_err(write_err)?;
            progress.finish_and_clear();
            bail!(
                "{}: the run stopped: {failure}; the trace up to step {last_recorded} is in {}",
                scene.source,
                out_path.display()
            );
        }
        contact_stats.add(&world);
        if let Some(dir) = &args.dump_problems {
            for solve in &world.frame_contacts {
                let path = dir.join(format!("step-{k:06}-{:02}.json", solve.substep));
                let file = solve.problem_file(&world.params.name, k, world.params.h());
                let text = serde_json::to_string(&file).context("serialising a contact problem")?;
                std::fs::write(&path, text + "\n")
                    .with_context(|| format!("{}: cannot write", path.display()))?;
            }
        }
        let stop_here = world.params.stop_on_contact && !world.frame_contacts.is_empty();
        if k % args.every == 0 || k == steps || stop_here {
            writer
                .write(&TraceRecord::of_world(&world))
                .map_err(write_err)?;
            records += 1;
            last_recorded = k;
        }
        if !args.quiet && !progress_shown && started.elapsed() > Duration::from_secs(1) {
            // Only runs longer than about a second get a bar; indicatif hides it when stderr
            // is not a terminal.
            progress.set_draw_target(ProgressDrawTarget::stderr());
            progress_shown = true;
        }
        if progress_shown && k % 64 == 0 {
            progress.set_position(k);
        }
        if stop_here {
            stopped_at_contact = Some(k);
            break;
        }
    }
    writer.flush().map_err(write_err)?;
    progress.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();

    if !args.quiet {
        let end_energy = world.energy();
        let end_momentum = world.momentum();
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
        eprintln!("scene          {} ({source})", p.name);
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
        eprintln!(
            "momentum drift |Δp − M g t| = {momentum_drift:.3e} kg·m/s, |ΔL_com| = {angular_drift:.3e} kg·m²/s{}",
            relative(angular_drift, start_momentum.angular_com.norm())
        );
        if world.params.check_collisions {
            let c = &contact_stats;
            if c.solves > 0 {
                eprintln!(
                    "contacts       {} solves in {} frames, up to {} contacts; PGS {:.1} sweeps on average, worst residual {:.3e} m/s, deepest penetration {:.3e} m",
                    c.solves,
                    c.frames,
                    c.max_contacts,
                    c.iterations as f64 / c.solves as f64,
                    c.max_residual,
                    c.max_depth
                );
            } else {
                eprintln!("contacts       none");
            }
        }
        eprintln!(
            "trace          {} ({records} records, {format:?})",
            out_path.display()
        );
    }
    if let Some(k) = stopped_at_contact {
        let n = world.frame_contacts.last().map_or(0, |s| s.contacts.len());
        eprintln!(
            "stop_on_contact: stopped at the first frame with contacts, step {k} (t = {} s), {n} contacts; inspect them with `rigidref contacts {}`",
            world.time(),
            args.scene
                .as_ref()
                .map_or("".to_string(), |p| p.display().to_string())
        );
    }
    Ok(())
}

/// Contact figures for the summary.
#[derive(Default)]
struct ContactStats {
    frames: u64,
    solves: u64,
    max_contacts: usize,
    iterations: u64,
    max_residual: f64,
    max_depth: f64,
}

impl ContactStats {
    fn add(&mut self, world: &World) {
        if !world.frame_contacts.is_empty() {
            self.frames += 1;
        }
        for s in &world.frame_contacts {
            self.solves += 1;
            self.max_contacts = self.max_contacts.max(s.contacts.len());
            self.iterations += u64::from(s.report.iterations);
            self.max_residual = self.max_residual.max(s.report.residual);
            for c in &s.contacts {
                self.max_depth = self.max_depth.max(c.depth);
            }
        }
    }
}
