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

#[test]
fn the_java_writer_traces_a_student_simulator_that_compare_grades() {
    if std::process::Command::new("javac")
        .arg("-version")
        .output()
        .is_err()
    {
        eprintln!("skipped: no javac on PATH (Debian's default-jdk-headless gives one)");
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
    std::fs::copy(
        common::project_root().join("java/RigidrefTrace.java"),
        dir.join("RigidrefTrace.java"),
    )
    .unwrap();
    std::fs::write(dir.join("Student.java"), STUDENT).unwrap();
    let javac = std::process::Command::new("javac")
        .args(["RigidrefTrace.java", "Student.java"])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        javac.status.success(),
        "{}",
        String::from_utf8_lossy(&javac.stderr)
    );
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
