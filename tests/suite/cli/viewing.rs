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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
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
            let stderr = String::from_utf8_lossy(&out.stderr);
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
}
