//! Polyhedral mass properties against the assignment's body files and the project's own.

use crate::common;

use rigidref::rigid3d::massprops::mass_properties;
use rigidref::rigid3d::mesh::TriMesh;
use std::process::Command;

fn read_json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Relative error in mass and in every J entry above 1e-6 of the largest (smaller entries are
/// round-off in the reference files, e.g. 1e-16 off-diagonals).
fn worst_relative_error(mass: f64, j: &[Vec<f64>], reference: &serde_json::Value) -> f64 {
    let ref_mass = reference["mass"].as_f64().unwrap();
    let ref_j: Vec<Vec<f64>> = serde_json::from_value(reference["J"].clone()).unwrap();
    let largest = ref_j.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut worst = (mass - ref_mass).abs() / ref_mass;
    for i in 0..3 {
        for k in 0..3 {
            if ref_j[i][k].abs() > 1e-6 * largest {
                worst = worst.max((j[i][k] - ref_j[i][k]).abs() / ref_j[i][k].abs());
            }
        }
    }
    worst
}

/// `rigidref massprops` on each assignment OBJ at density 1000 reproduces its body JSON to 1e-9.
#[test]
fn massprops_reproduces_the_assignment_body_files() {
    let Some(dir) = common::rigid3d_assignment() else {
        return;
    };
    for name in ["brick", "cube", "sphere", "thing"] {
        let tmp = tempfile::tempdir().unwrap();
        let root = tmp.path().join(name);
        let out = Command::new(common::rigidref_bin())
            .args(["massprops", "--density", "1000", "--out"])
            .arg(&root)
            .arg(dir.join(format!("data/{name}.obj")))
            .output()
            .unwrap();
        common::assert_success(&out);
        let ours = read_json(&root.with_extension("json"));
        let j: Vec<Vec<f64>> = serde_json::from_value(ours["J"].clone()).unwrap();
        let worst = worst_relative_error(
            ours["mass"].as_f64().unwrap(),
            &j,
            &read_json(&dir.join(format!("data/{name}.json"))),
        );
        eprintln!("{name}: worst relative error {worst:.2e}");
        assert!(worst <= 1e-9, "{name}: {worst:e}");
        assert_eq!(ours["mesh_file"], format!("{name}.obj"));
        // The written mesh is centred: its own centre of mass is at the origin to round-off.
        let centred = TriMesh::load_obj(&root.with_extension("obj")).unwrap();
        let c = mass_properties(&centred, 1000.0).center_of_mass;
        assert!(c.norm() < 1e-12 * centred.bounding_radius(), "{name}: {c}");
    }
}

/// The project's canonical body files are what massprops makes from scenes/src (scenes/README.md
/// says how they were made); a hand edit of one without the other fails here.
#[test]
fn canonical_body_files_are_the_massprops_of_their_source_meshes() {
    let root = common::project_root();
    let mut names: Vec<String> = std::fs::read_dir(root.join("scenes/src"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.len() >= 10, "{names:?}");
    for name in &names {
        let source = TriMesh::load_obj(&root.join(format!("scenes/src/{name}.obj"))).unwrap();
        let props = mass_properties(&source, 1000.0);
        let j: Vec<Vec<f64>> = (0..3)
            .map(|i| (0..3).map(|k| props.inertia[(i, k)]).collect())
            .collect();
        let worst = worst_relative_error(
            props.mass,
            &j,
            &read_json(&root.join(format!("scenes/data/{name}.json"))),
        );
        assert!(worst <= 1e-12, "{name}: {worst:e}");
        let centred = TriMesh::load_obj(&root.join(format!("scenes/data/{name}.obj"))).unwrap();
        // The same geometry (the written file lists the vertices in index order, so the
        // vertices' numbers in the file, TriMesh::file_numbers, may differ from the source's).
        let expected = source.translated(&-props.center_of_mass);
        assert_eq!(
            (&centred.vertices, &centred.triangles),
            (&expected.vertices, &expected.triangles),
            "{name}"
        );
    }
}

/// An open mesh is an error naming the problem, with a non-zero exit, not a wrong inertia.
#[test]
fn massprops_rejects_an_open_mesh_with_a_named_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("open.obj");
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n",
    )
    .unwrap();
    let out = Command::new(common::rigidref_bin())
        .arg("massprops")
        .arg(&path)
        .output()
        .unwrap();
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr.contains("open.obj") && stderr.contains("open surface"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}
