//! `rigidref render` of a 3D scene or trace: the run (or the trace read back), the camera fitted
//! to the run's bounds, and the frames drawn with contacts.

use super::*;

/// Runs the 3D scene to a trace (or reads the trace given) and draws every K-th record.
pub(super) fn render_3d(args: &RenderArgs) -> anyhow::Result<()> {
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
    let given_trace = args
        .scene
        .as_ref()
        .filter(|p| crate::cli::common::is_trace(p));
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
            let ran = crate::cli::run::run_to_trace(
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
    let (trace, _warnings) = crate::cli::common::read_trace_file(&trace_path, &[])?;
    let RunTrace::Three { header, records } = trace else {
        bail!("{name}: a 2D trace; render draws 2D runs from their image scene (give the .png)");
    };
    if records.is_empty() {
        bail!("{name}: the trace has no records to draw");
    }
    let scene = crate::cli::common::scene_of_3d_trace(&name, &header.source, header.bodies.len())?;
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
                    colour: rigidref::tools::viewing::view::palette(b),
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
