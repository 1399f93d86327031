//! Argument groups that several subcommands share (clap `flatten`): how long to run, where the
//! trace goes, the rest threshold, `--set`; the 2D system's options are in [`super::args2d`]. A
//! subcommand offers only the groups it uses.

use anyhow::{Context, bail};
use clap::Args;
use rigidref::common::scene_json::Overrides;
use rigidref::rigid3d::trace::TraceFormat;
use std::path::PathBuf;

/// The kinetic energy below which a 2D body counts as at rest, by default (mass units ·
/// blocks² per time unit²).
pub const REST_THRESHOLD: f64 = 1e-3;

/// How long to run.
#[derive(Args, Clone, Debug)]
pub struct RunLength {
    /// Simulated time to run, s (2D: time units) [default: 10]. `--duration` is taken as the
    /// same option (the name users reach for first).
    #[arg(
        long,
        alias = "duration",
        conflicts_with = "steps",
        allow_negative_numbers = true
    )]
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
pub(crate) const HEADING_2D: &str =
    "2D scenes (an image, run with these; a 2D scene file sets its own)";

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
    /// Threads of the contact solver's coloured sweeps (`pgs_order`/`order: coloured`): the
    /// same as `--set threads=N`; the result is bit for bit the one-thread result
    /// (docs/contact.md §"Coloured order") [default: 1].
    #[arg(long, value_name = "N")]
    pub threads: Option<u32>,
}

impl SceneSets {
    /// The overrides, parsed (`--threads N` as `threads=N`).
    pub fn overrides(&self) -> anyhow::Result<Overrides> {
        let mut texts = self.set.clone();
        if let Some(n) = self.threads {
            texts.push(format!("threads={n}"));
        }
        Overrides::parse(&texts).map_err(anyhow::Error::msg)
    }
}
