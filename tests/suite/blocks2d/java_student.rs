//! Grading a Java class (issue 47): a student-like 2D simulator written in Java in the starter's
//! layout (tests/data/java-student: package comp559.lcp, package-private fields, the contact
//! solve and the disc tree behind private switches that default to off, as the starter ships
//! them; written for these tests from the assignment's equations with the starter's
//! conventions: point-mass inertia, the normal from body 1 to body 2, contacts in the order
//! found, no warm start, no post-stabilisation), compiled with javac against stubs of the
//! starter's jars, run headless by java/RigidrefRun.java compiled beside it (the student's files
//! untouched), its trace and first contact problem written by java/RigidrefTrace.java, and
//! compared with `rigidref run IMAGE --preset starter`. The steps are java/README.md's.
//!
//! The simulator is compiled once per run of the test binary and shared by the tests here.
//! Skipped, saying why, without javac or without ../shared.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The variants of the student: the correct one, then the mistakes (tests/data/java-student's
/// Bug.java), each with what names it.
const BUGS: [&str; 4] = [
    "normal_sign",
    "rigidref_inertia",
    "friction_bound",
    "jacobian_entry",
];

/// The folder where the student's project was compiled (src/, jars/, grader/, build/), or `None`
/// (printed why) when there is no javac.
fn compiled() -> Option<&'static Path> {
    static BUILT: OnceLock<Option<PathBuf>> = OnceLock::new();
    BUILT
        .get_or_init(|| {
            if Command::new("javac").arg("-version").output().is_err() {
                eprintln!("skipped: no javac on PATH (Debian's default-jdk-headless gives one)");
                return None;
            }
            Some(build(
                &PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("java-student"),
            ))
        })
        .as_deref()
}

/// Runs a command in `dir`, panicking with its output when it fails.
fn check(dir: &Path, program: &str, args: &[&str]) {
    let o = Command::new(program)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("{program}: {e}"));
    assert!(
        o.status.success(),
        "{program} {args:?}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The student's project as a grader has it (its sources and the starter's jars, here stubs),
/// then java/README.md's steps: RigidrefRun.java and a copy of RigidrefTrace.java with the
/// package line in a folder of their own, everything compiled with the jars on the class path.
fn build(dir: &Path) -> PathBuf {
    let fixture = common::project_root().join("tests/data/java-student");
    let _ = std::fs::remove_dir_all(dir);
    let package = dir.join("src/comp559/lcp");
    std::fs::create_dir_all(&package).unwrap();
    let java_files = |folder: &Path| -> Vec<String> {
        let mut files: Vec<String> = walk(folder)
            .into_iter()
            .filter(|p| p.extension().is_some_and(|e| e == "java"))
            .map(|p| p.display().to_string())
            .collect();
        files.sort();
        files
    };
    for f in std::fs::read_dir(fixture.join("src/comp559/lcp")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, package.join(f.file_name().unwrap())).unwrap();
    }
    // The starter's jars/: mintools and vecmath, as stubs of the classes used.
    let stubs = dir.join("stubs");
    let mut args = vec!["-d".to_string(), stubs.display().to_string()];
    args.extend(java_files(&fixture.join("stubs")));
    check(
        dir,
        "javac",
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    std::fs::create_dir_all(dir.join("jars")).unwrap();
    check(
        dir,
        "jar",
        &["cf", "jars/mintools.jar", "-C", "stubs", "mintools"],
    );
    check(
        dir,
        "jar",
        &["cf", "jars/vecmath.jar", "-C", "stubs", "javax"],
    );
    // java/README.md: the grader's two files beside the student's, in their package.
    let grader = dir.join("grader/comp559/lcp");
    std::fs::create_dir_all(&grader).unwrap();
    let java = common::project_root().join("java");
    std::fs::copy(
        java.join("RigidrefRun.java"),
        grader.join("RigidrefRun.java"),
    )
    .unwrap();
    let trace = std::fs::read_to_string(java.join("RigidrefTrace.java")).unwrap();
    std::fs::write(
        grader.join("RigidrefTrace.java"),
        format!("package comp559.lcp;\n{trace}"),
    )
    .unwrap();
    let mut args: Vec<String> = ["-d", "build", "-cp", "jars/*"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.extend(java_files(&dir.join("src")));
    args.extend(java_files(&dir.join("grader")));
    check(
        dir,
        "javac",
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    dir.to_path_buf()
}

fn walk(folder: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(folder).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// Runs the student (variant `bug`) headless on `image` for `time` time units, writing
/// `folder/STEM.jsonl` and `folder/STEM.problem.json` (its own Jacobian rows in the problem).
fn run_student(build: &Path, image: &Path, bug: &str, time: &str, folder: &Path) {
    std::fs::create_dir_all(folder).unwrap();
    let classpath = format!("{0}/build:{0}/jars/*", build.display());
    let image = image.display().to_string();
    let bug = format!("-Dstudent.bug={bug}");
    check(
        folder,
        "java",
        &[
            "-Djava.awt.headless=true",
            &bug,
            "-cp",
            &classpath,
            "comp559.lcp.RigidrefRun",
            &image,
            "--time",
            time,
            "--jacobian",
            "jacobianNormal,jacobianTangent",
        ],
    );
}

/// The reference's run of `image` with `options` for `time` into `dir/NAME.jsonl`, and its
/// first contact problem as `dir/NAME.problem.json`.
fn run_reference(dir: &Path, image: &Path, time: &str, options: &[&str], name: &str) {
    let dumps = dir.join(format!("{name}-problems"));
    let trace = format!("{name}.jsonl");
    let mut args = vec![
        "run",
        image.to_str().unwrap(),
        "--time",
        time,
        "-q",
        "--out",
        &trace,
    ];
    let dumps_arg = dumps.display().to_string();
    args.extend(["--dump-problems", &dumps_arg]);
    args.extend_from_slice(options);
    common::assert_success(&common::rigidref(&args, dir));
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dumps)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    std::fs::copy(&files[0], dir.join(format!("{name}.problem.json"))).unwrap();
}

/// `rigidref compare` (with `extra` options) as (exit status, stdout + stderr).
fn compare(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let o = common::rigidref(args, dir);
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        common::stderr(&o)
    );
    (o.status.code(), text)
}

/// The largest error over the bodies' positions, angles, velocities and angular velocities.
fn largest_state_error(dir: &Path, reference: &str, other: &str) -> f64 {
    let o = common::rigidref(&["compare", reference, other, "--json"], dir);
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    report["errors"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["quantity"].as_str().unwrap().starts_with("body "))
        .map(|e| e["max_error"].as_f64().unwrap())
        .fold(0.0, f64::max)
}

/// The correct student agrees with `--preset starter` in trajectory mode to 1e-9 over 8 time
/// units on simple1, simple2 and simple (measured: within 6e-15 in every state quantity; the
/// order of floating-point operations differs, so round-off, not zero), and its first contact
/// problem (its own Jacobian rows, the inverse masses and the velocities the solve started
/// from) agrees under `compare-problem`. The same student with rigidref's default inertia
/// (Σ m (r² + 1/6)) agrees with `--preset starter --inertia blocks` to 1e-9 instead, and
/// against the starter preset its problem is flagged by the inertia: `body 0 inverse mass [2][2]`
/// on the bar (simple2) and the four-block body (simple).
#[test]
fn the_java_student_agrees_with_the_starter_preset_to_round_off_on_the_simple_images() {
    let Some(assignment) = common::blocks2d_assignment() else {
        return;
    };
    let Some(build) = compiled() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for name in ["simple1", "simple2", "simple"] {
        let image = assignment.join(format!("{name}.png"));
        run_reference(
            dir,
            &image,
            "8",
            &["--preset", "starter"],
            &format!("ref_{name}"),
        );
        run_student(build, &image, "correct", "8", &dir.join("correct"));
        let (reference, mine) = (format!("ref_{name}.jsonl"), format!("correct/{name}.jsonl"));
        let (code, text) = compare(dir, &["compare", &reference, &mine, "--tolerance", "1e-9"]);
        assert_eq!(code, Some(0), "{name}: {text}");
        eprintln!(
            "{name}: the Java student against --preset starter: largest state error {:.1e}",
            largest_state_error(dir, &reference, &mine)
        );
        let problems = [
            format!("ref_{name}.problem.json"),
            format!("correct/{name}.problem.json"),
        ];
        let (code, text) = compare(dir, &["compare-problem", &problems[0], &problems[1]]);
        assert_eq!(code, Some(0), "{name}: {text}");

        // rigidref's inertia: the same physics as the preset with --inertia blocks ...
        run_student(build, &image, "rigidref_inertia", "8", &dir.join("inertia"));
        let blocks = format!("blocks_{name}");
        run_reference(
            dir,
            &image,
            "8",
            &["--preset", "starter", "--inertia", "blocks"],
            &blocks,
        );
        let mine = format!("inertia/{name}.jsonl");
        let (code, text) = compare(
            dir,
            &[
                "compare",
                &format!("{blocks}.jsonl"),
                &mine,
                "--tolerance",
                "1e-9",
            ],
        );
        assert_eq!(code, Some(0), "{name}: {text}");
        // ... and flagged by it against the starter's, where a body has more than one block.
        let (code, text) = compare(
            dir,
            &[
                "compare-problem",
                &problems[0],
                &format!("inertia/{name}.problem.json"),
            ],
        );
        if name == "simple1" {
            assert_eq!(code, Some(0), "one block: m/6 either way: {text}");
        } else {
            assert_eq!(code, Some(1), "{name}: {text}");
            assert!(
                text.contains("body 0 inverse mass [2][2]"),
                "{name}: {text}"
            );
            let (code, text) = compare(dir, &["compare", &reference, &mine]);
            assert_eq!(code, Some(1), "{name}: {text}");
        }
    }
}

/// On tower10 the correct student agrees with the preset in trajectory mode too (the same body
/// numbering, column by column, and the same contact order, so the same 10-sweep solves; at the
/// default tolerances, measured within 1e-14), and on tower25 in outcome mode.
#[test]
fn the_java_student_agrees_on_tower10_in_trajectory_mode_and_tower25_in_outcome_mode() {
    let Some(assignment) = common::blocks2d_assignment() else {
        return;
    };
    let Some(build) = compiled() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (name, mode) in [("tower10", None), ("tower25", Some("--outcome"))] {
        let image = assignment.join(format!("{name}.png"));
        run_reference(
            dir,
            &image,
            "8",
            &["--preset", "starter"],
            &format!("ref_{name}"),
        );
        run_student(build, &image, "correct", "8", &dir.join("correct"));
        let (reference, mine) = (format!("ref_{name}.jsonl"), format!("correct/{name}.jsonl"));
        let mut args = vec!["compare", reference.as_str(), mine.as_str()];
        args.extend(mode);
        let (code, text) = compare(dir, &args);
        assert_eq!(code, Some(0), "{name}: {text}");
        // The same numbering: every body matched to the body of its own index.
        let o = common::rigidref(&["compare", &reference, &mine, "--json"], dir);
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let matching: Vec<u64> = report["matching"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m.as_u64().unwrap())
            .collect();
        assert!(
            matching.iter().enumerate().all(|(i, &m)| m == i as u64),
            "{name}: {matching:?}"
        );
        eprintln!(
            "{name}: the Java student against --preset starter: largest state error {:.1e}",
            largest_state_error(dir, &reference, &mine)
        );
    }
}

/// `rigidref grade` on a class of the Java student and its mistakes, on simple1, simple2 and
/// simple against `--set preset=starter`: the correct student passes every scene, and each
/// mistake fails a scene, its rows naming the quantity: the normal's sign by the problem's
/// normal and the trajectory's position, rigidref's inertia by `inverse mass [2][2]`, friction
/// bounded by μ instead of μ λn by the trajectory alone (the bound is not in the problem), the
/// sign of one Jacobian entry by `normal row, body 1 entry 2 (ω)`.
#[test]
fn grade_passes_the_java_student_and_names_each_of_its_mistakes() {
    let Some(assignment) = common::blocks2d_assignment() else {
        return;
    };
    let Some(build) = compiled() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scenes: Vec<PathBuf> = ["simple1", "simple2", "simple"]
        .iter()
        .map(|n| assignment.join(format!("{n}.png")))
        .collect();
    for bug in std::iter::once("correct").chain(BUGS) {
        for image in &scenes {
            run_student(build, image, bug, "8", &dir.join("class").join(bug));
        }
    }
    let mut args = vec!["grade", "class", "--scenes"];
    args.extend(scenes.iter().map(|p| p.to_str().unwrap()));
    args.extend(["--set", "preset=starter", "--time", "8", "--out", "report"]);
    common::assert_success(&common::rigidref(&args, dir));
    let csv = std::fs::read_to_string(dir.join("report/grade.csv")).unwrap();
    let rows = |who: &str| -> Vec<&str> {
        csv.lines()
            .filter(|l| l.starts_with(&format!("{who},")))
            .collect()
    };
    let failing = |who: &str| -> Vec<&str> {
        rows(who)
            .into_iter()
            .filter(|l| l.contains(",fail,"))
            .collect()
    };
    assert!(!rows("correct").is_empty(), "{csv}");
    assert!(
        rows("correct")
            .iter()
            .all(|l| l.contains(",pass,") || l.contains(",note,")),
        "{csv}"
    );
    for (bug, named) in [
        ("normal_sign", &["normal n[1]", "position"][..]),
        (
            "rigidref_inertia",
            &["inverse mass [2][2]", "angular velocity"][..],
        ),
        (
            "friction_bound",
            &["simple2,\"body 0 (\"\"body0\"\") position"][..],
        ),
        (
            "jacobian_entry",
            &["normal row, body 1 entry 2 (ω)", "angle"][..],
        ),
    ] {
        let fails = failing(bug).join("\n");
        for quantity in named {
            assert!(
                fails.contains(quantity),
                "{bug}: no failing row names {quantity}:\n{fails}"
            );
        }
    }
    // Friction's bound is not part of the contact problem: its problem rows pass.
    let problems: Vec<&str> = rows("friction_bound")
        .into_iter()
        .filter(|l| l.contains("first contact problem"))
        .collect();
    assert!(
        problems.len() == 3 && problems.iter().all(|l| l.contains(",pass,")),
        "{problems:?}"
    );
}

/// The runner's command line: a parameter the student's classes do not have, a value outside a
/// parameter's range and a Jacobian field that does not exist are each refused with exit status 2
/// and a line naming what is wrong (the first listing the parameters there are), before any
/// trace is written.
#[test]
fn the_runner_refuses_a_bad_command_line_naming_what_is_wrong() {
    let Some(assignment) = common::blocks2d_assignment() else {
        return;
    };
    let Some(build) = compiled() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let image = assignment.join("simple1.png").display().to_string();
    let classpath = format!("{0}/build:{0}/jars/*", build.display());
    for (extra, says) in [
        (
            &["--set", "noSuchField=1"][..],
            "--set noSuchField: no such parameter; the parameters are useGravity",
        ),
        (
            &["--set", "iterations=1000"][..],
            "--set iterations=1000: the parameter keeps 500 (outside its range)",
        ),
        (
            &["--set", "doLCP=yes"][..],
            "--set doLCP=yes: not a boolean",
        ),
        (
            &["--jacobian", "nope,nope"][..],
            "--jacobian: Contact has no field nope",
        ),
        (
            &["--white", "2"][..],
            "--white must be a number in [0, 1), got 2",
        ),
    ] {
        let mut args = vec![
            "-cp",
            &classpath,
            "comp559.lcp.RigidrefRun",
            &image,
            "--time",
            "1",
        ];
        args.extend_from_slice(extra);
        let o = Command::new("java")
            .args(&args)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(says), "{extra:?}: {stderr}");
    }
}
