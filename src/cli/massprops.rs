//! `rigidref massprops`: polyhedral mass properties of a mesh, written as an assignment body file.

use anyhow::{Context, bail};
use clap::Args;
use rigidref::rigid3d::massprops::mass_properties;
use rigidref::rigid3d::mesh::TriMesh;
use std::path::PathBuf;

/// Arguments of `rigidref massprops`.
#[derive(Args)]
#[command(after_long_help = "\
The mesh must be a closed, consistently oriented triangle mesh with outward normals (faces
counter-clockwise seen from outside); anything else is an error naming the problem, because its
inertia would be wrong. Method: docs/massprops.md.

With --out ROOT, writes ROOT.json ({\"mesh_file\", \"mass\", \"J\"}, the 3D assignment's body format)
and ROOT.obj, the mesh translated so that its centre of mass is at the origin.")]
pub struct MasspropsArgs {
    /// Closed triangle mesh (OBJ).
    pub mesh: PathBuf,
    /// Uniform density, kg/m³ (the assignment's body files use 1000).
    #[arg(long, default_value_t = 1000.0)]
    pub density: f64,
    /// Write ROOT.json and ROOT.obj (centred) for use as a scene's file_root.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the result as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Computes, prints and optionally writes the mass properties.
pub fn massprops(args: MasspropsArgs) -> anyhow::Result<()> {
    if !(args.density.is_finite() && args.density > 0.0) {
        bail!(
            "--density must be a positive number of kg/m³, got {}",
            args.density
        );
    }
    let source = args.mesh.display().to_string();
    let mesh = TriMesh::load_obj(&args.mesh)?;
    for w in mesh.check_solid(&source)? {
        eprintln!("warning: {w}");
    }
    let props = mass_properties(&mesh, args.density);
    let j = props.inertia;
    let rows = |m: &nalgebra::Matrix3<f64>| -> Vec<Vec<f64>> {
        (0..3)
            .map(|i| (0..3).map(|k| m[(i, k)]).collect())
            .collect()
    };
    let c = props.center_of_mass;
    if args.json {
        let out = serde_json::json!({
            "mesh": source, "density": props.density, "volume": props.volume, "mass": props.mass,
            "center_of_mass": [c.x, c.y, c.z], "J": rows(&j),
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let moments = j.symmetric_eigenvalues();
        println!(
            "mesh            {source} ({} vertices, {} triangles)",
            mesh.vertices.len(),
            mesh.triangles.len()
        );
        println!("density         {} kg/m³", props.density);
        println!("volume          {:.12e} m³", props.volume);
        println!("mass            {:.12e} kg", props.mass);
        println!(
            "centre of mass  ({:.12e}, {:.12e}, {:.12e}) m",
            c.x, c.y, c.z
        );
        println!("J about COM     kg·m², body axes of the mesh:");
        for i in 0..3 {
            println!(
                "                [{:>20.12e} {:>20.12e} {:>20.12e}]",
                j[(i, 0)],
                j[(i, 1)],
                j[(i, 2)]
            );
        }
        println!(
            "principal       {:.9e}, {:.9e}, {:.9e} kg·m²",
            moments[0], moments[1], moments[2]
        );
    }
    if let Some(root) = &args.out {
        let json_path = PathBuf::from(format!("{}.json", root.display()));
        let obj_path = PathBuf::from(format!("{}.obj", root.display()));
        let mesh_file = obj_path
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let body = serde_json::json!({ "mesh_file": mesh_file, "mass": props.mass, "J": rows(&j) });
        if let Some(dir) = json_path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
        }
        std::fs::write(&json_path, serde_json::to_string_pretty(&body)? + "\n")
            .with_context(|| format!("{}: cannot write", json_path.display()))?;
        std::fs::write(&obj_path, mesh.translated(&-c).to_obj())
            .with_context(|| format!("{}: cannot write", obj_path.display()))?;
        eprintln!(
            "wrote {} and {} (centre of mass moved to the origin)",
            json_path.display(),
            obj_path.display()
        );
    }
    Ok(())
}
