//! Helpers shared by the integration tests.
#![allow(dead_code)]

use nalgebra::{Matrix3, Vector3};
use rigidref::body::RigidBody;
use rigidref::mesh::TriMesh;
use std::path::PathBuf;
use std::sync::Arc;

/// The project root (where Cargo.toml is).
pub fn project_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `../shared/assignments/rigid3d`, or None after printing why the caller skips.
pub fn rigid3d_assignment() -> Option<PathBuf> {
    let dir = project_root().join("../shared/assignments/rigid3d");
    if dir.join("scenes").is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: {} is absent (it exists beside the project on developer and CI machines, not in a user's clone)",
            dir.display()
        );
        None
    }
}

/// A body with the given mass (kg), principal moments (kg·m²) along the axes of `frame`, state.
pub fn body(mass: f64, moments: [f64; 3], frame: Matrix3<f64>) -> RigidBody {
    let inertia = frame * Matrix3::from_diagonal(&Vector3::from(moments)) * frame.transpose();
    let mesh = Arc::new(TriMesh::cuboid(Vector3::repeat(-0.5), Vector3::repeat(0.5)));
    RigidBody::new("random", mass, (inertia + inertia.transpose()) * 0.5, mesh)
}

/// Path of the built `rigidref` binary.
pub fn rigidref_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_rigidref"))
}
