//! `rigidref view TRACE.jsonl|SCENE`: one self-contained HTML page showing the run (bodies,
//! contacts, plots, a body's state), which opens offline in a browser. docs/viewing.md.

use super::args::{RunLength, SceneSets};
use super::args2d::Blocks2dOptions;
use super::common::{is_trace, read_trace_file, scene_of_3d_trace};
use super::run::run_to_trace;
use anyhow::{Context, bail};
use clap::Args;
use rigidref::tools::viewing::view::{
    DEFAULT_MAX_FRAMES, RunTrace, html, view_data_2d, view_data_3d,
};
use std::path::{Path, PathBuf};

/// Arguments of `rigidref view`.
#[derive(Args)]
#[command(after_long_help = "\
Writes one HTML file that any current browser opens offline (no network: the page's script and
the run's data are inside it). It shows the bodies at the recorded states (3D: shaded meshes over
a ground grid, mouse orbit, zoom and pan; 2D: the blocks in their colours), with play/pause, a
time slider, the playback speed and single steps (space, ← and →); the contacts of the shown
record (points, normals, impulses as arrows scaled by λ; 3D: the tangent frame t1, t2, off by
default); plots over time synchronised with the slider (energies, momenta, angular velocities,
contacts, PGS sweeps and residual, penetration; click a plot to jump to that time); and the state
of the body chosen in the panel (x, R or θ, v, ω).

Given a trace, the page draws the bodies from the scene its header names (`source`), which must
still be readable. Given a scene, the scene is run first, with the same options as `rigidref run`
(--time, --steps, --set, the 2D options), its trace kept beside the page (--trace), and 2D
contacts recorded (as `run --all-contacts`). Records beyond --max-frames are thinned evenly.
PGS sweeps and residuals are plotted from traces that record them (written by this version).
docs/viewing.md describes each view.")]
pub struct ViewArgs {
    /// A trace written by `rigidref run` (.jsonl), or a scene to run first: a 3D scene (.json), a
    /// 2D image (.png) or a 2D scene file. Without one, the built-in default 3D scene runs.
    pub input: Option<PathBuf>,
    /// The page to write [default: the input's file name with .html, in the working directory;
    /// view.html for the built-in scene].
    #[arg(long, short)]
    pub out: Option<PathBuf>,
    /// When running a scene: where its trace goes [default: the page's path with .jsonl].
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// The most records the page holds; longer traces are thinned evenly, the first and last
    /// record always kept.
    #[arg(long, default_value_t = DEFAULT_MAX_FRAMES)]
    pub max_frames: usize,
    /// Bodies whose angular velocity is plotted, by index, comma-separated [default: the first
    /// four that are not pinned].
    #[arg(long, value_delimiter = ',', value_name = "I,J,…")]
    pub bodies: Vec<usize>,
    /// When running a scene: record every K-th frame (the first and the last always).
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Print no progress bar and no summary.
    #[arg(long, short)]
    pub quiet: bool,
    #[command(flatten)]
    pub length: RunLength,
    #[command(flatten)]
    pub sets: SceneSets,
    #[command(flatten)]
    pub blocks: Blocks2dOptions,
}

/// Writes the page.
pub fn view(args: ViewArgs) -> anyhow::Result<()> {
    if args.max_frames < 2 {
        bail!("--max-frames must be at least 2, got {}", args.max_frames);
    }
    if args.every == 0 {
        bail!("--every must be at least 1");
    }
    if let Some(input) = &args.input {
        super::common::check_readable(Some(input))?;
    }
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args
            .input
            .as_ref()
            .and_then(|p| p.file_stem())
            .map_or("view".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.html"))
    });
    let given_trace = args.input.as_ref().filter(|p| is_trace(p));
    let (trace_path, ran) = match given_trace {
        Some(p) => {
            if !args.sets.set.is_empty()
                || args.sets.threads.is_some()
                || args.length.time.is_some()
                || args.length.steps.is_some()
            {
                bail!(
                    "{}: is a trace; --set, --time and --steps apply when viewing a scene (the run is already done)",
                    p.display()
                );
            }
            (p.clone(), None)
        }
        None => {
            let trace = args
                .trace
                .clone()
                .unwrap_or_else(|| out.with_extension("jsonl"));
            (trace.clone(), Some(run_scene(&args, &trace)))
        }
    };
    // A run that failed midway left a valid trace of what it did: show that, then report.
    if let Some(Err(e)) = &ran
        && !trace_path.exists()
    {
        bail!("{e:#}");
    }
    let page = page_for_trace(&trace_path, &args)?;
    std::fs::write(&out, page).with_context(|| format!("{}: cannot write", out.display()))?;
    if !args.quiet {
        eprintln!(
            "view           {} ({:.1} MB; open it in a browser){}",
            out.display(),
            std::fs::metadata(&out).map_or(0.0, |m| m.len() as f64 / 1e6),
            if ran.is_some() {
                format!(", trace {}", trace_path.display())
            } else {
                String::new()
            }
        );
    }
    match ran {
        Some(Err(e)) => Err(e.context(format!(
            "the page {} shows the run up to where it stopped",
            out.display()
        ))),
        _ => Ok(()),
    }
}

/// Runs the scene of `args` as `rigidref run` would, its trace to `trace`.
fn run_scene(args: &ViewArgs, trace: &Path) -> anyhow::Result<()> {
    run_to_trace(
        args.input.as_deref(),
        &args.length,
        &args.sets,
        &args.blocks,
        args.every,
        args.quiet,
        trace,
    )
}

/// The page for the trace at `path`, its geometry from the scene the header names.
fn page_for_trace(path: &Path, args: &ViewArgs) -> anyhow::Result<String> {
    let name = path.display().to_string();
    let (trace, warnings) = read_trace_file(path, &args.bodies)?;
    let n = trace.body_count();
    let omega = trace.omega_bodies(&args.bodies);
    let source = trace.source().to_string();
    let cannot = |e: &dyn std::fmt::Display| {
        anyhow::anyhow!(
            "{name}: the page draws the bodies of the scene the trace names, {source}, which cannot be loaded: {e}"
        )
    };
    let data = match &trace {
        RunTrace::Three { header, records } => {
            let scene = scene_of_3d_trace(&name, &source, n)?;
            let meshes: Vec<_> = scene.bodies.iter().map(|b| &*b.mesh).collect();
            view_data_3d(header, records, &meshes, &warnings, args.max_frames, &omega)
        }
        RunTrace::Two { header, records } => {
            // The overrides may change the physics, never the bodies; the 2D options likewise.
            let scene = super::common::load_scene_2d(
                Path::new(&source),
                &Blocks2dOptions::default(),
                &SceneSets::default(),
            )
            .map_err(|e| cannot(&e))?;
            let world = scene.world;
            if world.bodies.len() != n {
                bail!(
                    "{name}: the trace has {n} bodies but its scene {source} makes {}; was the image changed after the run?",
                    world.bodies.len()
                );
            }
            view_data_2d(header, records, &world, &warnings, args.max_frames, &omega)
        }
    };
    Ok(html(&data))
}
