//! What several commands need: loading a 3D scene, opening outputs, writing problem files.

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
) -> anyhow::Result<Box<dyn std::io::Write>> {
    use anyhow::Context;
    Ok(if path.as_os_str() == "-" {
        Box::new(std::io::stdout().lock())
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
