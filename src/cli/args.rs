//! Argument groups that several subcommands share (clap `flatten`): how long to run, where the
//! trace goes, and the 2D system's options. A subcommand offers only the groups it uses.

use anyhow::{Context, bail};
use clap::Args;
use rigidref::blocks2d::scene::{CommandLine2, Parameters2, parse_impulse, parse_shake};
use rigidref::common::scene_json::Overrides;
use rigidref::rigid3d::trace::TraceFormat;
use std::path::PathBuf;

/// How long to run.
#[derive(Args, Clone, Debug)]
pub struct RunLength {
    /// Simulated time to run, s (2D: time units) [default: 10].
    #[arg(long, conflicts_with = "steps", allow_negative_numbers = true)]
    pub time: Option<f64>,
    /// Number of frames (steps of dt) to run.
    #[arg(long)]
    pub steps: Option<u64>,
}

impl RunLength {
    /// The number of steps: `--steps`, else `--time` (default 10) by the one time-to-steps rule
    /// ([`rigidref::sim::steps_in`]). `unit` names the time unit in errors (" of seconds" in 3D).
    pub fn steps(&self, dt: f64, unit: &str) -> anyhow::Result<u64> {
        match self.steps {
            Some(n) => {
                rigidref::sim::check_step_count(n as f64, dt).map_err(anyhow::Error::msg)?;
                Ok(n)
            }
            None => {
                let time = self.time.unwrap_or(10.0);
                let steps = rigidref::sim::steps_in(time, dt, unit).map_err(anyhow::Error::msg)?;
                // Not silent about the rounding: the run ends at whole steps of dt.
                let end = steps as f64 * dt;
                if (end - time).abs() > 1e-9 * time.max(dt) {
                    eprintln!(
                        "note: --time {time} is not a whole number of steps of dt = {dt}; the run takes {steps} steps and ends at t = {end}"
                    );
                }
                Ok(steps)
            }
        }
    }
}

/// Where the trace and the contact problems go.
#[derive(Args, Clone, Debug)]
pub struct TraceOutput {
    /// Trace file; "-" writes to standard output [default: trace.jsonl, or trace.csv with --format csv].
    #[arg(long, short)]
    pub out: Option<PathBuf>,
    /// Record every K-th frame (the first and the last are always recorded).
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Trace encoding [default: from the --out extension, else jsonl; 2D traces are jsonl only].
    #[arg(long, value_enum)]
    pub format: Option<TraceFormat>,
    /// Write each contact problem to DIR as step-KKKKKK-SS.json (frame K, substep S;
    /// docs/contact-problem-format.md), with the contacts' geometry and the PGS solution
    /// (3D and 2D: 6 or 3 degrees of freedom per body).
    #[arg(long, value_name = "DIR")]
    pub dump_problems: Option<PathBuf>,
}

impl TraceOutput {
    /// The encoding: `--format`, else from the `--out` extension, else JSON Lines.
    pub fn format(&self) -> TraceFormat {
        self.format.unwrap_or(match &self.out {
            Some(p) if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) => {
                TraceFormat::Csv
            }
            _ => TraceFormat::Jsonl,
        })
    }

    /// The trace path: `--out`, else trace.jsonl (trace.csv for CSV).
    pub fn path(&self) -> PathBuf {
        self.out.clone().unwrap_or_else(|| {
            PathBuf::from(match self.format() {
                TraceFormat::Csv => "trace.csv",
                TraceFormat::Jsonl => "trace.jsonl",
            })
        })
    }

    /// Checks `--every` and creates the problem folder, before the run starts.
    pub fn prepare(&self) -> anyhow::Result<()> {
        if self.every == 0 {
            bail!("--every must be at least 1");
        }
        if let Some(dir) = &self.dump_problems {
            std::fs::create_dir_all(dir).with_context(|| {
                format!("{}: cannot create the problem directory", dir.display())
            })?;
        }
        Ok(())
    }
}

/// The heading of the 2D options in `--help`.
const HEADING_2D: &str = "2D scenes (an image, run with these; a 2D scene file sets its own)";

/// The 2D system's physics options (for an image; a 2D scene file sets its own parameters).
#[derive(Args, Clone, Debug, Default)]
#[command(next_help_heading = HEADING_2D)]
pub struct Blocks2dOptions {
    /// 2D: the parameters to start from: `default` (the demonstration settings: 4 substeps, 200
    /// sweeps, random order) or `starter` (the Java starter's: 1 substep, 10 sweeps in order);
    /// the options below override it [default: default].
    #[arg(long, value_enum)]
    pub preset: Option<rigidref::blocks2d::params::Preset>,
    /// 2D: step size [default: 0.05, the starter's].
    #[arg(long, allow_negative_numbers = true)]
    pub step: Option<f64>,
    /// 2D: substeps per step [default: 4; starter: 1].
    #[arg(long)]
    pub substeps: Option<u32>,
    /// 2D: gravity magnitude, blocks per time² [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f64>,
    /// 2D: gravity direction, degrees from +x (image column) toward +y (image row, down)
    /// [default: 90, toward increasing row].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity_angle: Option<f64>,
    /// 2D: friction coefficient [default: 0.33].
    #[arg(long, allow_negative_numbers = true)]
    pub mu: Option<f64>,
    /// 2D: coefficient of restitution in [0, 1] [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub restitution: Option<f64>,
    /// 2D: PGS iterations per solve [default: 200; starter: 10, with which the demonstration
    /// images do not come to rest: docs/blocks2d.md §"Demonstration settings"].
    #[arg(long)]
    pub iterations: Option<u32>,
    /// 2D: stop PGS when its residual is below this.
    #[arg(long, allow_negative_numbers = true)]
    pub pgs_tolerance: Option<f64>,
    /// 2D: contact order in PGS [default: random; starter: sequential].
    #[arg(long, value_enum)]
    pub order: Option<rigidref::solve::ContactOrder>,
    /// 2D: seed of the random order [default: 0].
    #[arg(long)]
    pub seed: Option<u64>,
    /// 2D: how a PGS visit updates its contact: `rows` (normal row, then friction row) or `exact`
    /// (the contact's 2 × 2 problem solved exactly) [default: rows].
    #[arg(long, value_enum)]
    pub pgs_local_solve: Option<rigidref::solve::LocalSolve>,
    /// 2D: start each solve cold.
    #[arg(long)]
    pub no_warm_start: bool,
    /// 2D: no post-stabilisation of penetration.
    #[arg(long)]
    pub no_post_stabilization: bool,
    /// 2D: penetration left alone by post-stabilisation, blocks [default: 0.01].
    #[arg(long, allow_negative_numbers = true)]
    pub slop: Option<f64>,
    /// 2D: contact model [default: pgs].
    #[arg(long, value_enum)]
    pub contact_model: Option<rigidref::blocks2d::params::ContactModel>,
    /// 2D: near-white threshold: a pixel is empty when every channel is ≥ 1 − this [default: 0.05].
    #[arg(long, allow_negative_numbers = true)]
    pub white_threshold: Option<f64>,
    /// 2D: adaptive substeps: take enough substeps each step that no block moves more than this
    /// many blocks per substep (fast bodies then cannot pass through a one-block wall; at most
    /// 4096 substeps) [default: off, the fixed --substeps].
    #[arg(long, allow_negative_numbers = true)]
    pub max_travel: Option<f64>,
    /// 2D: shock propagation after each velocity solve: bodies re-solved layer by layer from the
    /// pinned ones up, each layer's supports treated as fixed (stiffer stacks; docs/blocks2d.md
    /// §"Shock propagation") [default: off].
    #[arg(long)]
    pub shock_propagation: bool,
    /// 2D: apply an impulse TIME:BODY:JX,JY[:PX,PY] (at the body's centre of mass unless a world
    /// point is given); repeatable.
    #[arg(long)]
    pub impulse: Vec<String>,
    /// 2D: prescribed motion BODY:VX,VY:OMEGA:FREQ: the body's velocity is (VX,VY)·cos(2π FREQ t)
    /// and its angular velocity OMEGA·cos(2π FREQ t) (shaking the nut bag's container).
    #[arg(long)]
    pub shake: Vec<String>,
}

impl Blocks2dOptions {
    /// The options as the 2D loader takes them (impulses and shakes parsed), with the names of
    /// the flags given.
    pub fn command_line(&self, sets: &SceneSets) -> anyhow::Result<CommandLine2> {
        let impulses = self.impulse.iter().map(|t| parse_impulse(t));
        let shakes = self.shake.iter().map(|t| parse_shake(t));
        Ok(CommandLine2 {
            parameters: self.parameters(),
            impulses: impulses
                .collect::<Result<_, _>>()
                .map_err(anyhow::Error::msg)?,
            shakes: shakes
                .collect::<Result<_, _>>()
                .map_err(anyhow::Error::msg)?,
            given: self.given(),
            overrides: sets.overrides()?,
        })
    }

    /// The names of the flags given, in the order `--help` lists them.
    pub fn given(&self) -> Vec<String> {
        let mut given: Vec<String> = self
            .parameters()
            .given()
            .iter()
            .map(|key| match *key {
                "warm_start" => "--no-warm-start".to_string(),
                "post_stabilization" => "--no-post-stabilization".to_string(),
                key => format!("--{}", key.replace('_', "-")),
            })
            .collect();
        given.extend((!self.impulse.is_empty()).then(|| "--impulse".to_string()));
        given.extend((!self.shake.is_empty()).then(|| "--shake".to_string()));
        given
    }

    /// The physics options as 2D parameters.
    fn parameters(&self) -> Parameters2 {
        Parameters2 {
            preset: self.preset,
            step: self.step,
            substeps: self.substeps,
            gravity: self.gravity,
            gravity_angle: self.gravity_angle,
            mu: self.mu,
            restitution: self.restitution,
            iterations: self.iterations,
            pgs_tolerance: self.pgs_tolerance,
            order: self.order,
            seed: self.seed,
            pgs_local_solve: self.pgs_local_solve,
            warm_start: self.no_warm_start.then_some(false),
            post_stabilization: self.no_post_stabilization.then_some(false),
            slop: self.slop,
            contact_model: self.contact_model,
            white_threshold: self.white_threshold,
            max_travel: self.max_travel,
            shock_propagation: self.shock_propagation.then_some(true),
            solver: None,
        }
    }
}

/// The kinetic energy below which a 2D body counts as at rest, by default (mass units ·
/// blocks² per time unit²).
pub const REST_THRESHOLD: f64 = 1e-3;

/// A 2D body's rest threshold (the summary's count; render's solid circles).
#[derive(Args, Clone, Debug)]
#[command(next_help_heading = HEADING_2D)]
pub struct RestThreshold {
    /// 2D: a body is at rest below this kinetic energy (summary; render's solid circles) [default: 1e-3].
    #[arg(long, allow_negative_numbers = true)]
    pub rest_threshold: Option<f64>,
}

impl RestThreshold {
    /// `--rest-threshold`, or its default [`REST_THRESHOLD`], checked.
    pub fn value(&self) -> anyhow::Result<f64> {
        let t = self.rest_threshold.unwrap_or(REST_THRESHOLD);
        if !(t.is_finite() && t >= 0.0) {
            bail!("--rest-threshold must be a number ≥ 0, got {t}");
        }
        Ok(t)
    }
}

/// Scene parameters from the command line: `--set KEY=VALUE`, for 3D and 2D scenes alike.
#[derive(Args, Clone, Debug, Default)]
pub struct SceneSets {
    /// Set a scene parameter, as if the scene file said so: KEY=VALUE with a key of the 3D
    /// scene's sim_parameters (e.g. pgs_iterations=50, mu=0.3, integrator=body,
    /// gravity=[0,-9.8,0]) or of a 2D scene's parameters (e.g. iterations=50, preset=starter);
    /// checked exactly as the file's value; repeatable. Shown in the summary and the trace header.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl SceneSets {
    /// The overrides, parsed.
    pub fn overrides(&self) -> anyhow::Result<Overrides> {
        Overrides::parse(&self.set).map_err(anyhow::Error::msg)
    }
}
