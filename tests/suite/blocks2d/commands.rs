//! The 2D system through the command line: scene files, problem dumps, run and render, bad
//! input, and `contacts` (docs/blocks2d.md).

use crate::common;

use nalgebra::Vector2;
use rigidref::solve::ContactOrder;

use common::rigidref;

/// The project's own 2D scenes (scenes/blocks/*.json, images made for the project) load and run;
/// the stack stands until its scripted impulse knocks the top bar off, and the dominoes fall.
#[test]
fn canonical_2d_scenes_run_and_their_scripted_impulses_act() {
    let dir = common::project_root().join("scenes/blocks");
    for name in ["stack", "pyramid", "dominoes"] {
        let scene =
            rigidref::blocks2d::scene::load_scene2(&dir.join(format!("{name}.json"))).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        let mut world = scene.world;
        let start: Vec<Vector2<f64>> = world.bodies.iter().map(|b| b.x).collect();
        let steps = (20.0 / world.params.dt) as u64;
        common::run(&mut world, steps, |_, _| {});
        let moved: Vec<f64> = world
            .bodies
            .iter()
            .zip(&start)
            .map(|(b, x)| (b.x.x - x.x).abs())
            .collect();
        let tilted = world.bodies.iter().filter(|b| b.theta.abs() > 0.5).count();
        println!(
            "{name}: sideways moves {:?}, {tilted} bodies turned over 0.5 rad",
            moved.iter().map(|m| format!("{m:.2}")).collect::<Vec<_>>()
        );
        match name {
            // The impulse at t = 15 hits the top bar (body 0): it leaves (dragging the bar
            // below it a little, measured 0.9), and the rest of the stack stands.
            "stack" => {
                assert!(moved[0] > 3.0);
                assert!(moved[1] < 2.0 && moved[2..].iter().all(|m| *m < 0.5));
            }
            "pyramid" => assert!(moved.iter().all(|m| *m < 0.5)),
            // The first domino is pushed at its top at t = 2; most of the row falls.
            "dominoes" => assert!(tilted >= 5, "{tilted} dominoes fell"),
            _ => unreachable!(),
        }
    }
}

/// `run IMAGE --dump-problems DIR` writes the 2D contact problems the run solved (3 degrees of
/// freedom per body, 2 rows per contact): one file per step with contacts (one substep), none for
/// a step without; each file's λ is the trace's, and the shared PGS re-run on the file (the
/// starter's 10 sweeps in order, from the file's warm start) gives that λ bit for bit.
#[test]
fn dump_problems_writes_the_2d_problems_the_run_solved() {
    let tmp = tempfile::tempdir().unwrap();
    let (trace, dump) = (tmp.path().join("t.jsonl"), tmp.path().join("problems"));
    let out = rigidref(
        &[
            "run",
            "scenes/blocks/stack.png",
            // The starter's settings (1 substep, 10 sweeps in order), which the re-solve below
            // repeats; every contact with its impulse in the trace.
            "--preset",
            "starter",
            "--all-contacts",
            "--time",
            "8",
            "--dump-problems",
            dump.to_str().unwrap(),
            "--quiet",
            "--out",
            trace.to_str().unwrap(),
        ],
        &common::project_root(),
    );
    common::assert_success(&out);
    let records: Vec<serde_json::Value> = std::fs::read_to_string(&trace)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let settings = rigidref::solve::PgsSettings {
        max_iterations: 10,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: rigidref::solve::LocalSolve::Rows,
    };
    let mut with_contacts = 0;
    for record in records.iter().skip(1) {
        let step = record["step"].as_u64().unwrap();
        let contacts = record["contacts"].as_array().unwrap();
        let path = dump.join(format!("step-{step:06}-00.json"));
        if contacts.is_empty() {
            assert!(
                !path.exists(),
                "{} written for a step without contacts",
                path.display()
            );
            continue;
        }
        with_contacts += 1;
        let file = rigidref::problem::json::ProblemFile::read(&path).unwrap();
        assert_eq!((file.dof_per_body, file.rows_per_contact), (3, 2));
        assert_eq!(file.step, Some(step));
        let problem: rigidref::blocks2d::assemble::ContactProblem2 = file.to_problem().unwrap();
        let solution = file.solution.as_ref().unwrap();
        assert_eq!(solution.lambda.len(), contacts.len());
        for (l, c) in solution.lambda.iter().zip(contacts) {
            let traced: Vec<f64> = serde_json::from_value(c["lambda"].clone()).unwrap();
            assert_eq!(l, &traced);
        }
        let mut workspace = rigidref::solve::PgsWorkspace::<3, 2>::new(0);
        let mut lambda = Vec::new();
        rigidref::solve::solve_pgs(&problem, &settings, &mut workspace, &mut lambda);
        for (mine, theirs) in lambda.iter().zip(&solution.lambda) {
            assert_eq!(mine.as_slice(), theirs.as_slice());
        }
    }
    println!(
        "{with_contacts} of {} steps had contacts and a problem file",
        records.len() - 1
    );
    assert!(
        with_contacts >= 10,
        "only {with_contacts} steps with contacts"
    );
    assert_eq!(std::fs::read_dir(&dump).unwrap().count(), with_contacts);
}

#[test]
fn run_and_render_commands_write_2d_traces_frames_and_gifs() {
    let tmp = tempfile::tempdir().unwrap();
    let scenes = common::project_root().join("scenes/blocks");
    let trace = tmp.path().join("t.jsonl");
    let out = rigidref(
        &[
            "run",
            "stack.json",
            "--time",
            "2",
            "--every",
            "10",
            "--out",
            trace.to_str().unwrap(),
        ],
        &scenes,
    );
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("at rest") && stderr.contains("13 bodies, 1 pinned"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&trace).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines[0]["dimension"], 2);
    assert_eq!(lines[0]["gravity"], serde_json::json!([0.0, 1.0]));
    assert_eq!(lines.len(), 1 + 1 + 4);
    let keys: Vec<&String> = lines[1]["bodies"][0].as_object().unwrap().keys().collect();
    assert_eq!(keys, ["x", "theta", "v", "omega"]);
    for k in [
        "step",
        "t",
        "bodies",
        "energy",
        "momentum",
        "contact_count",
        "deepest_overlap",
    ] {
        assert!(lines[5].get(k).is_some(), "record lacks {k}");
    }
    // Each contact is recorded only when asked for (--all-contacts): they are most of a trace.
    assert!(lines[5].get("contacts").is_none(), "{}", lines[5]);
    // The same image with the same options from the command line gives the same trace.
    let trace2 = tmp.path().join("t2.jsonl");
    let out = rigidref(
        &[
            "run",
            "stack.png",
            "--time",
            "2",
            "--every",
            "10",
            "--substeps",
            "4",
            "--iterations",
            "50",
            "--order",
            "random",
            "--impulse",
            "15:0:40,0",
            "--out",
            trace2.to_str().unwrap(),
        ],
        &scenes,
    );
    assert!(out.status.success());
    let a: Vec<&str> = text.lines().skip(1).collect();
    let text2 = std::fs::read_to_string(&trace2).unwrap();
    let b: Vec<&str> = text2.lines().skip(1).collect();
    assert_eq!(a, b);
    // Render: PNG frames and a GIF.
    let frames = tmp.path().join("frames");
    let gif = tmp.path().join("a.gif");
    let out = rigidref(
        &[
            "render",
            "dominoes.json",
            "--time",
            "1",
            "--frame-every",
            "10",
            "--frames",
            frames.to_str().unwrap(),
            "--gif",
            gif.to_str().unwrap(),
            "--show-contacts",
            "--show-discs",
            "--opacity",
            "0.5",
        ],
        &scenes,
    );
    common::assert_success(&out);
    let n = std::fs::read_dir(&frames).unwrap().count();
    assert_eq!(n, 3, "frames at steps 0, 10, 20");
    let png = image::open(frames.join("frame-00020.png")).unwrap();
    assert!(png.width() > 100 && png.height() > 20);
    assert_eq!(&std::fs::read(&gif).unwrap()[..6], b"GIF89a");
}

#[test]
fn bad_2d_input_is_a_one_line_error() {
    let tmp = tempfile::tempdir().unwrap();
    let scenes = common::project_root().join("scenes/blocks");
    let white = tmp.path().join("white.png");
    image::RgbImage::from_pixel(5, 5, image::Rgb([255, 255, 255]))
        .save(&white)
        .unwrap();
    let not_png = tmp.path().join("fake.png");
    std::fs::write(&not_png, "not an image").unwrap();
    // Near-white (every channel ≥ 0.95 of full scale): empty space, so no bodies.
    let near_white = tmp.path().join("near_white.png");
    image::RgbImage::from_pixel(5, 5, image::Rgb([250, 246, 255]))
        .save(&near_white)
        .unwrap();
    let missing = tmp.path().join("missing.png");
    let bad_scene = tmp.path().join("bad.json");
    std::fs::write(
        &bad_scene,
        "{\"image\": \"x.png\", \"parameters\": {\"step\": -1}}",
    )
    .unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["run".into(), white.display().to_string()],
            "no non-white pixels",
        ),
        (
            vec!["run".into(), not_png.display().to_string()],
            "fake.png",
        ),
        (
            vec!["run".into(), bad_scene.display().to_string()],
            "bad.json:1:",
        ),
        (
            vec!["run".into(), near_white.display().to_string()],
            "no non-white pixels",
        ),
        (
            vec!["run".into(), missing.display().to_string()],
            "missing.png: cannot open",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--step".into(),
                "0".into(),
            ],
            "--step must be a positive number",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--step".into(),
                "-0.05".into(),
            ],
            "--step must be a positive number",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--mu".into(),
                "-0.5".into(),
            ],
            "--mu must be a number ≥ 0",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--gravity".into(),
                "-1".into(),
            ],
            "--gravity must be a number ≥ 0",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--white-threshold".into(),
                "1.5".into(),
            ],
            "--white-threshold must be in [0, 1)",
        ),
        (
            vec![
                "render".into(),
                "stack.png".into(),
                "--time".into(),
                "-3".into(),
                "--gif".into(),
                tmp.path().join("x.gif").display().to_string(),
            ],
            "--time must be a positive number",
        ),
        (
            vec![
                "factory".into(),
                "--drop-speed".into(),
                "-1".into(),
                "--out".into(),
                tmp.path().join("f").display().to_string(),
            ],
            "--drop-speed must be a number ≥ 0",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--restitution".into(),
                "2".into(),
            ],
            "--restitution must be in [0, 1]",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--impulse".into(),
                "1:0:oops".into(),
            ],
            "--impulse",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--impulse".into(),
                "1:99:1,0".into(),
            ],
            "body 99 does not exist",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--shake".into(),
                "0:1:2".into(),
            ],
            "--shake",
        ),
        // Scripts that would silently do nothing or something else: an impulse on the pinned
        // floor (body 12) is lost; a shake of a free body (0) would overwrite its velocity.
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--impulse".into(),
                "0:12:1,0".into(),
            ],
            "body 12 is pinned",
        ),
        (
            vec![
                "run".into(),
                "stack.png".into(),
                "--shake".into(),
                "0:1,0:0:1".into(),
            ],
            "body 0 is not pinned",
        ),
        (
            vec![
                "run".into(),
                "stack.json".into(),
                "--mu".into(),
                "0.2".into(),
            ],
            "sets its own parameters",
        ),
        (
            vec!["render".into(), "stack.png".into()],
            "nothing to write",
        ),
    ];
    // Absurd sizes are errors, not an aborted allocation or a run that never ends; options
    // that do not apply are refused, not ignored.
    let big = tmp.path().join("big.png");
    let mut pixels = image::RgbImage::from_pixel(3001, 3001, image::Rgb([255, 255, 255]));
    pixels.put_pixel(0, 0, image::Rgb([0, 0, 0]));
    pixels.put_pixel(3000, 3000, image::Rgb([0, 0, 0]));
    pixels.save(&big).unwrap();
    let flat = tmp.path().join("flat.png");
    let mut pixels = image::RgbImage::from_pixel(30, 4, image::Rgb([255, 255, 255]));
    (0..30).for_each(|x| pixels.put_pixel(x, 3, image::Rgb([0, 0, 163])));
    pixels.save(&flat).unwrap();
    let no_kind = tmp.path().join("neither.json");
    std::fs::write(&no_kind, "{\"imag\": \"stack.png\"}").unwrap();
    let penalty = tmp.path().join("penalty.json");
    std::fs::write(
        &penalty,
        format!(
            "{{\"image\": {:?}, \"parameters\": {{\"contact_model\": \"penalty\"}}}}",
            scenes.join("stack.png").display().to_string()
        ),
    )
    .unwrap();
    let dir = |name: &str| tmp.path().join(name).display().to_string();
    let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let more: Vec<(Vec<String>, &str)> = vec![
        (
            words(&["run", "stack.png", "--step", "1e-300"]),
            "more than the limit",
        ),
        (
            words(&[
                "render",
                &big.display().to_string(),
                "--steps",
                "1",
                "--scale",
                "64",
                "--frames",
                &dir("fr"),
            ]),
            "exceed the limit",
        ),
        (
            words(&[
                "factory",
                "--width",
                "100000000",
                "--depth",
                "5",
                "--out",
                &dir("f1"),
            ]),
            "more than the limit of 100 million blocks",
        ),
        (
            words(&["factory", "--piece-scale", "1000", "--out", &dir("f2")]),
            "--piece-scale may be at most 16",
        ),
        (
            words(&[
                "factory",
                "--container",
                &flat.display().to_string(),
                "--out",
                &dir("f3"),
            ]),
            "needs walls",
        ),
        (
            words(&["run", "stack.png", "--format", "csv"]),
            "JSON lines only",
        ),
        (
            words(&["run", "stack.png", "--no-collisions"]),
            "3D scenes only",
        ),
        (
            words(&["run", "../box_stack.json", "--mu", "0.5", "--substeps", "2"]),
            "--substeps, --mu apply to 2D scenes",
        ),
        (
            words(&[
                "render",
                "../box_stack.json",
                "--scale",
                "2",
                "--frames",
                &dir("fr"),
            ]),
            "--scale apply to 2D renders only",
        ),
        (
            words(&["run", &no_kind.display().to_string()]),
            "neither a 3D scene",
        ),
        (
            words(&["run", "stakc.json", "--mu", "0.3"]),
            "stakc.json: cannot open",
        ),
        (
            words(&["render", "stakc.json", "--frames", &dir("fr")]),
            "stakc.json: cannot open",
        ),
        (
            words(&["run", "../box_stack.json", "--rest-threshold", "0.1"]),
            "--rest-threshold applies to 2D",
        ),
        (
            words(&["factory", "--settle", "1e300", "--out", &dir("f4")]),
            "more than the limit",
        ),
        (
            words(&["crosscheck", "stack.json", "--time", "1e300"]),
            "more than the limit",
        ),
        (
            words(&["contacts", &penalty.display().to_string()]),
            "penalty contacts",
        ),
    ];
    for (args, says) in cases.into_iter().chain(more) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = rigidref(&args, &scenes);
        let stderr = common::stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| !l.starts_with("warning:"))
            .collect();
        assert_eq!(errors.len(), 1, "{args:?}: {stderr}");
        assert!(
            errors[0].contains(says) && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
    }
    // render does not offer run's outputs at all (it writes --frames and --gif): the argument
    // parser refuses them as unknown, with its usage status 2.
    for flag in ["--every", "--out", "--format", "--dump-problems"] {
        let out = rigidref(
            &["render", "stack.png", flag, "3", "--frames", &dir("fr")],
            &scenes,
        );
        let stderr = common::stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{flag}: {stderr}");
        assert!(
            stderr.contains(&format!("unexpected argument '{flag}'")),
            "{flag}: {stderr}"
        );
    }
}

/// A run whose state overflows (absurd but positive parameters) stops at the first non-finite
/// quantity with a one-line error naming the step, and keeps the trace written so far, every
/// line of it valid JSON with finite numbers.
#[test]
fn a_2d_run_that_overflows_stops_naming_the_step_and_keeps_its_trace() {
    let tmp = tempfile::tempdir().unwrap();
    let trace = tmp.path().join("t.jsonl");
    let out = rigidref(
        &[
            "run",
            "stack.png",
            "--gravity",
            "1e100",
            "--step",
            "1e100",
            "--out",
            trace.to_str().unwrap(),
        ],
        &common::project_root().join("scenes/blocks"),
    );
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    // One error line (a step longer than --time is also noted, on its own line).
    let errors: Vec<&str> = stderr.lines().filter(|l| !l.starts_with("note:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(
        stderr.contains("non-finite") && stderr.contains("at step 1"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&trace).unwrap();
    assert_eq!(text.lines().count(), 2, "header and the step-0 record");
    for line in text.lines() {
        assert!(!line.contains("null"), "{line}");
        serde_json::from_str::<serde_json::Value>(line).unwrap();
    }
}

/// `rigidref contacts IMAGE` prints every quantity of a 2D contact solve: the frame, the 2 × 6
/// Jacobian, the 2 × 2 Delassus block, b, λ₀ and λ. They agree with the problem file `run
/// --dump-problems` writes for the same step (two inspection paths, one problem), the Delassus
/// block is symmetric with a positive diagonal, n ⟂ t, and λ is feasible (λn ≥ 0, |λt| ≤ μ λn).
#[test]
fn contacts_command_prints_a_2d_solve_consistent_with_its_problem_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = common::project_root().join("scenes/blocks");
    let out = rigidref(&["contacts", "stack.png", "--json"], &dir);
    common::assert_success(&out);
    let shown: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(shown["dimension"], 2);
    let step = shown["step"].as_u64().unwrap();
    let substep = shown["substep"].as_u64().unwrap();
    let mu = shown["mu"].as_f64().unwrap();
    let contacts = shown["contacts"].as_array().unwrap();
    assert!(!contacts.is_empty());

    let dump = tmp.path().join("p");
    let out = rigidref(
        &[
            "run",
            "stack.png",
            "--steps",
            &step.to_string(),
            "--quiet",
            "--out",
            tmp.path().join("t.jsonl").to_str().unwrap(),
            "--dump-problems",
            dump.to_str().unwrap(),
        ],
        &dir,
    );
    assert!(out.status.success());
    let file: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dump.join(format!("step-{step:06}-{substep:02}.json"))).unwrap(),
    )
    .unwrap();
    let file_contacts = file["contacts"].as_array().unwrap();
    let lambdas = file["solution"]["lambda"].as_array().unwrap();
    assert_eq!(file_contacts.len(), contacts.len());
    let numbers = |v: &serde_json::Value| -> Vec<f64> {
        let mut out = Vec::new();
        let mut stack = vec![v.clone()];
        while let Some(v) = stack.pop() {
            match v {
                serde_json::Value::Array(a) => stack.extend(a.into_iter().rev()),
                serde_json::Value::Number(n) => out.push(n.as_f64().unwrap()),
                _ => panic!("not a number: {v}"),
            }
        }
        out
    };
    for ((c, f), l) in contacts.iter().zip(file_contacts).zip(lambdas) {
        assert_eq!(numbers(&c["jacobian"]).len(), 12);
        // The printed Jacobian is [J₁ | J₂] row by row; the file's is J₁ then J₂.
        let j = numbers(&c["jacobian"]);
        let jf = numbers(&f["jacobian"]);
        let joined: Vec<f64> = (0..2)
            .flat_map(|r| [&jf[3 * r..3 * r + 3], &jf[6 + 3 * r..6 + 3 * r + 3]].concat())
            .collect();
        assert_eq!(j, joined);
        assert_eq!(numbers(&c["b"]), numbers(&f["b"]));
        assert_eq!(numbers(&c["lambda0"]), numbers(&f["lambda0"]));
        assert_eq!(numbers(&c["lambda"]), numbers(l));
        // A = J₁ M₁⁻¹ J₁ᵀ + J₂ M₂⁻¹ J₂ᵀ from the file's own inverse masses; 1e-12 of the
        // block's largest entry leaves room for a different summation order only.
        let a = numbers(&c["delassus"]);
        let mut expected = [0.0; 4];
        for (side, body) in f["bodies"].as_array().unwrap().iter().enumerate() {
            let Some(b) = body.as_i64().filter(|&b| b >= 0) else {
                continue;
            };
            let minv = numbers(&file["bodies"][b as usize]["inverse_mass"]);
            let js = &jf[6 * side..6 * side + 6];
            for r in 0..2 {
                for c in 0..2 {
                    for i in 0..3 {
                        for k in 0..3 {
                            expected[2 * r + c] += js[3 * r + i] * minv[3 * i + k] * js[3 * c + k];
                        }
                    }
                }
            }
        }
        let largest = expected.iter().fold(0.0f64, |m, y| m.max(y.abs()));
        for (x, y) in a.iter().zip(expected) {
            assert!((x - y).abs() <= 1e-12 * largest, "{a:?} vs {expected:?}");
        }
        assert!(a[0] > 0.0 && a[3] > 0.0, "{a:?}");
        // n is a unit vector and t is n turned by +90°, as documented.
        let (n, t) = (numbers(&c["n"]), numbers(&c["t"]));
        assert!((n[0].hypot(n[1]) - 1.0).abs() < 1e-15, "{n:?}");
        assert_eq!(t, vec![-n[1], n[0]]);
        let lambda = numbers(&c["lambda"]);
        assert!(lambda[0] >= 0.0 && lambda[1].abs() <= mu * lambda[0] * (1.0 + 1e-12));
    }
    // The table form names the Delassus block, and a step without contacts is a clear error.
    let out = rigidref(&["contacts", "stack.png"], &dir);
    assert!(String::from_utf8_lossy(&out.stdout).contains("A      = J M⁻¹ Jᵀ"));
    let out = rigidref(&["contacts", "stack.png", "--step", "1"], &dir);
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("step 1 has no contacts"), "{stderr}");
}

/// A 2D scene file's `"preset": "starter"` starts from the Java starter's values, which its
/// other keys override; without a preset the defaults are the demonstration settings.
#[test]
fn a_scene_file_preset_starts_from_the_starter_and_its_keys_override_it() {
    use rigidref::blocks2d::params::Params2;
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(
        common::project_root().join("scenes/blocks/stack.png"),
        tmp.path().join("stack.png"),
    )
    .unwrap();
    let load = |parameters: &str| {
        let path = tmp.path().join("scene.json");
        std::fs::write(
            &path,
            format!(r#"{{"image": "stack.png", "parameters": {parameters}}}"#),
        )
        .unwrap();
        rigidref::blocks2d::scene::load_scene2(&path)
            .unwrap()
            .world
            .params
    };
    assert_eq!(load("{}"), Params2::demonstration());
    assert_eq!(load(r#"{"preset": "starter"}"#), Params2::starter());
    assert_eq!(
        load(r#"{"preset": "starter", "iterations": 30}"#),
        Params2 {
            iterations: 30,
            ..Params2::starter()
        }
    );
    assert_ne!(Params2::starter(), Params2::demonstration());
}

/// The 2D summary is not silent about what the run changed (docs/blocks2d.md §"Running"): it
/// leads the energy line with the total and its change (in a pile the potential dominates), gives
/// the post-stabilisation solve's worst residual, and warns when a scripted impulse falls after
/// the end of the run (stack.json's impulse at t = 15, run for 0.5).
#[test]
fn a_2d_summary_reports_total_energy_post_stabilisation_and_unapplied_impulses() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/blocks/stack.json");
    let out = common::rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "0.5",
            "--out",
            "t.jsonl",
        ],
        tmp.path(),
    );
    assert!(out.status.success());
    let err = common::stderr(&out);
    let energy = err.lines().find(|l| l.starts_with("energy")).unwrap();
    assert!(
        energy.contains(" → ") && energy.contains("change") && energy.contains("potential"),
        "{energy}"
    );
    assert!(err.contains("post-stab.     worst residual"), "{err}");
    assert!(
        err.contains(
            "1 scripted impulse(s) from t = 15 were never applied: the run ended at t = 0.5"
        ),
        "{err}"
    );
    // Run past the impulse: no warning.
    let out = common::rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "15.05",
            "--every",
            "100",
            "--out",
            "t.jsonl",
            "-q",
        ],
        tmp.path(),
    );
    assert!(!common::stderr(&out).contains("never applied"));
}
