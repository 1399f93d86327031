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
    common::assert_success(&o);
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
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
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
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = rigidref(&["compare", "a.jsonl", "b.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    let message = common::stderr(&o);
    assert!(
        message.contains("body 0 (\"block\") velocity exceeds 1.000e-3 m/s first at t = 0 s"),
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
    assert_eq!(o.status.code(), Some(2), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains("bad.jsonl:1:"),
        "{}",
        common::stderr(&o)
    );
}

/// Records 0.07 s apart against every 0.01 s of the same run, either way round: compared at
/// the sparser trace's record times, where both hold the same states, they agree exactly
/// (with the default tolerances; interpolating the sparse trace instead would err by up to
/// 1e-2 rad/s on this tumbling body).
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
    for (a, b) in [
        ("every1.jsonl", "every7.jsonl"),
        ("every7.jsonl", "every1.jsonl"),
    ] {
        let o = rigidref(&["compare", a, b, "--json"], dir);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{a} against {b}: {}",
            common::stderr(&o)
        );
        let report = json_of(&o);
        for e in report["errors"].as_array().unwrap() {
            assert!(
                e["max_error"].as_f64().unwrap() <= 1e-12,
                "{a} against {b}: {e}"
            );
        }
    }
    // A reference that ends earlier than the other trace is compared over its own span; the
    // other way round, the short trace is refused (`a_trace_that_cannot_be_judged_is_refused_…`).
    run(dir, "tumbling_brick.json", "2", "short.jsonl", &[]);
    let o = rigidref(&["compare", "short.jsonl", "every1.jsonl", "--json"], dir);
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
    assert_eq!(json_of(&o)["span"][1], 2.0);
}

/// Writes `name` in `dir`: the header of `from` and the records `records` makes of its records.
fn derived(dir: &Path, from: &str, name: &str, records: impl FnOnce(Vec<String>) -> Vec<String>) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let header = lines.remove(0);
    let mut out = vec![header];
    out.extend(records(lines));
    std::fs::write(dir.join(name), out.join("\n") + "\n").unwrap();
}

/// A candidate that cannot be judged fairly is refused before any comparison, with its own
/// verdict and one line saying what is wrong, in both modes and in `grade` (docs/grading.md
/// §"Refused traces"): the projectile's 2 s reference (201 records) against its first 51 records,
/// 200 copies of one record, two records swapped, its first and last record only, and a trace of
/// two bodies; a NaN (which JSON cannot hold) is an unreadable line naming the reason.
#[test]
fn a_trace_that_cannot_be_judged_is_refused_in_both_modes_and_in_grade() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "projectile.json", "2", "ref.jsonl", &[]);
    derived(dir, "ref.jsonl", "short.jsonl", |r| r[..51].to_vec());
    derived(dir, "ref.jsonl", "repeated.jsonl", |r| {
        vec![r[1].clone(); 200]
    });
    derived(dir, "ref.jsonl", "swapped.jsonl", |mut r| {
        r.swap(5, 6);
        r
    });
    derived(dir, "ref.jsonl", "sparse.jsonl", |r| {
        vec![r[0].clone(), r[r.len() - 1].clone()]
    });
    derived(dir, "ref.jsonl", "nan.jsonl", |mut r| {
        // As Python's json module writes a NaN.
        r[10] = r[10].replacen("\"x\":[", "\"x\":[NaN,", 1);
        r
    });
    // Two bodies: the projectile twice, in the header and in every record.
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let doubled: Vec<String> = text
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            let b = v["bodies"].as_array().unwrap().clone();
            v["bodies"] = serde_json::Value::Array([b.clone(), b].concat());
            v.to_string()
        })
        .collect();
    std::fs::write(dir.join("bodies.jsonl"), doubled.join("\n")).unwrap();
    let cases = [
        ("short.jsonl", "incomplete", "ends at 0.5 s of 2 s"),
        (
            "repeated.jsonl",
            "repeated times",
            "time 0.01 s repeated 200 times",
        ),
        (
            "swapped.jsonl",
            "times out of order",
            "the time goes back from 0.06 s to 0.05 s",
        ),
        ("sparse.jsonl", "too sparse", "records 2 s apart"),
        (
            "bodies.jsonl",
            "wrong bodies",
            "the trace has 2 bodies, the reference 1",
        ),
    ];
    for (file, kind, message) in cases {
        for mode in [&[][..], &["--outcome"][..]] {
            let o = rigidref(&[&["compare", "ref.jsonl", file][..], mode].concat(), dir);
            let err = common::stderr(&o);
            assert_eq!(o.status.code(), Some(1), "{file} {mode:?}: {err}");
            let line = err.lines().find(|l| l.starts_with("error:")).unwrap();
            assert!(
                line.contains(&format!("refused ({kind}): {message}")),
                "{file} {mode:?}: {err}"
            );
            let o = rigidref(
                &[&["compare", "ref.jsonl", file, "--json"][..], mode].concat(),
                dir,
            );
            let report = json_of(&o);
            assert_eq!(report["refused"]["kind"], kind);
            assert_eq!(report["agree"], false);
        }
    }
    for mode in [&[][..], &["--outcome"][..]] {
        let o = rigidref(
            &[&["compare", "ref.jsonl", "nan.jsonl"][..], mode].concat(),
            dir,
        );
        assert_eq!(o.status.code(), Some(2));
        assert!(
            common::stderr(&o).contains("nan.jsonl:12: a number is NaN or Infinity (not finite)"),
            "{}",
            common::stderr(&o)
        );
    }
    // grade: one submission per defect, each refused (nan unreadable) and the good one passing.
    let subs = dir.join("subs");
    for (name, file) in [
        ("good", "ref.jsonl"),
        ("short", "short.jsonl"),
        ("repeated", "repeated.jsonl"),
        ("swapped", "swapped.jsonl"),
        ("sparse", "sparse.jsonl"),
        ("bodies", "bodies.jsonl"),
        ("nan", "nan.jsonl"),
    ] {
        std::fs::create_dir_all(subs.join(name)).unwrap();
        std::fs::copy(dir.join(file), subs.join(name).join("projectile.jsonl")).unwrap();
    }
    for mode in ["trajectory", "outcome"] {
        let o = rigidref(
            &[
                "grade",
                "subs",
                "--scenes",
                &scene("projectile.json"),
                "--time",
                "2",
                "--mode",
                mode,
                "--out",
                mode,
            ],
            dir,
        );
        let csv = std::fs::read_to_string(dir.join(mode).join("grade.csv"))
            .unwrap_or_else(|_| common::stderr(&o));
        let result = |sub: &str| -> String {
            csv.lines()
                .filter(|l| l.starts_with(&format!("{sub},")))
                .map(|l| l.split(',').nth(3).unwrap().to_string())
                .find(|r| r != "pass")
                .unwrap_or_else(|| "pass".into())
        };
        assert_eq!(result("good"), "pass", "{csv}");
        for (sub, kind, _) in cases
            .iter()
            .map(|(f, k, m)| (f.trim_end_matches(".jsonl"), k, m))
        {
            assert_eq!(result(sub), "refused", "{sub}: {csv}");
            assert!(
                csv.lines().any(
                    |l| l.starts_with(&format!("{sub},projectile,trace,refused,"))
                        && l.contains(&format!("{kind}: "))
                ),
                "{sub}: {csv}"
            );
        }
        assert_eq!(result("nan"), "unreadable", "{csv}");
    }
}

/// `grade` treats a submission as untrusted (docs/grading.md §"Untrusted submissions"): a
/// symbolic link leaving the submission folder, a FIFO and a file above --max-file-mb are refused
/// without being opened (a FIFO opened for reading would block the grader), a link inside the
/// folder is followed, a header without its descriptive keys is a note, and the other
/// submissions are still graded.
#[test]
fn grade_refuses_links_out_fifos_and_large_files_unopened_and_grades_the_rest() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "projectile.json", "2", "ref.jsonl", &[]);
    let subs = dir.join("subs");
    for name in ["good", "link_out", "link_in", "fifo", "big", "bare_header"] {
        std::fs::create_dir_all(subs.join(name)).unwrap();
    }
    let file = |sub: &str| subs.join(sub).join("projectile.jsonl");
    std::fs::copy(dir.join("ref.jsonl"), file("good")).unwrap();
    std::os::unix::fs::symlink(dir.join("ref.jsonl"), file("link_out")).unwrap();
    std::fs::copy(
        dir.join("ref.jsonl"),
        subs.join("link_in").join("actual.jsonl"),
    )
    .unwrap();
    std::os::unix::fs::symlink("actual.jsonl", file("link_in")).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(file("fifo"))
        .status()
        .unwrap();
    assert!(made.success());
    std::fs::copy(dir.join("ref.jsonl"), file("big")).unwrap();
    std::fs::OpenOptions::new()
        .write(true)
        .open(file("big"))
        .unwrap()
        .set_len(3 << 20)
        .unwrap();
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut header: serde_json::Value = serde_json::from_str(&lines[0]).unwrap();
    for key in ["scene", "source", "integrator", "substeps"] {
        header.as_object_mut().unwrap().remove(key);
    }
    lines[0] = header.to_string();
    std::fs::write(file("bare_header"), lines.join("\n")).unwrap();
    let o = rigidref(
        &[
            "grade",
            "subs",
            "--scenes",
            &scene("projectile.json"),
            "--time",
            "2",
            "--max-file-mb",
            "1",
            "--out",
            "out",
        ],
        dir,
    );
    let csv =
        std::fs::read_to_string(dir.join("out/grade.csv")).unwrap_or_else(|_| common::stderr(&o));
    let rows = |sub: &str| -> Vec<String> {
        csv.lines()
            .filter(|l| l.starts_with(&format!("{sub},")))
            .map(String::from)
            .collect()
    };
    let only = |sub: &str, wanted: &str| {
        let r = rows(sub);
        assert_eq!(r.len(), 1, "{sub}: {csv}");
        assert!(
            r[0].contains(",trace,refused,") && r[0].contains(wanted),
            "{sub}: {}",
            r[0]
        );
    };
    only("link_out", "a symbolic link leaving the submission folder");
    only("fifo", "not a regular file");
    only(
        "big",
        "3.0 MB is more than the limit of 1 MB (raise it with --max-file-mb)",
    );
    for sub in ["good", "link_in"] {
        assert!(
            rows(sub).iter().all(|r| r.contains(",pass,")),
            "{sub}: {csv}"
        );
    }
    let bare = rows("bare_header");
    assert!(
        bare.iter().any(|r| r.contains(",trace header,note,")
            && r.contains("no scene, source, integrator, substeps")),
        "{bare:?}"
    );
    assert!(
        bare.iter()
            .filter(|r| !r.contains(",note,"))
            .all(|r| r.contains(",pass,")),
        "{bare:?}"
    );
}

/// Two valid runs that differ only in PGS's contact order: the equal-box stack's first contact
/// solves differ by 1.7e-3 rad/s (beyond the 1e-3 tolerance), so trajectory mode reports
/// divergence, while what happened (first contacts, rest, rest positions and orientations up to
/// the cubes' symmetries, final energy) agrees.
#[test]
fn contact_order_changes_the_trajectory_but_not_the_outcome() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "cube_stack.json", "5", "sequential.jsonl", &[]);
    run(
        dir,
        "cube_stack.json",
        "5",
        "random.jsonl",
        &["--set", "pgs_order=random"],
    );
    let o = rigidref(&["compare", "sequential.jsonl", "random.jsonl"], dir);
    assert_eq!(
        o.status.code(),
        Some(1),
        "trajectory mode: {}",
        common::stderr(&o)
    );
    let s = scene("cube_stack.json");
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
    assert_eq!(
        o.status.code(),
        Some(0),
        "outcome mode: {}",
        common::stderr(&o)
    );
    let report = json_of(&o);
    let names: Vec<&str> = report["outcomes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["name"].as_str().unwrap())
        .collect();
    let count = |suffix: &str| names.iter().filter(|n| n.ends_with(suffix)).count();
    assert_eq!(count("rest position"), 4, "{names:?}");
    assert_eq!(count("rest orientation (after symmetries)"), 4, "{names:?}");
    assert!(
        names.contains(
            &"first contact of body 1 (\"box (level 2)\") with body 0 (\"box (level 1)\")"
        ),
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
        common::stderr(&o)
    );
    let mut flipped = reference.clone();
    for row in &mut flipped.contacts[2].jacobian[0] {
        row[3] = -row[3];
    }
    let flipped_path = write("flipped.json", &flipped);
    let o = rigidref(&["compare-problem", &reference_path, &flipped_path], dir);
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains("first: contact 2: normal row, body 1 entry 3 (ω_x)"),
        "{}",
        common::stderr(&o)
    );
}

#[test]
fn compare_problem_reads_2d_problems_up_to_order_and_the_tangents_sign() {
    // A 2D stack's dumped problem against a copy with its contacts in reverse order and every
    // contact's tangent flipped (t → −t: the tangent row, b_t and λ_t change sign): the same
    // problem. A copy with one Jacobian entry changed (a lever arm) is flagged, naming it.
    use rigidref::problem::json::ProblemFile;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = common::project_root().join("scenes/blocks/stack.json");
    let o = rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "4",
            "-q",
            "--out",
            "t.jsonl",
            "--dump-problems",
            "problems",
        ],
        dir,
    );
    common::assert_success(&o);
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let path = files.last().unwrap();
    let reference = ProblemFile::read(path).unwrap();
    assert_eq!((reference.dof_per_body, reference.rows_per_contact), (3, 2));
    assert!(
        reference.contacts.len() >= 3,
        "{}",
        reference.contacts.len()
    );
    let mut other = reference.clone();
    for c in &mut other.contacts {
        for side in 0..2 {
            for value in &mut c.jacobian[side][1] {
                *value = -*value;
            }
        }
        c.b[1] = -c.b[1];
        c.lambda0[1] = -c.lambda0[1];
    }
    other.contacts.reverse();
    if let Some(solution) = &mut other.solution {
        solution.lambda.reverse();
        for l in &mut solution.lambda {
            l[1] = -l[1];
        }
        if let Some(criteria) = &mut solution.criteria {
            criteria.reverse();
        }
    }
    let write = |name: &str, p: &ProblemFile| {
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string(p).unwrap()).unwrap();
        path.display().to_string()
    };
    let reference_path = path.display().to_string();
    let other_path = write("reordered.json", &other);
    let o = rigidref(&["compare-problem", &reference_path, &other_path], dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        common::stderr(&o)
    );
    // Contact 1's normal row, its body 1's ω entry (a lever arm), changed by 10%.
    let mut changed = reference.clone();
    changed.contacts[1].jacobian[0][0][2] *= 1.1;
    if changed.contacts[1].jacobian[0][0][2] == 0.0 {
        changed.contacts[1].jacobian[0][0][2] = 0.1;
    }
    let changed_path = write("changed.json", &changed);
    let o = rigidref(&["compare-problem", &reference_path, &changed_path], dir);
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains("contact 1: normal row, body 1 entry 2 (ω)"),
        "{}",
        common::stderr(&o)
    );
    // A 2D file against a 3D one is refused as such (exit status 2).
    let three = common::project_root().join("scenes/box_stack.json");
    let o = rigidref(
        &[
            "run",
            three.to_str().unwrap(),
            "--steps",
            "2",
            "-q",
            "--out",
            "t3.jsonl",
            "--dump-problems",
            "p3",
        ],
        dir,
    );
    common::assert_success(&o);
    let p3 = std::fs::read_dir(dir.join("p3"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let o = rigidref(
        &["compare-problem", &reference_path, p3.to_str().unwrap()],
        dir,
    );
    assert_eq!(o.status.code(), Some(2), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains("the reference problem is 2D and the other 3D"),
        "{}",
        common::stderr(&o)
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
    // First contact problems: the exact submission's is the reference's; the wrong-gravity
    // one's has the bodies moving up.
    for (sub, extra) in [
        ("exact", "gravity=[0,-9.8,0]"),
        ("wrong_gravity", "gravity=[0,9.8,0]"),
    ] {
        let dumps = format!("dumps-{sub}");
        run(
            dir,
            "box_stack.json",
            "0.02",
            "d.jsonl",
            &["--set", extra, "--dump-problems", &dumps],
        );
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join(&dumps))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        std::fs::copy(&files[0], subs.join(sub).join("box_stack.problem.json")).unwrap();
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
    assert!(o.status.success(), "{}", common::stderr(&o));
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
    assert!(
        csv.lines()
            .any(|l| l.starts_with("exact,box_stack,first contact problem,pass,")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("wrong_gravity,box_stack,first contact problem,fail,")),
        "{csv}"
    );
    // In trajectory mode every quantity is compared over time: the exact submission still
    // passes and the wrong gravity still fails.
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
    assert!(o.status.success(), "{}", common::stderr(&o));
    let md = std::fs::read_to_string(dir.join("trajectory/grade.md")).unwrap();
    assert!(
        md.contains("| exact | pass |") && md.contains("| wrong_gravity | fail |"),
        "{md}"
    );
}

/// `compare A B --outcome --scene SCENE` in `dir` must agree (exit 0); returns its report.
fn assert_outcomes_agree(dir: &Path, a: &str, b: &str, scene_name: &str) -> String {
    let s = scene(scene_name);
    let o = rigidref(&["compare", a, b, "--outcome", "--scene", &s], dir);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{a} against {b}: {stdout}{}",
        common::stderr(&o)
    );
    stdout
}

/// Rewrites a JSON Lines trace in `dir`, applying `edit` to every record (not the header).
fn edit_records(dir: &Path, from: &str, to: &str, mut edit: impl FnMut(&mut serde_json::Value)) {
    let text = std::fs::read_to_string(dir.join(from)).unwrap();
    let mut lines: Vec<String> = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
        if k > 0 {
            edit(&mut v);
        }
        lines.push(v.to_string());
    }
    std::fs::write(dir.join(to), lines.join("\n") + "\n").unwrap();
}

/// Turns body `i`'s orientation by `turn` (in its own frame: R ← R · turn) in a record.
fn turn_body(record: &mut serde_json::Value, i: usize, turn: &nalgebra::Matrix3<f64>) {
    let r = &mut record["bodies"][i]["R"];
    let m = nalgebra::Matrix3::from_fn(|a, b| r[a][b].as_f64().unwrap());
    let turned = m * turn;
    *r = serde_json::json!(
        (0..3)
            .map(|a| (0..3).map(|b| turned[(a, b)]).collect::<Vec<_>>())
            .collect::<Vec<_>>()
    );
}

/// A reflection for R is refused as not a rotation (exit 1, its own verdict), and so are bodies
/// of other masses (exit 1, `wrong bodies`); a blank line at the end is not an error; a
/// body resting turned by one of its mesh's symmetries rests in the same orientation (a cube by
/// 90°, the icosphere ball by 180°).
#[test]
fn compare_refuses_what_is_not_a_trace_and_respects_symmetries() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    run(dir, "tumbling_brick.json", "1", "a.jsonl", &[]);
    edit_records(dir, "a.jsonl", "reflected.jsonl", |r| {
        if r["step"] == 10 {
            r["bodies"][0]["R"] =
                serde_json::json!([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        }
    });
    let o = rigidref(&["compare", "a.jsonl", "reflected.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o)
            .contains("refused (not a rotation): body 0 at step 10 (t = 0.1 s): R is a reflection"),
        "{}",
        common::stderr(&o)
    );
    let mut text = std::fs::read_to_string(dir.join("a.jsonl")).unwrap();
    text.push('\n');
    std::fs::write(dir.join("blank.jsonl"), text).unwrap();
    assert_eq!(
        rigidref(&["compare", "a.jsonl", "blank.jsonl"], dir)
            .status
            .code(),
        Some(0)
    );
    // Another scene's body, renamed: no body of its mass, refused (exit 1, its own verdict;
    // issue 47: it was exit 2, "unreadable", which a grader reads as a broken file, not as
    // another scene's trace).
    run(dir, "sphere_drop.json", "1", "ball.jsonl", &[]);
    let o = rigidref(&["compare", "a.jsonl", "ball.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains("not the same scene"),
        "{}",
        common::stderr(&o)
    );

    let quarter = *nalgebra::Rotation3::from_axis_angle(
        &nalgebra::Vector3::y_axis(),
        std::f64::consts::FRAC_PI_2,
    )
    .matrix();
    let half =
        *nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::z_axis(), std::f64::consts::PI)
            .matrix();
    run(dir, "cube_stack.json", "3", "stack.jsonl", &[]);
    edit_records(dir, "stack.jsonl", "stack-turned.jsonl", |r| {
        for i in 0..4 {
            turn_body(r, i, &quarter);
        }
    });
    assert_outcomes_agree(dir, "stack.jsonl", "stack-turned.jsonl", "cube_stack.json");
    run(dir, "sphere_drop.json", "3", "ball.jsonl", &[]);
    edit_records(dir, "ball.jsonl", "ball-turned.jsonl", |r| {
        turn_body(r, 0, &half)
    });
    assert_outcomes_agree(dir, "ball.jsonl", "ball-turned.jsonl", "sphere_drop.json");
    // The Dzhanibekov slab cut at 12 s as the reference, the same run over 20 s as the other:
    // the flips both show within the reference's span. The other way round the cut trace is
    // refused as incomplete (`a_trace_that_cannot_be_judged_is_refused_in_both_modes_and_in_grade`).
    run(dir, "dzhanibekov.json", "20", "long.jsonl", &[]);
    run(dir, "dzhanibekov.json", "12", "cut.jsonl", &[]);
    let stdout = assert_outcomes_agree(dir, "cut.jsonl", "long.jsonl", "dzhanibekov.json");
    assert!(stdout.contains("Dzhanibekov flip times"), "{stdout}");
}

#[test]
fn compare_problem_accepts_another_frictional_solution_by_its_residual() {
    // The 2D example of docs/contact-problem-format.md in 3D (a decoupled second tangent row):
    // M⁻¹ = diag(0.1, 0.1, 0.1, 1, 1, 1), n = [0, 1, 0, 0, 0, 0.9], t1 = [−1, 0, 0, 0, 0, −2],
    // t2 = [0, 0, 1, 0, 0, 0], b = (1, −5, 0), μ = 1. It has three solutions (separate, slide,
    // stick) with different velocities afterwards. A reference that separates and another file
    // that slides are both right: compare-problem must not call the second one wrong, and must
    // still name a λ that solves nothing.
    use rigidref::problem::json::{ProblemFile, SolutionJson};
    use rigidref::problem::{
        ContactProblem3, FrictionModel, ProblemBody, ProblemContact, RowBounds,
    };
    use rigidref::tools::grading::compare_problem::{ProblemTolerance, compare_problems};
    let mut inverse_mass = nalgebra::SMatrix::<f64, 6, 6>::zeros();
    inverse_mass.set_diagonal(&nalgebra::SVector::from([0.1, 0.1, 0.1, 1.0, 1.0, 1.0]));
    let mut jacobian = nalgebra::SMatrix::<f64, 3, 6>::zeros();
    jacobian[(0, 1)] = 1.0;
    jacobian[(0, 5)] = 0.9;
    jacobian[(1, 0)] = -1.0;
    jacobian[(1, 5)] = -2.0;
    jacobian[(2, 2)] = 1.0;
    let problem = ContactProblem3 {
        friction: FrictionModel::Box,
        bodies: vec![ProblemBody {
            inverse_mass,
            velocity: nalgebra::SVector::zeros(),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [jacobian, nalgebra::SMatrix::zeros()],
            b: nalgebra::SVector::from([1.0, -5.0, 0.0]),
            mu: 1.0,
            compliance: 0.0,
            lambda0: nalgebra::SVector::zeros(),
            bounds: RowBounds::Contact,
        }],
    };
    let with = |lambda: [f64; 3]| {
        let mut file = ProblemFile::new(&problem);
        file.solution = Some(SolutionJson {
            solver: "test".into(),
            lambda: vec![lambda.to_vec()],
            iterations: 1,
            residual: 0.0,
            coulomb_residual: None,
            criteria: None,
        });
        file
    };
    let reference = with([0.0, 0.0, 0.0]);
    let slide = 1.0 / 0.89;
    let stick = [4.9 / 0.491, 2.75 / 0.491, 0.0];
    let tol = ProblemTolerance::default();
    for other in [[slide, slide, 0.0], stick] {
        let (differences, compared) = compare_problems(&reference, &with(other), tol).unwrap();
        assert!(differences.is_empty(), "{other:?}: {differences:?}");
        assert!(compared > 0);
    }
    // Half the sliding impulse solves nothing: named.
    let (differences, _) =
        compare_problems(&reference, &with([slide / 2.0, slide / 2.0, 0.0]), tol).unwrap();
    assert!(
        differences.iter().any(|d| d.quantity.contains("λn")),
        "{differences:?}"
    );
}

#[test]
fn compare_reads_2d_traces_whatever_order_the_bodies_are_listed_in() {
    // The 2D stack's trace against itself (agrees), against a copy whose bodies are listed in
    // reverse order (agrees: bodies are matched by the image), against a copy with one body
    // moved by 0.01 block from t = 2 (flagged, naming that body's position), and against a
    // copy cut at half time (refused as incomplete).
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = common::project_root().join("scenes/blocks/stack.json");
    let o = rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "4",
            "-q",
            "--out",
            "ref.jsonl",
        ],
        dir,
    );
    common::assert_success(&o);
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let mut lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let write = |name: &str, lines: &[serde_json::Value]| {
        let body: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        std::fs::write(dir.join(name), body.join("\n") + "\n").unwrap();
    };
    let o = rigidref(&["compare", "ref.jsonl", "ref.jsonl"], dir);
    common::assert_success(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("bodies matched by image"));
    let bodies = lines[0]["bodies"].as_array().unwrap().len();
    assert!(bodies >= 3, "{bodies}");
    let mut reversed = lines.clone();
    // The header's body list and every record's, reversed alike.
    for line in reversed.iter_mut() {
        if let Some(list) = line.get_mut("bodies").and_then(|b| b.as_array_mut()) {
            list.reverse();
        }
    }
    write("reversed.jsonl", &reversed);
    let o = rigidref(&["compare", "ref.jsonl", "reversed.jsonl"], dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        common::stderr(&o)
    );
    // The matching is reported: reference body 0 is the reversed trace's last.
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!(
            "reference body = other trace's body: 0 = {}",
            bodies - 1
        )),
        "{stdout}"
    );
    for line in lines.iter_mut().skip(1) {
        if line["t"].as_f64().unwrap() >= 2.0 {
            let x = line["bodies"][1]["x"][0].as_f64().unwrap();
            line["bodies"][1]["x"][0] = serde_json::json!(x + 0.01);
        }
    }
    write("moved.jsonl", &lines);
    let o = rigidref(&["compare", "ref.jsonl", "moved.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    let stderr = common::stderr(&o);
    assert!(
        stderr.contains("body 1")
            && stderr.contains("position exceeds")
            && stderr.contains("first at t = 2"),
        "{stderr}"
    );
    let half = text.lines().count() / 2;
    std::fs::write(
        dir.join("cut.jsonl"),
        text.lines().take(half).collect::<Vec<_>>().join("\n") + "\n",
    )
    .unwrap();
    let o = rigidref(&["compare", "ref.jsonl", "cut.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("refused (incomplete)"),
        "{}",
        common::stderr(&o)
    );
}

/// 2D outcome mode on the dominoes (docs/grading.md §"2D outcome mode"): a valid run in another
/// random contact order differs in trajectory (the falls part ways) but agrees in outcome; the
/// last domino (a 2 × 4 bar, symmetric under a half turn) turned by π everywhere still agrees,
/// by a quarter turn it is flagged; a domino stood back up at the end is flagged standing, one
/// moved by half a block is flagged by its rest position.
#[test]
fn outcome_mode_judges_2d_bodies_by_how_they_end_up_modulo_their_symmetry() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = common::project_root().join("scenes/blocks/dominoes.json");
    let scene = scene.to_str().unwrap();
    for (seed, out) in [("seed=0", "ref.jsonl"), ("seed=7", "seed7.jsonl")] {
        let o = rigidref(
            &[
                "run", scene, "--time", "25", "-q", "--set", seed, "--out", out,
            ],
            dir,
        );
        common::assert_success(&o);
    }
    let o = rigidref(&["compare", "ref.jsonl", "ref.jsonl", "--outcome"], dir);
    assert_eq!(o.status.code(), Some(0), "the run against itself");
    let o = rigidref(&["compare", "ref.jsonl", "seed7.jsonl"], dir);
    assert_eq!(
        o.status.code(),
        Some(1),
        "another order: trajectories part ways"
    );
    let o = rigidref(&["compare", "ref.jsonl", "seed7.jsonl", "--outcome"], dir);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", common::stderr(&o));
    assert!(
        stdout.contains("body 7 (\"body7\") rest angle (after 2 symmetries)")
            && stdout.contains("toppled"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let edited = |name: &str, edit: &dyn Fn(f64, &mut serde_json::Value)| {
        let mut out = vec![lines[0].to_string()];
        for line in &lines[1..] {
            let mut line = line.clone();
            let t = line["t"].as_f64().unwrap();
            edit(t, &mut line["bodies"]);
            out.push(line.to_string());
        }
        std::fs::write(dir.join(name), out.join("\n") + "\n").unwrap();
    };
    let turn = |by: f64| {
        move |_: f64, bodies: &mut serde_json::Value| {
            let th = bodies[7]["theta"].as_f64().unwrap();
            bodies[7]["theta"] = serde_json::json!(th + by);
        }
    };
    edited("half_turn.jsonl", &turn(std::f64::consts::PI));
    edited("quarter_turn.jsonl", &turn(std::f64::consts::FRAC_PI_2));
    edited("stood_up.jsonl", &|t, bodies| {
        if t >= 24.0 {
            bodies[0]["theta"] = serde_json::json!(0.0);
        }
    });
    edited("moved.jsonl", &|t, bodies| {
        if t >= 24.0 {
            let x = bodies[3]["x"][0].as_f64().unwrap();
            bodies[3]["x"][0] = serde_json::json!(x + 0.5);
        }
    });
    let o = rigidref(
        &["compare", "ref.jsonl", "half_turn.jsonl", "--outcome"],
        dir,
    );
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
    for (file, named) in [
        ("quarter_turn.jsonl", "body 7 (\"body7\") rest angle"),
        ("stood_up.jsonl", "body 0 (\"body0\") rest angle"),
        ("moved.jsonl", "body 3 (\"body3\") rest position"),
    ] {
        let o = rigidref(&["compare", "ref.jsonl", file, "--outcome"], dir);
        assert_eq!(o.status.code(), Some(1), "{file}");
        assert!(
            common::stderr(&o).contains(named),
            "{file}: {}",
            common::stderr(&o)
        );
    }
    let o = rigidref(
        &["compare", "ref.jsonl", "stood_up.jsonl", "--outcome"],
        dir,
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout
            .lines()
            .any(|l| l.starts_with("body 0 (\"body0\") standing or toppled")
                && l.contains("DIFFERS")),
        "{stdout}"
    );
}

/// The assignment's tower25 (a chaotic scene: contacts shared by every block) graded by outcome
/// (docs/grading.md §"2D outcome mode"): a valid run in another random contact order differs in
/// trajectory from t ≈ 3 but agrees in outcome (every block at rest where the reference's is, none
/// toppled); the starter's (`--preset starter`: 10 sweeps in the order found, one substep, no warm
/// start, no post-stabilisation) let it fall (every block toppled, still moving at t = 20), which
/// outcome mode flags.
#[test]
fn the_tower_is_graded_by_outcome_where_valid_runs_part_ways() {
    let Some(assignment) = common::blocks2d_assignment() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let tower = assignment.join("tower25.png");
    let tower = tower.to_str().unwrap();
    for (extra, out) in [
        (&[][..], "ref.jsonl"),
        (&["--set", "seed=7"][..], "seed7.jsonl"),
        (&["--preset", "starter"][..], "starter.jsonl"),
    ] {
        let mut args = vec!["run", tower, "--time", "20", "-q", "--out", out];
        args.extend_from_slice(extra);
        common::assert_success(&rigidref(&args, dir));
    }
    let o = rigidref(&["compare", "ref.jsonl", "seed7.jsonl"], dir);
    assert_eq!(o.status.code(), Some(1), "another order: the path differs");
    let o = rigidref(&["compare", "ref.jsonl", "seed7.jsonl", "--outcome"], dir);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", common::stderr(&o));
    assert!(
        stdout.contains("body 24 (\"body24\") standing or toppled")
            && !stdout.contains("toppled ("),
        "{stdout}"
    );
    let o = rigidref(&["compare", "ref.jsonl", "starter.jsonl", "--outcome"], dir);
    assert_eq!(o.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        stdout.contains("body 0 (\"body0\") standing or toppled")
            && stdout.contains("toppled (")
            && common::stderr(&o).contains("at rest at the end"),
        "{stdout}{}",
        common::stderr(&o)
    );
}
