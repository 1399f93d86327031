//! `rigidref validate` (docs/validation.md): the mirror description carries the scene, the rapier
//! mirror reads back the scene's masses, inertias, μ and step, rigidref judged by the same code is
//! at round-off or at its documented first-order term, an engine that is not installed is
//! reported, and bad names are one-line errors. The Python engines' own tests (MuJoCo, PyBullet,
//! Drake: read-back and free flight) are python/tests/test_mirrors.py.

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::tools::validation::judge::explicit_gains;
use rigidref::tools::validation::mirror::{MirrorScene, MirrorShape};
use rigidref::tools::validation::scenes::SCENES_3D;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

fn validate(out: &Path, args: &[&str]) -> std::process::Output {
    Command::new(common::rigidref_bin())
        .current_dir(common::project_root())
        .arg("validate")
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn report(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap()
}

fn scene<'a>(report: &'a Value, file: &str) -> &'a Value {
    report["scenes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["file"] == file)
        .unwrap_or_else(|| panic!("no {file} in the report"))
}

fn run<'a>(scene: &'a Value, engine: &str, settings: Option<&str>) -> &'a Value {
    scene["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["engine"] == engine && r["settings"].as_str() == settings)
        .unwrap_or_else(|| panic!("no {engine} {settings:?} run in {}", scene["file"]))
}

fn value(run: &Value, key: &str) -> f64 {
    run["measured"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["key"] == key)
        .and_then(|m| m["value"].as_f64())
        .unwrap_or_else(|| panic!("no {key} in {}", run["engine"]))
}

#[test]
fn the_mirror_description_carries_every_scenes_masses_inertias_mu_gravity_and_step() {
    for known in SCENES_3D {
        let scene = load_scene(&common::project_root().join("scenes").join(known.file)).unwrap();
        let d = MirrorScene::of_scene(&scene, "x", 10).unwrap();
        // Copied, not recomputed: equal to the bit.
        assert_eq!(
            (d.dt, d.h, d.mu, d.substeps),
            (
                scene.params.dt,
                scene.params.h(),
                scene.params.mu,
                scene.params.substeps
            )
        );
        assert_eq!(d.gravity, <[f64; 3]>::from(scene.params.gravity));
        for (m, b) in d.bodies.iter().zip(&scene.bodies) {
            assert_eq!(m.mass, b.mass, "{}", known.file);
            for i in 0..3 {
                for j in 0..3 {
                    assert_eq!(m.inertia[i][j], b.inertia[(i, j)], "{}", known.file);
                }
            }
            // Every shape holds the body's mesh (a box's corners or a hull's vertices are the
            // mesh's extreme points; a sphere is the `ellipsoid` key).
            match &m.shape {
                MirrorShape::Box { half_extents } => {
                    for v in &b.mesh.vertices {
                        for k in 0..3 {
                            assert!(
                                v[k].abs() <= half_extents[k] * (1.0 + 1e-12),
                                "{}",
                                known.file
                            );
                        }
                    }
                }
                MirrorShape::Sphere { radius } => {
                    assert_eq!(*radius, b.ellipsoid.unwrap().semi_axes.x)
                }
                MirrorShape::Hull { vertices } => assert!(vertices.len() >= 4),
            }
        }
    }
}

/// One run of every scene with rapier (in-process), shared by the tests below (about 3 s).
fn rapier_report() -> &'static (tempfile::TempDir, Value) {
    static REPORT: std::sync::OnceLock<(tempfile::TempDir, Value)> = std::sync::OnceLock::new();
    REPORT.get_or_init(|| {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("report with spaces");
        let o = validate(&out, &["--engines", "rapier"]);
        common::assert_success(&o);
        let r = report(&out);
        (tmp, r)
    })
}

#[test]
fn validate_with_rapier_writes_the_markdown_json_and_a_plot_per_scene() {
    let (tmp, report) = rapier_report();
    let out = tmp.path().join("report with spaces");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("| rapier | rapier3d-f64"), "{md}");
    for known in SCENES_3D {
        let stem = known.file.trim_end_matches(".json");
        let svg = std::fs::read_to_string(out.join("plots").join(format!("{stem}.svg"))).unwrap();
        assert!(
            svg.starts_with("<svg") || svg.starts_with("<?xml"),
            "{stem}.svg"
        );
        assert!(
            svg.contains("rapier (default)") && svg.contains("rigidref (Newton)"),
            "{stem}.svg has no legend"
        );
        assert!(md.contains(&format!("## {stem}")));
        let s = scene(report, known.file);
        for settings in ["default", "accurate"] {
            let r = run(s, "rapier", Some(settings));
            assert_eq!(
                r["status"]["status"], "ran",
                "{stem} {settings}: {}",
                r["status"]
            );
            assert!(out.join(r["trace"].as_str().unwrap()).is_file());
        }
    }
}

#[test]
fn rapiers_model_reads_back_the_scenes_masses_inertias_mu_and_step() {
    let (_, report) = rapier_report();
    for known in SCENES_3D {
        let scene_file = common::project_root().join("scenes").join(known.file);
        let sc = load_scene(&scene_file).unwrap();
        let r = run(scene(report, known.file), "rapier", Some("default"));
        let back = &r["model"]["readback"];
        assert_eq!(back["h"].as_f64().unwrap(), sc.params.h(), "{}", known.file);
        for (b, body) in back["bodies"].as_array().unwrap().iter().zip(&sc.bodies) {
            // rapier stores the inverse mass and principal moments in a principal frame (f64):
            // read back to a few ulps of the scale.
            let mass = b["mass"].as_f64().unwrap();
            assert!(
                (mass - body.mass).abs() <= 1e-12 * body.mass,
                "{}: mass {mass} vs {}",
                known.file,
                body.mass
            );
            let scale = body.inertia.norm();
            for i in 0..3 {
                for j in 0..3 {
                    let got = b["inertia"][i][j].as_f64().unwrap();
                    assert!(
                        (got - body.inertia[(i, j)]).abs() <= 1e-12 * scale,
                        "{}: J[{i}][{j}] {got} vs {}",
                        known.file,
                        body.inertia[(i, j)]
                    );
                }
            }
            if sc.params.check_collisions {
                assert_eq!(b["mu"][0].as_f64().unwrap(), sc.params.mu, "{}", known.file);
            }
        }
        if sc.params.check_collisions {
            assert_eq!(back["ground_mu"][0].as_f64().unwrap(), sc.params.mu);
        }
    }
}

#[test]
fn rigidref_judged_by_the_same_code_passes_every_observable_with_a_closed_form() {
    let (_, report) = rapier_report();
    for known in SCENES_3D {
        let r = run(scene(report, known.file), "rigidref", None);
        for m in r["measured"].as_array().unwrap() {
            assert_ne!(
                m["passed"],
                Value::Bool(false),
                "{}: rigidref fails {}",
                known.file,
                m
            );
        }
    }
}

#[test]
fn rigidrefs_errors_are_its_documented_first_order_terms() {
    let (_, report) = rapier_report();
    let root = common::project_root().join("scenes");
    // Free flight: symplectic Euler lands exactly g h t/2 from the parabola (docs/dynamics.md).
    let s = scene(report, "projectile.json");
    let sc = load_scene(&root.join("projectile.json")).unwrap();
    let t = 2.0;
    let documented = sc.params.gravity.norm() * sc.params.h() * t / 2.0;
    let error = value(run(s, "rigidref", None), "position_error");
    assert!(
        (error - documented).abs() <= 1e-12 * 10.0,
        "projectile: {error} vs g h t/2 = {documented}"
    );
    // |L| and E of the free body grow by the explicit step's documented gain (to first order:
    // the gain is summed along the exact solution, the run's own differs by O(h)).
    let b = &sc.bodies[0];
    let (_, l_gain) = explicit_gains(&b.inertia, &(b.r0.transpose() * b.omega0), sc.params.h(), t);
    let drift = value(run(s, "rigidref", None), "angular_momentum_drift");
    assert!(
        (drift / l_gain - 1.0).abs() < 0.2,
        "projectile: |L| drift {drift} vs documented {l_gain}"
    );
    let s = scene(report, "dzhanibekov.json");
    let sc = load_scene(&root.join("dzhanibekov.json")).unwrap();
    let b = &sc.bodies[0];
    let (e_gain, _) = explicit_gains(
        &b.inertia,
        &(b.r0.transpose() * b.omega0),
        sc.params.h(),
        10.0,
    );
    let drift = value(run(s, "rigidref", None), "energy_drift");
    assert!(
        (drift / e_gain - 1.0).abs() < 0.2,
        "dzhanibekov: energy drift {drift} vs documented {e_gain}"
    );
    // A slide stops v₀h/2 short of v₀²/(2μg), up to one step's travel at the end (≤ v₀ h).
    for file in ["sliding_cube.json", "sliding_box.json"] {
        let sc = load_scene(&root.join(file)).unwrap();
        let (v0, h) = (sc.bodies[0].v0.norm(), sc.params.h());
        let exact = v0 * v0 / (2.0 * sc.params.mu * sc.params.gravity.norm());
        let d = value(run(scene(report, file), "rigidref", None), "stop_distance");
        assert!(
            (d - (exact - v0 * h / 2.0)).abs() <= v0 * h / 2.0,
            "{file}: {d} vs {exact} − v₀h/2"
        );
    }
    // Rolling: the exact solver's contact does not slip (round-off), its acceleration is (5/7) g sin θ.
    let r = run(scene(report, "ball_incline_rolls.json"), "rigidref", None);
    assert!(value(r, "slip_speed") < 1e-9);
    // The exact solver's impulses meet Coulomb's law: the criteria are round-off wherever no
    // stabilisation push is in the contact velocity (sphere_drop's impact is; docs/validation.md).
    for known in SCENES_3D.iter().filter(|k| k.file != "sphere_drop.json") {
        let r = run(scene(report, known.file), "rigidref", None);
        for m in r["measured"].as_array().unwrap() {
            if m["key"].as_str().unwrap().starts_with("criterion") {
                assert!(
                    m["value"].as_f64().unwrap() <= 1e-9,
                    "{}: {}",
                    known.file,
                    m
                );
            }
        }
    }
    // Every layer of the heavy-on-light stack carries the weight above it, to 1e-6.
    let r = run(scene(report, "heavy_on_light.json"), "rigidref", None);
    for key in ["lower_layer", "upper_layer"] {
        assert!(
            (value(r, key) - 1.0).abs() < 1e-6,
            "{key}: {}",
            value(r, key)
        );
    }
}

#[test]
fn an_engine_that_is_not_installed_is_reported_never_dropped() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = validate(
        &out,
        &[
            "--engines",
            "rapier,mujoco,drake",
            "--scenes",
            "sliding_cube",
            "--python",
            "/nonexistent/python3",
        ],
    );
    common::assert_success(&o);
    let err = common::stderr(&o);
    assert!(
        err.contains(
            "mujoco: not installed: cannot run the Python interpreter /nonexistent/python3"
        ),
        "{err}"
    );
    let r = report(&out);
    let s = scene(&r, "sliding_cube.json");
    for engine in ["mujoco", "drake"] {
        for settings in ["default", "accurate"] {
            assert_eq!(
                run(s, engine, Some(settings))["status"]["status"],
                "not_installed"
            );
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("| mujoco | **not installed**: cannot run the Python interpreter"),
        "{md}"
    );
    assert!(md.contains("not installed | not installed"), "{md}");
}

#[test]
fn unknown_engines_and_scenes_are_one_line_errors() {
    let tmp = tempfile::tempdir().unwrap();
    for (args, says) in [
        (
            vec!["--engines", "bullet"],
            "--engines: unknown engine \"bullet\"",
        ),
        (
            vec!["--engines", "rapier", "--scenes", "sliding cube"],
            "--scenes: \"sliding cube\" is not a known-answer scene",
        ),
    ] {
        let o = validate(&tmp.path().join("out"), &args);
        assert!(!o.status.success());
        let err = common::stderr(&o);
        assert!(err.contains(says), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

/// The 2D set run with pymunk asked for but no Python: rigidref's exact run of each 2D scene
/// is written, measured and judged (the stack rests to round-off, the slide rides the discs and
/// stops short of the flat Coulomb distance), pymunk's rows say not installed, and no 3D scene
/// runs.
#[test]
fn validate_with_pymunk_runs_the_2d_scenes_and_writes_their_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = validate(
        &out,
        &["--engines", "pymunk", "--python", "/nonexistent/python3"],
    );
    common::assert_success(&o);
    let r = report(&out);
    let files: Vec<&str> = r["scenes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["file"].as_str().unwrap())
        .collect();
    assert_eq!(
        files,
        ["block_slide.json", "bar_topple.json", "stack_rest.json"]
    );
    for file in &files {
        let s = scene(&r, file);
        assert_eq!(s["dimension"], 2);
        let reference = run(s, "rigidref", None);
        // Every judged observable passes; the criteria are reported (checked below).
        for m in reference["measured"].as_array().unwrap() {
            if !m["key"].as_str().unwrap().starts_with("criterion_") {
                assert_eq!(m["passed"], true, "{file}: {m}");
            }
        }
        for settings in ["default", "accurate"] {
            assert_eq!(
                run(s, "pymunk", Some(settings))["status"]["status"],
                "not_installed"
            );
        }
    }
    // The stack stays put to round-off once settled; the slide over the ground's discs stops
    // short of the flat slide's v0²/(2μg) = 1/(2·0.33·1) (it climbs their bumps).
    assert!(
        value(
            run(scene(&r, "stack_rest.json"), "rigidref", None),
            "rest_drift"
        ) < 1e-9
    );
    let slide = value(
        run(scene(&r, "block_slide.json"), "rigidref", None),
        "stop_distance",
    );
    assert!(slide > 0.1 && slide < 0.9 / 0.66, "{slide}");
    // rigidref's exact run meets Coulomb's law on its own impulses to round-off: the criteria on
    // each step's last substep's contacts (their impulses and the solved problem's contact
    // velocity, written into the trace). 1e-9: the Newton solve's tolerance is far below it, and
    // the velocities are O(1) blocks/time.
    for file in &files {
        let reference = run(scene(&r, file), "rigidref", None);
        for key in [
            "criterion_primal",
            "criterion_dual",
            "criterion_complementarity",
        ] {
            let k = value(reference, key);
            assert!(k <= 1e-9, "{file}: {key} = {k:e}");
        }
        // One plot per 2D scene, each observable's series against time, linked from report.md.
        let stem = file.trim_end_matches(".json");
        let svg = std::fs::read_to_string(out.join("plots").join(format!("{stem}.svg"))).unwrap();
        for title in [
            "largest displacement of a body",
            "largest |θ| of a body",
            "deepest disc overlap",
        ] {
            assert!(svg.contains(title), "{stem}.svg lacks {title:?}");
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("Plots: [`plots/block_slide.svg`](plots/block_slide.svg)"),
        "{md}"
    );
    assert!(md.contains("## Headline, 2D scenes"), "{md}");
    assert!(
        md.contains("| block_slide | 3/3 ✓ | not installed | not installed |"),
        "{md}"
    );
    assert!(!md.contains("Headline, 3D scenes"), "{md}");
    assert!(out.join("mirrors/pymunk_mirror.py").is_file());
}

/// The 2D description is the loaded scene's: every body's mass, moment, pin, pose and block
/// offsets, μ, gravity and the step h = dt / substeps, equal to the bit.
#[test]
fn the_2d_mirror_description_carries_every_bodys_mass_moment_blocks_mu_gravity_and_step() {
    use rigidref::tools::validation::two_d::{MirrorScene2, SCENES_2D, stem};
    for k in SCENES_2D {
        let path = common::project_root().join("scenes").join(k.file);
        let world = rigidref::blocks2d::scene::load_scene2(&path).unwrap().world;
        let d = MirrorScene2::of_world(&world, "x", stem(k.file), 10).unwrap();
        let p = &world.params;
        assert_eq!(
            (d.dt, d.substeps, d.h, d.mu, d.slop),
            (p.dt, p.substeps, p.dt / f64::from(p.substeps), p.mu, p.slop)
        );
        assert_eq!(d.gravity, [p.gravity_vector().x, p.gravity_vector().y]);
        assert_eq!(d.block_radius, std::f64::consts::FRAC_1_SQRT_2);
        assert_eq!(d.bodies.len(), world.bodies.len());
        for (m, b) in d.bodies.iter().zip(&world.bodies) {
            assert_eq!(
                (m.mass, m.inertia, m.pinned, m.x0, m.theta0),
                (b.mass, b.inertia, b.pinned, [b.x.x, b.x.y], b.theta)
            );
            assert_eq!(m.blocks.len(), b.blocks.len());
            for (q, block) in m.blocks.iter().zip(&b.blocks) {
                assert_eq!(*q, [block.local.x, block.local.y]);
            }
        }
        assert_eq!(d.impulses.len(), world.impulses.len());
    }
}

/// A validation that stops midway leaves what it finished: the report is rewritten after every
/// run, so when the process dies during an engine's runs (here a stand-in Python that kills
/// rigidref as soon as it is asked to run MuJoCo's jobs), report.md, report.json and the scene's
/// plot hold rigidref's and rapier's finished runs and mark MuJoCo's pending. Were the report
/// written only at the end, there would be no report at all.
#[cfg(unix)]
#[test]
fn a_validation_that_stops_midway_keeps_the_runs_it_finished() {
    use std::os::unix::fs::PermissionsExt;
    let tmp = tempfile::tempdir().unwrap();
    let python = tmp.path().join("python");
    std::fs::write(
        &python,
        "#!/bin/sh\ncase \"$2\" in\n  probe) echo '{\"mujoco\":{\"installed\":true,\"version\":\"stand-in\"}}' ;;\n  run) kill -9 $PPID; exit 1 ;;\nesac\n",
    )
    .unwrap();
    std::fs::set_permissions(&python, std::fs::Permissions::from_mode(0o755)).unwrap();
    let out = tmp.path().join("out");
    let o = validate(
        &out,
        &[
            "--engines",
            "rapier,mujoco",
            "--scenes",
            "projectile",
            "--python",
            python.to_str().unwrap(),
        ],
    );
    assert!(
        !o.status.success(),
        "the stand-in Python was to stop the validation"
    );
    let r = report(&out);
    let s = scene(&r, "projectile.json");
    assert_eq!(run(s, "rigidref", None)["status"]["status"], "ran");
    for settings in ["default", "accurate"] {
        assert_eq!(run(s, "rapier", Some(settings))["status"]["status"], "ran");
        assert_eq!(
            run(s, "mujoco", Some(settings))["status"]["status"],
            "pending"
        );
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("| projectile | 2/2 ✓ | 2/2 ✓ | 2/2 ✓ | pending | pending |"),
        "{md}"
    );
    let svg = std::fs::read_to_string(out.join("plots/projectile.svg")).unwrap();
    assert!(
        svg.contains("rapier (accurate)"),
        "the plot lacks rapier's finished run"
    );
}
