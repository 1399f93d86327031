//! Bad input gets one clear line naming the file (and for JSON the line and column) and exit
//! code 1, never a panic and never a silent default.

use crate::common;

use std::path::PathBuf;
use std::process::{Command, Output};

const GOOD_SCENE: &str = r#"{
    "sim_parameters": [{"name": "t", "dt": 0.01, "gravity": [0, -9.8, 0], "substeps": 1, "check_collisions": false}],
    "bodies": [{"name": "b", "file_root": "data/block", "x0": [0, 1, 0], "R0": [[1,0,0],[0,1,0],[0,0,1]], "v0": [0,0,0], "omega0": [0,1,0]}]
}"#;

/// An assignment-shaped folder: ROOT/scenes/s.json and ROOT/data/block.{json,obj}.
struct Case {
    dir: tempfile::TempDir,
}

impl Case {
    fn new(scene: &str) -> Case {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("scenes")).unwrap();
        std::fs::create_dir_all(dir.path().join("data")).unwrap();
        let data = common::project_root().join("scenes/data");
        for ext in ["json", "obj"] {
            std::fs::copy(
                data.join(format!("block.{ext}")),
                dir.path().join(format!("data/block.{ext}")),
            )
            .unwrap();
        }
        std::fs::write(dir.path().join("scenes/s.json"), scene).unwrap();
        Case { dir }
    }
    fn path(&self, rel: &str) -> PathBuf {
        self.dir.path().join(rel)
    }
    fn run(&self) -> Output {
        Command::new(common::rigidref_bin())
            .args(["run", "--steps", "3", "--quiet", "--out"])
            .arg(self.path("trace.jsonl"))
            .arg(self.path("scenes/s.json"))
            .output()
            .unwrap()
    }
}

/// The error line (warnings are other lines, prefixed "warning:").
fn error_line(out: &Output) -> String {
    let stderr = common::stderr(out);
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.starts_with("warning:"))
        .collect();
    assert_eq!(errors.len(), 1, "expected one error line, got: {stderr}");
    errors[0].to_string()
}

fn expect_error(case: &Case, file: &str, fragments: &[&str]) {
    let out = case.run();
    assert_eq!(
        out.status.code(),
        Some(1),
        "should fail: {}",
        common::stderr(&out)
    );
    let line = error_line(&out);
    assert!(line.starts_with("error: "), "{line}");
    assert!(line.contains(file), "error should name {file}: {line}");
    for f in fragments {
        assert!(line.contains(f), "error should say {f:?}: {line}");
    }
}

fn scene_with(from: &str, to: &str) -> Case {
    assert!(GOOD_SCENE.contains(from), "{from}");
    Case::new(&GOOD_SCENE.replace(from, to))
}

#[test]
fn the_good_scene_runs() {
    let case = Case::new(GOOD_SCENE);
    let out = case.run();
    common::assert_success(&out);
}

#[test]
fn malformed_json_names_the_file_line_and_column() {
    expect_error(
        &scene_with("\"x0\": [0, 1, 0],", "\"x0\": [0, 1, 0],,"),
        "s.json:3:",
        &["key must be a string"],
    );
}

#[test]
fn missing_body_file_lists_every_path_tried() {
    let case = scene_with("data/block", "data/nothing");
    let out = case.run();
    let line = error_line(&out);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        line.contains("s.json") && line.contains("nothing.json not found; tried"),
        "{line}"
    );
    // Assignment root, scene folder, working directory.
    assert_eq!(line.matches("nothing.json").count(), 4, "{line}");
}

#[test]
fn missing_mesh_file_is_named() {
    let case = Case::new(GOOD_SCENE);
    std::fs::remove_file(case.path("data/block.obj")).unwrap();
    expect_error(&case, "block.obj", &["mesh file not found"]);
}

#[test]
fn non_numeric_vector_is_an_error_at_its_position() {
    expect_error(
        &scene_with("\"v0\": [0,0,0]", "\"v0\": [0,\"fast\",0]"),
        "s.json:3:",
        &["bodies[0].v0", "invalid type"],
    );
}

#[test]
fn wrong_length_vector_is_an_error_at_its_position() {
    expect_error(
        &scene_with("\"x0\": [0, 1, 0]", "\"x0\": [0, 1]"),
        "s.json:3:",
        &["bodies[0].x0", "invalid length 2"],
    );
}

#[test]
fn infinity_is_rejected() {
    expect_error(
        &scene_with("\"x0\": [0, 1, 0]", "\"x0\": [0, 1e999, 0]"),
        "s.json:3:",
        &["out of range"],
    );
}

#[test]
fn nan_is_rejected() {
    expect_error(
        &scene_with("\"x0\": [0, 1, 0]", "\"x0\": [0, NaN, 0]"),
        "s.json:3:",
        &["expected value"],
    );
}

/// The block's body file with `edit` applied to its JSON.
fn body_file_with(edit: impl FnOnce(&mut serde_json::Value)) -> Case {
    let case = Case::new(GOOD_SCENE);
    let path = case.path("data/block.json");
    let mut body: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edit(&mut body);
    std::fs::write(&path, serde_json::to_string_pretty(&body).unwrap()).unwrap();
    case
}

#[test]
fn zero_and_negative_mass_are_rejected() {
    expect_error(
        &body_file_with(|b| b["mass"] = 0.0.into()),
        "block.json:",
        &["mass", "positive"],
    );
    expect_error(
        &body_file_with(|b| b["mass"] = (-3.0).into()),
        "block.json:",
        &["mass", "positive"],
    );
}

#[test]
fn inertia_that_is_not_symmetric_positive_definite_is_rejected() {
    expect_error(
        &body_file_with(|b| b["J"][0][0] = (-11.925).into()),
        "block.json:",
        &["J", "not positive definite"],
    );
    expect_error(
        &body_file_with(|b| b["J"][0][1] = 2.0.into()),
        "block.json:",
        &["J", "not symmetric"],
    );
}

#[test]
fn r0_that_is_not_a_rotation_is_rejected() {
    expect_error(
        &scene_with("[[1,0,0],[0,1,0],[0,0,1]]", "[[1,0.1,0],[0,1,0],[0,0,1]]"),
        "s.json:3:",
        &["R0", "not a rotation"],
    );
    expect_error(
        &scene_with("[[1,0,0],[0,1,0],[0,0,1]]", "[[2,0,0],[0,1,0],[0,0,1]]"),
        "s.json:3:",
        &["R0", "not a rotation"],
    );
}

/// An irregular tetrahedron has no mirror symmetry: a reflection R0 cannot be turned into a
/// rotation, so it is an error. (The symmetric block is accepted: see
/// `reflected_r0_of_a_mirror_symmetric_body_becomes_the_equivalent_rotation`.)
#[test]
fn reflected_r0_of_an_asymmetric_body_is_rejected() {
    use rigidref::rigid3d::massprops::mass_properties;
    use rigidref::rigid3d::mesh::TriMesh;
    let tetra = TriMesh::parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 2 0\nv 0 0 3\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
        "t",
    )
    .unwrap();
    let props = mass_properties(&tetra, 1000.0);
    let case = body_file_with(|b| {
        b["mass"] = props.mass.into();
        b["J"] = serde_json::json!(
            (0..3)
                .map(|i| (0..3).map(|k| props.inertia[(i, k)]).collect::<Vec<f64>>())
                .collect::<Vec<_>>()
        );
    });
    std::fs::write(
        case.path("data/block.obj"),
        tetra.translated(&-props.center_of_mass).to_obj(),
    )
    .unwrap();
    std::fs::write(
        case.path("scenes/s.json"),
        GOOD_SCENE.replace("[[1,0,0],[0,1,0],[0,0,1]]", "[[1,0,0],[0,1,0],[0,0,-1]]"),
    )
    .unwrap();
    expect_error(
        &case,
        "s.json",
        &["R0 has determinant −1", "not mirror-symmetric"],
    );
}

#[test]
fn reflected_r0_of_a_mirror_symmetric_body_becomes_the_equivalent_rotation() {
    let case = scene_with("[[1,0,0],[0,1,0],[0,0,1]]", "[[0,1,0],[1,0,0],[0,0,1]]");
    let scene = rigidref::rigid3d::scene::load_scene(&case.path("scenes/s.json")).unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("R0 has determinant −1")),
        "{:?}",
        scene.warnings
    );
    let r = scene.bodies[0].r0;
    assert!((r.determinant() - 1.0).abs() < 1e-15);
    // Same placed shape: every vertex placed by the reflection is a vertex placed by the rotation.
    let reflection = nalgebra::Matrix3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let mesh = &scene.bodies[0].mesh;
    for v in &mesh.vertices {
        assert!(
            mesh.vertices
                .iter()
                .any(|w| (r * w - reflection * v).norm() < 1e-12)
        );
    }
    // Same world inertia.
    let j = scene.bodies[0].inertia;
    assert!(
        (r * j * r.transpose() - reflection * j * reflection.transpose()).amax() < 1e-9 * j.amax()
    );
}

#[test]
fn non_positive_dt_and_zero_substeps_are_rejected() {
    expect_error(
        &scene_with("\"dt\": 0.01", "\"dt\": 0"),
        "s.json:2:",
        &["sim_parameters[0].dt", "positive"],
    );
    expect_error(
        &scene_with("\"dt\": 0.01", "\"dt\": -0.01"),
        "s.json:2:",
        &["sim_parameters[0].dt", "positive"],
    );
    expect_error(
        &scene_with("\"substeps\": 1", "\"substeps\": 0"),
        "s.json:2:",
        &["sim_parameters[0].substeps", "≥ 1"],
    );
    expect_error(
        &scene_with("\"substeps\": 1", "\"substeps\": 2.5"),
        "s.json:2:",
        &["substeps"],
    );
}

#[test]
fn negative_mu_zero_pgs_iterations_and_nonzero_damping_are_rejected() {
    expect_error(
        &scene_with("\"substeps\": 1", "\"mu\": -0.5"),
        "s.json:2:",
        &["sim_parameters[0].mu"],
    );
    expect_error(
        &scene_with("\"substeps\": 1", "\"pgs_iterations\": 0"),
        "s.json:2:",
        &["pgs_iterations"],
    );
    expect_error(
        &scene_with("\"substeps\": 1", "\"damping\": 0.1"),
        "s.json:2:",
        &["damping", "not supported"],
    );
    expect_error(
        &scene_with("\"substeps\": 1", "\"integrator\": \"rk4\""),
        "s.json:2:",
        &["integrator", "unknown variant"],
    );
}

#[test]
fn contact_parameters_out_of_range_are_rejected() {
    for (value, key, says) in [
        (
            "\"compliance\": -0.01",
            "sim_parameters[0].compliance",
            "≥ 0",
        ),
        (
            "\"stabilization\": -0.2",
            "sim_parameters[0].stabilization",
            "[0, 1]",
        ),
        (
            "\"stabilization\": 1.5",
            "sim_parameters[0].stabilization",
            "[0, 1]",
        ),
        (
            "\"stabilization_slop\": -0.001",
            "sim_parameters[0].stabilization_slop",
            "≥ 0",
        ),
        (
            "\"pgs_tolerance\": 0",
            "sim_parameters[0].pgs_tolerance",
            "positive",
        ),
        (
            "\"pgs_iterations\": -3",
            "sim_parameters[0].pgs_iterations",
            "≥ 1",
        ),
        (
            "\"friction_model\": \"pyramid\"",
            "sim_parameters[0].friction_model",
            "unknown variant",
        ),
        (
            "\"pgs_order\": \"shuffled\"",
            "sim_parameters[0].pgs_order",
            "unknown variant",
        ),
        (
            "\"warm_start\": 1",
            "sim_parameters[0].warm_start",
            "boolean",
        ),
        ("\"pgs_seed\": -1", "sim_parameters[0].pgs_seed", "u64"),
    ] {
        expect_error(
            &scene_with("\"substeps\": 1", value),
            "s.json:2:",
            &[key, says],
        );
    }
}

#[test]
fn unknown_keys_warn_and_do_not_stop_the_run() {
    let case = scene_with("\"substeps\": 1", "\"substeps\": 1, \"sub_steps\": 4");
    let out = case.run();
    assert!(out.status.success());
    let stderr = common::stderr(&out);
    assert!(
        stderr.contains("warning:") && stderr.contains("sub_steps"),
        "{stderr}"
    );
}

#[test]
fn open_body_mesh_is_reported_not_a_panic() {
    let case = Case::new(GOOD_SCENE);
    let obj = case.path("data/block.obj");
    let text = std::fs::read_to_string(&obj).unwrap();
    let without_last_face: Vec<&str> = text.lines().collect();
    std::fs::write(
        &obj,
        without_last_face[..without_last_face.len() - 1].join("\n"),
    )
    .unwrap();
    expect_error(&case, "block.obj", &["open surface"]);
}

/// A vertex no face uses is not part of the body: the OBJ reader keeps only the vertices the
/// object's faces use, so a stray vertex 5 m below the block is neither a contact point nor in its
/// bounding box (the mesh read is the original one, vertex for vertex).
#[test]
fn a_mesh_vertex_no_face_uses_is_not_part_of_the_body() {
    use rigidref::rigid3d::mesh::TriMesh;
    let path = common::project_root().join("scenes/data/block.obj");
    let text = std::fs::read_to_string(&path).unwrap();
    // The stray vertex first, the faces renumbered past it.
    let mut shifted = vec!["v 0 -5 0".to_string()];
    for l in text.lines() {
        shifted.push(match l.strip_prefix("f ") {
            Some(rest) => format!(
                "f {}",
                rest.split_whitespace()
                    .map(
                        |t| (t.split('/').next().unwrap().parse::<usize>().unwrap() + 1)
                            .to_string()
                    )
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
            None => l.to_string(),
        });
    }
    let original = TriMesh::parse_obj(&text, "block.obj").unwrap();
    let stray = TriMesh::parse_obj(&shifted.join("\n"), "stray.obj").unwrap();
    assert_eq!(stray.vertices, original.vertices);
    assert_eq!(stray.triangles, original.triangles);
}

/// A closed, consistently oriented mesh with one zero-area triangle: the mesh still bounds a
/// solid, so it loads, and the degenerate face is reported as a warning.
#[test]
fn degenerate_triangles_are_reported_as_a_warning() {
    use nalgebra::Vector3;
    let mut mesh =
        rigidref::rigid3d::mesh::TriMesh::cuboid(Vector3::repeat(-0.5), Vector3::repeat(0.5));
    // Split triangle (0, 2, 1) at the midpoint m of edge 0–2 and close the gap with the
    // zero-area triangle (2, m, 0); triangle (0, 4, 2) still uses the edge 2→0.
    let m = mesh.vertices.len();
    mesh.vertices
        .push((mesh.vertices[0] + mesh.vertices[2]) / 2.0);
    assert_eq!(mesh.triangles[0], [0, 2, 1]);
    mesh.triangles[0] = [0, m, 1];
    mesh.triangles.push([m, 2, 1]);
    mesh.triangles.push([2, m, 0]);
    let case = Case::new(GOOD_SCENE);
    std::fs::write(case.path("data/block.obj"), mesh.to_obj()).unwrap();
    let out = case.run();
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning:")
            && stderr.contains("block.obj")
            && stderr.contains("1 degenerate (zero-area) triangles"),
        "{stderr}"
    );
    // With contact on: two such bodies resting on the ground and pressed into each other, so
    // that ground, broad-phase and signed-distance queries all meet the zero-area face.
    let scene = r#"{
        "sim_parameters": [{"dt": 0.01, "gravity": [0, -9.8, 0], "mu": 0.5, "check_collisions": true}],
        "bodies": [{"name": "a", "file_root": "data/block", "x0": [0, 0.49, 0]},
                   {"name": "b", "file_root": "data/block", "x0": [0.97, 0.49, 0.1], "R0": [[0,0,1],[0,1,0],[-1,0,0]]}]
    }"#;
    std::fs::write(case.path("scenes/s.json"), scene).unwrap();
    let out = Command::new(common::rigidref_bin())
        .args(["run", "--steps", "100", "--out"])
        .arg(case.path("trace.jsonl"))
        .arg(case.path("scenes/s.json"))
        .output()
        .unwrap();
    let stderr = common::stderr(&out);
    assert!(
        out.status.success() && !stderr.contains("panicked"),
        "{stderr}"
    );
    assert!(
        stderr.contains("degenerate") && stderr.contains("contacts "),
        "{stderr}"
    );
}

#[test]
fn a_nan_during_the_run_stops_it_naming_step_body_and_quantity_and_keeps_a_valid_trace() {
    // The explicit gyroscopic term's energy growth at this spin overflows at step 39.
    let case = scene_with("\"omega0\": [0,1,0]", "\"omega0\": [60, 40, 20]");
    let out = Command::new(common::rigidref_bin())
        .args(["run", "--steps", "100", "--every", "7", "--quiet", "--out"])
        .arg(case.path("trace.jsonl"))
        .arg(case.path("scenes/s.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out);
    assert!(
        line.contains("s.json")
            && line.contains("non-finite")
            && line.contains("body 0 (\"b\")")
            && line.contains("at step"),
        "{line}"
    );
    let trace = rigidref::rigid3d::trace::read_trace(
        std::io::BufReader::new(std::fs::File::open(case.path("trace.jsonl")).unwrap()),
        "trace",
    )
    .unwrap();
    assert!(!trace.records.is_empty());
    let last = trace.records.last().unwrap();
    assert!(last.bodies[0].omega.iter().all(|w| w.is_finite()));
    assert!(
        last.step >= 14 && last.step.is_multiple_of(7),
        "the run should fail after several records: {}",
        last.step
    );
    assert!(
        line.contains(&format!("the trace up to step {}", last.step)),
        "{line}"
    );
}

#[test]
fn bad_command_line_values_are_errors() {
    let case = Case::new(GOOD_SCENE);
    for args in [
        &["--time", "-1"][..],
        &["--every", "0"][..],
        &["--time", "nan"][..],
    ] {
        let out = Command::new(common::rigidref_bin())
            .arg("run")
            .args(args)
            .arg("--out")
            .arg(case.path("t.jsonl"))
            .arg(case.path("scenes/s.json"))
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        error_line(&out);
    }
    let out = Command::new(common::rigidref_bin())
        .args(["run", "/no/such/scene.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(error_line(&out).contains("/no/such/scene.json"));
}

/// A thread count of 0 means nothing a user could want; `--set threads=0` is refused, and so are
/// the commands' own thread options (before, `factory --threads 0`, `bench --threads 0` and
/// `grade --jobs 0` quietly ran on one thread). The refusal is clap's: exit code 2, the first line
/// naming the option and the range.
#[test]
fn thread_counts_of_zero_are_refused_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    for (command, option) in [
        ("factory", "--threads"),
        ("bench", "--threads"),
        ("grade", "--jobs"),
    ] {
        let out = Command::new(common::rigidref_bin())
            .current_dir(dir.path())
            .args([command, option, "0"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{command} {option} 0");
        let stderr = common::stderr(&out);
        assert!(!stderr.contains("panicked"), "panic: {stderr}");
        let first = stderr.lines().next().unwrap_or_default();
        assert!(
            first.starts_with("error:") && first.contains(option) && first.contains("1.."),
            "{command}: {stderr}"
        );
        assert!(
            std::fs::read_dir(dir.path()).unwrap().next().is_none(),
            "{command} {option} 0 wrote something"
        );
    }
}

#[test]
fn unknown_collision_method_is_rejected_naming_the_allowed_values() {
    expect_error(
        &scene_with("\"substeps\": 1", "\"collision\": \"exact\""),
        "s.json:2:",
        &[
            "collision",
            "unknown variant `exact`",
            "vertices",
            "complete",
        ],
    );
    // The same value from the command line is refused the same way.
    let case = Case::new(GOOD_SCENE);
    let out = Command::new(common::rigidref_bin())
        .args([
            "run",
            "--steps",
            "1",
            "--quiet",
            "--set",
            "collision=exact",
            "--out",
        ])
        .arg(case.path("trace.jsonl"))
        .arg(case.path("scenes/s.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out);
    assert!(
        line.contains("collision") && line.contains("vertices") && line.contains("complete"),
        "{line}"
    );
}

/// Input beyond the limits is a one-line error naming the file and the option that raises it
/// (docs/scene-format.md §"Input limits"), never an allocation the machine cannot hold: a mesh
/// of 2.1 MB under `--max-input-mb 1` (the scene itself is small), a trace under
/// `--max-input-mb 0` in `compare` (exit 2, unreadable), and a 30 × 41 image under
/// `--max-image-pixels 100` (judged from its header, before decoding). Raised, the same inputs run.
#[test]
fn inputs_beyond_the_limits_are_one_line_errors_naming_the_option() {
    let case = Case::new(GOOD_SCENE);
    let obj = case.path("data/block.obj");
    let mut text = std::fs::read_to_string(&obj).unwrap();
    text.push_str(&"# padding to two megabytes\n".repeat(80_000));
    std::fs::write(&obj, text).unwrap();
    let run = |limit: &str| {
        Command::new(common::rigidref_bin())
            .args([
                "run",
                "--steps",
                "2",
                "--quiet",
                "--max-input-mb",
                limit,
                "--out",
            ])
            .arg(case.path("trace.jsonl"))
            .arg(case.path("scenes/s.json"))
            .output()
            .unwrap()
    };
    let out = run("1");
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out);
    assert!(
        line.contains("block.obj")
            && line.contains(
                "2.1 MB is more than the input limit of 1.0 MB (raise it with --max-input-mb)"
            ),
        "{line}"
    );
    assert!(run("3").status.success());

    let out = Command::new(common::rigidref_bin())
        .args(["compare", "--max-input-mb", "0"])
        .arg(case.path("trace.jsonl"))
        .arg(case.path("trace.jsonl"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let line = error_line(&out);
    assert!(
        line.contains("trace.jsonl") && line.contains("--max-input-mb"),
        "{line}"
    );

    let image = common::project_root().join("scenes/blocks/stack.png");
    let run_image = |pixels: &str| {
        Command::new(common::rigidref_bin())
            .args([
                "run",
                "--steps",
                "1",
                "--quiet",
                "--max-image-pixels",
                pixels,
                "--out",
            ])
            .arg(case.path("t2.jsonl"))
            .arg(&image)
            .output()
            .unwrap()
    };
    let out = run_image("100");
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out);
    assert!(
        line.contains("stack.png")
            && line.contains("30 × 41 = 1230 pixels, more than the limit of 100 (raise it with --max-image-pixels)"),
        "{line}"
    );
    assert!(run_image("1230").status.success());
}
