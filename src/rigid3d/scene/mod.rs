//! Reading scenes: the 3D assignment's scene JSON, its body JSON (`mass`, `J`) and OBJ meshes,
//! read as they are. All validation of input happens here; a [`Scene`] that loads is physically
//! meaningful. The format, the defaults and the keys this project adds: docs/scene-format.md.

pub mod embedded;
pub(crate) mod json;
pub mod params;
pub mod values;

pub use params::{DEFAULT_MAX_PUSH_SPEED, DEFAULT_SLOP, DEFAULT_STABILIZATION, SimParameters};

use crate::rigid3d::mesh::TriMesh;
use nalgebra::{Matrix3, Vector3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// One body as the scene describes it, with its body file and mesh loaded and checked.
#[derive(Clone, Debug)]
pub struct BodyDescription {
    /// `name`.
    pub name: String,
    /// Where the body file came from (a path, or `<embedded>/…`).
    pub source: String,
    /// Mass from the body file, kg.
    pub mass: f64,
    /// Inertia about the centre of mass in the body frame, from the body file, kg·m².
    pub inertia: Matrix3<f64>,
    /// The mesh, centre of mass at its origin, m.
    pub mesh: Arc<TriMesh>,
    /// `x0`, m.
    pub x0: Vector3<f64>,
    /// `R0` (default identity), projected to an exact rotation.
    pub r0: Matrix3<f64>,
    /// `v0`, m/s (default zero).
    pub v0: Vector3<f64>,
    /// `omega0`, rad/s, world frame (default zero).
    pub omega0: Vector3<f64>,
    /// `ellipsoid`: an analytic contact shape in place of the mesh (docs/contact.md
    /// §"Ellipsoid contact").
    pub ellipsoid: Option<crate::rigid3d::shape::Ellipsoid>,
    /// `force`: a constant force at the centre of mass, world frame, N (default zero).
    pub force: Vector3<f64>,
    /// `force_rate`: a force growing linearly in time from zero, F(t) = force_rate · t, at the
    /// centre of mass, world frame, N/s (default zero).
    pub force_rate: Vector3<f64>,
}

/// A loaded scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Where the scene came from (a path, or `<embedded>/…`).
    pub source: String,
    /// The simulation parameters.
    pub params: SimParameters,
    /// The bodies in file order; a body's index is its place here.
    pub bodies: Vec<BodyDescription>,
    /// Things the user should know that do not stop the run (unknown keys, mesh oddities).
    pub warnings: Vec<String>,
    /// The parameters set on the command line (`--set KEY=VALUE`), as `KEY=VALUE`.
    pub overrides: Vec<String>,
}

pub use crate::common::scene_json::{Overrides, SceneError};

/// The text of a body's two files, found by [`BodyFiles`] from its `file_root`.
pub struct BodyFileTexts {
    /// Body JSON text and where it came from.
    pub json: (String, String),
    /// OBJ text and where it came from.
    pub obj: (String, String),
}

/// Finds a body's files from its `file_root`.
pub trait BodyFiles {
    /// The texts of `ROOT.json` and `ROOT.obj`, or an error naming what was tried.
    fn find(&self, file_root: &str) -> Result<BodyFileTexts, SceneError>;
}

/// One body's files held in memory, given for every `file_root` (a scene and one body file in
/// memory, as the fuzz targets and their replay in the suite hold them). The texts are named
/// `body.json` and `body.obj` in messages.
pub struct SameBodyFiles {
    /// The body JSON text.
    pub json: String,
    /// The OBJ text.
    pub obj: String,
}

impl BodyFiles for SameBodyFiles {
    fn find(&self, _file_root: &str) -> Result<BodyFileTexts, SceneError> {
        Ok(BodyFileTexts {
            json: (self.json.clone(), "body.json".into()),
            obj: (self.obj.clone(), "body.obj".into()),
        })
    }
}

/// Body files on disk: `file_root` is tried relative to the assignment root (the parent of the
/// scene's folder), then the scene's folder, then the working directory.
pub struct DiskBodyFiles {
    /// Folders tried in order.
    pub search: Vec<PathBuf>,
}

impl DiskBodyFiles {
    /// The search order for a scene at `scene_path`.
    pub fn for_scene(scene_path: &Path) -> DiskBodyFiles {
        let scene_dir = scene_path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let scene_dir = if scene_dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            scene_dir
        };
        let mut search = Vec::new();
        if let Some(root) = scene_dir
            .join("..")
            .canonicalize()
            .ok()
            .or_else(|| scene_dir.parent().map(Path::to_path_buf))
        {
            search.push(root);
        }
        search.push(scene_dir);
        search.push(PathBuf::from("."));
        DiskBodyFiles { search }
    }
}

impl BodyFiles for DiskBodyFiles {
    fn find(&self, file_root: &str) -> Result<BodyFileTexts, SceneError> {
        let mut tried = Vec::new();
        for dir in &self.search {
            let json = dir.join(format!("{file_root}.json"));
            tried.push(json.display().to_string());
            if json.is_file() {
                let obj = dir.join(format!("{file_root}.obj"));
                let read = |p: &Path| {
                    crate::common::input::read_text(p)
                        .map_err(|e| SceneError(format!("{}: cannot read: {e}", p.display())))
                };
                if !obj.is_file() {
                    return Err(SceneError(format!(
                        "{}: mesh file not found (body file is {})",
                        obj.display(),
                        json.display()
                    )));
                }
                return Ok(BodyFileTexts {
                    json: (read(&json)?, json.display().to_string()),
                    obj: (read(&obj)?, obj.display().to_string()),
                });
            }
        }
        Err(SceneError(format!(
            "body file {file_root}.json not found; tried {}",
            tried.join(", ")
        )))
    }
}

/// Loads a scene file from disk. Errors are one line and name the file (and for JSON syntax or
/// value errors the line and column).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    load_scene_with(path, &Overrides::default())
}

/// Loads the scene at `path` with `overrides` of its `sim_parameters[0]` (`--set KEY=VALUE`),
/// each checked as the file's value of that key would be.
pub fn load_scene_with(path: &Path, overrides: &Overrides) -> Result<Scene, SceneError> {
    let text = crate::common::input::read_text(path)
        .map_err(|e| SceneError(format!("{}: cannot read scene: {e}", path.display())))?;
    // A JSON object with neither a 3D scene's parameters nor a 2D scene's image: say both,
    // rather than only the 3D reader's "missing field `sim_parameters`".
    if let Ok(serde_json::Value::Object(map)) = serde_json::from_str(&text)
        && !map.contains_key("sim_parameters")
        && !map.contains_key("image")
    {
        return Err(SceneError(format!(
            "{}: neither a 3D scene (no \"sim_parameters\") nor a 2D scene (no \"image\")",
            path.display()
        )));
    }
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    parse_scene(
        &text,
        &path.display().to_string(),
        &stem,
        &DiskBodyFiles::for_scene(path),
        overrides,
    )
}

/// Parses scene text. `source` names it in messages, `default_name` is used when it has no
/// `name`, and `files` finds the body files.
pub fn parse_scene(
    text: &str,
    source: &str,
    default_name: &str,
    files: &dyn BodyFiles,
    overrides: &Overrides,
) -> Result<Scene, SceneError> {
    let mut warnings = Vec::new();
    let mut file: json::SceneJson =
        crate::common::scene_json::from_str(text, source, &mut warnings)?;
    if !overrides.is_empty() {
        overrides.check::<json::SimParametersJson>("sim_parameters")?;
        // The file is valid and so is each override: set them in its first sim_parameters entry
        // and read it again.
        let mut value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| SceneError(format!("{source}: {e}")))?;
        if let Some(first) = value
            .get_mut("sim_parameters")
            .and_then(|p| p.get_mut(0))
            .and_then(|p| p.as_object_mut())
        {
            overrides.apply(first);
        }
        file = serde_json::from_value(value).map_err(|e| SceneError(format!("{source}: {e}")))?;
    }
    let params = file.sim_parameters.first().ok_or_else(|| {
        SceneError(format!(
            "{source}: sim_parameters is empty; it needs one entry"
        ))
    })?;
    if file.sim_parameters.len() > 1 {
        warnings.push(format!(
            "{source}: {} sim_parameters entries; only the first is used, as in the starter code",
            file.sim_parameters.len()
        ));
    }
    let params = params.resolve(default_name);
    if file.bodies.is_empty() {
        return Err(SceneError(format!("{source}: the scene has no bodies")));
    }
    let mut bodies = Vec::with_capacity(file.bodies.len());
    for (index, body) in file.bodies.iter().enumerate() {
        let texts = files.find(&body.file_root).map_err(|e| {
            SceneError(format!("{source}: body {index} ({:?}): {}", body.name, e.0))
        })?;
        let (mass, inertia) =
            json::parse_body_file(&texts.json.0, &texts.json.1, &body.file_root, &mut warnings)?;
        let mesh = load_body_mesh(
            &texts.obj.0,
            &texts.obj.1,
            body.off_centre_mesh,
            &mut warnings,
        )?;
        let r0 = match body.r0 {
            None => Matrix3::identity(),
            Some(o) if o.proper => o.matrix,
            Some(o) => {
                let what = format!(
                    "{source}: body {index} ({:?}): R0 has determinant −1 (a reflection)",
                    body.name
                );
                let mirror = mirror_symmetry(&mesh, &inertia).ok_or_else(|| {
                    SceneError(format!("{what}, and the body is not mirror-symmetric, so no rotation places it as given"))
                })?;
                let rotation = crate::rigid3d::rotation::nearest_rotation(&(o.matrix * mirror));
                warnings.push(format!(
                    "{what}; the body is symmetric under the body-frame reflection diag({}, {}, {}), so the rotation R0·S places the same shape with the same inertia and is used instead",
                    mirror[(0, 0)], mirror[(1, 1)], mirror[(2, 2)]
                ));
                rotation
            }
        };
        bodies.push(BodyDescription {
            name: body.name.clone(),
            source: texts.json.1.clone(),
            mass,
            inertia,
            mesh: Arc::new(mesh),
            x0: body.x0.0,
            r0,
            v0: body.v0.map_or(Vector3::zeros(), |v| v.0),
            omega0: body.omega0.map_or(Vector3::zeros(), |v| v.0),
            ellipsoid: body.ellipsoid.map(|e| crate::rigid3d::shape::Ellipsoid {
                centre: e.centre.map_or(Vector3::zeros(), |c| c.0),
                semi_axes: Vector3::from(e.semi_axes.map(|a| a.0)),
            }),
            force: body.force.map_or(Vector3::zeros(), |v| v.0),
            force_rate: body.force_rate.map_or(Vector3::zeros(), |v| v.0),
        });
    }
    warnings.extend(slop_warnings(source, &params, &bodies));
    if params.check_collisions
        && params.collision == crate::rigid3d::collide::CollisionMethod::Starter
    {
        warnings.extend(starter_warnings(source, &bodies));
    }
    if params.check_collisions && bodies.len() > 1 {
        // Not silent about what the ellipsoid replaces: its surface is exact against the ground
        // and other meshes' vertices, its mesh stands in for it everywhere else.
        for b in bodies.iter().filter(|b| b.ellipsoid.is_some()) {
            warnings.push(format!(
                "note: {source}: body {:?}'s ellipsoid is its surface against the ground and against other bodies' vertices; its own mesh's vertices stand for it against other bodies, and `collision: complete` and the penetration measure use its mesh (docs/contact.md §\"Ellipsoid contact\")",
                b.name
            ));
        }
    }
    Ok(Scene {
        source: source.to_string(),
        params,
        bodies,
        warnings,
        overrides: overrides.describe(),
    })
}

/// What `collision: starter` cannot do as the starter does: a body's ellipsoid (the starter
/// knows meshes only, so its mesh is used), and vertices of the OBJ file no face uses (libigl
/// reads them and the starter tests them; rigidref's reader drops them).
fn starter_warnings(source: &str, bodies: &[BodyDescription]) -> Vec<String> {
    let mut out = Vec::new();
    for b in bodies {
        if b.ellipsoid.is_some() {
            out.push(format!(
                "{source}: body {:?}: `collision: starter` tests meshes only, as the starter does: its ellipsoid is not used for contact",
                b.name
            ));
        }
        let unused = b
            .mesh
            .file_vertex_count()
            .saturating_sub(b.mesh.vertices.len());
        if unused > 0 {
            out.push(format!(
                "{source}: body {:?}: its mesh has {unused} vertices no face uses; the starter (libigl's reader) keeps and tests them, `collision: starter` does not",
                b.name
            ));
        }
    }
    out
}

/// The slop is more than this fraction of a body's smallest extent: a warning
/// (docs/contact.md §"Stabilisation").
pub const SLOP_FRACTION: f64 = 0.1;

/// One warning per body whose smallest extent (its ellipsoid's smallest diameter, else its mesh's
/// smallest bounding-box side) is less than `stabilization_slop` / [`SLOP_FRACTION`]: such a body
/// can rest sunk up to the slop into the ground or another body with nothing pushing it out (the
/// Kane–Levinson rattleback, 2 cm thick, sinks 3 mm under the default 5 mm), so the slop is not
/// small against it. Only with collisions on and stabilisation acting (β > 0).
fn slop_warnings(source: &str, params: &SimParameters, bodies: &[BodyDescription]) -> Vec<String> {
    if !params.check_collisions || params.stabilization == 0.0 {
        return Vec::new();
    }
    let slop = params.stabilization_slop;
    bodies
        .iter()
        .filter_map(|b| {
            let extent = match &b.ellipsoid {
                Some(e) => 2.0 * e.semi_axes.min(),
                None => crate::rigid3d::collide::penetration::mesh_size(&b.mesh),
            };
            (slop > SLOP_FRACTION * extent).then(|| {
                format!(
                    "{source}: stabilization_slop {slop} m is more than a tenth of body {:?}'s smallest extent ({extent:.4} m): it can rest that deep in a contact with nothing pushing it out; set stabilization_slop to at most {:.1e} m (docs/contact.md §\"Stabilisation\")",
                    b.name,
                    SLOP_FRACTION * extent
                )
            })
        })
        .collect()
}

/// A body-frame coordinate reflection S (diag with one −1) that maps the mesh onto itself and
/// leaves the inertia unchanged (S J S = J, to 1e-6 of the largest entry), if there is one.
/// Vertices must map to vertices within 1e-5 of the mesh's radius (the assignment's sphere is
/// symmetric to 2.9e-6 of its radius: its coordinates were rounded to six digits), and either
/// triangles to triangles or the mesh be convex (a convex solid is the hull of its vertices, so
/// a different triangulation of a flat face, as in the assignment's brick, is the same solid).
/// docs/scene-format.md §"R0 and reflections".
pub fn mirror_symmetry(mesh: &TriMesh, inertia: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let tolerance = 1e-5 * mesh.bounding_radius();
    let mut triangles: Vec<[usize; 3]> = mesh.triangles.iter().map(|t| sorted(*t)).collect();
    triangles.sort_unstable();
    (0..3).find_map(|axis| {
        let mut diagonal = Vector3::repeat(1.0);
        diagonal[axis] = -1.0;
        let s = Matrix3::from_diagonal(&diagonal);
        if (s * inertia * s - inertia).amax() > 1e-6 * inertia.amax() {
            return None;
        }
        // Where each vertex goes under S.
        let image: Option<Vec<usize>> = mesh
            .vertices
            .iter()
            .map(|v| {
                let target = s * v;
                mesh.vertices
                    .iter()
                    .position(|w| (w - target).norm() <= tolerance)
            })
            .collect();
        let image = image?;
        let mut mapped: Vec<[usize; 3]> = mesh
            .triangles
            .iter()
            .map(|t| sorted(t.map(|i| image[i])))
            .collect();
        mapped.sort_unstable();
        (mapped == triangles || mesh.is_convex(tolerance)).then_some(s)
    })
}

fn sorted(mut t: [usize; 3]) -> [usize; 3] {
    t.sort_unstable();
    t
}

/// Reads and checks a body mesh: it must bound a solid, and its centre of mass should be at its
/// origin (the body frame's origin is taken to be the centre of mass, as in the assignment).
fn load_body_mesh(
    text: &str,
    source: &str,
    off_centre_on_purpose: bool,
    warnings: &mut Vec<String>,
) -> Result<TriMesh, SceneError> {
    let mesh = TriMesh::parse_obj(text, source).map_err(|e| SceneError(e.0))?;
    warnings.extend(mesh.check_solid(source).map_err(|e| SceneError(e.0))?);
    let com = crate::rigid3d::massprops::mass_properties(&mesh, 1.0).center_of_mass;
    // 1e-3 of the body's size: far above the round-off of a mesh written with 15 digits, far
    // below an offset that would visibly change contact or rotation.
    if com.norm() > 1e-3 * mesh.bounding_radius() && off_centre_on_purpose {
        warnings.push(format!(
            "note: {source}: the mesh's centre of mass (uniform density) is at ({:.4}, {:.4}, {:.4}), not at its origin, as the scene declares (`off_centre_mesh`): the body's mass and inertia are the body file's",
            com.x, com.y, com.z
        ));
    } else if com.norm() > 1e-3 * mesh.bounding_radius() {
        warnings.push(format!(
            "{source}: the mesh's centre of mass is at ({:.4}, {:.4}, {:.4}), not at its origin; the body rotates about the origin (make a centred mesh with `rigidref massprops`)",
            com.x, com.y, com.z
        ));
    }
    Ok(mesh)
}
