//! `rigidref view TRACE.jsonl|SCENE`: one self-contained HTML page showing the run (bodies,
//! contacts, plots, a body's state), which opens offline in a browser. docs/viewing.md.

use super::args::{Blocks2dOptions, RestThreshold, RunLength, SceneSets, TraceOutput};
use super::run_args::{Run2dReports, RunArgs};
use anyhow::{Context, bail};
use clap::Args;
use rigidref::blocks2d::scene::is_2d_scene;
use rigidref::rigid3d::scene::embedded::{BUILT_IN_SOURCE, default_scene_with};
use rigidref::rigid3d::scene::{Overrides, load_scene_with};
use rigidref::tools::view::{
    DEFAULT_MAX_FRAMES, ViewTrace, html, read_view_trace, view_data_2d, view_data_3d,
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

/// Whether `path` is a trace (its first line a JSON object with a `format` key) rather than a
/// scene.
pub(crate) fn is_trace(path: &Path) -> bool {
    use std::io::BufRead;
    let Ok(file) = std::fs::File::open(path) else {
        return false;
    };
    let mut first = String::new();
    if std::io::BufReader::new(file).read_line(&mut first).is_err() {
        return false;
    }
    serde_json::from_str::<serde_json::Value>(&first)
        .is_ok_and(|v| v.get("format").is_some() && v.get("sim_parameters").is_none())
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

/// Runs `input` (a 3D scene, a 2D image or scene file, or the built-in default when `None`) as
/// `rigidref run` would, recording every `every`-th frame to `trace` (2D: with all contacts).
/// `view` and `render` run scenes through this.
pub(crate) fn run_to_trace(
    input: Option<&Path>,
    length: &RunLength,
    sets: &SceneSets,
    blocks: &Blocks2dOptions,
    every: u64,
    quiet: bool,
    trace: &Path,
) -> anyhow::Result<()> {
    let two_d = input.is_some_and(is_2d_scene);
    if !two_d && !blocks.given().is_empty() {
        bail!(
            "{}: {} apply to 2D scenes only",
            input.map_or("the built-in default scene".into(), |p| p
                .display()
                .to_string()),
            blocks.given().join(", ")
        );
    }
    let run = RunArgs {
        scene: input.map(Path::to_path_buf),
        length: length.clone(),
        sets: sets.clone(),
        output: TraceOutput {
            out: Some(trace.to_path_buf()),
            every,
            format: None,
            dump_problems: None,
        },
        quiet,
        no_collisions: false,
        blocks: blocks.clone(),
        rest: RestThreshold {
            rest_threshold: None,
        },
        reports: Run2dReports {
            nut_report: None,
            scaling_csv: None,
            all_contacts: two_d,
        },
    };
    super::run::run(run)
}

/// Reads the trace at `path` for viewing or plotting, printing its warnings (and returning
/// them, for the page); fails, naming the
/// file, when it is not a trace or `bodies` names a body it does not have.
pub(crate) fn read_trace_file(
    path: &Path,
    bodies: &[usize],
) -> anyhow::Result<(ViewTrace, Vec<String>)> {
    let name = path.display().to_string();
    let text =
        rigidref::common::input::read_text(path).with_context(|| format!("{name}: cannot read"))?;
    let mut warnings = Vec::new();
    let trace = read_view_trace(&text, &name, &mut warnings).map_err(anyhow::Error::msg)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let n = trace.body_count();
    if let Some(&b) = bodies.iter().find(|&&b| b >= n) {
        bail!(
            "{name}: --bodies: no body {b}; the trace has {n} (0 to {})",
            n - 1
        );
    }
    Ok((trace, warnings))
}

/// The scene a 3D trace names (`source`, or the built-in default), whose meshes draw its bodies;
/// fails, naming the trace `name`, when it cannot be loaded or has not `n` bodies.
pub(crate) fn scene_of_3d_trace(
    name: &str,
    source: &str,
    n: usize,
) -> anyhow::Result<rigidref::rigid3d::scene::Scene> {
    let cannot = |e: &dyn std::fmt::Display| {
        anyhow::anyhow!(
            "{name}: the bodies are drawn from the scene the trace names, {source}, which cannot be loaded: {e}"
        )
    };
    let none = Overrides::default();
    let scene = if source == BUILT_IN_SOURCE {
        default_scene_with(&none).map_err(|e| cannot(&e))?
    } else {
        load_scene_with(Path::new(source), &none).map_err(|e| cannot(&e))?
    };
    if scene.bodies.len() != n {
        bail!(
            "{name}: the trace has {n} bodies but its scene {source} has {}; was the scene changed after the run?",
            scene.bodies.len()
        );
    }
    Ok(scene)
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
        ViewTrace::Three { header, records } => {
            let scene = scene_of_3d_trace(&name, &source, n)?;
            let meshes: Vec<_> = scene.bodies.iter().map(|b| &*b.mesh).collect();
            view_data_3d(header, records, &meshes, &warnings, args.max_frames, &omega)
        }
        ViewTrace::Two { header, records } => {
            // The overrides may change the physics, never the bodies; the 2D options likewise.
            let scene = super::run2d::load_scene(
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
