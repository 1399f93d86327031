//! `rigidref render SCENE|TRACE`: draw a run as PNG frames, an animated GIF and an MP4 video.
//! 2D image scenes are run and drawn block by block (src/tools/render2d.rs); 3D scenes are run
//! to a trace first, and 3D traces are drawn from their records (src/tools/render3d.rs).
//! docs/viewing.md §"Rendering".

use super::args::{Blocks2dOptions, RestThreshold, RunLength, SceneSets};
use super::progress::{Progress, Stopped};
use anyhow::{Context, bail};
use clap::Args;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame};
use rigidref::sim::{Flow, drive};
use rigidref::tools::render2d::{RenderSettings, render};
use rigidref::tools::render3d::{BodyPose, Camera, ContactMark, FrameStyle, render_frame};
use rigidref::tools::view::ViewTrace;
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

/// Runs the 2D image scene and draws every K-th step.
fn render_2d(args: &RenderArgs, image_path: &Path) -> anyhow::Result<()> {
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
    let mut world = super::run2d::load_scene(image_path, &args.blocks, &args.sets)?.world;
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

/// Runs the 3D scene to a trace (or reads the trace given) and draws every K-th record.
fn render_3d(args: &RenderArgs) -> anyhow::Result<()> {
    refuse(
        &[
            ("--scale", args.scale.is_some()),
            ("--opacity", args.opacity.is_some()),
            ("--show-discs", args.show_discs),
            ("--rest-threshold", args.rest.rest_threshold.is_some()),
        ],
        "2D renders",
    )?;
    let (width, height) = (args.width.unwrap_or(800), args.height.unwrap_or(600));
    if !(16..=8192).contains(&width) || !(16..=8192).contains(&height) {
        bail!("--width and --height must be in [16, 8192] pixels, got {width} × {height}");
    }
    let azimuth = args.azimuth.unwrap_or(30.0);
    let elevation = args.elevation.unwrap_or(20.0);
    let orbit = args.orbit.unwrap_or(0.0);
    if !azimuth.is_finite() || !orbit.is_finite() || !(-89.0..=89.0).contains(&elevation) {
        bail!(
            "--azimuth and --orbit must be finite and --elevation in [-89, 89] degrees, got {azimuth}, {orbit}, {elevation}"
        );
    }
    let given_trace = args.scene.as_ref().filter(|p| super::view::is_trace(p));
    let (trace_path, ran) = match given_trace {
        Some(p) => {
            if !args.sets.set.is_empty()
                || args.length.time.is_some()
                || args.length.steps.is_some()
                || args.trace.is_some()
            {
                bail!(
                    "{}: is a trace; --set, --time, --steps and --trace apply when rendering a scene (the run is already done)",
                    p.display()
                );
            }
            (p.clone(), None)
        }
        None => {
            let trace = args
                .trace
                .clone()
                .unwrap_or_else(|| default_trace_path(args));
            // The default trace goes into the frames folder, which may not exist yet.
            if let Some(dir) = trace.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("{}: cannot create", dir.display()))?;
            }
            let ran = super::view::run_to_trace(
                args.scene.as_deref(),
                &args.length,
                &args.sets,
                &args.blocks,
                1,
                args.quiet,
                &trace,
            );
            (trace, Some(ran))
        }
    };
    // A run that failed midway left a valid trace of what it did: draw that, then report.
    if let Some(Err(e)) = &ran
        && !trace_path.exists()
    {
        bail!("{e:#}");
    }
    let name = trace_path.display().to_string();
    let (trace, _warnings) = super::view::read_trace_file(&trace_path, &[])?;
    let ViewTrace::Three { header, records } = trace else {
        bail!("{name}: a 2D trace; render draws 2D runs from their image scene (give the .png)");
    };
    if records.is_empty() {
        bail!("{name}: the trace has no records to draw");
    }
    let scene = super::view::scene_of_3d_trace(&name, &header.source, header.bodies.len())?;
    let meshes: Vec<_> = scene.bodies.iter().map(|b| &*b.mesh).collect();

    let picked: Vec<usize> = (0..records.len())
        .filter(|&k| (k as u64).is_multiple_of(args.frame_every) || k + 1 == records.len())
        .collect();
    let (centre, radius) = run_bounds(&records, &picked, &meshes);
    let mut radii: Vec<f64> = meshes.iter().map(|m| m.bounding_radius()).collect();
    radii.sort_by(f64::total_cmp);
    let style = FrameStyle {
        contacts: args.show_contacts,
        normal_length: 0.6 * radii[radii.len() / 2],
        ground_extent: (centre.x.abs().max(centre.z.abs()) + 2.5 * radius).max(1.0),
        ground: true,
    };
    let interval = if records.len() > 1 {
        (records[1].t - records[0].t) * args.frame_every as f64
    } else {
        header.dt
    };
    let mut frames = Frames::new(args, interval)?;
    let mut progress = Progress::steps(picked.len() as u64, args.quiet);
    let result = (|| -> anyhow::Result<()> {
        for (i, &k) in picked.iter().enumerate() {
            let r = &records[k];
            let bodies: Vec<BodyPose> = r
                .bodies
                .iter()
                .zip(&meshes)
                .enumerate()
                .map(|(b, (s, mesh))| BodyPose {
                    mesh,
                    x: nalgebra::Vector3::from(s.x),
                    rotation: nalgebra::Matrix3::from_fn(|i, j| s.rotation[i][j]),
                    colour: rigidref::tools::view::palette(b),
                })
                .collect();
            let contacts: Vec<ContactMark> = r
                .contacts
                .iter()
                .map(|c| ContactMark {
                    point: nalgebra::Vector3::from(c.p),
                    normal: nalgebra::Vector3::from(c.n),
                })
                .collect();
            let camera = Camera::framing(
                &centre,
                radius,
                (azimuth + orbit * r.t).to_radians(),
                elevation.to_radians(),
                width,
                height,
            );
            let overlay = if args.no_overlay {
                Vec::new()
            } else {
                vec![
                    format!("t = {:.3} s   step {}", r.t, r.step),
                    format!(
                        "E = {:.6} J (T {:.4}, U {:.4})",
                        r.energy.total,
                        r.energy.kinetic_linear + r.energy.kinetic_angular,
                        r.energy.potential
                    ),
                    format!("contacts {}", r.contacts.len()),
                ]
            };
            let img = render_frame(&camera, &bodies, &contacts, &overlay, &style);
            frames.draw(&img, r.step)?;
            progress.tick(i as u64 + 1);
        }
        Ok(())
    })();
    progress.finish();
    let finished = frames.finish();
    result?;
    finished?;
    frames.summary(args, &name, records.last().map_or(0, |r| r.step));
    match ran {
        Some(Err(e)) => Err(e.context(format!(
            "the frames show the run up to where it stopped (trace {name})"
        ))),
        _ => Ok(()),
    }
}

/// Where a 3D scene's trace goes when --trace is not given.
fn default_trace_path(args: &RenderArgs) -> PathBuf {
    if let Some(p) = args.gif.as_ref().or(args.mp4.as_ref()) {
        p.with_extension("jsonl")
    } else {
        args.frames
            .as_ref()
            .map_or_else(|| PathBuf::from("render.jsonl"), |d| d.join("trace.jsonl"))
    }
}

/// Centre and radius of a sphere holding every body of the drawn records (each body's centre
/// of mass ± its mesh's bounding radius), m.
fn run_bounds(
    records: &[rigidref::rigid3d::trace::TraceRecord],
    picked: &[usize],
    meshes: &[&rigidref::rigid3d::mesh::TriMesh],
) -> (nalgebra::Vector3<f64>, f64) {
    let radii: Vec<f64> = meshes.iter().map(|m| m.bounding_radius()).collect();
    let mut lo = nalgebra::Vector3::repeat(f64::INFINITY);
    let mut hi = nalgebra::Vector3::repeat(f64::NEG_INFINITY);
    for &k in picked {
        for (s, r) in records[k].bodies.iter().zip(&radii) {
            let x = nalgebra::Vector3::from(s.x);
            if x.iter().all(|c| c.is_finite()) {
                lo = lo.inf(&(x - nalgebra::Vector3::repeat(*r)));
                hi = hi.sup(&(x + nalgebra::Vector3::repeat(*r)));
            }
        }
    }
    if !lo.iter().all(|c| c.is_finite()) {
        return (nalgebra::Vector3::zeros(), 1.0);
    }
    ((lo + hi) / 2.0, ((hi - lo).norm() / 2.0).max(1e-3))
}

/// Where the frames go: PNG files in a folder, an animated GIF, an MP4 video made by ffmpeg.
struct Frames<'a> {
    dir: Option<&'a Path>,
    gif: Option<GifEncoder<std::io::BufWriter<std::fs::File>>>,
    mp4_path: Option<&'a Path>,
    mp4: Option<rigidref::tools::video::Mp4Writer>,
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
                    rigidref::tools::video::Mp4Writer::start(path, img.width(), img.height(), fps)
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
