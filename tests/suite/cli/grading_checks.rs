//! What `compare` and `grade` check of a trace before and beyond comparing it (issue 47, found
//! 5): positions that do not follow velocities, a missing last frame, the speeds at rest, header
//! values that make no sense, files that say what is wrong with them, and bodies listed in
//! another order under other names (docs/grading.md §"Refused traces", §"Positions follow
//! velocities").

use crate::common;

use common::rigidref;
use serde_json::Value;
use std::path::Path;

fn scene(name: &str) -> String {
    common::project_root()
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

/// `rigidref run SCENE --time T -q --out OUT` in `dir`.
fn run(dir: &Path, scene: &str, time: &str, out: &str) {
    common::assert_success(&rigidref(
        &["run", scene, "--time", time, "-q", "--out", out],
        dir,
    ));
}

/// The trace `from` in `dir` as JSON values: the header, then the records.
fn lines(dir: &Path, from: &str) -> Vec<Value> {
    std::fs::read_to_string(dir.join(from))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// Writes `lines` (header first) as the trace `name` in `dir`.
fn write(dir: &Path, name: &str, lines: &[Value]) {
    let text: Vec<String> = lines.iter().map(Value::to_string).collect();
    std::fs::write(dir.join(name), text.join("\n") + "\n").unwrap();
}

/// `rigidref compare REF OTHER [--outcome] --json` in `dir`: (exit status, report, stderr).
fn compare_json(dir: &Path, reference: &str, other: &str, outcome: bool) -> (i32, Value, String) {
    let mut args = vec!["compare", reference, other, "--json"];
    if outcome {
        args.push("--outcome");
    }
    let o = rigidref(&args, dir);
    let report = serde_json::from_slice(&o.stdout).unwrap_or(Value::Null);
    (o.status.code().unwrap(), report, common::stderr(&o))
}

/// The report's check that positions follow velocities.
fn motion_check(report: &Value) -> &Value {
    report["checks"]
        .as_array()
        .and_then(|c| {
            c.iter()
                .find(|c| c["name"] == "positions follow velocities (every record)")
        })
        .unwrap_or_else(|| panic!("no motion check in {report}"))
}

/// A ball dropped on the ground (at rest from about 1 s of 3 s), and copies that fake it: the
/// ball teleported 50 m sideways for 0.5 s with its velocity 0 and back, one record at
/// x = 1e308. Outcome mode judges the end, which both fakes leave alone; the check that
/// positions follow velocities judges every record and fails both, in both modes, naming the
/// body and when. The same in 2D: a block of the stack moved 20 blocks for 1 time unit and back.
/// The reference itself passes.
#[test]
fn a_body_teleported_at_rest_or_sent_to_1e308_at_one_record_fails_in_both_modes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, &scene("sphere_drop.json"), "3", "ref.jsonl");
    let records = lines(dir, "ref.jsonl");
    let edited = |edit: &dyn Fn(&mut Value)| -> Vec<Value> {
        let mut out = records.clone();
        for r in out.iter_mut().skip(1) {
            edit(r);
        }
        out
    };
    write(
        dir,
        "teleport.jsonl",
        &edited(&|r| {
            let t = r["t"].as_f64().unwrap();
            if (1.5..2.0).contains(&t) {
                let x = r["bodies"][0]["x"][0].as_f64().unwrap();
                r["bodies"][0]["x"][0] = (x + 50.0).into();
                r["bodies"][0]["v"] = serde_json::json!([0.0, 0.0, 0.0]);
            }
        }),
    );
    write(
        dir,
        "huge.jsonl",
        &edited(&|r| {
            if r["step"] == 150 {
                r["bodies"][0]["x"][0] = 1e308.into();
            }
        }),
    );
    for outcome in [false, true] {
        let (status, report, _) = compare_json(dir, "ref.jsonl", "ref.jsonl", outcome);
        assert_eq!(status, 0, "the reference against itself");
        let check = motion_check(&report);
        assert_eq!(check["passed"], true, "{check}");
        // rigidref's 3D step moves bodies by their velocities: round-off only.
        assert!(check["difference"].as_f64().unwrap() < 1e-6, "{check}");
        for (file, when) in [
            (
                "teleport.jsonl",
                &["between t = 1.49 and 1.5", "between t = 1.99 and 2 "][..],
            ),
            (
                "huge.jsonl",
                &["between t = 1.49 and 1.5", "between t = 1.5 and 1.51"][..],
            ),
        ] {
            let (status, report, stderr) = compare_json(dir, "ref.jsonl", file, outcome);
            assert_eq!(status, 1, "{file} outcome={outcome}: {stderr}");
            let check = motion_check(&report);
            assert_eq!(check["passed"], false, "{file}: {check}");
            let other = check["other"].as_str().unwrap();
            // The jump there or the one back, whichever is the larger beyond its velocities.
            assert!(
                other.starts_with("body 0 (\"ball\") moves")
                    && when.iter().any(|w| other.contains(w)),
                "{file}: {other}"
            );
            if outcome {
                // Nothing else gives the fake away: the end is the reference's.
                assert!(
                    report["outcomes"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .all(|o| o["passed"] == true),
                    "{file}: {report}"
                );
                assert!(
                    stderr.contains("positions follow velocities (every record)"),
                    "{stderr}"
                );
            }
        }
    }
    // 2D: a block of the stack sent 20 blocks up for one time unit, its velocity unchanged.
    let stack = common::project_root().join("scenes/blocks/stack.json");
    run(dir, stack.to_str().unwrap(), "6", "ref2.jsonl");
    let mut records = lines(dir, "ref2.jsonl");
    for r in records.iter_mut().skip(1) {
        let t = r["t"].as_f64().unwrap();
        if (4.0..5.0).contains(&t) {
            let y = r["bodies"][1]["x"][1].as_f64().unwrap();
            r["bodies"][1]["x"][1] = (y - 20.0).into();
        }
    }
    write(dir, "teleport2.jsonl", &records);
    for outcome in [false, true] {
        let (status, report, _) = compare_json(dir, "ref2.jsonl", "ref2.jsonl", outcome);
        assert_eq!(status, 0);
        assert_eq!(motion_check(&report)["passed"], true);
        let (status, report, stderr) = compare_json(dir, "ref2.jsonl", "teleport2.jsonl", outcome);
        assert_eq!(status, 1, "{stderr}");
        let check = motion_check(&report);
        assert!(
            check["passed"] == false
                && check["other"]
                    .as_str()
                    .unwrap()
                    .starts_with("body 1 (\"body1\") moves 2.0000e1 block"),
            "{check}"
        );
    }
}

/// rigidref's own runs pass the check with room to spare: the largest unexplained displacement
/// of a step, as a fraction of the allowance (4 reference steps at the top speed), on the 2D
/// scenes of scenes/blocks with their settings (post-stabilisation on) and on 3D scenes with
/// contacts. docs/grading.md §"Positions follow velocities" gives the figures of more scenes.
#[test]
fn rigidrefs_own_runs_follow_their_velocities_well_within_the_allowance() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let root = common::project_root();
    for (path, time, bound) in [
        ("scenes/blocks/dominoes.json", "25", 0.05),
        ("scenes/blocks/stack.json", "20", 0.05),
        ("scenes/blocks/pyramid.json", "10", 0.05),
        ("scenes/box_stack.json", "3", 1e-4),
        ("scenes/edge_landing.json", "3", 1e-4),
    ] {
        let p = root.join(path);
        run(dir, p.to_str().unwrap(), time, "t.jsonl");
        let (status, report, stderr) = compare_json(dir, "t.jsonl", "t.jsonl", true);
        assert_eq!(status, 0, "{path}: {stderr}");
        let ratio = motion_check(&report)["difference"].as_f64().unwrap();
        println!("{path}: largest unexplained displacement {ratio:.3e} of the allowance");
        assert!(ratio <= bound, "{path}: {ratio}");
    }
}

/// A writer that records every K steps with `step % K == 0` misses the reference's last frame
/// when K does not divide the step count: with K = 7 (gaps of 7 steps, accepted anywhere) the
/// missing end is within the same allowance and the trace agrees, in both modes; with K = 11 the
/// gaps themselves are too far apart, and a trace cut 11 steps before the end is incomplete.
#[test]
fn a_writer_that_skips_the_last_frame_is_judged_by_the_gap_allowance() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, &scene("projectile.json"), "2", "ref.jsonl");
    let records = lines(dir, "ref.jsonl");
    let every = |k: u64| -> Vec<Value> {
        let mut out = vec![records[0].clone()];
        out.extend(
            records[1..]
                .iter()
                .filter(|r| r["step"].as_u64().unwrap() % k == 0)
                .cloned(),
        );
        out
    };
    let seven = every(7);
    assert_ne!(
        seven.last().unwrap()["step"],
        200,
        "the last frame is skipped"
    );
    write(dir, "every7.jsonl", &seven);
    write(dir, "every11.jsonl", &every(11));
    let mut cut = records.clone();
    cut.truncate(records.len() - 11);
    write(dir, "cut.jsonl", &cut);
    for outcome in [false, true] {
        let (status, report, stderr) = compare_json(dir, "ref.jsonl", "every7.jsonl", outcome);
        assert_eq!(status, 0, "every 7, outcome={outcome}: {stderr}");
        assert_eq!(report["agree"], true);
        let (_, report, _) = compare_json(dir, "ref.jsonl", "every11.jsonl", outcome);
        assert_eq!(report["refused"]["kind"], "too sparse", "{report}");
        let (_, report, _) = compare_json(dir, "ref.jsonl", "cut.jsonl", outcome);
        assert_eq!(report["refused"]["kind"], "incomplete", "{report}");
        assert!(
            report["refused"]["message"]
                .as_str()
                .unwrap()
                .starts_with("ends at 1.89 s of 2 s"),
            "{report}"
        );
    }
}

/// Outcome mode's rest is a margin, not a cut (docs/grading.md §"2D outcome mode"): a body at
/// rest in the reference that ends at 0.062 block/t in the other trace is settling, which
/// agrees with at rest (the real case: 0.044 against 0.062), and its rest position and
/// angle are still compared; at 0.3 block/t it is moving, which does not. The rows show the
/// speeds judged. The same in 3D with |v| = 0.07 m/s (settling) and 0.5 m/s (moving).
#[test]
fn outcome_mode_reports_the_speeds_it_judged_and_accepts_a_settling_body() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let stack = common::project_root().join("scenes/blocks/stack.json");
    run(dir, stack.to_str().unwrap(), "12", "ref.jsonl");
    let records = lines(dir, "ref.jsonl");
    let body = records[0]["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .position(|b| b["pinned"] == false)
        .unwrap();
    let ends_at = |speed: f64| -> Vec<Value> {
        // The last 0.5 time units at `speed` along x, the position moving with it.
        let mut out = records.clone();
        let n = out.len();
        let start = out[n - 11]["t"].as_f64().unwrap();
        for r in out[n - 10..].iter_mut() {
            let t = r["t"].as_f64().unwrap();
            let x = r["bodies"][body]["x"][0].as_f64().unwrap();
            r["bodies"][body]["x"][0] = (x + speed * (t - start)).into();
            r["bodies"][body]["v"] = serde_json::json!([speed, 0.0]);
            r["bodies"][body]["omega"] = 0.0.into();
        }
        out
    };
    write(dir, "settling.jsonl", &ends_at(0.062));
    write(dir, "moving.jsonl", &ends_at(0.3));
    let row = |report: &Value, suffix: &str| -> Value {
        report["outcomes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| {
                let name = o["name"].as_str().unwrap();
                name.starts_with(&format!("body {body} ")) && name.ends_with(suffix)
            })
            .cloned()
            .unwrap_or_else(|| panic!("no row {suffix} in {report}"))
    };
    let (status, report, stderr) = compare_json(dir, "ref.jsonl", "settling.jsonl", true);
    assert_eq!(status, 0, "{stderr}");
    let rest = row(&report, "at rest at the end");
    assert!(
        rest["reference"]
            .as_str()
            .unwrap()
            .contains("at rest from t = ")
            && rest["reference"].as_str().unwrap().contains("block/t)")
            && rest["other"] == "settling (speed 6.200e-2 block/t)",
        "{rest}"
    );
    assert!(row(&report, "rest position")["passed"] == true);
    let (status, report, _) = compare_json(dir, "ref.jsonl", "moving.jsonl", true);
    assert_eq!(status, 1);
    let rest = row(&report, "at rest at the end");
    assert!(
        rest["passed"] == false && rest["other"] == "moving (speed 3.000e-1 block/t)",
        "{rest}"
    );
    // 3D: the ball at rest on the ground, then at 0.07 and at 0.5 m/s for the last 0.1 s.
    run(dir, &scene("sphere_drop.json"), "3", "ball.jsonl");
    let records = lines(dir, "ball.jsonl");
    let ends_at = |speed: f64| -> Vec<Value> {
        let mut out = records.clone();
        let n = out.len();
        let start = out[n - 11]["t"].as_f64().unwrap();
        for r in out[n - 10..].iter_mut() {
            let t = r["t"].as_f64().unwrap();
            let x = r["bodies"][0]["x"][0].as_f64().unwrap();
            r["bodies"][0]["x"][0] = (x + speed * (t - start)).into();
            r["bodies"][0]["v"] = serde_json::json!([speed, 0.0, 0.0]);
        }
        out
    };
    write(dir, "ball_settling.jsonl", &ends_at(0.07));
    write(dir, "ball_moving.jsonl", &ends_at(0.5));
    let (status, report, stderr) = compare_json(dir, "ball.jsonl", "ball_settling.jsonl", true);
    let rest = report["outcomes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["name"] == "body 0 (\"ball\") comes to rest at")
        .cloned()
        .unwrap();
    assert_eq!(status, 0, "{stderr}");
    assert!(
        rest["other"]
            .as_str()
            .unwrap()
            .starts_with("never: settling (|v| 7.000e-2 m/s, |ω|"),
        "{rest}"
    );
    let (status, _, stderr) = compare_json(dir, "ball.jsonl", "ball_moving.jsonl", true);
    assert_eq!(status, 1);
    assert!(stderr.contains("comes to rest at"), "{stderr}");
}

/// A header whose values make no sense is refused with its own verdict (`bad header`, exit 1),
/// naming the value: a step dt of 0 or −0.01, a body's mass of 0 or −1 (3D and 2D; a pinned 2D
/// body's mass is not judged). A problem file whose body has a negative inverse inertia (an
/// inertia ≤ 0) is an error saying so (the problem reader's rule, which `compare-problem` keeps).
#[test]
fn headers_and_problems_whose_values_make_no_sense_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, &scene("projectile.json"), "1", "ref.jsonl");
    let stack = common::project_root().join("scenes/blocks/stack.json");
    run(dir, stack.to_str().unwrap(), "1", "ref2.jsonl");
    let records = lines(dir, "ref.jsonl");
    let records2 = lines(dir, "ref2.jsonl");
    let free2 = records2[0]["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .position(|b| b["pinned"] == false)
        .unwrap();
    let pinned2 = records2[0]["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .position(|b| b["pinned"] == true)
        .unwrap();
    let cases: Vec<(&str, &str, Value, String)> = vec![
        (
            "ref.jsonl",
            "dt0",
            serde_json::json!({"dt": 0.0}),
            "the header's dt is 0 s: a step must be a positive number".into(),
        ),
        (
            "ref.jsonl",
            "dtneg",
            serde_json::json!({"dt": -0.01}),
            "the header's dt is -0.01 s".into(),
        ),
        (
            "ref.jsonl",
            "mass0",
            serde_json::json!({"mass": 0.0}),
            "body 0's mass in the header is 0: a mass must be positive".into(),
        ),
        (
            "ref.jsonl",
            "massneg",
            serde_json::json!({"mass": -1.0}),
            "body 0's mass in the header is -1".into(),
        ),
        (
            "ref2.jsonl",
            "dt0_2d",
            serde_json::json!({"dt": 0.0}),
            "the header's dt is 0: a step must be a positive number".into(),
        ),
        (
            "ref2.jsonl",
            "mass0_2d",
            serde_json::json!({"mass": 0.0}),
            format!("body {free2}'s mass in the header is 0"),
        ),
    ];
    for (reference, name, edit, message) in &cases {
        let source = if *reference == "ref.jsonl" {
            &records
        } else {
            &records2
        };
        let mut out = source.clone();
        if let Some(dt) = edit.get("dt") {
            out[0]["dt"] = dt.clone();
        } else {
            let i = if *reference == "ref.jsonl" { 0 } else { free2 };
            out[0]["bodies"][i]["mass"] = edit["mass"].clone();
        }
        let file = format!("{name}.jsonl");
        write(dir, &file, &out);
        for outcome in [false, true] {
            let (status, report, stderr) = compare_json(dir, reference, &file, outcome);
            assert_eq!(status, 1, "{name}: {stderr}");
            assert_eq!(report["refused"]["kind"], "bad header", "{name}: {report}");
            assert!(
                report["refused"]["message"]
                    .as_str()
                    .unwrap()
                    .contains(message.as_str()),
                "{name}: {report}"
            );
        }
    }
    // A pinned body reports its blocks' mass; 0 there is not judged.
    let mut out = records2.clone();
    out[0]["bodies"][pinned2]["mass"] = 0.0.into();
    write(dir, "pinned0.jsonl", &out);
    let (_, report, _) = compare_json(dir, "ref2.jsonl", "pinned0.jsonl", false);
    assert_ne!(report["refused"]["kind"], "bad header", "{report}");
    // A problem whose body has a negative inverse inertia.
    let o = rigidref(
        &[
            "run",
            stack.to_str().unwrap(),
            "--time",
            "2",
            "-q",
            "--out",
            "t.jsonl",
            "--dump-problems",
            "problems",
        ],
        dir,
    );
    common::assert_success(&o);
    let mut files: Vec<_> = std::fs::read_dir(dir.join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let path = files.last().unwrap();
    let mut problem: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    problem["bodies"][free2]["inverse_mass"][2][2] = (-0.5).into();
    std::fs::write(dir.join("negative.json"), problem.to_string()).unwrap();
    let o = rigidref(
        &["compare-problem", path.to_str().unwrap(), "negative.json"],
        dir,
    );
    assert_eq!(o.status.code(), Some(2), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains(&format!(
            "the other problem: body {free2}: the inverse mass is not positive semi-definite"
        )),
        "{}",
        common::stderr(&o)
    );
}

/// A file that is not a trace says what is wrong with it, never a bare parser message
/// ("expected value at line 1 column 1"): a UTF-8 byte-order mark; a second header in the file;
/// a 2D trace where the reference is 3D and the reverse (also in `grade`: "a 2D trace where a
/// 3D one is compared: the scene is 3D"); a header nested 127 deep (which used to be read with a
/// false note that its descriptive keys were missing). Exit status 2 from `compare`.
#[test]
fn unreadable_traces_say_what_is_wrong_with_them() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, &scene("projectile.json"), "0.5", "ref.jsonl");
    let stack = common::project_root().join("scenes/blocks/stack.json");
    run(dir, stack.to_str().unwrap(), "0.5", "ref2.jsonl");
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(dir.join("bom.jsonl"), format!("\u{feff}{text}")).unwrap();
    let mut twice = lines.clone();
    twice.insert(5, lines[0]);
    std::fs::write(dir.join("twice.jsonl"), twice.join("\n") + "\n").unwrap();
    let deep = |depth: usize| {
        let header = lines[0].trim_end_matches('}').to_string()
            + ",\"x\":"
            + &"[".repeat(depth)
            + &"]".repeat(depth)
            + "}";
        let mut out = lines.clone();
        out[0] = &header;
        out.join("\n") + "\n"
    };
    std::fs::write(dir.join("deep126.jsonl"), deep(126)).unwrap();
    std::fs::write(dir.join("deep127.jsonl"), deep(127)).unwrap();
    for (reference, file, wanted) in [
        (
            "ref.jsonl",
            "bom.jsonl",
            "bom.jsonl:1: the file starts with a UTF-8 byte-order mark (BOM)",
        ),
        (
            "ref.jsonl",
            "twice.jsonl",
            "twice.jsonl:6: a second header line (a trace has one, its first line)",
        ),
        (
            "ref.jsonl",
            "ref2.jsonl",
            "ref2.jsonl: a 2D trace where a 3D one is compared (its header says \"dimension\": 2): the reference is 3D",
        ),
        (
            "ref2.jsonl",
            "ref.jsonl",
            "ref.jsonl: a 3D trace where a 2D one is compared (its header says \"dimension\": 3): the reference is 2D",
        ),
        (
            "ref.jsonl",
            "deep127.jsonl",
            "deep127.jsonl:1: not a rigidref trace: its first line is not a JSON header: its arrays and objects are nested more than 127 deep",
        ),
    ] {
        let o = rigidref(&["compare", reference, file], dir);
        let stderr = common::stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{file}: {stderr}");
        assert!(stderr.contains(wanted), "{file}: {stderr}");
        assert!(!stderr.contains("expected value"), "{stderr}");
        assert!(!stderr.contains("note:"), "{stderr}");
    }
    // 126 levels are read, without a note.
    let o = rigidref(&["compare", "ref.jsonl", "deep126.jsonl"], dir);
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
    assert!(
        !common::stderr(&o).contains("note:"),
        "{}",
        common::stderr(&o)
    );
    // grade says which system the scene wants.
    for (name, file) in [("a", "ref2.jsonl"), ("b", "bom.jsonl")] {
        std::fs::create_dir_all(dir.join("subs").join(name)).unwrap();
        std::fs::copy(
            dir.join(file),
            dir.join("subs").join(name).join("projectile.jsonl"),
        )
        .unwrap();
    }
    let o = rigidref(
        &[
            "grade",
            "subs",
            "--scenes",
            &scene("projectile.json"),
            "--time",
            "0.5",
            "--out",
            "out",
        ],
        dir,
    );
    common::assert_success(&o);
    let csv = std::fs::read_to_string(dir.join("out/grade.csv")).unwrap();
    assert!(
        csv.contains("a,projectile,trace,unreadable,") && csv.contains("a 2D trace where a 3D one is compared (its header says \"\"dimension\"\": 2): the scene is 3D"),
        "{csv}"
    );
    assert!(csv.contains("byte-order mark"), "{csv}");
}

/// Bodies listed in another order under other names are matched by body (3D: mass and first
/// position) and agree; another scene's body is refused (exit 1, `wrong bodies`, the reason
/// named), not unreadable; in `grade` it is `refused`. 2D: another image's trace is refused the
/// same way.
#[test]
fn reordered_and_renamed_bodies_are_matched_or_refused_with_a_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, &scene("cube_stack.json"), "2", "ref.jsonl");
    let mut records = lines(dir, "ref.jsonl");
    for (k, r) in records.iter_mut().enumerate() {
        let list = r["bodies"].as_array_mut().unwrap();
        list.reverse();
        if k == 0 {
            for (i, b) in list.iter_mut().enumerate() {
                b["name"] = format!("cube #{i}").into();
            }
        }
        // Contacts name bodies by index: renumbered with the reversal.
        if let Some(contacts) = r.get_mut("contacts").and_then(Value::as_array_mut) {
            for c in contacts {
                for b in c["bodies"].as_array_mut().unwrap() {
                    let i = b.as_i64().unwrap();
                    if i >= 0 {
                        *b = (3 - i).into();
                    }
                }
            }
        }
    }
    write(dir, "renamed.jsonl", &records);
    for outcome in [false, true] {
        let (status, report, stderr) = compare_json(dir, "ref.jsonl", "renamed.jsonl", outcome);
        assert_eq!(status, 0, "{stderr}");
        assert_eq!(report["matched_by"], "body");
        assert_eq!(report["matching"], serde_json::json!([3, 2, 1, 0]));
    }
    run(dir, &scene("tumbling_brick.json"), "2", "brick.jsonl");
    run(dir, &scene("sphere_drop.json"), "2", "ball.jsonl");
    let (status, report, stderr) = compare_json(dir, "brick.jsonl", "ball.jsonl", false);
    assert_eq!(status, 1, "{stderr}");
    assert_eq!(report["refused"]["kind"], "wrong bodies");
    assert!(
        report["refused"]["message"]
            .as_str()
            .unwrap()
            .contains("has no body of the trace with its mass"),
        "{report}"
    );
    // 2D: the stack's reference against the dominoes'.
    for (scene_file, out) in [
        ("stack.json", "stack.jsonl"),
        ("dominoes.json", "dominoes.jsonl"),
    ] {
        let p = common::project_root()
            .join("scenes/blocks")
            .join(scene_file);
        run(dir, p.to_str().unwrap(), "1", out);
    }
    let (status, report, stderr) = compare_json(dir, "stack.jsonl", "dominoes.jsonl", true);
    assert_eq!(status, 1, "{stderr}");
    assert_eq!(report["refused"]["kind"], "wrong bodies", "{report}");
    // grade: refused, not unreadable.
    std::fs::create_dir_all(dir.join("subs/other_scene")).unwrap();
    std::fs::copy(
        dir.join("ball.jsonl"),
        dir.join("subs/other_scene/tumbling_brick.jsonl"),
    )
    .unwrap();
    let o = rigidref(
        &[
            "grade",
            "subs",
            "--scenes",
            &scene("tumbling_brick.json"),
            "--time",
            "2",
            "--out",
            "out",
        ],
        dir,
    );
    common::assert_success(&o);
    let csv = std::fs::read_to_string(dir.join("out/grade.csv")).unwrap();
    assert!(
        csv.contains("other_scene,tumbling_brick,trace,refused,\"wrong bodies: "),
        "{csv}"
    );
}
