//! A rigidref scene as every engine's mirror reads it: the mirror description
//! (docs/validation.md §"Mirror description"). The scene file is read once, by rigidref's own
//! reader; the mirrors (python/mirrors/) build their models from this, so no engine parses a
//! scene and every engine gets the same masses, inertias, shapes, μ, gravity and step.

use crate::rigid3d::collide::pieces::ConvexPieces;
use crate::rigid3d::scene::{BodyDescription, Scene};
use serde::Serialize;

/// The description's format name and version.
pub const MIRROR_FORMAT: &str = "rigidref-mirror";
/// See [`MIRROR_FORMAT`].
pub const MIRROR_VERSION: u32 = 1;

/// A body's collision shape in the engines' terms, body frame (centred on the centre of mass).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum MirrorShape {
    /// A box centred on the centre of mass, edges along the body axes: half extents, m.
    Box {
        /// Half the edge lengths along x, y, z, m.
        half_extents: [f64; 3],
    },
    /// A sphere centred on the centre of mass (the `ellipsoid` key with equal semi-axes), m.
    Sphere {
        /// Radius, m.
        radius: f64,
    },
    /// The convex hull of these vertices, m.
    Hull {
        /// The hull's vertices, m.
        vertices: Vec<[f64; 3]>,
    },
}

/// One body of the description.
#[derive(Clone, Debug, Serialize)]
pub struct MirrorBody {
    /// The scene's name for it.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the centre of mass, body frame, kg·m² (rows).
    pub inertia: [[f64; 3]; 3],
    /// Initial centre of mass, m.
    pub x0: [f64; 3],
    /// Initial rotation body → world (rows).
    #[serde(rename = "R0")]
    pub r0: [[f64; 3]; 3],
    /// Initial velocity, m/s.
    pub v0: [f64; 3],
    /// Initial angular velocity, world frame, rad/s.
    pub omega0: [f64; 3],
    /// Constant applied force at the centre of mass, N.
    pub force: [f64; 3],
    /// Its rate, N/s (the force at time t is force + force_rate t).
    pub force_rate: [f64; 3],
    /// Collision shape.
    pub shape: MirrorShape,
}

/// What a mirror needs of a scene.
#[derive(Clone, Debug, Serialize)]
pub struct MirrorScene {
    /// [`MIRROR_FORMAT`].
    pub format: &'static str,
    /// [`MIRROR_VERSION`].
    pub version: u32,
    /// The scene's name.
    pub scene: String,
    /// The scene file's stem (names files the mirror writes beside its trace).
    pub scene_file: String,
    /// The scene file.
    pub source: String,
    /// Frame step, s.
    pub dt: f64,
    /// Engine steps per frame (the scene's substeps).
    pub substeps: u32,
    /// The engine's step, dt / substeps, s.
    pub h: f64,
    /// Frames to run.
    pub frames: u64,
    /// Gravity, m/s².
    pub gravity: [f64; 3],
    /// Friction coefficient of every pair (body–ground and body–body).
    pub mu: f64,
    /// Whether there is a ground and contact at all.
    pub check_collisions: bool,
    /// The bodies, in scene order.
    pub bodies: Vec<MirrorBody>,
}

fn rows(m: &nalgebra::Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// The shape of a body: its analytic sphere, else its mesh as a box when it is one, else its
/// convex hull; a non-convex mesh is refused (the mirrors take convex bodies).
pub fn mirror_shape(body: &BodyDescription) -> Result<MirrorShape, String> {
    if let Some(e) = &body.ellipsoid {
        let a = e.semi_axes;
        if e.centre.norm() == 0.0 && a.x == a.y && a.y == a.z {
            return Ok(MirrorShape::Sphere { radius: a.x });
        }
        return Err(format!(
            "{}: body {:?}: an ellipsoid that is not a sphere about the centre of mass has no mirror",
            body.source, body.name
        ));
    }
    let pieces = ConvexPieces::of_mesh(&body.mesh)
        .map_err(|e| format!("{}: body {:?}: {e}", body.source, body.name))?;
    if !pieces.convex {
        return Err(format!(
            "{}: body {:?}: its mesh is not convex ({} convex pieces); the mirrors take convex bodies",
            body.source,
            body.name,
            pieces.pieces.len()
        ));
    }
    let piece = &pieces.pieces[0];
    if let Some(c) = &piece.cuboid {
        let aligned = c.centre.norm() <= 1e-9 * c.half.norm()
            && c.axes
                .iter()
                .all(|a| (a.x.abs().max(a.y.abs()).max(a.z.abs()) - 1.0).abs() <= 1e-12);
        if aligned {
            let mut half = [0.0; 3];
            for (axis, h) in c.axes.iter().zip(c.half.iter()) {
                let k = (0..3)
                    .max_by(|&i, &j| axis[i].abs().total_cmp(&axis[j].abs()))
                    .unwrap_or(0);
                half[k] = *h;
            }
            return Ok(MirrorShape::Box { half_extents: half });
        }
    }
    Ok(MirrorShape::Hull {
        vertices: piece.vertices.iter().map(|v| [v.x, v.y, v.z]).collect(),
    })
}

impl MirrorScene {
    /// The description of `scene` run for `frames` frames; `file` is the scene file's stem.
    pub fn of_scene(scene: &Scene, file: &str, frames: u64) -> Result<MirrorScene, String> {
        let p = &scene.params;
        let bodies = scene
            .bodies
            .iter()
            .map(|b| {
                Ok(MirrorBody {
                    name: b.name.clone(),
                    mass: b.mass,
                    inertia: rows(&b.inertia),
                    x0: b.x0.into(),
                    r0: rows(&b.r0),
                    v0: b.v0.into(),
                    omega0: b.omega0.into(),
                    force: b.force.into(),
                    force_rate: b.force_rate.into(),
                    shape: mirror_shape(b)?,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(MirrorScene {
            format: MIRROR_FORMAT,
            version: MIRROR_VERSION,
            scene: p.name.clone(),
            scene_file: file.to_string(),
            source: scene.source.clone(),
            dt: p.dt,
            substeps: p.substeps,
            h: p.h(),
            frames,
            gravity: p.gravity.into(),
            mu: p.mu,
            check_collisions: p.check_collisions,
            bodies,
        })
    }
}
