//! `compare`, `compare-problem` and `grade` (docs/grading.md): what they accept, what they
//! catch, and that they name it.

use crate::common;

use common::rigidref;
use std::path::{Path, PathBuf};

fn scene(name: &str) -> String {
    common::project_root()
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

/// `rigidref run SCENE --time T --quiet --out OUT` plus `extra`, in `dir`.
fn run(dir: &Path, scene_name: &str, time: &str, out: &str, extra: &[&str]) {
    let s = scene(scene_name);
    let mut args = vec!["run", s.as_str(), "--time", time, "--quiet", "--out", out];
    args.extend_from_slice(extra);
    let o = rigidref(&args, dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

fn json_of(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&o.stdout)))
}

#[test]
fn compare_finds_a_trace_equal_to_itself_and_names_a_one_percent_change() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "tumbling_brick.json", "5", "a.jsonl", &[]);
    let o = rigidref(&["compare", "a.jsonl", "a.jsonl", "--json"], dir);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let report = json_of(&o);
    assert_eq!(report["agree"], true);
    for e in report["errors"].as_array().unwrap() {
        assert_eq!(e["max_error"], 0.0, "{e}");
    }
    // One body's initial velocity changed by 1% (0.5 → 0.505 m/s): the velocity differs by
    // 5 mm/s from t = 0, and the position drifts past 1 mm at t = 0.2 s.
    let edited = std::fs::read_to_string(scene("tumbling_brick.json"))
        .unwrap()
        .replacen("0.5,", "0.505,", 1);
    let scenes = common::project_root().join("scenes");
    let path = scenes.join(".grading-test-tumbling-brick.json");
    std::fs::write(&path, edited).unwrap();
    let o = rigidref(
        &[
            "run",
            path.to_str().unwrap(),
            "--time",
            "5",
            "--quiet",
            "--out",
            "b.jsonl",
        ],
        dir,
    );
    std::fs::remove_file(&path).unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rigidref(&["compare", "a.jsonl", "b.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let message = stderr(&o);
    assert!(
        message.contains("body 0 (\"block\") velocity exceeds 1e-3 m/s first at t = 0 s"),
        "{message}"
    );
    let o = rigidref(&["compare", "a.jsonl", "b.jsonl", "--json"], dir);
    let report = json_of(&o);
    let position = report["errors"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["quantity"] == "body 0 (\"block\") position")
        .unwrap();
    let first = position["first_exceeded"].as_f64().unwrap();
    assert!((first - 0.2).abs() < 0.011, "{position}");
    // Unreadable input: exit 2, naming the file.
    std::fs::write(dir.join("bad.jsonl"), "not a trace\n").unwrap();
    let o = rigidref(&["compare", "a.jsonl", "bad.jsonl"], dir);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("bad.jsonl:1:"), "{}", stderr(&o));
}

/// Records 0.07 s apart against every 0.01 s of the same run: the differences are the
/// interpolation's, bounded by Δ²/8 · max|f''| with f'' estimated from the dense trace.
#[test]
fn traces_recorded_at_different_rates_agree_within_interpolation_error() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "tumbling_brick.json", "5", "every1.jsonl", &[]);
    run(
        dir,
        "tumbling_brick.json",
        "5",
        "every7.jsonl",
        &["--every", "7"],
    );
    let trace = rigidref::rigid3d::trace::read_trace(
        std::io::BufReader::new(std::fs::File::open(dir.join("every1.jsonl")).unwrap()),
        "every1",
    )
    .unwrap();
    let omega: Vec<nalgebra::Vector3<f64>> = trace
        .records
        .iter()
        .map(|r| nalgebra::Vector3::from(r.bodies[0].omega))
        .collect();
    let d = 0.01;
    let second = omega
        .windows(3)
        .map(|w| (w[0] - 2.0 * w[1] + w[2]).norm() / (d * d))
        .fold(0.0, f64::max);
    let first = omega
        .windows(2)
        .map(|w| (w[1] - w[0]).norm() / d)
        .fold(0.0, f64::max);
    let spacing: f64 = 0.07;
    // Linear interpolation of ω errs by at most Δ²/8 · max|ω̈|; slerp of R, whose rate ω
    // changes, by about Δ²/8 · max|ω̇|. 20% margin for the estimates.
    let omega_bound = 1.2 * spacing * spacing / 8.0 * second;
    let angle_bound = 1.2 * spacing * spacing / 8.0 * first;
    let o = rigidref(
        &[
            "compare",
            "every1.jsonl",
            "every7.jsonl",
            "--json",
            "--tolerance",
            "1",
        ],
        dir,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let report = json_of(&o);
    let error = |q: &str| {
        report["errors"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["quantity"] == q)
            .unwrap()["max_error"]
            .as_f64()
            .unwrap()
    };
    let (w, a) = (
        error("body 0 (\"block\") angular velocity"),
        error("body 0 (\"block\") orientation"),
    );
    println!(
        "ω error {w:.3e} (bound {omega_bound:.3e}), angle error {a:.3e} (bound {angle_bound:.3e})"
    );
    assert!(
        w > 0.0 && w <= omega_bound,
        "ω error {w}, bound {omega_bound}"
    );
    assert!(
        a > 0.0 && a <= angle_bound,
        "angle error {a}, bound {angle_bound}"
    );
    assert!(error("body 0 (\"block\") position") < 1e-12);
}

/// Two valid runs that differ only in PGS's contact order: the stack's first contact solves
/// already differ beyond 1e-3 rad/s, so trajectory mode reports divergence, while what happened
/// (first contact, rest, rest positions and orientations, final energy) agrees.
#[test]
fn contact_order_changes_the_trajectory_but_not_the_outcome() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "box_stack.json", "5", "sequential.jsonl", &[]);
    run(
        dir,
        "box_stack.json",
        "5",
        "random.jsonl",
        &["--set", "pgs_order=random"],
    );
    let o = rigidref(&["compare", "sequential.jsonl", "random.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "trajectory mode: {}", stderr(&o));
    let s = scene("box_stack.json");
    let o = rigidref(
        &[
            "compare",
            "sequential.jsonl",
            "random.jsonl",
            "--outcome",
            "--scene",
            &s,
            "--json",
        ],
        dir,
    );
    assert_eq!(o.status.code(), Some(0), "outcome mode: {}", stderr(&o));
    let report = json_of(&o);
    let names: Vec<&str> = report["outcomes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"time of first contact"), "{names:?}");
    assert!(
        names
            .iter()
            .filter(|n| n.ends_with("rest position"))
            .count()
            == 5,
        "{names:?}"
    );
}

/// A rigidref problem file; the same with every contact's tangent basis turned by a random
/// angle about n; and with one Jacobian column's sign flipped.
#[test]
fn compare_problem_ignores_the_tangent_basis_and_names_a_flipped_column() {
    use rigidref::problem::json::ProblemFile;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(
        dir,
        "box_stack.json",
        "0.05",
        "t.jsonl",
        &["--dump-problems", "problems"],
    );
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let reference = ProblemFile::read(&files[0]).unwrap();
    // Fixed pseudo-random angles (a Weyl sequence), so that a failure reproduces.
    let mut rotated = reference.clone();
    for (k, c) in rotated.contacts.iter_mut().enumerate() {
        let angle = std::f64::consts::TAU * ((k as f64 + 1.0) * 0.618_033_988_749_895).fract();
        let (s, co) = angle.sin_cos();
        let turn = |v: &mut Vec<f64>| {
            let (a, b) = (v[1], v[2]);
            v[1] = co * a + s * b;
            v[2] = -s * a + co * b;
        };
        for side in 0..2 {
            for k in 0..6 {
                let mut column = vec![
                    c.jacobian[side][0][k],
                    c.jacobian[side][1][k],
                    c.jacobian[side][2][k],
                ];
                turn(&mut column);
                for (row, value) in c.jacobian[side].iter_mut().zip(&column) {
                    row[k] = *value;
                }
            }
        }
        turn(&mut c.b);
        turn(&mut c.lambda0);
    }
    if let Some(solution) = &mut rotated.solution {
        // λ's tangential part turns with the basis; a quarter turn here (only |λ_t| is compared).
        for l in &mut solution.lambda {
            let (a, b) = (l[1], l[2]);
            l[1] = -b;
            l[2] = a;
        }
    }
    let write = |name: &str, p: &ProblemFile| {
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string(p).unwrap()).unwrap();
        path.display().to_string()
    };
    let reference_path = files[0].display().to_string();
    let rotated_path = write("rotated.json", &rotated);
    let o = rigidref(&["compare-problem", &reference_path, &rotated_path], dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        stderr(&o)
    );
    let mut flipped = reference.clone();
    for row in &mut flipped.contacts[2].jacobian[0] {
        row[3] = -row[3];
    }
    let flipped_path = write("flipped.json", &flipped);
    let o = rigidref(&["compare-problem", &reference_path, &flipped_path], dir);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("first: contact 2: normal row, body 1 entry 3 (ω_x)"),
        "{}",
        stderr(&o)
    );
}

/// Five fabricated submissions for two scenes: exact; slightly off (a valid run with a
/// different contact order: outcome mode passes it); gravity's sign wrong; a malformed trace; a
/// scene missing. One table, every row accounted for, the batch never stopped.
#[test]
fn grade_gives_the_expected_table_for_five_fabricated_submissions() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let subs = dir.join("submissions");
    for s in [
        "exact",
        "slightly_off",
        "wrong_gravity",
        "malformed",
        "missing_scene",
    ] {
        std::fs::create_dir_all(subs.join(s)).unwrap();
    }
    let time = "3";
    for (name, file) in [
        ("sphere_drop", "sphere_drop.json"),
        ("box_stack", "box_stack.json"),
    ] {
        let out = |s: &str| format!("submissions/{s}/{name}.jsonl");
        run(dir, file, time, &out("exact"), &[]);
        run(
            dir,
            file,
            time,
            &out("slightly_off"),
            &["--set", "pgs_order=random", "--every", "3"],
        );
        run(
            dir,
            file,
            time,
            &out("wrong_gravity"),
            &["--set", "gravity=[0,9.8,0]"],
        );
        run(dir, file, time, &out("malformed"), &[]);
        if name == "sphere_drop" {
            run(dir, file, time, &out("missing_scene"), &[]);
        }
    }
    std::fs::write(
        subs.join("malformed/box_stack.jsonl"),
        "{\"format\": \"rigidref-trace\"\n",
    )
    .unwrap();
    let (a, b) = (scene("sphere_drop.json"), scene("box_stack.json"));
    let o = rigidref(
        &[
            "grade",
            "submissions",
            "--scenes",
            &a,
            &b,
            "--time",
            time,
            "--mode",
            "outcome",
            "--out",
            "report",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let md = std::fs::read_to_string(dir.join("report/grade.md")).unwrap();
    println!("{md}");
    for expected in [
        "| exact | pass | pass |",
        "| malformed | pass | unreadable |",
        "| missing_scene | pass | missing |",
        "| slightly_off | pass | pass |",
        "| wrong_gravity | fail | fail |",
    ] {
        assert!(md.contains(expected), "{expected} not in\n{md}");
    }
    let csv = std::fs::read_to_string(dir.join("report/grade.csv")).unwrap();
    assert!(csv.starts_with("submission,scene,observable,result,figure\n"));
    assert!(
        csv.lines()
            .any(|l| l.starts_with("malformed,box_stack,trace,unreadable,")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("missing_scene,box_stack,trace,missing,")),
        "{csv}"
    );
    // In trajectory mode the valid run with another contact order is reported as diverging.
    let o = rigidref(
        &[
            "grade",
            "submissions",
            "--scenes",
            &b,
            "--time",
            time,
            "--out",
            "trajectory",
            "--jobs",
            "2",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let md = std::fs::read_to_string(dir.join("trajectory/grade.md")).unwrap();
    assert!(
        md.contains("| exact | pass |") && md.contains("| slightly_off | fail |"),
        "{md}"
    );
}
