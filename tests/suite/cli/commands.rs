//! The command-line program: the default run, the trace formats, determinism.

use crate::common;

use rigidref::rigid3d::trace::{FORMAT_NAME, csv_columns, read_trace};

use common::rigidref;

/// `cargo run --release` with no arguments runs the embedded scene and writes trace.jsonl.
#[test]
fn run_without_a_scene_uses_the_embedded_default() {
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(&["--steps", "50"], tmp.path());
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{stderr}");
    for row in [
        "scene",
        "bodies",
        "steps",
        "wall time",
        "energy",
        "momentum drift",
        "trace",
    ] {
        assert!(stderr.contains(row), "summary lacks {row}: {stderr}");
    }
    let trace = read_trace(
        std::io::BufReader::new(std::fs::File::open(tmp.path().join("trace.jsonl")).unwrap()),
        "t",
    )
    .unwrap();
    assert_eq!(trace.header.format, FORMAT_NAME);
    // The run names the compiled-in copy it ran, not a file that may not be there.
    assert_eq!(
        trace.header.source,
        "built-in (compiled-in copy of scenes/dzhanibekov.json)"
    );
    assert!(stderr.contains("built-in"), "{stderr}");
    assert_eq!(trace.records.len(), 51);
    assert_eq!(trace.records[50].step, 50);
}

/// The header and record lines have exactly the keys docs/trace-format.md lists, in that order.
#[test]
fn trace_lines_have_the_documented_keys() {
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(
        &["run", "--steps", "3", "--quiet", "--out", "-"],
        tmp.path(),
    );
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let keys = |v: &serde_json::Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(
        keys(&lines[0]),
        [
            "format",
            "version",
            "dimension",
            "scene",
            "source",
            "dt",
            "substeps",
            "gravity",
            "integrator",
            "collision",
            "bodies"
        ]
    );
    assert_eq!(keys(&lines[0]["bodies"][0]), ["name", "mass"]);
    assert_eq!(
        keys(&lines[1]),
        [
            "step",
            "t",
            "bodies",
            "energy",
            "momentum",
            "contacts",
            "penetration"
        ]
    );
    assert_eq!(keys(&lines[1]["bodies"][0]), ["x", "R", "v", "omega"]);
    assert_eq!(
        keys(&lines[1]["energy"]),
        ["kinetic_linear", "kinetic_angular", "potential", "total"]
    );
    assert_eq!(
        keys(&lines[1]["momentum"]),
        ["linear", "angular", "angular_com"]
    );
    assert_eq!(lines.len(), 5);
}

/// --every K records the first, every K-th and the last frame.
#[test]
fn every_records_first_multiples_and_last() {
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(
        &[
            "run", "--steps", "25", "--every", "10", "--quiet", "--out", "t.jsonl",
        ],
        tmp.path(),
    );
    assert!(out.status.success());
    let trace = read_trace(
        std::io::BufReader::new(std::fs::File::open(tmp.path().join("t.jsonl")).unwrap()),
        "t",
    )
    .unwrap();
    let steps: Vec<u64> = trace.records.iter().map(|r| r.step).collect();
    assert_eq!(steps, [0, 10, 20, 25]);
}

/// The CSV has one header row and rows of numbers of the same width, as numpy/pandas expect,
/// and carries the same numbers as the JSON Lines trace.
#[test]
fn csv_trace_is_a_flat_numeric_table_matching_the_jsonl_trace() {
    let tmp = tempfile::tempdir().unwrap();
    assert!(
        rigidref(
            &["run", "--steps", "20", "--quiet", "--out", "t.csv"],
            tmp.path()
        )
        .status
        .success()
    );
    assert!(
        rigidref(
            &["run", "--steps", "20", "--quiet", "--out", "t.jsonl"],
            tmp.path()
        )
        .status
        .success()
    );
    let text = std::fs::read_to_string(tmp.path().join("t.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, csv_columns(1));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 21);
    assert!(rows.iter().all(|r| r.len() == header.len()));
    let trace = read_trace(
        std::io::BufReader::new(std::fs::File::open(tmp.path().join("t.jsonl")).unwrap()),
        "t",
    )
    .unwrap();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (row, record) in rows.iter().zip(&trace.records) {
        assert_eq!(row[col("b0_y")], record.bodies[0].x[1]);
        assert_eq!(row[col("b0_R12")], record.bodies[0].rotation[1][2]);
        assert_eq!(row[col("b0_wy")], record.bodies[0].omega[1]);
        assert_eq!(row[col("total")], record.energy.total);
        assert_eq!(row[col("Lcom_z")], record.momentum.angular_com[2]);
    }
}

/// Two runs of the same scene write byte-identical traces.
#[test]
fn same_inputs_give_a_bitwise_identical_trace() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/tumbling_brick.json");
    let scene = scene.to_str().unwrap();
    for name in ["a.jsonl", "b.jsonl"] {
        assert!(
            rigidref(
                &["run", scene, "--time", "3", "--quiet", "--out", name],
                tmp.path()
            )
            .status
            .success()
        );
    }
    let a = std::fs::read(tmp.path().join("a.jsonl")).unwrap();
    let b = std::fs::read(tmp.path().join("b.jsonl")).unwrap();
    assert!(a.len() > 10_000);
    assert!(a == b, "traces differ");
}

/// Every canonical scene in scenes/ loads without warnings and runs.
#[test]
fn canonical_scenes_load_cleanly_and_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = common::project_root().join("scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let out = rigidref(
                &[
                    "run",
                    path.to_str().unwrap(),
                    "--time",
                    "2",
                    "--out",
                    "t.jsonl",
                ],
                tmp.path(),
            );
            let stderr = common::stderr(&out);
            assert!(out.status.success(), "{}: {stderr}", path.display());
            assert!(!stderr.contains("warning"), "{}: {stderr}", path.display());
            count += 1;
        }
    }
    assert!(count >= 5);
}

/// `rigidref scene` shows the defaults it filled in.
#[test]
fn scene_command_prints_the_resolved_parameters() {
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(&["scene"], tmp.path());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(
        stdout.contains("pgs_iterations   100") && stdout.contains("integrator       spatial"),
        "{stdout}"
    );
}

/// `run --help` documents the scene keys this project adds.
#[test]
fn run_help_documents_the_project_scene_keys() {
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(&["run", "--help"], tmp.path());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("integrator")
            && stdout.contains("implicit_gyroscopic")
            && stdout.contains("file_root"),
        "{stdout}"
    );
}

fn scenes_dir() -> std::path::PathBuf {
    common::project_root().join("scenes")
}

/// `rigidref contacts` prints the first contact of a sphere drop: the quantities the assignment
/// asks students to inspect, as JSON and as a table.
#[test]
fn contacts_command_prints_the_first_contact_of_scene2() {
    let mut scenes = vec![("sphere_drop.json".to_string(), scenes_dir())];
    if let Some(dir) = common::rigid3d_assignment() {
        scenes.push(("scene2.json".to_string(), dir.join("scenes")));
    }
    for (name, dir) in scenes {
        let out = rigidref(&["contacts", &name, "--json"], &dir);
        common::assert_success(&out);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let contacts = v["contacts"].as_array().unwrap();
        assert_eq!(contacts.len(), 1, "{name}: one vertex lands first");
        let c = &contacts[0];
        assert_eq!(c["bodies"], serde_json::json!([0, -1]));
        assert_eq!(c["n"], serde_json::json!([0.0, 1.0, 0.0]));
        let j: Vec<Vec<f64>> = serde_json::from_value(c["jacobian"].clone()).unwrap();
        assert_eq!(j.len(), 3);
        assert_eq!(j[0].len(), 12);
        // Normal row: [0 1 0 | −r_z 0 r_x | 0 …] with r almost vertical.
        assert_eq!(&j[0][..3], &[0.0, 1.0, 0.0]);
        assert!(
            j[0][3..].iter().all(|x| x.abs() < 1e-6),
            "{name}: {:?}",
            j[0]
        );
        let a: Vec<Vec<f64>> = serde_json::from_value(c["delassus"].clone()).unwrap();
        for (r, row) in a.iter().enumerate() {
            for (s, entry) in row.iter().enumerate() {
                assert_eq!(*entry, a[s][r], "{name}: A is symmetric to the bit");
            }
        }
        let lambda: Vec<f64> = serde_json::from_value(c["lambda"].clone()).unwrap();
        assert!(lambda[0] > 0.0, "{name}: the ground pushes up");
        // The table says the same in words.
        let out = rigidref(&["contacts", &name], &dir);
        let table = String::from_utf8_lossy(&out.stdout);
        for word in [
            "contact 0: body 1 = 0",
            "body 2 = ground",
            "J      =",
            "A      = J M⁻¹ Jᵀ",
            "b      =",
            "λ      =",
        ] {
            assert!(
                table.contains(word),
                "{name}: table lacks {word:?}:\n{table}"
            );
        }
    }
    // A step without contacts is an error, not an empty answer.
    let out = rigidref(
        &["contacts", "sphere_drop.json", "--step", "3"],
        &scenes_dir(),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(common::stderr(&out).contains("step 3 has no contacts"));
}

/// With `stop_on_contact` the run ends at the first frame with contacts, which it records.
#[test]
fn stop_on_contact_stops_at_the_first_contact_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scenes_dir().join("sphere_drop.json"))
        .unwrap()
        .replace(
            "\"substeps\": 1",
            "\"substeps\": 1, \"stop_on_contact\": true",
        );
    let scene = tmp.path().join("stop.json");
    std::fs::write(&scene, text).unwrap();
    let trace_path = tmp.path().join("t.jsonl");
    // Run from scenes/ so that file_root "data/ball" resolves through the working directory.
    let out = rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "5",
            "--every",
            "10",
            "--out",
            trace_path.to_str().unwrap(),
        ],
        &scenes_dir(),
    );
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("stop_on_contact: stopped at the first frame with contacts, step 46"),
        "{stderr}"
    );
    // The summary counts the steps that ran, not the 500 asked for.
    assert!(
        stderr.contains("steps          46 × 1 substeps"),
        "{stderr}"
    );
    let trace = read_trace(
        std::io::BufReader::new(std::fs::File::open(&trace_path).unwrap()),
        "t",
    )
    .unwrap();
    let last = trace.records.last().unwrap();
    assert_eq!(
        last.step, 46,
        "the contact frame is recorded even off the --every grid"
    );
    assert!(!last.contacts.is_empty());
    assert!(
        trace.records[..trace.records.len() - 1]
            .iter()
            .all(|r| r.contacts.is_empty())
    );
}

/// `--dump-problems DIR` writes one problem file per frame with contacts (substeps = 1), each
/// readable as a contact problem and carrying the λ the trace reports.
#[test]
fn dump_problems_writes_one_readable_file_per_contact_step() {
    let tmp = tempfile::tempdir().unwrap();
    let dump = tmp.path().join("problems");
    let trace_path = tmp.path().join("t.jsonl");
    let out = rigidref(
        &[
            "run",
            "sphere_drop.json",
            "--time",
            "1",
            "--quiet",
            "--dump-problems",
            dump.to_str().unwrap(),
            "--out",
            trace_path.to_str().unwrap(),
        ],
        &scenes_dir(),
    );
    common::assert_success(&out);
    let trace = read_trace(
        std::io::BufReader::new(std::fs::File::open(&trace_path).unwrap()),
        "t",
    )
    .unwrap();
    let with_contacts: Vec<_> = trace
        .records
        .iter()
        .filter(|r| !r.contacts.is_empty())
        .collect();
    let mut files: Vec<_> = std::fs::read_dir(&dump)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), with_contacts.len());
    assert!(!files.is_empty());
    for (path, record) in files.iter().zip(&with_contacts) {
        assert_eq!(
            path.file_name().unwrap().to_str().unwrap(),
            format!("step-{:06}-00.json", record.step)
        );
        let file = rigidref::problem::json::ProblemFile::read(path).unwrap();
        let problem: rigidref::problem::ContactProblem3 = file.to_problem().unwrap();
        assert_eq!(problem.contacts.len(), record.contacts.len());
        let solution = file.solution.unwrap();
        for (l, c) in solution.lambda.iter().zip(&record.contacts) {
            assert_eq!(l.as_slice(), c.lambda.as_slice());
        }
        assert_eq!(file.step, Some(record.step));
    }
}

/// Both systems' summaries give the same solver figures (solves, PGS sweeps, worst residual,
/// deepest penetration), so that the effect of warm start or more sweeps shows without a CSV.
#[test]
fn summaries_report_the_same_solver_figures_in_both_systems() {
    let tmp = tempfile::tempdir().unwrap();
    let root = common::project_root();
    for (scene, time) in [
        ("scenes/sphere_drop.json", "2"),
        ("scenes/blocks/stack.json", "4"),
    ] {
        let out = rigidref(
            &[
                "run",
                root.join(scene).to_str().unwrap(),
                "--time",
                time,
                "--out",
                "t.jsonl",
            ],
            tmp.path(),
        );
        let stderr = common::stderr(&out);
        assert!(out.status.success(), "{scene}: {stderr}");
        let line = stderr
            .lines()
            .find(|l| l.starts_with("contacts"))
            .unwrap_or_else(|| panic!("{scene}: no contacts line: {stderr}"));
        for figure in [
            "solves in",
            "sweeps on average",
            "worst residual",
            "deepest penetration",
        ] {
            assert!(line.contains(figure), "{scene}: {line}");
        }
    }
}

/// `rigidref run SCENE.json --preset starter` is `--set preset=starter` (the same trace, bit for
/// bit); the summary's preset line and the trace header show the starter's collision detection
/// and tangents as in effect, a key given overrides them, `rigidref scene` prints both, and a
/// default run's header is unchanged (no `tangents` key). docs/scene-format.md §"The starter
/// preset".
#[test]
fn the_3d_starter_preset_is_taken_from_the_command_line_and_shown() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/box_stack.json");
    let scene = scene.to_str().unwrap();
    let header = |name: &str| -> serde_json::Value {
        let text = std::fs::read_to_string(tmp.path().join(name)).unwrap();
        serde_json::from_str(text.lines().next().unwrap()).unwrap()
    };
    let run = |extra: &[&str], out: &str| {
        let mut args = vec!["run", scene, "--steps", "30", "--out", out];
        args.extend_from_slice(extra);
        let o = rigidref(&args, tmp.path());
        let stderr = common::stderr(&o);
        assert!(o.status.success(), "{extra:?}: {stderr}");
        stderr
    };
    let stderr = run(&["--preset", "starter"], "a.jsonl");
    assert!(
        stderr.contains("preset         starter")
            && stderr.contains("warm_start false, stabilization 0, collision starter, tangents starter, pgs_iterations 100"),
        "{stderr}"
    );
    let h = header("a.jsonl");
    assert_eq!(h["collision"], "starter", "{h}");
    assert_eq!(h["tangents"], "starter", "{h}");
    assert_eq!(h["overrides"], serde_json::json!(["preset=starter"]), "{h}");
    run(&["--set", "preset=starter"], "b.jsonl");
    assert_eq!(
        std::fs::read(tmp.path().join("a.jsonl")).unwrap(),
        std::fs::read(tmp.path().join("b.jsonl")).unwrap()
    );
    // A key given overrides the preset's, and the line says so.
    let stderr = run(
        &["--preset", "starter", "--set", "tangents=orthonormal"],
        "c.jsonl",
    );
    assert!(
        stderr.contains("collision starter, tangents orthonormal"),
        "{stderr}"
    );
    assert!(header("c.jsonl").get("tangents").is_none());
    // The default: vertices, orthonormal tangents, and no `tangents` in the header.
    let stderr = run(&[], "d.jsonl");
    assert!(!stderr.contains("preset "), "{stderr}");
    let h = header("d.jsonl");
    assert_eq!(h["collision"], "vertices", "{h}");
    assert!(h.get("tangents").is_none(), "{h}");
    // Both ways at once is refused, naming them.
    let o = rigidref(
        &[
            "run",
            scene,
            "--steps",
            "1",
            "--preset",
            "starter",
            "--set",
            "preset=default",
        ],
        tmp.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(common::stderr(&o).contains("--preset and --set preset="));
    let o = rigidref(&["scene", scene, "--set", "preset=starter"], tmp.path());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("collision        starter") && stdout.contains("tangents         starter"),
        "{stdout}"
    );
    let o = rigidref(&["scene", scene], tmp.path());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("collision        vertices")
            && stdout.contains("tangents         orthonormal"),
        "{stdout}"
    );
    // `run --help` lists the key and the starter's values.
    let o = rigidref(&["run", "--help"], tmp.path());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("    tangents          ")
            && stdout.contains("Python starter's collision.py"),
        "{stdout}"
    );
}

/// `--set KEY=VALUE` overrides a scene parameter in both systems, is checked exactly as the
/// file's value (a bad key or value is a one-line error naming the key, exit 1), and shows in
/// the summary and the trace header.
#[test]
fn set_overrides_scene_parameters_in_both_systems_and_is_checked_like_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let root = common::project_root();
    let scene3 = root.join("scenes/sliding_box.json");
    let scene2 = root.join("scenes/blocks/stack.json");
    let image = root.join("scenes/blocks/stack.png");
    let header = |path: &std::path::Path| -> serde_json::Value {
        let text = std::fs::read_to_string(path).unwrap();
        serde_json::from_str(text.lines().next().unwrap()).unwrap()
    };
    for (scene, sets, key, expect) in [
        (
            &scene3,
            ["pgs_iterations=7", "integrator=body"],
            "integrator",
            "body",
        ),
        (
            &scene2,
            ["preset=starter", "image_reader=rigidref"],
            "preset",
            "starter",
        ),
        (&image, ["iterations=7", "mu=0.5"], "mu", "0.5"),
    ] {
        let out = rigidref(
            &[
                "run",
                scene.to_str().unwrap(),
                "--steps",
                "3",
                "--out",
                "t.jsonl",
                "--set",
                sets[0],
                "--set",
                sets[1],
            ],
            tmp.path(),
        );
        let stderr = common::stderr(&out);
        assert!(out.status.success(), "{sets:?}: {stderr}");
        assert!(
            stderr.contains(&format!("overrides      {}, {}", sets[0], sets[1])),
            "{stderr}"
        );
        let h = header(&tmp.path().join("t.jsonl"));
        assert_eq!(h["overrides"], serde_json::json!(sets), "{h}");
        assert!(sets.contains(&format!("{key}={expect}").as_str()));
    }
    // An override that renumbers the image's bodies is refused on a scene file that names
    // bodies by index (stack.json strikes body 0): it would strike another body, silently.
    let out = rigidref(
        &[
            "run",
            scene2.to_str().unwrap(),
            "--steps",
            "3",
            "--out",
            "t.jsonl",
            "--set",
            "preset=starter",
        ],
        tmp.path(),
    );
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("would name other bodies") && stderr.contains("image_reader=rigidref"),
        "{stderr}"
    );
    // The override takes effect: the summary of a 3D run shows the integrator and the sweeps.
    let out = rigidref(
        &[
            "run",
            scene3.to_str().unwrap(),
            "--steps",
            "20",
            "--out",
            "t.jsonl",
            "--set",
            "pgs_iterations=7",
        ],
        tmp.path(),
    );
    let stderr = common::stderr(&out);
    assert!(stderr.contains("PGS 7.0 sweeps on average"), "{stderr}");
    // Without overrides the header has no such key (traces are unchanged).
    rigidref(
        &[
            "run",
            scene3.to_str().unwrap(),
            "--steps",
            "1",
            "--out",
            "u.jsonl",
            "-q",
        ],
        tmp.path(),
    );
    assert!(
        header(&tmp.path().join("u.jsonl"))
            .get("overrides")
            .is_none()
    );
    for (scene, set, says) in [
        (
            &scene3,
            "pgs_iterations=0",
            "--set pgs_iterations=0: must be a whole number ≥ 1",
        ),
        (&scene3, "pgs_iterations=many", "--set pgs_iterations="),
        (
            &scene3,
            "bogus=1",
            "--set bogus: not a key of sim_parameters",
        ),
        (&scene3, "mu", "--set \"mu\": expected KEY=VALUE"),
        (&scene2, "iterations=-3", "--set iterations=-3"),
        (
            &image,
            "restitution=2",
            "--set restitution=2: restitution must be in [0, 1]",
        ),
        (
            &image,
            "nonsense=2",
            "--set nonsense: not a key of a 2D scene's parameters",
        ),
        (
            &image,
            "pgs_order=coloured",
            "--set pgs_order: not a key of a 2D scene's parameters (its 2D name is `order`)",
        ),
        (
            &scene3,
            "order=coloured",
            "--set order: not a key of sim_parameters (its 3D name is `pgs_order`)",
        ),
    ] {
        let out = rigidref(
            &[
                "run",
                scene.to_str().unwrap(),
                "--steps",
                "1",
                "-q",
                "--out",
                "t.jsonl",
                "--set",
                set,
            ],
            tmp.path(),
        );
        let stderr = common::stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{set}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{set}: {stderr}");
        assert!(stderr.contains(says), "{set}: {stderr}");
    }
}

/// The options a subcommand's `--help` lists, by long name (`--help` and `--version` left out).
fn help_options(command: &str, dir: &std::path::Path) -> Vec<String> {
    let out = rigidref(&[command, "--help"], dir);
    assert!(out.status.success());
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l
                .strip_prefix("-q, ")
                .or(l.strip_prefix("-o, "))
                .unwrap_or(l);
            let name: String = l
                .strip_prefix("--")?
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '-')
                .collect();
            (!name.is_empty() && name != "help" && name != "version").then(|| format!("--{name}"))
        })
        .collect()
}

/// Every option a subcommand's `--help` lists is accepted by that subcommand: for each, a run
/// with the option (and a value that fits it) on one of the subcommand's inputs succeeds. An
/// option listed in `--help` and then refused, whatever the input, fails this; so does an option
/// added without a value here.
#[test]
fn every_option_a_subcommand_lists_is_accepted_by_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let root = common::project_root();
    let path = |p: &str| root.join(p).to_str().unwrap().to_string();
    // A copy of scenes/ and golden/, so that `golden --update` rewrites the copy.
    for sub in ["scenes", "golden"] {
        let _ = std::process::Command::new("cp")
            .args(["-r", &path(sub), dir.to_str().unwrap()])
            .status();
    }
    let (box3, stack2, ball3) = (
        path("scenes/sliding_box.json"),
        path("scenes/blocks/stack.png"),
        path("scenes/sphere_drop.json"),
    );
    let tube = common::blocks2d_assignment().map(|d| d.join("tetrisTube.png"));
    let value = |command: &str, option: &str| -> Vec<String> {
        let v: &[&str] = match (command, option) {
            (_, "--time") if command == "crosscheck" => &["0.05"],
            ("contacts", "--time") => &["1"],
            (_, "--time") => &["0.1"],
            ("contacts", "--step") => &["46"],
            (_, "--steps") => &["2"],
            (_, "--set") => &["mu=0.1"],
            ("factory", "--out") | ("massprops", "--out") => &["outdir/x"],
            ("bench", "--out") => &["benchdir"],
            ("bench", "--only") => &["grid"],
            ("bench", "--contact-order") => &["coloured"],
            (_, "--threads") => &["2"],
            ("factory", "--order") => &["coloured"],
            (_, "--out") => &["t.jsonl"],
            (_, "--every") | (_, "--frame-every") => &["2"],
            (_, "--format") => &["jsonl"],
            (_, "--dump-problems") => &["problems"],
            (_, "--preset") => &["starter"],
            (_, "--inertia") => &["block_centres"],
            (_, "--image-reader") => &["starter"],
            (_, "--disc-tree") => &["starter"],
            (_, "--step") => &["0.05"],
            (_, "--substeps") => &["2"],
            (_, "--gravity") => &["1"],
            (_, "--gravity-angle") => &["90"],
            (_, "--mu") => &["0.3"],
            (_, "--restitution") => &["0.1"],
            (_, "--iterations") => &["5"],
            (_, "--pgs-tolerance") => &["1e-6"],
            (_, "--order") => &["random"],
            (_, "--seed") => &["3"],
            (_, "--slop") => &["0.01"],
            (_, "--contact-model") => &["penalty"],
            (_, "--white-threshold") => &["0.05"],
            (_, "--max-travel") => &["0.25"],
            (_, "--impulse") => &["0:0:1,0"],
            // Body 12 of stack.png is its pinned (all-blue) floor: only a pinned body is shaken.
            (_, "--shake") => &["12:1,0:0:1"],
            (_, "--rest-threshold") => &["0.001"],
            (_, "--nut-report") => &["nuts.csv"],
            (_, "--scaling-csv") => &["scaling.csv"],
            (_, "--frames") => &["frames"],
            (_, "--gif") => &["a.gif"],
            (_, "--scale") => &["2"],
            (_, "--opacity") => &["0.5"],
            (_, "--substep") => &["0"],
            (_, "--tolerance") => &["1e-5"],
            (_, "--objective-tolerance") => &["1e-8"],
            (_, "--root") => &["."],
            (_, "--density") => &["1000"],
            (_, "--bodies") => &["5"],
            (_, "--batch") => &["5"],
            (_, "--interval") => &["1"],
            (_, "--drop-speed") => &["5"],
            (_, "--settle") => &["0"],
            (_, "--width") | (_, "--height") => &["20"],
            (_, "--azimuth") => &["45"],
            (_, "--elevation") => &["30"],
            (_, "--orbit") => &["10"],
            (_, "--mp4") => &["a.mp4"],
            (_, "--view-every") => &["2"],
            ("render", "--trace") => &["r.jsonl"],
            (_, "--depth") => &["12"],
            (_, "--pieces") => &["tetris"],
            (_, "--pgs-local-solve") => &["exact"],
            (_, "--piece-scale") => &["2"],
            (_, "--max-input-mb") => &["1024"],
            (_, "--max-image-pixels") => &["16777216"],
            // Flags.
            (
                _,
                "--quiet"
                | "--no-collisions"
                | "--no-warm-start"
                | "--no-post-stabilization"
                | "--shock-propagation"
                | "--quick"
                | "--show-contacts"
                | "--no-overlay"
                | "--show-discs"
                | "--json"
                | "--table"
                | "--strict"
                | "--rapier"
                | "--update"
                | "--all-contacts"
                | "--persistent-manifolds",
            ) => &[],
            ("factory", "--container") => {
                return tube.iter().map(|p| p.display().to_string()).collect();
            }
            _ => panic!("{command} {option}: no value in this test; add one"),
        };
        v.iter().map(|s| s.to_string()).collect()
    };
    // Each subcommand's inputs (the option may fit only one of them), and how long to run.
    // (subcommand, its inputs, the run length added unless the option replaces it)
    type Command<'a> = (&'a str, Vec<Vec<String>>, Vec<&'a str>);
    let commands: [Command; 9] = [
        (
            "run",
            vec![vec![box3.clone()], vec![stack2.clone()]],
            vec!["--steps", "2"],
        ),
        (
            "render",
            vec![
                vec![stack2.clone(), "--gif".into(), "g.gif".into()],
                vec![box3.clone(), "--gif".into(), "g.gif".into()],
            ],
            vec!["--steps", "2"],
        ),
        (
            "contacts",
            vec![vec![ball3.clone()], vec![stack2.clone()]],
            vec![],
        ),
        (
            "crosscheck",
            vec![vec![box3.clone()]],
            vec!["--time", "0.05"],
        ),
        ("golden", vec![vec![]], vec![]),
        ("scene", vec![vec![box3.clone()]], vec![]),
        (
            "massprops",
            vec![vec![path("scenes/src/block.obj")]],
            vec![],
        ),
        (
            "factory",
            vec![vec!["--out".into(), "f".into()]],
            vec!["--bodies", "5", "--settle", "0"],
        ),
        ("bench", vec![vec!["--quick".into()]], vec![]),
    ];
    let mut tried = 0;
    for (command, inputs, length) in &commands {
        for option in help_options(command, dir) {
            if option == "--container" && tube.is_none() {
                continue; // needs ../shared's tetrisTube.png
            }
            if option == "--mp4" && !common::has_ffmpeg() {
                eprintln!("SKIPPED render --mp4: no ffmpeg on the PATH (.ci/run installs it)");
                continue;
            }
            let v = value(command, &option);
            let mut failures = Vec::new();
            let accepted = inputs.iter().any(|input| {
                let mut args: Vec<String> = vec![command.to_string()];
                args.extend(input.iter().cloned());
                // The run's length, unless the option is the length or replaces an input's.
                let replaces = |o: &str| option == o || input.contains(&o.to_string());
                if !["--time", "--steps"].iter().any(|o| replaces(o)) {
                    let mut l = length.iter().map(|s| s.to_string()).peekable();
                    while let Some(flag) = l.next() {
                        let val = l.next().unwrap();
                        if !replaces(&flag) {
                            args.extend([flag, val]);
                        }
                    }
                }
                if !input.contains(&option) {
                    args.push(option.clone());
                    args.extend(v.iter().cloned());
                }
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                let out = rigidref(&args, dir);
                if !out.status.success() {
                    failures.push(format!("{args:?}: {}", common::stderr(&out)));
                }
                out.status.success()
            });
            tried += 1;
            assert!(
                accepted,
                "{command} lists {option} but refuses it:\n{}",
                failures.join("\n")
            );
        }
    }
    assert!(tried > 70, "only {tried} options tried");
}

/// A run that loses contacts says so: one warning per pair, naming the step, the bodies and the
/// depth, and pointing to `collision: complete`; the summary's deepest penetration is the
/// measured one (docs/contact.md §"Penetration measure"). With `complete`, no warning.
#[test]
fn vertex_rule_run_warns_about_interpenetration_naming_pair_and_step() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/cube_stack.json");
    let scene = scene.to_str().unwrap();
    let out = rigidref(
        &[
            "run",
            scene,
            "--time",
            "1",
            "--set",
            "collision=vertices",
            "--out",
            "t.jsonl",
        ],
        tmp.path(),
    );
    assert!(out.status.success());
    let stderr = common::stderr(&out);
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    assert_eq!(warnings.len(), 6, "{stderr}");
    assert!(
        warnings[0].starts_with("warning: step 16 (t = 0.16 s): body 0 (\"box (level 1)\") and body 1 (\"box (level 2)\") interpenetrate by 0.13"),
        "{}",
        warnings[0]
    );
    assert!(
        warnings
            .iter()
            .all(|w| w.contains("`collision: complete` (or --set collision=complete) finds them"))
    );
    let summary = stderr.lines().find(|l| l.starts_with("contacts")).unwrap();
    assert!(summary.contains("deepest penetration 5.0"), "{summary}");
    assert!(
        summary.contains("measured between the bodies; deepest contact found"),
        "{summary}"
    );
    // The trace records the measure after every step.
    let trace = std::fs::read_to_string(tmp.path().join("t.jsonl")).unwrap();
    let last: serde_json::Value = serde_json::from_str(trace.lines().last().unwrap()).unwrap();
    assert!(last["penetration"].as_f64().unwrap() > 0.4);

    let out = rigidref(
        &["run", scene, "--time", "1", "--out", "t.jsonl"],
        tmp.path(),
    );
    assert!(out.status.success());
    let stderr = common::stderr(&out);
    assert!(!stderr.contains("warning:"), "{stderr}");
}

/// `rigidref crosscheck` on a 3D scene checks detection against the separating-axis oracle on
/// every substep (docs/contact.md §"The oracle campaign"): the stacks written exactly touching
/// agree (pairs checked, contacts counted, none disagreeing), in the text report and in JSON; a
/// scene of bodies written overlapping by more than the bound warns about it, naming them.
#[test]
fn crosscheck_checks_detection_against_the_oracle() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/touching_three_boxes.json");
    let scene = scene.to_str().unwrap();
    let args = [
        "crosscheck",
        scene,
        "--time",
        "0.3",
        "--set",
        "solver=newton",
    ];
    let out = rigidref(&args, tmp.path());
    common::assert_success(&out);
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let line = stdout
        .lines()
        .find(|l| l.starts_with("detection"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        line.contains("pairs checked against the separating-axis oracle")
            && line.ends_with(": agree"),
        "{line}"
    );
    let out = rigidref(&[&args[..], &["--json"]].concat(), tmp.path());
    common::assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let d = &v["summary"]["detection"];
    // Two pairs (box 1 on box 2, box 2 on box 3) on each of 30 substeps.
    assert_eq!(d["pairs"].as_u64(), Some(60), "{d}");
    assert_eq!(d["disagreements"].as_u64(), Some(0), "{d}");
    assert!(d["contacts"].as_u64().unwrap() >= 240, "{d}");
}

/// Version 2 readers accept version 1 traces (docs/trace-format.md §"Versions"): the header's
/// `collision` is then "vertices" and the records' `penetration` absent; an unknown version is
/// refused, naming the file and the versions read.
#[test]
fn version_1_traces_are_still_read() {
    let v1 = r#"{"format":"rigidref-trace","version":1,"dimension":3,"scene":"s","source":"s.json","dt":0.01,"substeps":1,"gravity":[0.0,-9.8,0.0],"integrator":"spatial","bodies":[{"name":"b","mass":1.0}]}
{"step":0,"t":0.0,"bodies":[{"x":[0.0,1.0,0.0],"R":[[1.0,0.0,0.0],[0.0,1.0,0.0],[0.0,0.0,1.0]],"v":[0.0,0.0,0.0],"omega":[0.0,0.0,0.0]}],"energy":{"kinetic_linear":0.0,"kinetic_angular":0.0,"potential":9.8,"total":9.8},"momentum":{"linear":[0.0,0.0,0.0],"angular":[0.0,0.0,0.0],"angular_com":[0.0,0.0,0.0]},"contacts":[]}
"#;
    let trace = read_trace(std::io::Cursor::new(v1), "old.jsonl").unwrap();
    assert_eq!(trace.header.version, 1);
    assert_eq!(trace.header.collision, "vertices");
    assert_eq!(trace.records.len(), 1);
    assert_eq!(trace.records[0].penetration, None);
    let v3 = v1.replacen("\"version\":1", "\"version\":3", 1);
    let err = read_trace(std::io::Cursor::new(v3), "new.jsonl").unwrap_err();
    assert!(
        err.starts_with("new.jsonl:1:") && err.contains("version 1 to 2"),
        "{err}"
    );
}

/// `rigidref bench --quick` (docs/performance.md) runs the smallest sizes of both 3D families in
/// rigidref and the rapier mirror and the smallest 2D factory pile, and prints the table: one
/// row per case with every column a number (times are not checked: this machine is shared;
/// the 2D row has no rapier columns), the fitted exponents, the targets read off the rows, the
/// peak memory; and writes the same table to DIR/bench.md and the plot to DIR/bench.svg.
#[test]
fn bench_quick_prints_the_side_by_side_table() {
    let tmp = tempfile::tempdir().unwrap();
    let root = common::project_root();
    let out = rigidref(
        &[
            "bench",
            "--quick",
            "--out",
            "b",
            "--root",
            root.to_str().unwrap(),
        ],
        tmp.path(),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    common::assert_success(&out);
    let cells_of = |row: &str| -> Vec<String> {
        row.trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect()
    };
    // The main table's rows (the exponents' table has rows named for the families alone).
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("| stack grid ") || l.starts_with("| cube pyramid "))
        .filter(|l| l.contains('×') || l.contains(" rows |"))
        .collect();
    assert_eq!(rows.len(), 4, "{stdout}");
    for row in &rows {
        let cells = cells_of(row);
        assert_eq!(cells.len(), 18, "{row}");
        // The last cell is the share of pair visits detection's kept lists served, then in
        // brackets (where vertices were queried) the share of queries on kept nearest triangles.
        let (kept, nearest) = match cells[17].split_once(" % (") {
            Some((kept, nearest)) => {
                let nearest = nearest.strip_suffix(" %)");
                (
                    kept,
                    Some(nearest.unwrap_or_else(|| panic!("{row}: nearest share"))),
                )
            }
            None => (
                cells[17]
                    .strip_suffix(" %")
                    .unwrap_or_else(|| panic!("{row}")),
                None,
            ),
        };
        for share in std::iter::once(kept).chain(nearest) {
            let share: f64 = share.parse().unwrap_or_else(|_| panic!("{row}: {share:?}"));
            assert!((0.0..=100.0).contains(&share), "{row}");
        }
        for cell in &cells[1..17] {
            let x: f64 = cell.parse().unwrap_or_else(|_| panic!("{row}: {cell:?}"));
            assert!(x.is_finite() && x >= 0.0, "{row}");
        }
        // Both engines ran: positive times, and contacts (the stacks rest on the ground).
        assert!(cells[2].parse::<f64>().unwrap() > 0.0 && cells[4].parse::<f64>().unwrap() > 0.0);
    }
    // The 2D factory's pile: rigidref's columns are numbers, rapier's are "–"; in contact.
    let pile = stdout
        .lines()
        .find(|l| l.starts_with("| 2D factory 100 |"))
        .unwrap_or_else(|| panic!("{stdout}"));
    let cells = cells_of(pile);
    assert_eq!(cells.len(), 18, "{pile}");
    assert!(cells[17].ends_with(" %"), "{pile}");
    assert!(cells[2].parse::<f64>().unwrap() > 50.0, "{pile}");
    assert!(cells[3].parse::<f64>().unwrap() > 0.0, "{pile}");
    assert_eq!(&cells[4], "–", "{pile}");
    assert_eq!(&cells[16], "–", "{pile}");
    assert!(stdout.contains("Fitted exponents") && stdout.contains("Peak resident memory"));
    // The targets are read off the rows, each said to be met or not.
    assert!(stdout.contains("Targets, from the rows above"), "{stdout}");
    let whole_step = stdout
        .lines()
        .find(|l| l.starts_with("| whole step ≤ 1.0× rapier's"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        whole_step.ends_with("| yes |") || whole_step.ends_with("| no |"),
        "{whole_step}"
    );
    let written = std::fs::read_to_string(tmp.path().join("b/bench.md")).unwrap();
    assert!(written.contains("| stack grid 2×2 |"), "{written}");
    let plot = std::fs::read_to_string(tmp.path().join("b/bench.svg")).unwrap();
    assert!(
        plot.starts_with("<svg")
            && plot.contains("rigidref: stack grid")
            && plot.contains("rapier3d: cube pyramid"),
        "{}",
        &plot[..plot.len().min(400)]
    );
    // --only keeps the scenes whose name holds the text, and says so when none does.
    let out = rigidref(
        &[
            "bench",
            "--quick",
            "--only",
            "grid 2",
            "--root",
            root.to_str().unwrap(),
        ],
        tmp.path(),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("| stack grid 2×2 |"),
        "{stdout}"
    );
    assert!(
        !stdout.contains("| stack grid 1×1 |") && !stdout.contains("| cube pyramid"),
        "{stdout}"
    );
    let out = rigidref(
        &[
            "bench",
            "--quick",
            "--only",
            "nothing",
            "--root",
            root.to_str().unwrap(),
        ],
        tmp.path(),
    );
    let stderr = common::stderr(&out);
    assert!(
        !out.status.success() && stderr.contains("--only") && stderr.contains("stack grid 1×1"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    // And outside the project, a one-line error naming what is missing.
    let out = rigidref(&["bench", "--quick"], tmp.path());
    let stderr = common::stderr(&out);
    assert!(
        !out.status.success() && stderr.contains("box_stack.json") && stderr.contains("--root"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}

/// The six physical criteria (docs/contact.md §"Physical criteria") in `rigidref contacts --json`
/// (per contact and their maximum), in a cone-friction trace's per-step solver record and in
/// dumped problem files; on the resting box stack with cone friction every one is small.
#[test]
fn contacts_json_traces_and_problem_files_carry_the_physical_criteria() {
    const KEYS: [&str; 6] = [
        "primal",
        "dual",
        "complementarity",
        "signorini",
        "cone_boundary",
        "max_dissipation",
    ];
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/box_stack.json");
    let scene = scene.to_str().unwrap();
    let out = rigidref(&["contacts", scene, "--json"], tmp.path());
    common::assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in KEYS {
        assert!(v["criteria"][key].as_f64().is_some(), "{key}: {v}");
        for c in v["contacts"].as_array().unwrap() {
            assert!(c[key].as_f64().unwrap() >= 0.0, "{key}: {c}");
        }
    }
    let out = rigidref(
        &[
            "run",
            scene,
            "--time",
            "1",
            "--set",
            "friction_model=cone",
            "--out",
            "t.jsonl",
            "--dump-problems",
            "p",
        ],
        tmp.path(),
    );
    assert!(out.status.success());
    let stderr = common::stderr(&out);
    assert!(stderr.contains("criteria       primal"), "{stderr}");
    let text = std::fs::read_to_string(tmp.path().join("t.jsonl")).unwrap();
    let last: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
    let record = &last["solver"]["criteria"];
    for key in KEYS {
        // At rest with cone friction PGS's 100 warm-started sweeps leave every criterion far
        // below the stack's scale (λn ~ 10 N·s, velocities ~ 0.1 m/s): 1e-3.
        assert!(record[key].as_f64().unwrap() <= 1e-3, "{key}: {record}");
    }
    let problem = std::fs::read_dir(tmp.path().join("p"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(problem).unwrap()).unwrap();
    let per_contact = file["solution"]["criteria"].as_array().unwrap();
    assert_eq!(
        per_contact.len(),
        file["contacts"].as_array().unwrap().len()
    );
    for key in KEYS {
        assert!(per_contact[0][key].as_f64().is_some());
    }
}

/// `rigidref converge` (docs/verification.md §"Convergence order"): the sliding cube's stopping
/// distance at three step sizes, as a table and as JSON, with its closed form and first-order
/// errors; `--expect 1` accepts its orders and `--expect 2` fails with status 1 naming them; a
/// given number as reference, `--body`, `--set` and `--quiet` are honoured; bad input (an unknown
/// observable, one step size, a 2D scene, a missing file, a number for two observables) is a
/// one-line error with status 1.
#[test]
fn converge_reports_observed_orders_and_refuses_what_it_cannot_measure() {
    let dir = tempfile::tempdir().unwrap();
    let cube = common::project_root().join("scenes/sliding_cube.json");
    let cube = cube.to_str().unwrap();
    let base = [
        "converge",
        cube,
        "--dt",
        "1e-3,5e-4,2.5e-4",
        "--observable",
        "stop_distance",
    ];
    let out = common::rigidref(&base, dir.path());
    let text = String::from_utf8_lossy(&out.stdout);
    common::assert_success(&out);
    assert!(
        text.contains("closed form v₀²/(2μg)") && text.contains("1.000"),
        "{text}"
    );
    assert!(common::stderr(&out).contains("stop_distance: dt 0.0005 s"));

    let json = common::rigidref(&[&base[..], &["--json", "--quiet"]].concat(), dir.path());
    assert!(json.status.success());
    assert!(json.stderr.is_empty(), "--quiet: {}", common::stderr(&json));
    let reports: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let report = &reports[0];
    assert_eq!(report["observable"], "stop_distance");
    assert_eq!(report["unit"], "m");
    assert_eq!(report["runs"].as_array().unwrap().len(), 3);
    // v₀²/(2μg) with v₀ = 1 m/s, μ = 0.4, g = 9.81 m/s².
    let exact = 1.0 / (2.0 * 0.4 * 9.81);
    assert!((report["reference"]["value"].as_f64().unwrap() - exact).abs() < 1e-15);
    assert!((report["runs"][2]["order"].as_f64().unwrap() - 1.0).abs() < 0.01);

    let expect = |p: &str| {
        common::rigidref(
            &[&base[..], &["-q", "--expect", p, "--band", "0.05"]].concat(),
            dir.path(),
        )
    };
    assert!(expect("1").status.success());
    let failed = expect("2");
    assert_eq!(failed.status.code(), Some(1));
    let message = common::stderr(&failed);
    assert!(
        message.contains("outside 2 ± 0.05") && message.contains("stop_distance 1.000"),
        "{message}"
    );

    // A reference given as a number (0.12742 m: the closed form to 5 digits), --body 0, --set.
    let given = common::rigidref(
        &[
            &base[..],
            &[
                "-q",
                "--reference",
                "0.12742",
                "--body",
                "0",
                "--set",
                "mu=0.4",
                "--time",
                "1",
            ],
        ]
        .concat(),
        dir.path(),
    );
    common::assert_success(&given);
    assert!(String::from_utf8_lossy(&given.stdout).contains("reference 0.12742 m (given)"));

    let stack = common::project_root().join("scenes/blocks/stack.png");
    for (args, wanted) in [
        (
            vec![
                "converge",
                cube,
                "--dt",
                "1e-3,5e-4",
                "--observable",
                "stop_speed",
            ],
            "unknown observable `stop_speed`",
        ),
        (
            vec![
                "converge",
                cube,
                "--dt",
                "1e-3",
                "--observable",
                "stop_time",
            ],
            "at least two different step sizes",
        ),
        (
            vec![
                "converge",
                stack.to_str().unwrap(),
                "--dt",
                "1e-3,5e-4",
                "--observable",
                "stop_time",
            ],
            "this is a 2D scene",
        ),
        (
            vec![
                "converge",
                "missing.json",
                "--dt",
                "1e-3,5e-4",
                "--observable",
                "stop_time",
            ],
            "missing.json",
        ),
        (
            vec![
                "converge",
                cube,
                "--dt",
                "1e-3,5e-4",
                "--observable",
                "stop_time",
                "--observable",
                "stop_distance",
                "--reference",
                "1",
            ],
            "give one --observable",
        ),
        (
            vec![
                "converge",
                cube,
                "--dt",
                "1e-3,5e-4",
                "--observable",
                "stop_time",
                "--body",
                "3",
            ],
            "--body 3",
        ),
    ] {
        let out = common::rigidref(&args, dir.path());
        let err = common::stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains(wanted) && err.trim().lines().count() == 1,
            "{args:?}: {err}"
        );
    }
}

/// A `--time` that is not a whole number of steps is not rounded silently: the run takes the
/// whole steps (at least one) and a note says how many and where it ends (sliding_box, dt 0.01 s:
/// 0.015 s is 1 step ending at 0.01 s); a whole number of steps gives no note.
#[test]
fn a_time_that_is_not_whole_steps_says_where_the_run_ends() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::project_root().join("scenes/sliding_box.json");
    let run = |time: &str| {
        let out = common::rigidref(
            &[
                "run",
                scene.to_str().unwrap(),
                "--time",
                time,
                "--out",
                "t.jsonl",
                "-q",
            ],
            tmp.path(),
        );
        assert!(out.status.success());
        common::stderr(&out)
    };
    let err = run("0.015");
    assert!(
        err.contains("note: --time 0.015 is not a whole number of steps of dt = 0.01; the run takes 1 steps and ends at t = 0.01"),
        "{err}"
    );
    assert!(!run("0.02").contains("note: --time"));
}

/// `--duration` is `--time` by another name: the same trace to the byte (a user's first guess
/// was answered with clap's suggestion of `--iterations`, an unrelated option).
#[test]
fn duration_is_time_by_another_name() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (
        tmp.path().join("time.jsonl"),
        tmp.path().join("duration.jsonl"),
    );
    for (flag, path) in [("--time", &a), ("--duration", &b)] {
        let out = rigidref(
            &[
                "run",
                "sphere_drop.json",
                flag,
                "0.5",
                "--quiet",
                "--out",
                path.to_str().unwrap(),
            ],
            &scenes_dir(),
        );
        assert!(out.status.success(), "{flag}: {}", common::stderr(&out));
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

/// The bench times every size of a family in the same phase of its motion
/// (docs/performance.md §"How to reproduce"): the warm-up is the same above 2 000 bodies as
/// below (only the rounds are shorter there), so that the fitted exponents compare like with
/// like; and the table's header says so.
#[test]
fn the_bench_warms_up_every_size_alike() {
    use rigidref::tools::experiments::bench::{BenchSettings, markdown};
    let s = BenchSettings {
        warmup: 100,
        steps: 30,
        rounds: 5,
        iterations: 20,
        contact_order: rigidref::solve::ContactOrder::Coloured,
        threads: 1,
        persistent_manifolds: false,
    };
    for bodies in [5, 2000, 2001, 10_140, usize::MAX] {
        let at = s.for_bodies(bodies);
        assert_eq!(at.warmup, s.warmup, "{bodies} bodies");
        assert_eq!((at.rounds, at.iterations), (s.rounds, s.iterations));
        assert_eq!(
            at.steps,
            if bodies > 2000 { 10 } else { 30 },
            "{bodies} bodies"
        );
    }
    let header = markdown(&[], &s);
    assert!(
        header.contains("medians of 5 rounds of 30 steps (10 above 2 000 bodies) after 100 warm-up steps at every size"),
        "{header}"
    );
}
