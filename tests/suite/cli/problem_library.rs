//! `rigidref solve-problems`, `convert-problem` and `crosscheck` on local-form files, as a user
//! runs them (docs/problem-library.md).

use crate::common;

fn data() -> std::path::PathBuf {
    common::project_root().join("tests/data/siconos")
}

#[test]
fn solve_problems_tables_every_problem_and_draws_a_profile() {
    let dir = tempfile::tempdir().unwrap();
    let profile = dir.path().join("profile.svg");
    let out = common::rigidref(
        &[
            "solve-problems",
            data().to_str().unwrap(),
            "--profile",
            profile.to_str().unwrap(),
        ],
        dir.path(),
    );
    common::assert_success(&out);
    let table = String::from_utf8(out.stdout.clone()).unwrap();
    // One row per local problem (21), each solver solving all of them to 1e-8.
    assert_eq!(
        table.lines().filter(|l| l.starts_with("| Rover")).count(),
        14,
        "{table}"
    );
    assert!(
        table.contains("| **solved** | 21 problems | | **21** | | | | | **21** | | | | | **21** |"),
        "{table}"
    );
    // The global problem in the folder is skipped with a note that says why.
    let stderr = common::stderr(&out);
    assert!(
        stderr.contains("skipped")
            && stderr.contains("GFC3D_Example00.dat")
            && stderr.contains("global problem"),
        "{stderr}"
    );
    let svg = std::fs::read_to_string(&profile).unwrap();
    assert!(
        svg.starts_with("<svg")
            && svg.contains("newton (21/21)")
            && svg.contains("pgs-exact (21/21)")
    );
    // JSON has the per-solve criteria and residuals too.
    let out = common::rigidref(
        &[
            "solve-problems",
            data().join("Rover4396.dat").to_str().unwrap(),
            "--json",
            "--solver",
            "newton",
        ],
        dir.path(),
    );
    common::assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let attempt = &v["problems"][0]["attempts"][0];
    assert_eq!(attempt["solver"], "newton");
    assert_eq!(attempt["converged"], true);
    assert!(attempt["error"].as_f64().unwrap() <= 1e-8);
    assert!(attempt["criteria"]["signorini"].as_f64().unwrap() < 1e-8);
    // A tight cap makes PGS fail honestly on a problem that needs more sweeps.
    let out = common::rigidref(
        &[
            "solve-problems",
            data().join("Rover1039.dat").to_str().unwrap(),
            "--solver",
            "pgs",
            "--sweeps",
            "10",
        ],
        dir.path(),
    );
    common::assert_success(&out);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.contains("| Rover1039.dat | 4 | 9e-6 | **no** | 10 |"),
        "{table}"
    );
}

#[test]
fn problem_commands_refuse_bad_input_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let folder = data();
    let folder = folder.to_str().unwrap();
    let not_a_problem = dir.path().join("notes.dat");
    std::fs::write(&not_a_problem, "3\n1\nhello\n").unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["solve-problems", "missing.dat"],
            "missing.dat: no such file or folder",
        ),
        (
            &["solve-problems", not_a_problem.to_str().unwrap()],
            "none of the 1 files could be read",
        ),
        (
            &["solve-problems", folder, "--tolerance", "0"],
            "--tolerance must be a positive number",
        ),
        (
            &["convert-problem", not_a_problem.to_str().unwrap(), "x.json"],
            "notes.dat: token 3: W's storage type: \"hello\"",
        ),
    ];
    for (args, expected) in cases {
        let out = common::rigidref(args, dir.path());
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let stderr = common::stderr(&out);
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

#[test]
fn converted_problems_solve_alike_and_crosscheck_reads_the_local_form() {
    let dir = tempfile::tempdir().unwrap();
    // A run's problem (body form) → local JSON → Siconos .dat → local JSON: the same W and q.
    let scene = common::project_root().join("scenes/cube_stack.json");
    let out = common::rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--steps",
            "3",
            "-q",
            "--dump-problems",
            "problems",
            "--out",
            "t.jsonl",
        ],
        dir.path(),
    );
    common::assert_success(&out);
    let mut dumps: Vec<_> = std::fs::read_dir(dir.path().join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dumps.sort();
    let body = dumps.last().unwrap().clone();
    for (from, to) in [
        (body.clone(), "a.json"),
        (dir.path().join("a.json"), "b.dat"),
        (dir.path().join("b.dat"), "c.json"),
    ] {
        let out = common::rigidref(&["convert-problem", from.to_str().unwrap(), to], dir.path());
        common::assert_success(&out);
        // The scene's box friction is written to Siconos' format with a warning that its
        // solvers answer for the cone; the warm start is said to be dropped.
        if to == "b.dat" {
            let stderr = common::stderr(&out);
            assert!(
                stderr.contains("box friction") && stderr.contains("warm start"),
                "{stderr}"
            );
        }
    }
    // A problem with joint rows (the seesaw's pins) is refused for Siconos' format: its rows
    // would become contacts.
    let seesaw = common::project_root().join("scenes/blocks/seesaw.json");
    let out = common::rigidref(
        &[
            "run",
            seesaw.to_str().unwrap(),
            "--steps",
            "2",
            "-q",
            "--dump-problems",
            "joints",
            "--out",
            "s.jsonl",
        ],
        dir.path(),
    );
    common::assert_success(&out);
    let joint = std::fs::read_dir(dir.path().join("joints"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let out = common::rigidref(
        &["convert-problem", joint.to_str().unwrap(), "j.dat"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        common::stderr(&out).contains("is a joint (bounds \"free\")"),
        "{}",
        common::stderr(&out)
    );
    assert!(!dir.path().join("j.dat").exists());
    let read = |name: &str| -> rigidref::problem::LocalProblem<3> {
        rigidref::problem::local_json::AnyProblemFile::read(&dir.path().join(name))
            .unwrap()
            .to_local::<3>()
            .unwrap()
    };
    let (a, c) = (read("a.json"), read("c.json"));
    assert_eq!(a.dense_w(), c.dense_w());
    assert_eq!(a.dense_q(), c.dense_q());
    let body_local = rigidref::problem::local_json::AnyProblemFile::read(&body)
        .unwrap()
        .to_local::<3>()
        .unwrap();
    assert_eq!(a, body_local);
    // crosscheck accepts the local file and agrees with clarabel on it.
    let out = common::rigidref(&["crosscheck", "a.json"], dir.path());
    common::assert_success(&out);
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("agree"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    // A non-symmetric W (Siconos' Rover problems) is refused by crosscheck with the reason.
    let out = common::rigidref(
        &[
            "convert-problem",
            data().join("Rover4396.dat").to_str().unwrap(),
            "rover.json",
        ],
        dir.path(),
    );
    common::assert_success(&out);
    let out = common::rigidref(&["crosscheck", "rover.json"], dir.path());
    assert_ne!(out.status.code(), Some(0));
    assert!(
        common::stderr(&out).contains("W is not symmetric"),
        "{}",
        common::stderr(&out)
    );
    // compare-problem needs bodies and says so.
    let out = common::rigidref(&["compare-problem", "a.json", "a.json"], dir.path());
    assert_ne!(out.status.code(), Some(0));
    assert!(
        common::stderr(&out).contains("local-form problem"),
        "{}",
        common::stderr(&out)
    );
}
