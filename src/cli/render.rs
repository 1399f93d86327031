//! `rigidref render IMAGE.png`: run the 2D system and write PNG frames and an animated GIF.

use super::run::RunArgs;
use anyhow::{Context, bail};
use clap::Args;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame};
use rigidref::blocks::render::{RenderSettings, render};
use std::path::PathBuf;

/// Arguments of `rigidref render`.
#[derive(Args)]
#[command(after_long_help = "\
Runs the image scene with the same options as `rigidref run IMAGE.png` and draws every K-th step:
blocks in their own colours, each moving body's centre of mass as a blue circle that turns solid
when its kinetic energy is below --rest-threshold, and optionally contacts (red points, green
normals) and root bounding discs. Frames go to DIR/frame-NNNNN.png, the animation to --gif.")]
pub struct RenderArgs {
    /// The run: image and 2D options (see `rigidref run --help`).
    #[command(flatten)]
    pub run: RunArgs,
    /// Folder for PNG frames.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
    /// Animated GIF of the frames.
    #[arg(long, value_name = "FILE")]
    pub gif: Option<PathBuf>,
    /// Draw every K-th step.
    #[arg(long, default_value_t = 5)]
    pub frame_every: u64,
    /// Pixels per block.
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub scale: f64,
    /// Block opacity in [0, 1] (0.5 shows whether bodies interpenetrate).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub opacity: f64,
    /// Draw contacts.
    #[arg(long)]
    pub show_contacts: bool,
    /// Draw root bounding discs.
    #[arg(long)]
    pub show_discs: bool,
}

/// The largest frame rendered, in pixels (100 million: 400 MB of RGBA).
const MAX_FRAME_PIXELS: f64 = 1e8;

/// Renders.
pub fn render_command(args: RenderArgs) -> anyhow::Result<()> {
    let Some(image_path) = args.run.scene.clone() else {
        bail!("render needs an image (a .png scene)");
    };
    super::check_readable(Some(&image_path))?;
    if !super::run2d::is_2d(&image_path) {
        bail!(
            "{}: render draws 2D scenes (a .png image or a 2D scene file naming one); this is not one",
            image_path.display()
        );
    }
    let ignored = args.run.run_outputs_given();
    if !ignored.is_empty() {
        bail!(
            "{}: {} are options of `run`; render writes --frames and --gif",
            image_path.display(),
            ignored.join(", ")
        );
    }
    if args.frames.is_none() && args.gif.is_none() {
        bail!("nothing to write: give --frames DIR and/or --gif FILE");
    }
    if !(args.scale > 0.0 && args.scale <= 64.0) {
        bail!("--scale must be in (0, 64], got {}", args.scale);
    }
    if !(0.0..=1.0).contains(&args.opacity) {
        bail!("--opacity must be in [0, 1], got {}", args.opacity);
    }
    if args.frame_every == 0 {
        bail!("--frame-every must be at least 1");
    }
    let mut world = super::run2d::world_from_args(&image_path, &args.run)?;
    let steps = super::steps_of(&args.run, world.params.step, "")?;
    let mut settings = RenderSettings::fit(&world, args.scale);
    // A frame is width × height RGBA pixels, all held at once: refuse what cannot be held
    // rather than abort on a failed allocation.
    let pixels = (settings.size.x * args.scale).ceil() * (settings.size.y * args.scale).ceil();
    if pixels > MAX_FRAME_PIXELS {
        bail!(
            "{}: frames of {:.0} × {:.0} pixels at --scale {} exceed the limit of {} million pixels; lower --scale",
            image_path.display(),
            (settings.size.x * args.scale).ceil(),
            (settings.size.y * args.scale).ceil(),
            args.scale,
            MAX_FRAME_PIXELS / 1e6
        );
    }
    settings.opacity = args.opacity;
    settings.contacts = args.show_contacts;
    settings.discs = args.show_discs;
    settings.rest_threshold = args.run.rest_threshold();
    if let Some(dir) = &args.frames {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create", dir.display()))?;
    }
    let mut gif = match &args.gif {
        Some(p) => {
            let f = std::fs::File::create(p)
                .with_context(|| format!("{}: cannot create", p.display()))?;
            let mut e = GifEncoder::new_with_speed(std::io::BufWriter::new(f), 20);
            e.set_repeat(Repeat::Infinite)?;
            Some(e)
        }
        None => None,
    };
    // Frame delay: the simulated time between frames, shown in real time (at least 20 ms).
    let delay_ms = ((world.params.step * args.frame_every as f64) * 1000.0)
        .round()
        .max(20.0) as u32;
    let mut written = 0;
    let started = std::time::Instant::now();
    let progress = super::progress_bar(steps, super::STEPS_TEMPLATE);
    let mut shown = false;
    for k in 0..=steps {
        if k > 0 {
            world.step();
            world
                .check_finite()
                .map_err(|e| anyhow::anyhow!("{}: the run stopped: {e}", image_path.display()))?;
        }
        super::show_progress_after_a_second(&progress, started, args.run.quiet, &mut shown);
        progress.set_position(k);
        if k % args.frame_every != 0 && k != steps {
            continue;
        }
        let img = render(&world, &settings);
        if let Some(dir) = &args.frames {
            let path = dir.join(format!("frame-{k:05}.png"));
            img.save(&path)
                .with_context(|| format!("{}: cannot write", path.display()))?;
        }
        if let Some(e) = &mut gif {
            e.encode_frame(Frame::from_parts(
                img,
                0,
                0,
                Delay::from_numer_denom_ms(delay_ms, 1),
            ))?;
        }
        written += 1;
    }
    progress.finish_and_clear();
    if args.run.quiet {
        return Ok(());
    }
    eprintln!(
        "{written} frames of {} ({} steps){}{}",
        image_path.display(),
        steps,
        args.frames
            .as_ref()
            .map_or(String::new(), |d| format!(", PNG in {}", d.display())),
        args.gif
            .as_ref()
            .map_or(String::new(), |g| format!(", GIF {}", g.display()))
    );
    Ok(())
}
