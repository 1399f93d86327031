//! `rigidref render SCENE|TRACE`: draw a run as PNG frames, an animated GIF and an MP4 video.
//! 2D image scenes are run and drawn block by block (src/tools/viewing/render2d.rs); 3D scenes are run
//! to a trace first, and 3D traces are drawn from their records (src/tools/viewing/render3d.rs).
//! docs/viewing.md §"Rendering".

mod render2d;
mod render3d;

use super::args::{RestThreshold, RunLength, SceneSets};
use super::args2d::Blocks2dOptions;
use super::progress::{Progress, Stopped};
use anyhow::{Context, bail};
use clap::Args;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame};
use render2d::render_2d;
use render3d::render_3d;
use rigidref::sim::{Flow, drive};
use rigidref::tools::viewing::render2d::{RenderSettings, render};
use rigidref::tools::viewing::render3d::{BodyPose, Camera, ContactMark, FrameStyle, render_frame};
use rigidref::tools::viewing::view::RunTrace;
use std::path::{Path, PathBuf};

/// Arguments of `rigidref render`.
#[derive(Args)]
#[command(after_long_help = "\
2D: runs the image scene with the same options as `rigidref run IMAGE.png` and draws every K-th
step: blocks in their own colours, each moving body's centre of mass as a blue circle that turns
solid when its kinetic energy is below --rest-threshold, and optionally contacts (red points,
green normals) and root bounding discs.

3D: runs the scene (or, without one, the built-in default scene) with the same options as
`rigidref run`, its trace kept (--trace), or reads a trace written by `rigidref run`, and draws
every K-th record: the meshes flat-shaded over the ground grid from a camera that frames the whole
run, fixed (--azimuth, --elevation) or orbiting (--orbit), optionally the contacts (red points,
green normals), and the time, energy and contact count at the top left (--no-overlay removes it).

Frames go to DIR/frame-NNNNN.png (NNNNN the step), the animation to --gif and/or --mp4 (MP4 needs
ffmpeg on the PATH), both in real time where the frame interval allows (GIF: at most 50 frames
per second; MP4: at most 60). A run that stops midway keeps the frames already written.
docs/viewing.md §\"Rendering\".")]
pub struct RenderArgs {
    /// What to draw: a 2D scene (an image .png, or a 2D scene file), a 3D scene (.json), or a 3D
    /// trace (.jsonl) written by `rigidref run`. Without one, the built-in default 3D scene runs.
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
    /// MP4 video (H.264) of the frames, made by ffmpeg, which must be on the PATH.
    #[arg(long, value_name = "FILE")]
    pub mp4: Option<PathBuf>,
    /// Draw every K-th step (3D trace: every K-th record; the last is always drawn).
    #[arg(long, default_value_t = 5)]
    pub frame_every: u64,
    /// Draw contacts.
    #[arg(long)]
    pub show_contacts: bool,
    /// 2D: pixels per block [default: 3].
    #[arg(long, allow_negative_numbers = true)]
    pub scale: Option<f64>,
    /// 2D: block opacity in [0, 1] (0.5 shows whether bodies interpenetrate) [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    pub opacity: Option<f64>,
    /// 2D: draw root bounding discs.
    #[arg(long)]
    pub show_discs: bool,
    /// 3D: frame width, pixels [default: 800].
    #[arg(long)]
    pub width: Option<u32>,
    /// 3D: frame height, pixels [default: 600].
    #[arg(long)]
    pub height: Option<u32>,
    /// 3D: camera azimuth, degrees about +y (0 looks along −z, 90 along −x) [default: 30].
    #[arg(long, allow_negative_numbers = true)]
    pub azimuth: Option<f64>,
    /// 3D: camera elevation above the horizon, degrees, in [−89, 89] [default: 20].
    #[arg(long, allow_negative_numbers = true)]
    pub elevation: Option<f64>,
    /// 3D: orbit the camera about the vertical at this many degrees per simulated second
    /// [default: 0, a fixed camera].
    #[arg(long, allow_negative_numbers = true)]
    pub orbit: Option<f64>,
    /// 3D: no text overlay (time, energy, contacts).
    #[arg(long)]
    pub no_overlay: bool,
    /// 3D, when running a scene: where its trace goes [default: beside the first output, with
    /// .jsonl: the GIF's or MP4's path, or DIR/trace.jsonl].
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
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
    check_common_args(&args)?;
    if let Some(path) = &args.scene {
        super::common::check_readable(Some(path))?;
    }
    match &args.scene {
        Some(path) if rigidref::blocks2d::scene::is_2d_scene(path) => render_2d(&args, path),
        _ => render_3d(&args),
    }
}

/// Checks the options every render takes.
fn check_common_args(args: &RenderArgs) -> anyhow::Result<()> {
    if args.frames.is_none() && args.gif.is_none() && args.mp4.is_none() {
        bail!("nothing to write: give --frames DIR, --gif FILE and/or --mp4 FILE");
    }
    if args.frame_every == 0 {
        bail!("--frame-every must be at least 1");
    }
    if args.mp4.is_some() {
        check_ffmpeg()?;
    }
    Ok(())
}

/// Fails with a clear message when ffmpeg cannot be started.
fn check_ffmpeg() -> anyhow::Result<()> {
    match std::process::Command::new("ffmpeg")
        .arg("-version")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
    {
        Ok(s) if s.success() => Ok(()),
        _ => bail!(
            "--mp4 needs ffmpeg on the PATH, which was not found (install it, e.g. apt-get install ffmpeg), or write --gif/--frames instead"
        ),
    }
}

/// Names the options given that the other system's render does not take.
fn refuse(given: &[(&str, bool)], what: &str) -> anyhow::Result<()> {
    let names: Vec<&str> = given.iter().filter(|(_, g)| *g).map(|(n, _)| *n).collect();
    if !names.is_empty() {
        bail!("{} apply to {what} only", names.join(", "));
    }
    Ok(())
}

/// Where the frames go: PNG files in a folder, an animated GIF, an MP4 video made by ffmpeg.
struct Frames<'a> {
    dir: Option<&'a Path>,
    gif: Option<GifEncoder<std::io::BufWriter<std::fs::File>>>,
    mp4_path: Option<&'a Path>,
    mp4: Option<rigidref::tools::viewing::video::Mp4Writer>,
    /// Simulated time between frames, s (shown in real time where the format allows).
    interval: f64,
    written: usize,
}

impl<'a> Frames<'a> {
    fn new(args: &'a RenderArgs, interval: f64) -> anyhow::Result<Frames<'a>> {
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
        Ok(Frames {
            dir: args.frames.as_deref(),
            gif,
            mp4_path: args.mp4.as_deref(),
            mp4: None,
            interval,
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
            // GIF delays are in hundredths of a second, at least 2 in practice.
            let delay_ms = (self.interval * 1000.0).round().max(20.0) as u32;
            let delay = Delay::from_numer_denom_ms(delay_ms, 1);
            e.encode_frame(Frame::from_parts(img.clone(), 0, 0, delay))?;
        }
        if let Some(path) = self.mp4_path {
            if self.mp4.is_none() {
                let fps = (1.0 / self.interval).clamp(1.0, 60.0);
                self.mp4 = Some(
                    rigidref::tools::viewing::video::Mp4Writer::start(
                        path,
                        img.width(),
                        img.height(),
                        fps,
                    )
                    .map_err(anyhow::Error::msg)?,
                );
            }
            if let Some(w) = &mut self.mp4 {
                w.write(img).map_err(anyhow::Error::msg)?;
            }
        }
        self.written += 1;
        Ok(())
    }

    /// Completes the GIF and the video (also after an error: what was drawn is kept).
    fn finish(&mut self) -> anyhow::Result<()> {
        self.gif = None; // the encoder writes the GIF trailer when dropped
        match self.mp4.take() {
            Some(w) => w.finish().map_err(anyhow::Error::msg),
            None => Ok(()),
        }
    }

    /// Prints what was written.
    fn summary(&self, args: &RenderArgs, source: &str, steps: u64) {
        if args.quiet {
            return;
        }
        let mut outputs = Vec::new();
        if let Some(d) = &args.frames {
            outputs.push(format!("PNG in {}", d.display()));
        }
        if let Some(g) = &args.gif {
            outputs.push(format!("GIF {}", g.display()));
        }
        if let Some(m) = &args.mp4 {
            outputs.push(format!("MP4 {}", m.display()));
        }
        eprintln!(
            "{} frames of {source} ({steps} steps): {}",
            self.written,
            outputs.join(", ")
        );
    }
}
