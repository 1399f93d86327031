//! The JSON shapes of the 3D assignment's scene and body files, and the one reader that turns
//! serde errors into `file:line:column: key.path: message` and unknown keys into warnings.

use super::params::{DEFAULT_MAX_PUSH_SPEED, DEFAULT_SLOP, DEFAULT_STABILIZATION, SimParameters};
use super::values::{Inertia, Orientation, Vec3, ZeroDamping};
use crate::common::preset::Preset;
use crate::common::scene_json::SceneError;
use crate::common::values::{Count, Fraction, NonNegative, Positive};
use crate::problem::FrictionModel;
use crate::rigid3d::body::AngularIntegrator;
use crate::rigid3d::collide::{CollisionMethod, Culling};
use crate::rigid3d::frame::Tangents;
use crate::solve::{ContactOrder, LocalSolve, Solver};
use nalgebra::{Matrix3, Vector3};
use serde::Deserialize;

/// `{"sim_parameters": [...], "bodies": [...]}`.
#[derive(Deserialize)]
pub(super) struct SceneJson {
    pub sim_parameters: Vec<SimParametersJson>,
    pub bodies: Vec<BodyJson>,
}

#[derive(Deserialize)]
pub(super) struct SimParametersJson {
    preset: Option<Preset>,
    name: Option<String>,
    dt: Option<Positive>,
    gravity: Option<Vec3>,
    mu: Option<NonNegative>,
    substeps: Option<Count>,
    check_collisions: Option<bool>,
    stop_on_contact: Option<bool>,
    #[allow(dead_code)] // UI only, read so that it is not reported as unknown
    show_contacts: Option<bool>,
    #[allow(dead_code)]
    is_running: Option<bool>,
    #[allow(dead_code)] // validated to be 0
    damping: Option<ZeroDamping>,
    pgs_iterations: Option<Count>,
    integrator: Option<AngularIntegrator>,
    friction_model: Option<FrictionModel>,
    compliance: Option<NonNegative>,
    stabilization: Option<Fraction>,
    stabilization_slop: Option<NonNegative>,
    stabilization_max_speed: Option<Positive>,
    warm_start: Option<bool>,
    pgs_tolerance: Option<Positive>,
    pgs_order: Option<ContactOrder>,
    pgs_seed: Option<u64>,
    threads: Option<Count>,
    pgs_local_solve: Option<LocalSolve>,
    solver: Option<Solver>,
    collision: Option<CollisionMethod>,
    tangents: Option<Tangents>,
    culling: Option<Culling>,
    detection_cache: Option<bool>,
    persistent_manifolds: Option<bool>,
    check_detection: Option<bool>,
}

impl SimParametersJson {
    /// Applies the starter's defaults (docs/scene-format.md §"Simulation parameters"); with
    /// `"preset": "starter"` also the starter's own behaviour where the project's defaults
    /// differ: no warm start, no Baumgarte stabilisation, the starter's collision detection and
    /// tangents (docs/scene-format.md §"The starter preset").
    pub fn resolve(&self, default_name: &str) -> SimParameters {
        let preset = self.preset.unwrap_or_default();
        let starter = preset == Preset::Starter;
        SimParameters {
            preset,
            name: self
                .name
                .clone()
                .unwrap_or_else(|| default_name.to_string()),
            dt: self.dt.map_or(0.01, |x| x.0),
            gravity: self.gravity.map_or(Vector3::zeros(), |g| g.0),
            mu: self.mu.map_or(0.0, |x| x.0),
            substeps: self.substeps.map_or(1, |x| x.0),
            check_collisions: self.check_collisions.unwrap_or(true),
            stop_on_contact: self.stop_on_contact.unwrap_or(false),
            pgs_iterations: self.pgs_iterations.map_or(100, |x| x.0),
            integrator: self.integrator.unwrap_or_default(),
            friction_model: self.friction_model.unwrap_or_default(),
            compliance: self.compliance.map_or(0.0, |x| x.0),
            stabilization: self
                .stabilization
                .map_or(if starter { 0.0 } else { DEFAULT_STABILIZATION }, |x| x.0),
            stabilization_slop: self.stabilization_slop.map_or(DEFAULT_SLOP, |x| x.0),
            stabilization_max_speed: self
                .stabilization_max_speed
                .map_or(DEFAULT_MAX_PUSH_SPEED, |x| x.0),
            warm_start: self.warm_start.unwrap_or(!starter),
            pgs_tolerance: self.pgs_tolerance.map(|x| x.0),
            pgs_order: self.pgs_order.unwrap_or_default(),
            pgs_seed: self.pgs_seed.unwrap_or(0),
            threads: self.threads.map_or(1, |x| x.0),
            pgs_local_solve: self.pgs_local_solve.unwrap_or_default(),
            solver: self.solver.unwrap_or_default(),
            collision: self.collision.unwrap_or(if starter {
                CollisionMethod::Starter
            } else {
                CollisionMethod::default()
            }),
            tangents: self.tangents.unwrap_or(if starter {
                Tangents::Starter
            } else {
                Tangents::default()
            }),
            culling: self.culling.unwrap_or_default(),
            detection_cache: self.detection_cache.unwrap_or(true),
            persistent_manifolds: self.persistent_manifolds.unwrap_or(false),
            check_detection: self.check_detection.unwrap_or(false),
        }
    }
}

/// One entry of `bodies`.
#[derive(Deserialize)]
pub(super) struct BodyJson {
    pub name: String,
    pub file_root: String,
    pub x0: Vec3,
    #[serde(rename = "R0")]
    pub r0: Option<Orientation>,
    pub v0: Option<Vec3>,
    pub omega0: Option<Vec3>,
    /// An analytic ellipsoid contact shape (docs/scene-format.md §"Bodies").
    pub ellipsoid: Option<EllipsoidJson>,
    /// `true` declares that the mesh is not centred on the centre of mass on purpose (mass
    /// distributed differently inside, as in a rattleback): the warning becomes a note.
    #[serde(default)]
    pub off_centre_mesh: bool,
    /// A constant force at the centre of mass, world frame, N (docs/scene-format.md §"Bodies").
    pub force: Option<Vec3>,
    /// A force growing from zero at this rate, world frame, N/s.
    pub force_rate: Option<Vec3>,
}

/// `ellipsoid`: `{"semi_axes": [a, b, c], "centre": [x, y, z]}`, body frame, m.
#[derive(Deserialize, Clone, Copy)]
pub(super) struct EllipsoidJson {
    pub semi_axes: [Positive; 3],
    #[serde(default)]
    pub centre: Option<Vec3>,
}

/// A body file: `{"mesh_file", "mass", "J"}`.
#[derive(Deserialize)]
struct BodyFileJson {
    mesh_file: Option<String>,
    mass: Positive,
    #[serde(rename = "J")]
    inertia: Inertia,
}

/// Reads a body file: mass (kg) and inertia about the centre of mass (kg·m²). Warns when
/// `mesh_file` names a different file than `ROOT.obj` (the starter reads `ROOT.obj`) and when
/// the principal moments violate the triangle inequality (no mass distribution has them).
pub(super) fn parse_body_file(
    text: &str,
    source: &str,
    file_root: &str,
    warnings: &mut Vec<String>,
) -> Result<(f64, Matrix3<f64>), SceneError> {
    let body: BodyFileJson = crate::common::scene_json::from_str(text, source, warnings)?;
    let expected_mesh = format!("{}.obj", file_root.rsplit('/').next().unwrap_or(file_root));
    if let Some(mesh_file) = &body.mesh_file {
        let named = mesh_file.rsplit('/').next().unwrap_or(mesh_file);
        if named != expected_mesh {
            warnings.push(format!(
                "{source}: mesh_file is {mesh_file:?} but the mesh read is {expected_mesh} (the starter reads file_root + \".obj\")"
            ));
        }
    }
    let moments = body.inertia.0.symmetric_eigenvalues();
    let (a, b, c) = (moments[0], moments[1], moments[2]);
    let slack = 1e-9 * (a + b + c);
    if a + b + slack < c || a + c + slack < b || b + c + slack < a {
        warnings.push(format!(
            "{source}: principal moments {a:.6}, {b:.6}, {c:.6} violate the triangle inequality: no mass distribution has this inertia"
        ));
    }
    Ok((body.mass.0, body.inertia.0))
}
