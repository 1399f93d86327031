//! `rigidref render IMAGE.png`: run the 2D system and write PNG frames and an animated GIF.

use super::args::{Blocks2dOptions, RestThreshold, RunLength, SceneSets};
use super::progress::{Progress, Stopped};
use anyhow::{Context, bail};
use clap::Args;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame};
use rigidref::sim::{Flow, drive};
use rigidref::tools::render2d::{RenderSettings, render};
use std::path::PathBuf;

/// Arguments of `rigidref render`.
#[derive(Args)]
#[command(after_long_help = "\
Runs the image scene with the same options as `rigidref run IMAGE.png` and draws every K-th step:
blocks in their own colours, each moving body's centre of mass as a blue circle that turns solid
when its kinetic energy is below --rest-threshold, and optionally contacts (red points, green
normals) and root bounding discs. Frames go to DIR/frame-NNNNN.png, the animation to --gif.")]
pub struct RenderArgs {
    /// A 2D scene: an image (.png), run with the 2D options below, or a 2D scene file.
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub length: RunLength,
    /// Print no progress bar and no summary.
    #[arg(long, short)]
    pub quiet: bool,
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
    #[command(flatten)]
    pub sets: SceneSets,
    #[command(flatten)]
    pub blocks: Blocks2dOptions,
    #[command(flatten)]
    pub rest: RestThreshold,
}

/// The largest frame rendered, in pixels (100 million: 400 MB of RGBA).
const MAX_FRAME_PIXELS: f64 = 1e8;

/// Renders.
pub fn render_command(args: RenderArgs) -> anyhow::Result<()> {
    let Some(image_path) = args.scene.clone() else {
        bail!("render needs an image (a .png scene)");
    };
    super::common::check_readable(Some(&image_path))?;
    if !rigidref::blocks2d::scene::is_2d_scene(&image_path) {
        bail!(
            "{}: render draws 2D scenes (a .png image or a 2D scene file naming one); this is not one",
            image_path.display()
        );
    }
    check_render_args(&args)?;
    let rest_threshold = args.rest.value()?;
    let mut world = super::run2d::load_scene(&image_path, &args.blocks, &args.sets)?.world;
    let steps = args.length.steps(world.params.dt, "")?;
    let mut settings = RenderSettings::fit(&world, args.scale);
    // A frame is width × height RGBA pixels, all held at once: refuse what cannot be held
    // rather than abort on a failed allocation.
    let (width, height) = (
        (settings.size.x * args.scale).ceil(),
        (settings.size.y * args.scale).ceil(),
    );
    if width * height > MAX_FRAME_PIXELS {
        bail!(
            "{}: frames of {width:.0} × {height:.0} pixels at --scale {} exceed the limit of {} million pixels; lower --scale",
            image_path.display(),
            args.scale,
            MAX_FRAME_PIXELS / 1e6
        );
    }
    settings.opacity = args.opacity;
    settings.contacts = args.show_contacts;
    settings.discs = args.show_discs;
    settings.rest_threshold = rest_threshold;
    let mut frames = Frames::new(&args, world.params.dt)?;
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
    Stopped::outcome(ran, |e| {
        format!("{}: the run stopped: {e}", image_path.display())
    })?;
    if !args.quiet {
        eprintln!(
            "{} frames of {} ({steps} steps){}{}",
            frames.written,
            image_path.display(),
            args.frames
                .as_ref()
                .map_or(String::new(), |d| format!(", PNG in {}", d.display())),
            args.gif
                .as_ref()
                .map_or(String::new(), |g| format!(", GIF {}", g.display()))
        );
    }
    Ok(())
}

/// Checks the drawing options.
fn check_render_args(args: &RenderArgs) -> anyhow::Result<()> {
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
    Ok(())
}

/// Where the frames go: PNG files in a folder and/or an animated GIF.
struct Frames<'a> {
    dir: Option<&'a std::path::Path>,
    gif: Option<GifEncoder<std::io::BufWriter<std::fs::File>>>,
    /// Frame delay, ms: the simulated time between frames, shown in real time (at least 20 ms).
    delay_ms: u32,
    written: usize,
}

impl<'a> Frames<'a> {
    fn new(args: &'a RenderArgs, step: f64) -> anyhow::Result<Frames<'a>> {
        if let Some(dir) = &args.frames {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("{}: cannot create", dir.display()))?;
        }
        let gif = match &args.gif {
            Some(p) => {
                let f = std::fs::File::create(p)
                    .with_context(|| format!("{}: cannot create", p.display()))?;
                let mut e = GifEncoder::new_with_speed(std::io::BufWriter::new(f), 20);
                e.set_repeat(Repeat::Infinite)?;
                Some(e)
            }
            None => None,
        };
        let delay_ms = ((step * args.frame_every as f64) * 1000.0)
            .round()
            .max(20.0) as u32;
        Ok(Frames {
            dir: args.frames.as_deref(),
            gif,
            delay_ms,
            written: 0,
        })
    }

    /// Writes the frame of step `k`.
    fn draw(&mut self, img: &image::RgbaImage, k: u64) -> anyhow::Result<()> {
        if let Some(dir) = self.dir {
            let path = dir.join(format!("frame-{k:05}.png"));
            img.save(&path)
                .with_context(|| format!("{}: cannot write", path.display()))?;
        }
        if let Some(e) = &mut self.gif {
            let delay = Delay::from_numer_denom_ms(self.delay_ms, 1);
            e.encode_frame(Frame::from_parts(img.clone(), 0, 0, delay))?;
        }
        self.written += 1;
        Ok(())
    }
}
