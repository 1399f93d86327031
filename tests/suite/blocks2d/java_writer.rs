//! The Java trace writer (java/RigidrefTrace.java): compiled and run with a student-like 2D
//! simulator written here in Java, its trace compared with the reference's run of the same image
//! (docs/grading.md §"2D traces"; java/README.md). Skipped, saying why, without a JDK.

use crate::common;

/// A student's step for free fall, as the 2D starter's `RigidBody` advances a body: per substep
/// v += h g then x += h v (the reference's order), or, with `BUG`, the positions first.
const STUDENT: &str = r#"
public class Student {
    public static void main(String[] a) throws Exception {
        double dt = Double.parseDouble(a[1]), g = Double.parseDouble(a[3]), end = Double.parseDouble(a[4]);
        int substeps = Integer.parseInt(a[2]);
        boolean bug = a.length > 5;
        // The image's bodies as the starter finds them: pixels (column, row) of black blocks.
        int[][][] pixels = {
            {{5, 3}, {6, 3}, {5, 4}, {6, 4}},
            {{15, 10}, {16, 10}, {17, 10}},
        };
        int n = pixels.length;
        double[] x = new double[n], y = new double[n], th = new double[n], vx = new double[n], vy = new double[n], w = new double[n];
        try (RigidrefTrace trace = new RigidrefTrace(a[0], "fall", "fall.png", dt, substeps, 0.0, g)) {
            for (int i = 0; i < n; i++) {
                double m = pixels[i].length, inertia = 0;
                for (int[] p : pixels[i]) { x[i] += p[0] / m; y[i] += p[1] / m; }
                for (int[] p : pixels[i]) { inertia += 1.0 / 6.0 + (p[0] - x[i]) * (p[0] - x[i]) + (p[1] - y[i]) * (p[1] - y[i]); }
                trace.body("body" + i, m, inertia, false, pixels[i].length);
            }
            trace.record(0.0, x, y, th, vx, vy, w);
            double h = dt / substeps;
            long steps = Math.round(end / dt);
            for (long k = 1; k <= steps; k++) {
                for (int s = 0; s < substeps; s++) {
                    for (int i = 0; i < n; i++) {
                        if (bug) { y[i] += h * vy[i]; vy[i] += h * g; }
                        else { vy[i] += h * g; y[i] += h * vy[i]; }
                    }
                }
                trace.record(k * dt, x, y, th, vx, vy, w);
            }
        }
    }
}
"#;

/// Whether javac is on PATH; says why a test is skipped when not.
fn has_javac() -> bool {
    let found = std::process::Command::new("javac")
        .arg("-version")
        .output()
        .is_ok();
    if !found {
        eprintln!("skipped: no javac on PATH (Debian's default-jdk-headless gives one)");
    }
    found
}

/// Copies java/RigidrefTrace.java into `dir` and compiles it there with `program`.
fn compile_with_writer(dir: &std::path::Path, program: &str) {
    std::fs::copy(
        common::project_root().join("java/RigidrefTrace.java"),
        dir.join("RigidrefTrace.java"),
    )
    .unwrap();
    let javac = std::process::Command::new("javac")
        .args(["RigidrefTrace.java", program])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        javac.status.success(),
        "{}",
        String::from_utf8_lossy(&javac.stderr)
    );
}

#[test]
fn the_java_writer_traces_a_student_simulator_that_compare_grades() {
    if !has_javac() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // The image: two black bodies in white, nothing below them: they fall freely.
    let mut img = image::RgbImage::from_pixel(32, 40, image::Rgb([255, 255, 255]));
    for (c, r) in [(5, 3), (6, 3), (5, 4), (6, 4), (15, 10), (16, 10), (17, 10)] {
        img.put_pixel(c, r, image::Rgb([0, 0, 0]));
    }
    img.save(dir.join("fall.png")).unwrap();
    let o = common::rigidref(
        &["run", "fall.png", "--time", "2", "-q", "--out", "ref.jsonl"],
        dir,
    );
    common::assert_success(&o);
    let header: serde_json::Value = serde_json::from_str(
        std::fs::read_to_string(dir.join("ref.jsonl"))
            .unwrap()
            .lines()
            .next()
            .unwrap(),
    )
    .unwrap();
    let (dt, substeps, g) = (
        header["dt"].as_f64().unwrap(),
        header["substeps"].as_u64().unwrap(),
        header["gravity"][1].as_f64().unwrap(),
    );
    std::fs::write(dir.join("Student.java"), STUDENT).unwrap();
    compile_with_writer(dir, "Student.java");
    let run = |out: &str, bug: bool| {
        let mut args = vec![
            "-cp".to_string(),
            ".".into(),
            "Student".into(),
            out.into(),
            dt.to_string(),
            substeps.to_string(),
            g.to_string(),
            "2".into(),
        ];
        if bug {
            args.push("bug".into());
        }
        let o = std::process::Command::new("java")
            .args(&args)
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run("student.jsonl", false);
    let o = common::rigidref(&["compare", "ref.jsonl", "student.jsonl"], dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        common::stderr(&o)
    );
    // Positions updated before velocities: a typical bug, flagged by the position it moves.
    run("buggy.jsonl", true);
    let o = common::rigidref(&["compare", "ref.jsonl", "buggy.jsonl"], dir);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let stderr = common::stderr(&o);
    assert!(
        stderr.contains("body 0 (\"body0\") position exceeds"),
        "{stderr}"
    );
}

/// The Java writer's contact problem (`RigidrefTrace.Problem`, `RigidrefTrace.jacobianRows`):
/// a Java program given the reference's first contact state of the toppling bar (bodies'
/// inverse masses and velocities, the contacts' points, normals and depths, the centres of mass,
/// the reference's λ) builds the Jacobian rows with the writer's helper and writes the problem.
/// `compare-problem` finds it equal to the reference's own dump, λ included, and the residual
/// the writer computed equals the reference's to 1e-12 (the same λ on the same problem); with
/// the normal given the wrong way round, the normal row is named.
#[test]
fn the_java_writer_writes_a_2d_problem_that_compare_problem_reads() {
    if !has_javac() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    super::grading::write_scenes(dir);
    let scene =
        rigidref::blocks2d::scene::load_2d(&dir.join("topple.json"), &Default::default()).unwrap();
    let mut world = scene.world;
    // Step until a substep solves a contact, keeping the centres the contacts were found at.
    let (centres, solve) = loop {
        let centres: Vec<[f64; 2]> = world.bodies.iter().map(|b| [b.x.x, b.x.y]).collect();
        world.step().unwrap();
        if let Some(s) = world.solves.iter().find(|s| !s.contacts.is_empty()) {
            break (centres, s.clone());
        }
        assert!(world.step < 1000, "the bar never reaches the floor");
    };
    let reference = solve.problem_file("topple", world.step, world.params.h());
    std::fs::write(
        dir.join("ref.problem.json"),
        serde_json::to_string(&reference).unwrap(),
    )
    .unwrap();
    let f = |x: f64| format!("{x:?}");
    let mut calls = String::new();
    for (b, pb) in world.bodies.iter().zip(&solve.problem.bodies) {
        let u = pb.velocity;
        calls += &format!(
            "        p.body({}, {}, {}, {}, {});\n",
            f(b.inv_mass),
            f(b.inv_inertia),
            f(u[0]),
            f(u[1]),
            f(u[2])
        );
    }
    for c in &solve.contacts {
        let (x1, x2) = (centres[c.body1], centres[c.body2]);
        calls += &format!(
            "        p.contact({}, {}, {}, {}, {}, {}, {}, {}, RigidrefTrace.jacobianRows({}, {}, s * {}, s * {}, {}, {}, {}, {}));\n",
            c.body1,
            c.body2,
            f(c.point.x),
            f(c.point.y),
            f(c.normal.x),
            f(c.normal.y),
            f(c.depth),
            f(world.params.mu),
            f(c.point.x),
            f(c.point.y),
            f(c.normal.x),
            f(c.normal.y),
            f(x1[0]),
            f(x1[1]),
            f(x2[0]),
            f(x2[1])
        );
    }
    let lambda: Vec<String> = solve
        .lambda
        .iter()
        .map(|l| format!("{{k * {}, k * {}}}", f(l[0]), f(l[1])))
        .collect();
    let program = format!(
        "public class Dump {{\n    public static void main(String[] a) throws Exception {{\n        \
         double s = a.length > 1 && a[1].equals(\"bug\") ? -1 : 1; // the normal the wrong way round\n        \
         double k = a.length > 1 && a[1].equals(\"scaled\") ? 1.5 : 1; // λ off the solution\n        \
         RigidrefTrace.Problem p = new RigidrefTrace.Problem();\n{calls}        \
         p.solution(new double[][] {{{}}}, {});\n        p.write(a[0]);\n    }}\n}}\n",
        lambda.join(", "),
        solve.report.iterations
    );
    std::fs::write(dir.join("Dump.java"), program).unwrap();
    compile_with_writer(dir, "Dump.java");
    for (out, variant) in [
        ("java.problem.json", None),
        ("flipped.problem.json", Some("bug")),
        ("scaled.problem.json", Some("scaled")),
    ] {
        let mut args = vec!["-cp", ".", "Dump", out];
        args.extend(variant);
        let o = std::process::Command::new("java")
            .args(&args)
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = common::rigidref(
        &["compare-problem", "ref.problem.json", "java.problem.json"],
        dir,
    );
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", common::stderr(&o));
    // The residual the writer computes is rigidref's (src/solve/residual.rs::residual), at the
    // solution (≈ 0) and at λ × 1.5 (where it is far from 0).
    let written = |name: &str| -> f64 {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap();
        v["solution"]["residual"].as_f64().unwrap()
    };
    let scaled: Vec<_> = solve.lambda.iter().map(|l| l * 1.5).collect();
    for (name, lambda) in [
        ("java.problem.json", solve.lambda.clone()),
        ("scaled.problem.json", scaled),
    ] {
        let expected = rigidref::solve::residual(&solve.problem, &lambda);
        let residual = written(name);
        assert!(
            (residual - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "{name}: the writer's residual {residual}, rigidref's {expected}"
        );
    }
    assert!(written("scaled.problem.json") > 1e-3);
    let o = common::rigidref(
        &[
            "compare-problem",
            "ref.problem.json",
            "flipped.problem.json",
        ],
        dir,
    );
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("normal row"), "{stdout}");
}
