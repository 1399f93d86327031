//! Grading 2D submissions (issue 36): student-like simulators with the assignment's typical
//! mistakes ([`super::student`]) against the reference, by `compare` and by `grade` in a mixed
//! batch with a 3D scene (docs/grading.md §"Grading a 2D submission").

use super::student::{Bug, Settings, simulate};
use crate::common;
use std::path::Path;

/// Writes the two graded scenes' images and scene files into `dir`: `slide` (a 4 × 2 box on a
/// pinned floor, gravity tilted 15° off the vertical, μ 0.2: it slides) and `topple` (a 2 × 8 bar
/// on the floor, the same gravity, μ 0.6: it tips over). One substep, 100 sweeps in order, no
/// warm start, no post-stabilisation: what the student implements.
pub fn write_scenes(dir: &Path) {
    let white = image::Rgb([255u8, 255, 255]);
    let (black, blue) = (image::Rgb([0u8, 0, 0]), image::Rgb([0u8, 0, 255]));
    for (name, cells, mu) in [
        (
            "slide",
            (8..12)
                .flat_map(|c| (12..14).map(move |r| (c, r)))
                .collect::<Vec<_>>(),
            0.2,
        ),
        (
            "topple",
            (10..12)
                .flat_map(|c| (6..14).map(move |r| (c, r)))
                .collect::<Vec<_>>(),
            0.6,
        ),
    ] {
        let mut img = image::RgbImage::from_pixel(48, 20, white);
        for c in 2..46 {
            img.put_pixel(c, 15, blue);
        }
        for (c, r) in cells {
            img.put_pixel(c, r, black);
        }
        img.save(dir.join(format!("{name}.png"))).unwrap();
        let scene = serde_json::json!({
            "image": format!("{name}.png"),
            "parameters": {
                "substeps": 1, "iterations": 100, "order": "sequential", "warm_start": false,
                "post_stabilization": false, "mu": mu, "gravity_angle": 75.0
            }
        });
        std::fs::write(dir.join(format!("{name}.json")), scene.to_string()).unwrap();
    }
}

/// Runs the student with `bug` on scene `name` (from [`write_scenes`]) for `time`, writing
/// `folder/name.jsonl` and `folder/name.problem.json`.
pub fn run_student(dir: &Path, name: &str, time: f64, bug: Bug, folder: &Path) {
    let scene =
        rigidref::blocks2d::scene::load_2d(&dir.join(format!("{name}.json")), &Default::default())
            .unwrap();
    let p = &scene.world.params;
    let settings = Settings {
        dt: p.dt,
        gravity: p.gravity_vector(),
        mu: p.mu,
        iterations: p.iterations,
    };
    let steps = (time / p.dt).round() as u64;
    std::fs::create_dir_all(folder).unwrap();
    simulate(
        scene.world.bodies.clone(),
        name,
        &settings,
        steps,
        bug,
        &folder.join(format!("{name}.jsonl")),
        &folder.join(format!("{name}.problem.json")),
    );
}

/// The reference's runs of both scenes for `time` time units: `ref_slide.jsonl`, `ref_topple.jsonl`.
fn run_reference(dir: &Path, time: &str) {
    for name in ["slide", "topple"] {
        let out = format!("ref_{name}.jsonl");
        let o = common::rigidref(
            &[
                "run",
                &format!("{name}.json"),
                "--time",
                time,
                "-q",
                "--out",
                &out,
            ],
            dir,
        );
        common::assert_success(&o);
    }
}

/// `rigidref compare REF OTHER [extra]` in `dir`: (exit status, stdout, stderr).
fn compare(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let o = common::rigidref(args, dir);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stdout).to_string(),
        common::stderr(&o),
    )
}

/// Item 5 of issue 36: the correct student agrees with the reference in trajectory mode (to the
/// default 1e-3) on both scenes, and its first contact problem agrees with the reference's; each
/// typical mistake is flagged by `compare` with the quantity it changes:
///
/// | mistake | flagged by |
/// |---|---|
/// | positions before velocities | body 0's position from the first step (t = 0.05), before any contact |
/// | no rotational dynamics | the toppling bar's angle; its problem's inverse inertia |
/// | the angular Jacobian entries' sign | the bar's angle first; its problem's Jacobian (ω entries) |
/// | friction bounds ±μ, not ±μλn | the sliding box's position and velocity |
/// | the normal flipped | position (it sinks through the floor); its problem's normal row |
/// | the tree missing contacts at node boundaries | the sliding box's position (it sinks) |
#[test]
fn compare_accepts_the_correct_2d_student_and_names_what_each_typical_bug_changes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_scenes(dir);
    run_reference(dir, "8");
    let o = common::rigidref(
        &[
            "run",
            "topple.json",
            "--time",
            "8",
            "-q",
            "--dump-problems",
            "dumps",
            "--out",
            "x.jsonl",
        ],
        dir,
    );
    common::assert_success(&o);
    // The reference's first problem with a contact (its first dumps have none).
    let mut dumps: Vec<_> = std::fs::read_dir(dir.join("dumps"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dumps.sort();
    let first = dumps
        .iter()
        .find(|p| {
            let v: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
            v["contacts"].as_array().is_some_and(|c| !c.is_empty())
        })
        .expect("the bar reaches the floor");
    for bug in Bug::ALL {
        let folder = dir.join(bug.name());
        for name in ["slide", "topple"] {
            run_student(dir, name, 8.0, bug, &folder);
        }
        let trace = |name: &str| format!("{}/{name}.jsonl", bug.name());
        let (slide, _, slide_err) = compare(dir, &["compare", "ref_slide.jsonl", &trace("slide")]);
        let (topple, _, topple_err) =
            compare(dir, &["compare", "ref_topple.jsonl", &trace("topple")]);
        let problem = format!("{}/topple.problem.json", bug.name());
        let (problem_status, problem_out, _) =
            compare(dir, &["compare-problem", first.to_str().unwrap(), &problem]);
        // Whether body 0's `quantity` exceeds its tolerance somewhere, from the JSON report.
        let exceeds = |name: &str, quantity: &str| {
            let (_, json, _) = compare(
                dir,
                &[
                    "compare",
                    &format!("ref_{name}.jsonl"),
                    &trace(name),
                    "--json",
                ],
            );
            let report: serde_json::Value = serde_json::from_str(&json).unwrap();
            report["errors"].as_array().unwrap().iter().any(|e| {
                e["quantity"] == format!("body 0 (\"body0\") {quantity}")
                    && !e["first_exceeded"].is_null()
            })
        };
        let context =
            format!("{bug:?}\nslide: {slide_err}\ntopple: {topple_err}\nproblem: {problem_out}");
        match bug {
            Bug::Correct => {
                assert_eq!(
                    (slide, topple, problem_status),
                    (Some(0), Some(0), Some(0)),
                    "{context}"
                );
            }
            Bug::PositionsFirst => {
                for err in [&slide_err, &topple_err] {
                    assert!(
                        err.contains("body 0 (\"body0\") position exceeds")
                            && err.contains("first at t = 0.05 s"),
                        "{context}"
                    );
                }
            }
            Bug::NoRotation => {
                assert_eq!(topple, Some(1), "{context}");
                assert!(exceeds("topple", "angle"), "{context}");
                assert_eq!(problem_status, Some(1), "{context}");
                assert!(problem_out.contains("inverse mass"), "{context}");
            }
            Bug::LeverArmSign => {
                assert!(
                    topple_err.contains("body 0 (\"body0\") angle exceeds"),
                    "{context}"
                );
                assert_eq!(problem_status, Some(1), "{context}");
                assert!(problem_out.contains("(ω)"), "{context}");
            }
            Bug::FrictionNotScaled => {
                assert!(
                    slide_err.contains("body 0 (\"body0\") position exceeds"),
                    "{context}"
                );
                assert!(exceeds("slide", "velocity"), "{context}");
            }
            Bug::FlippedNormal => {
                assert!(
                    slide_err.contains("position exceeds")
                        && topple_err.contains("position exceeds"),
                    "{context}"
                );
                assert_eq!(problem_status, Some(1), "{context}");
                assert!(problem_out.contains("normal row"), "{context}");
            }
            Bug::TreeMissesBoundary => {
                assert!(
                    slide_err.contains("body 0 (\"body0\") position exceeds"),
                    "{context}"
                );
            }
        }
    }
}

/// `grade` over a mixed batch: the two 2D scenes and a 3D one (sphere_drop), with a submission
/// per student (the correct one and each typical mistake, each with the reference's own 3D
/// trace), one cut at half time, one with malformed files (text that is not a trace; a 3D trace
/// where the 2D scene wants a 2D one) and one missing a scene. Trajectory mode: the correct
/// student passes every scene, each mistake fails a 2D scene and passes the 3D one, and the
/// others get `refused`, `unreadable` and `missing`. Outcome mode passes the correct student too.
#[test]
fn grade_reports_a_mixed_batch_of_2d_and_3d_submissions() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_scenes(dir);
    let sphere = common::project_root().join("scenes/sphere_drop.json");
    let o = common::rigidref(
        &[
            "run",
            sphere.to_str().unwrap(),
            "--time",
            "8",
            "-q",
            "--out",
            "sphere_drop.jsonl",
        ],
        dir,
    );
    common::assert_success(&o);
    let submissions = dir.join("submissions");
    for bug in Bug::ALL {
        let folder = submissions.join(bug.name());
        for name in ["slide", "topple"] {
            run_student(dir, name, 8.0, bug, &folder);
        }
        std::fs::copy(
            dir.join("sphere_drop.jsonl"),
            folder.join("sphere_drop.jsonl"),
        )
        .unwrap();
    }
    let correct = submissions.join("correct");
    let cut = submissions.join("truncated");
    std::fs::create_dir_all(&cut).unwrap();
    for name in ["slide.jsonl", "topple.jsonl", "sphere_drop.jsonl"] {
        let text = std::fs::read_to_string(correct.join(name)).unwrap();
        let half: Vec<&str> = text.lines().take(text.lines().count() / 2).collect();
        std::fs::write(cut.join(name), half.join("\n") + "\n").unwrap();
    }
    let malformed = submissions.join("malformed");
    std::fs::create_dir_all(&malformed).unwrap();
    std::fs::write(malformed.join("slide.jsonl"), "my simulator crashed\n").unwrap();
    std::fs::copy(
        dir.join("sphere_drop.jsonl"),
        malformed.join("topple.jsonl"),
    )
    .unwrap();
    std::fs::copy(
        dir.join("sphere_drop.jsonl"),
        malformed.join("sphere_drop.jsonl"),
    )
    .unwrap();
    let missing = submissions.join("missing");
    std::fs::create_dir_all(&missing).unwrap();
    std::fs::copy(correct.join("slide.jsonl"), missing.join("slide.jsonl")).unwrap();
    std::fs::copy(
        dir.join("sphere_drop.jsonl"),
        missing.join("sphere_drop.jsonl"),
    )
    .unwrap();
    let grade = |mode: &str, out: &str| {
        let o = common::rigidref(
            &[
                "grade",
                "submissions",
                "--scenes",
                "slide.json",
                "topple.json",
                sphere.to_str().unwrap(),
                "--time",
                "8",
                "--mode",
                mode,
                "--out",
                out,
                "--jobs",
                "2",
            ],
            dir,
        );
        common::assert_success(&o);
        let mut rdr = csv::Reader::from_path(dir.join(out).join("grade.csv")).unwrap();
        let rows: Vec<Vec<String>> = rdr
            .records()
            .map(|r| r.unwrap().iter().map(String::from).collect())
            .collect();
        (
            rows,
            std::fs::read_to_string(dir.join(out).join("grade.md")).unwrap(),
        )
    };
    let (rows, markdown) = grade("trajectory", "report");
    let verdict = |submission: &str, scene: &str| {
        let mine: Vec<&Vec<String>> = rows
            .iter()
            .filter(|r| r[0] == submission && r[1] == scene)
            .collect();
        assert!(!mine.is_empty(), "no rows for {submission} × {scene}");
        let worst = ["missing", "unreadable", "refused", "fail"];
        worst
            .iter()
            .find(|w| mine.iter().any(|r| r[3] == **w))
            .map_or("pass", |w| *w)
    };
    let table_line = |submission: &str| {
        markdown
            .lines()
            .find(|l| l.starts_with(&format!("| {submission} |")))
            .unwrap_or_default()
            .to_string()
    };
    assert!(
        markdown.starts_with("| submission | slide | topple | sphere_drop |"),
        "{markdown}"
    );
    assert_eq!(
        table_line("correct"),
        "| correct | pass | pass | pass |",
        "{markdown}"
    );
    for bug in &Bug::ALL[1..] {
        let name = bug.name();
        assert!(
            verdict(name, "slide") == "fail" || verdict(name, "topple") == "fail",
            "{name} passes both 2D scenes:\n{markdown}"
        );
        assert_eq!(verdict(name, "sphere_drop"), "pass", "{markdown}");
    }
    assert_eq!(
        table_line("truncated"),
        "| truncated | refused | refused | refused |",
        "{markdown}"
    );
    assert_eq!(verdict("malformed", "slide"), "unreadable");
    assert_eq!(verdict("malformed", "topple"), "unreadable");
    assert!(
        rows.iter().any(|r| r[0] == "malformed"
            && r[1] == "topple"
            && r[4].contains("a 3D trace where a 2D one is compared")),
        "{markdown}"
    );
    assert_eq!(
        table_line("missing"),
        "| missing | pass | missing | pass |",
        "{markdown}"
    );
    // The first contact problem row: the correct student's passes, the flipped normal's fails.
    let problem_row = |submission: &str| {
        rows.iter()
            .find(|r| r[0] == submission && r[1] == "topple" && r[2] == "first contact problem")
            .map(|r| r[3].clone())
    };
    assert_eq!(problem_row("correct").as_deref(), Some("pass"));
    assert_eq!(problem_row("flipped_normal").as_deref(), Some("fail"));
    let (_, markdown) = grade("outcome", "outcome");
    assert!(
        markdown.contains("| correct | pass | pass | pass |"),
        "{markdown}"
    );
    assert!(
        markdown.contains("| flipped_normal | fail | fail | pass |"),
        "{markdown}"
    );
}
