//! `rigidref view` and `rigidref plot` as a user runs them (docs/viewing.md): the page opened in
//! a real headless browser, the plot files read back, bad traces refused in one line.

use crate::common;
use common::{project_root, rigidref};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The system's Chromium, or None after printing why the caller skips (`.ci/run` installs it).
fn chromium() -> Option<PathBuf> {
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        if let Ok(out) = Command::new("which").arg(name).output()
            && out.status.success()
        {
            return Some(PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()));
        }
    }
    eprintln!("SKIPPED: no Chromium on the PATH (apt-get install chromium; .ci/run installs it)");
    None
}

/// Headless Chromium with WebGL on the CPU (SwiftShader through ANGLE: CI machines have no GPU).
fn browse(browser: &Path, page: &Path, fragment: &str, what: &[&str]) -> std::process::Output {
    Command::new(browser)
        .args([
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--window-size=1200,800",
            "--virtual-time-budget=5000",
            "--hide-scrollbars",
        ])
        .args(what)
        .arg(format!("file://{}{fragment}", page.display()))
        .output()
        .unwrap()
}

/// The `data-…` attributes of the page's body after load.
fn body_data(
    browser: &Path,
    page: &Path,
    fragment: &str,
) -> (std::collections::HashMap<String, String>, String) {
    let out = browse(browser, page, fragment, &["--dump-dom"]);
    let dom = String::from_utf8_lossy(&out.stdout).into_owned();
    let start = dom.find("<body").expect("a body element");
    let tag = &dom[start..start + dom[start..].find('>').unwrap()];
    let mut data = std::collections::HashMap::new();
    for part in tag.split(" data-").skip(1) {
        if let Some((key, rest)) = part.split_once("=\"") {
            let value = rest.split('"').next().unwrap_or("");
            data.insert(
                key.to_string(),
                value.replace("&quot;", "\"").replace("&amp;", "&"),
            );
        }
    }
    (data, dom)
}

/// A screenshot of the page at `fragment`.
fn screenshot(browser: &Path, page: &Path, fragment: &str, png: &Path) -> image::RgbaImage {
    let arg = format!("--screenshot={}", png.display());
    browse(browser, page, fragment, &[&arg]);
    image::open(png)
        .unwrap_or_else(|e| panic!("{}: no screenshot: {e}", png.display()))
        .to_rgba8()
}

/// Checks one page the way a person would: it loads without script errors, draws a view that
/// is not blank, shows the plots, and the view changes between two frames where a body moved.
fn check_page(browser: &Path, page: &Path, frames: (usize, usize), series: &[&str], dir: &Path) {
    let name = page.display();
    for k in [frames.0, frames.1] {
        let (data, dom) = body_data(browser, page, &format!("#frame={k}"));
        assert_eq!(
            data.get("status").map(String::as_str),
            Some("ready"),
            "{name}#frame={k}: status {data:?}"
        );
        assert!(
            data.get("errors").is_none_or(|e| e.is_empty()),
            "{name}: script errors {:?}",
            data.get("errors")
        );
        assert_eq!(
            data.get("frame"),
            Some(&k.to_string()),
            "{name}: the page did not go to frame {k}"
        );
        for s in series {
            assert!(dom.contains(s), "{name}: no plot series {s:?} in the page");
        }
    }
    let (data, _) = body_data(browser, page, "#frame=0");
    // The view's rectangle in CSS pixels, "x,y,width,height" (the page reports it).
    let rect: Vec<u32> = data["view-rect"]
        .split(',')
        .map(|v| v.trim().parse::<f64>().unwrap().round() as u32)
        .collect();
    let a = screenshot(
        browser,
        page,
        &format!("#frame={}", frames.0),
        &dir.join("a.png"),
    );
    let b = screenshot(
        browser,
        page,
        &format!("#frame={}", frames.1),
        &dir.join("b.png"),
    );
    let (x0, y0, w, h) = (
        rect[0],
        rect[1],
        rect[2].min(a.width() - rect[0]),
        rect[3].min(a.height() - rect[1]),
    );
    let mut colours = std::collections::HashSet::new();
    let mut changed = 0usize;
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            let (pa, pb) = (a.get_pixel(x, y), b.get_pixel(x, y));
            colours.insert(pa.0);
            changed += usize::from(pa.0.iter().zip(pb.0).any(|(p, q)| p.abs_diff(q) > 24));
        }
    }
    // Not blank: a drawn scene has shading and edges, hundreds of colours; a blank canvas one.
    assert!(
        colours.len() > 20,
        "{name}: the view has only {} colours",
        colours.len()
    );
    // A body moved between the frames: at least 0.1 % of the view's pixels changed clearly.
    assert!(
        changed * 1000 > (w * h) as usize,
        "{name}: only {changed} pixels changed between frames {frames:?}"
    );
}

#[test]
fn view_pages_load_draw_and_move_in_a_headless_browser() {
    let Some(browser) = chromium() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let root = project_root();
    // 3D: the project's box dropped onto one edge (it falls, lands and tips over); 2D: the
    // project's dominoes image, which topple.
    let brick = root.join("scenes/edge_landing.json");
    let out = rigidref(
        &[
            "view",
            brick.to_str().unwrap(),
            "--time",
            "2",
            "--out",
            "brick.html",
            "-q",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    assert!(
        tmp.path().join("brick.jsonl").is_file(),
        "the run's trace is kept beside the page"
    );
    check_page(
        &browser,
        &tmp.path().join("brick.html"),
        (0, 100),
        &["kinetic (linear)", "PGS sweeps", "p_y"],
        tmp.path(),
    );

    let image = root.join("scenes/blocks/dominoes.png");
    let out = rigidref(
        &[
            "view",
            image.to_str().unwrap(),
            "--time",
            "6",
            "--out",
            "dominoes.html",
            "-q",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    check_page(
        &browser,
        &tmp.path().join("dominoes.html"),
        (0, 110),
        &["kinetic", "Contacts"],
        tmp.path(),
    );
}

#[test]
fn view_of_a_trace_draws_from_its_scene_and_keeps_a_cut_off_traces_complete_records() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = project_root().join("scenes/sliding_box.json");
    let out = rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "1",
            "--out",
            "t.jsonl",
            "-q",
        ],
        tmp.path(),
    );
    assert!(out.status.success());
    let out = rigidref(&["view", "t.jsonl", "-q"], tmp.path());
    common::assert_success(&out);
    let page = std::fs::read_to_string(tmp.path().join("t.html")).unwrap();
    assert!(
        page.contains("\"format\":\"rigidref-view\""),
        "the page holds the run's data"
    );
    assert!(
        !page.contains("https://") && !page.contains("http://"),
        "the page must not load anything from the network"
    );

    // Cut the trace in the middle of its last line: the complete records are shown, with a
    // warning on the terminal and in the page.
    let text = std::fs::read_to_string(tmp.path().join("t.jsonl")).unwrap();
    let records = text.lines().count() - 1;
    std::fs::write(tmp.path().join("cut.jsonl"), &text[..text.len() - 40]).unwrap();
    let out = rigidref(&["view", "cut.jsonl"], tmp.path());
    common::assert_success(&out);
    let stderr = common::stderr(&out);
    let shown = records - 1;
    assert!(
        stderr.contains(&format!("showing the {shown} complete records")),
        "{stderr}"
    );
    let page = std::fs::read_to_string(tmp.path().join("cut.html")).unwrap();
    assert!(page.contains("the trace was cut off"));
}

#[test]
fn view_and_plot_refuse_what_is_not_a_trace_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("notes.jsonl"), "{\"hello\": 1}\n").unwrap();
    std::fs::write(tmp.path().join("garbage.jsonl"), "this is not json\n").unwrap();
    for command in ["view", "plot"] {
        for file in ["notes.jsonl", "garbage.jsonl"] {
            let out = rigidref(&[command, file], tmp.path());
            let stderr = common::stderr(&out);
            assert_eq!(out.status.code(), Some(1), "{command} {file}: {stderr}");
            assert_eq!(
                stderr.trim().lines().count(),
                1,
                "{command} {file}: one line, got {stderr}"
            );
            assert!(
                stderr.contains(file) && stderr.contains("not a rigidref trace"),
                "{command} {file}: {stderr}"
            );
            assert!(!stderr.contains("panicked"));
        }
    }
}

#[test]
fn plot_of_a_2d_run_labels_its_axes_in_the_2d_units() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/blocks/stack.json");
    let out = rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "2",
            "--out",
            "s.jsonl",
            "-q",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    let out = rigidref(
        &[
            "plot",
            "s.jsonl",
            "--out",
            "s.svg",
            "--quantities",
            "criteria,residual",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    let svg = std::fs::read_to_string(tmp.path().join("s.svg")).unwrap();
    // The 2D system's units are blocks, its own mass and time units (docs/blocks2d.md): no SI
    // unit may label its axes.
    for label in [
        "t (time units)",
        "log10 (block/time)",
        "log10 (mass·block/time, block/time, mass·block²/time²)",
    ] {
        assert!(svg.contains(label), "the 2D plot lacks the label {label:?}");
    }
    for si in ["N·s", "m/s", "t (s)"] {
        assert!(!svg.contains(si), "the 2D plot names the SI unit {si:?}");
    }
    // PGS's impulses lie in the cone, so the primal criterion is 0 at every step: on the log
    // axis it has no line, and its legend entry says so instead of leaving it out.
    assert!(
        svg.contains("primal (never above 0: no line on a log axis)"),
        "the legend leaves out the criterion that is zero throughout"
    );
}

#[test]
fn plot_of_the_dzhanibekov_run_names_the_angular_velocity_and_energy_series() {
    let tmp = tempfile::tempdir().unwrap();
    // The built-in default scene is the project's Dzhanibekov scene.
    let out = rigidref(
        &["run", "--time", "5", "--out", "dz.jsonl", "-q"],
        tmp.path(),
    );
    assert!(out.status.success());
    let out = rigidref(
        &[
            "plot",
            "dz.jsonl",
            "--out",
            "dz.svg",
            "--quantities",
            "omega,energy",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    let svg = std::fs::read_to_string(tmp.path().join("dz.svg")).unwrap();
    for name in [
        "ω_x",
        "ω_y",
        "ω_z",
        "kinetic (angular)",
        "total",
        "Angular velocity",
        "Energy",
    ] {
        assert!(svg.contains(name), "the SVG does not name {name:?}");
    }
    // Two traces overlaid: each series is named with its trace's file name.
    std::fs::copy(tmp.path().join("dz.jsonl"), tmp.path().join("again.jsonl")).unwrap();
    let out = rigidref(
        &[
            "plot",
            "dz.jsonl",
            "again.jsonl",
            "--out",
            "both.svg",
            "--quantities",
            "energy",
        ],
        tmp.path(),
    );
    assert!(out.status.success());
    let svg = std::fs::read_to_string(tmp.path().join("both.svg")).unwrap();
    assert!(svg.contains("dz.jsonl: total") && svg.contains("again.jsonl: total"));
    assert!(
        svg.contains("t (s)"),
        "the 3D time axis does not name seconds"
    );

    // The same plot as PNG: two panels of 1000 × 300 pixels under a 40-pixel title, the first
    // series in the first colour of the palette, and text (dark pixels) in the title strip.
    let out = rigidref(
        &[
            "plot",
            "dz.jsonl",
            "--out",
            "dz.png",
            "--quantities",
            "omega,energy",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    let png = image::open(tmp.path().join("dz.png")).unwrap().to_rgba8();
    assert_eq!(png.dimensions(), (1000, 640));
    let blue = png.pixels().filter(|p| p.0 == [31, 119, 180, 255]).count();
    assert!(blue > 500, "the first series' line has {blue} pixels");
    let title_ink = (0..1000)
        .flat_map(|x| (0..40).map(move |y| (x, y)))
        .filter(|&(x, y)| png.get_pixel(x, y).0[0] < 80)
        .count();
    assert!(title_ink > 50, "no title text ({title_ink} dark pixels)");
    // Any other extension is refused in one line.
    let out = rigidref(&["plot", "dz.jsonl", "--out", "dz.pdf"], tmp.path());
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr.contains("dz.pdf") && stderr.contains(".svg or .png"),
        "{stderr}"
    );
}

/// Pixels of body 0's colour (orange, any shade: red well above green, green well above blue)
/// and their centroid, in pixels.
fn orange_pixels(img: &image::RgbaImage) -> (usize, (f64, f64)) {
    let (mut n, mut sx, mut sy) = (0usize, 0.0, 0.0);
    for (x, y, p) in img.enumerate_pixels() {
        let [r, g, b, _] = p.0.map(f64::from);
        if r > 60.0 && r > 1.4 * g && g > 1.5 * b {
            n += 1;
            sx += f64::from(x);
            sy += f64::from(y);
        }
    }
    (n, (sx / n.max(1) as f64, sy / n.max(1) as f64))
}

/// The number of frames of an animated GIF.
fn gif_frames(path: &Path) -> usize {
    use image::AnimationDecoder;
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .count()
}

/// Whether `path` is an MP4 file (an ISO media file: its first box is `ftyp`) of some size.
fn is_mp4(path: &Path) -> bool {
    let bytes = std::fs::read(path).unwrap_or_default();
    bytes.len() > 1000 && &bytes[4..8] == b"ftyp"
}

#[test]
fn render_of_the_assignment_brick_draws_it_moving_and_writes_the_animations() {
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let scene = dir.join("scenes/scene6.json");
    let mp4 = common::has_ffmpeg();
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "--time",
        "1.5",
        "--frame-every",
        "10",
        "--frames",
        "fr",
        "--gif",
        "brick.gif",
    ];
    if mp4 {
        args.extend(["--mp4", "brick.mp4"]);
    } else {
        eprintln!("SKIPPED the MP4 part: no ffmpeg on the PATH (.ci/run installs it)");
    }
    let out = rigidref(&args, tmp.path());
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{stderr}");
    // 150 steps, every 10th drawn: frames 0, 10, …, 150.
    let first = image::open(tmp.path().join("fr/frame-00000.png"))
        .unwrap()
        .to_rgba8();
    let last = image::open(tmp.path().join("fr/frame-00150.png"))
        .unwrap()
        .to_rgba8();
    assert_eq!(first.dimensions(), (800, 600));
    let (n0, c0) = orange_pixels(&first);
    let (n1, c1) = orange_pixels(&last);
    // The brick covers a few percent of the frame: thousands of pixels, not a stray few.
    assert!(n0 > 2000 && n1 > 2000, "brick pixels {n0}, {n1}");
    // It falls 0.4 m and turns: its image moves down by tens of pixels.
    let moved = (c1.0 - c0.0).hypot(c1.1 - c0.1);
    assert!(
        c1.1 > c0.1 + 10.0,
        "the brick's image should move down: {c0:?} → {c1:?}"
    );
    eprintln!("brick: {n0} → {n1} pixels, centroid {c0:.1?} → {c1:.1?} ({moved:.1} px)");
    // The overlay: dark text pixels in the top-left corner.
    let ink = (0..300)
        .flat_map(|x| (0..60).map(move |y| (x, y)))
        .filter(|&(x, y)| first.get_pixel(x, y).0[0] < 60)
        .count();
    assert!(ink > 100, "no overlay text ({ink} dark pixels)");
    assert_eq!(gif_frames(&tmp.path().join("brick.gif")), 16);
    if mp4 {
        assert!(
            is_mp4(&tmp.path().join("brick.mp4")),
            "brick.mp4 is not an MP4 file"
        );
    }
    // The run's trace is kept beside the animation, and renders again: an orbiting camera
    // without the overlay draws a different picture of the same record.
    assert!(tmp.path().join("brick.jsonl").is_file());
    let out = rigidref(
        &[
            "render",
            "brick.jsonl",
            "--frames",
            "orbit",
            "--frame-every",
            "50",
            "--orbit",
            "60",
            "--no-overlay",
            "--show-contacts",
            "-q",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    let orbit_last = image::open(tmp.path().join("orbit/frame-00150.png"))
        .unwrap()
        .to_rgba8();
    let differing = orbit_last
        .pixels()
        .zip(last.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differing > 10_000, "only {differing} pixels differ");
}

#[test]
fn render_refuses_options_of_the_other_system_and_a_missing_output_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = project_root().join("scenes/sliding_box.json");
    let image = project_root().join("scenes/blocks/dominoes.png");
    let cases: [(Vec<&str>, &str); 4] = [
        (vec!["render", scene.to_str().unwrap()], "nothing to write"),
        (
            vec![
                "render",
                scene.to_str().unwrap(),
                "--gif",
                "a.gif",
                "--show-discs",
            ],
            "--show-discs apply to 2D renders only",
        ),
        (
            vec![
                "render",
                image.to_str().unwrap(),
                "--gif",
                "a.gif",
                "--orbit",
                "10",
            ],
            "--orbit apply to 3D renders only",
        ),
        (
            vec![
                "render",
                scene.to_str().unwrap(),
                "--gif",
                "a.gif",
                "--width",
                "5",
            ],
            "--width and --height must be in [16, 8192]",
        ),
    ];
    for (args, expected) in cases {
        let out = rigidref(&args, tmp.path());
        let stderr = common::stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

#[test]
fn render_of_a_2d_image_writes_an_mp4() {
    if !common::has_ffmpeg() {
        eprintln!("SKIPPED: no ffmpeg on the PATH (.ci/run installs it)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let image = project_root().join("scenes/blocks/dominoes.png");
    let out = rigidref(
        &[
            "render",
            image.to_str().unwrap(),
            "--steps",
            "40",
            "--mp4",
            "d.mp4",
            "-q",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    assert!(is_mp4(&tmp.path().join("d.mp4")));
}

#[test]
fn factory_page_shows_the_bodies_appearing_as_they_are_dropped() {
    // `factory --view-every K` writes DIR/view.html: the final world's bodies, each frame
    // saying how many are `present` (bodies are dropped over the run). In a browser the page
    // loads without errors and without the warning a missing pose would give, and the view
    // changes as bodies drop in.
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(
        &[
            "factory",
            "--bodies",
            "30",
            "--batch",
            "10",
            "--settle",
            "2",
            "--out",
            "f",
            "--view-every",
            "5",
            "-q",
        ],
        tmp.path(),
    );
    common::assert_success(&out);
    let page = tmp.path().join("f/view.html");
    let text = std::fs::read_to_string(&page).unwrap();
    // From the container alone (one pinned body) to every body of the report, never fewer.
    let present: Vec<usize> = text
        .split("\"present\":")
        .skip(1)
        .map(|s| {
            s[..s.find(|c: char| !c.is_ascii_digit()).unwrap()]
                .parse()
                .unwrap()
        })
        .collect();
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("f/report.json")).unwrap())
            .unwrap();
    assert_eq!(present.first(), Some(&1));
    assert_eq!(
        present.last().copied(),
        report["bodies"].as_u64().map(|b| b as usize)
    );
    assert!(present.windows(2).all(|w| w[0] <= w[1]), "{present:?}");
    let Some(browser) = chromium() else {
        return;
    };
    let (data, dom) = body_data(&browser, &page, "#frame=0");
    assert_eq!(
        data.get("status").map(String::as_str),
        Some("ready"),
        "{data:?}"
    );
    assert!(data.get("errors").is_none_or(|e| e.is_empty()), "{data:?}");
    assert!(
        !dom.contains("<div class=\"warning\">"),
        "absent bodies must not be reported as bad poses (no warning in the banner)"
    );
    let (data, _) = body_data(&browser, &page, "#frame=10");
    assert_eq!(
        data.get("status").map(String::as_str),
        Some("ready"),
        "{data:?}"
    );
}
