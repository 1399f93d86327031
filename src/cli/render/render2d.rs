//! `rigidref render` of a 2D image or scene file: the run, each frame drawn as it is recorded.

use super::*;

/// Runs the 2D image scene and draws every K-th step.
pub(super) fn render_2d(args: &RenderArgs, image_path: &Path) -> anyhow::Result<()> {
    refuse(
        &[
            ("--width", args.width.is_some()),
            ("--height", args.height.is_some()),
            ("--azimuth", args.azimuth.is_some()),
            ("--elevation", args.elevation.is_some()),
            ("--orbit", args.orbit.is_some()),
            ("--no-overlay", args.no_overlay),
            ("--trace", args.trace.is_some()),
        ],
        "3D renders",
    )?;
    let scale = args.scale.unwrap_or(3.0);
    let opacity = args.opacity.unwrap_or(1.0);
    if !(scale > 0.0 && scale <= 64.0) {
        bail!("--scale must be in (0, 64], got {scale}");
    }
    if !(0.0..=1.0).contains(&opacity) {
        bail!("--opacity must be in [0, 1], got {opacity}");
    }
    let rest_threshold = args.rest.value()?;
    let mut world = crate::cli::common::load_scene_2d(image_path, &args.blocks, &args.sets)?.world;
    let steps = args.length.steps(world.params.dt, "")?;
    let mut settings = RenderSettings::fit(&world, scale);
    // A frame is width × height RGBA pixels, all held at once: refuse what cannot be held
    // rather than abort on a failed allocation.
    let (width, height) = (
        (settings.size.x * scale).ceil(),
        (settings.size.y * scale).ceil(),
    );
    if width * height > MAX_FRAME_PIXELS {
        bail!(
            "{}: frames of {width:.0} × {height:.0} pixels at --scale {scale} exceed the limit of {} million pixels; lower --scale",
            image_path.display(),
            MAX_FRAME_PIXELS / 1e6
        );
    }
    settings.opacity = opacity;
    settings.contacts = args.show_contacts;
    settings.discs = args.show_discs;
    settings.rest_threshold = rest_threshold;
    let mut frames = Frames::new(args, world.params.dt * args.frame_every as f64)?;
    let mut progress = Progress::steps(steps, args.quiet);
    frames.draw(&render(&world, &settings), 0)?;
    let ran = drive(&mut world, steps, |w, k| -> Result<Flow, Stopped> {
        if k % args.frame_every == 0 || k == steps {
            frames.draw(&render(w, &settings), k)?;
        }
        progress.tick(k);
        Ok(Flow::Continue)
    });
    progress.finish();
    let finished = frames.finish();
    Stopped::outcome(ran, |e| {
        format!("{}: the run stopped: {e}", image_path.display())
    })?;
    finished?;
    frames.summary(args, &image_path.display().to_string(), steps);
    Ok(())
}
