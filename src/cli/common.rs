//! What several commands need: loading a 3D or 2D scene, running a scene to a trace and reading
//! traces back (view, plot, render), opening outputs, writing problem files.

use anyhow::{Context, bail};
use rigidref::blocks2d::scene::{Scene2, load_2d};
use rigidref::rigid3d::scene::embedded::{BUILT_IN_SOURCE, default_scene_with};
use rigidref::rigid3d::scene::{Overrides, load_scene_with};
use rigidref::tools::viewing::view::{RunTrace, read_run_trace};
use std::path::Path;

/// Loads the scene at `path`, or the embedded default, with the `--set` overrides, and prints its
/// warnings to stderr.
pub(crate) fn load_scene_or_default(
    path: Option<&std::path::Path>,
    sets: &super::args::SceneSets,
) -> anyhow::Result<rigidref::rigid3d::scene::Scene> {
    let overrides = sets.overrides()?;
    let scene = match path {
        Some(p) => rigidref::rigid3d::scene::load_scene_with(p, &overrides)?,
        None => rigidref::rigid3d::scene::embedded::default_scene_with(&overrides)?,
    };
    for w in &scene.warnings {
        // A condition the scene declares on purpose is reported as a note, not a warning.
        match w.strip_prefix("note: ") {
            Some(note) => eprintln!("note: {note}"),
            None => eprintln!("warning: {w}"),
        }
    }
    Ok(scene)
}

/// Fails, naming the file, when a scene path cannot be read (checked before options are
/// judged against the kind of scene, so that a typo is reported as a missing file).
pub(crate) fn check_readable(path: Option<&std::path::Path>) -> anyhow::Result<()> {
    if let Some(p) = path
        && let Err(e) = std::fs::File::open(p)
    {
        anyhow::bail!("{}: cannot open: {e}", p.display());
    }
    Ok(())
}

/// The trace's destination: `-` is standard output, anything else a file created (or truncated)
/// now, so that an unwritable path fails before the run starts.
pub(crate) fn create_trace_output(
    path: &std::path::Path,
) -> anyhow::Result<Box<dyn std::io::Write + Send>> {
    use anyhow::Context;
    Ok(if path.as_os_str() == "-" {
        Box::new(std::io::stdout())
    } else {
        Box::new(
            std::fs::File::create(path)
                .with_context(|| format!("{}: cannot create trace file", path.display()))?,
        )
    })
}

/// Creates `path` for writing, naming it in the error.
pub(crate) fn create_file(
    path: &std::path::Path,
) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    use anyhow::Context;
    Ok(std::io::BufWriter::new(
        std::fs::File::create(path)
            .with_context(|| format!("{}: cannot create", path.display()))?,
    ))
}

/// Writes one contact-problem file of `--dump-problems`: DIR/step-KKKKKK-SS.json.
pub(crate) fn dump_problem<C: rigidref::sim::ContactGeometry, const D: usize, const R: usize>(
    dir: &std::path::Path,
    scene: &str,
    step: u64,
    h: f64,
    solve: &rigidref::sim::SubstepSolve<C, D, R>,
) -> anyhow::Result<()> {
    use anyhow::Context;
    let path = dir.join(format!("step-{step:06}-{:02}.json", solve.substep));
    let file = solve.problem_file(scene, step, h);
    let text = serde_json::to_string(&file).context("serialising a contact problem")?;
    std::fs::write(&path, text + "\n").with_context(|| format!("{}: cannot write", path.display()))
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

/// Reads the trace at `path` for viewing or plotting, printing its warnings (and returning
/// them, for the page); fails, naming the
/// file, when it is not a trace or `bodies` names a body it does not have.
pub(crate) fn read_trace_file(
    path: &Path,
    bodies: &[usize],
) -> anyhow::Result<(RunTrace, Vec<String>)> {
    let name = path.display().to_string();
    let text =
        rigidref::common::input::read_text(path).with_context(|| format!("{name}: cannot read"))?;
    let mut warnings = Vec::new();
    let trace = read_run_trace(&text, &name, &mut warnings).map_err(anyhow::Error::msg)?;
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

/// A 2D scene with the command line's 2D options and `--set` overrides, its warnings printed.
pub(crate) fn load_scene_2d(
    path: &Path,
    options: &super::args2d::Blocks2dOptions,
    sets: &super::args::SceneSets,
) -> anyhow::Result<Scene2> {
    let scene = load_2d(path, &options.command_line(sets)?)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
}

/// What `check_detection` found over a run (docs/contact.md §"Temporal coherence"): a summary
/// line when it was on, or an error naming the scene when cached detection differed from fresh
/// detection on any substep (a bug; `detection_cache=false` runs without the cache).
pub(crate) fn detection_check(
    on: bool,
    stats: rigidref::common::pair_cache::CacheStats,
    source: &str,
) -> anyhow::Result<Option<String>> {
    if !on {
        return Ok(None);
    }
    if stats.mismatches > 0 {
        anyhow::bail!(
            "{source}: check_detection: cached detection differed from fresh detection on {} of {} substeps (a bug in the detection cache; --set detection_cache=false runs without it)",
            stats.mismatches,
            stats.checked
        );
    }
    let kept = match (stats.hit_rate(), stats.nearest_rate()) {
        (Some(lists), Some(nearest)) => format!(
            " (pair lists kept on {:.1} % of pair visits, nearest triangles on {:.1} % of vertex queries)",
            100.0 * lists,
            100.0 * nearest
        ),
        (Some(lists), None) => format!(
            " (pair lists kept on {:.1} % of pair visits)",
            100.0 * lists
        ),
        _ => String::new(),
    };
    let manifolds = match stats.manifold_rate() {
        Some(rate) if stats.kept_differs > 0 => format!(
            "; kept features gave {:.1} % of piece-pair manifolds, and the contacts differed within the bound of docs/contact.md §\"Persistent manifolds\" on {} substeps",
            100.0 * rate,
            stats.kept_differs
        ),
        Some(rate) => format!(
            "; kept features gave {:.1} % of piece-pair manifolds",
            100.0 * rate
        ),
        None => String::new(),
    };
    let same = if stats.kept_differs > 0 {
        "fresh detection's up to kept manifolds"
    } else {
        "fresh detection's, bit for bit"
    };
    Ok(Some(format!(
        "detection      checked on {} substeps: the cached contacts are {same}{kept}{manifolds}",
        stats.checked
    )))
}
