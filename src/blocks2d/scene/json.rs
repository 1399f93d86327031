//! The 2D scene file as read (docs/blocks2d.md §"Scene files"): serde structs that mirror its
//! JSON, before the values are checked.

use super::*;

#[derive(Deserialize)]
pub(super) struct SceneFile2 {
    pub(super) image: String,
    #[serde(default)]
    pub(super) parameters: ParametersFile2,
    #[serde(default)]
    pub(super) impulses: Vec<ImpulseFile>,
    #[serde(default)]
    pub(super) shakes: Vec<ShakeFile>,
    #[serde(default)]
    pub(super) pins: Vec<PinFile>,
    #[serde(default)]
    pub(super) springs: Vec<SpringFile>,
}

#[derive(Deserialize)]
pub(super) struct PinFile {
    pub(super) bodies: [Option<usize>; 2],
    pub(super) point: [f64; 2],
}

#[derive(Deserialize)]
pub(super) struct SpringFile {
    pub(super) bodies: [Option<usize>; 2],
    pub(super) points: [[f64; 2]; 2],
    pub(super) stiffness: NonNegative,
    #[serde(default)]
    pub(super) damping: Option<NonNegative>,
    #[serde(default)]
    pub(super) rest_length: Option<NonNegative>,
}

#[derive(Deserialize, Default)]
pub(super) struct ParametersFile2 {
    pub(super) preset: Option<Preset>,
    pub(super) step: Option<Positive>,
    pub(super) substeps: Option<Count>,
    pub(super) gravity: Option<NonNegative>,
    pub(super) gravity_angle: Option<f64>,
    pub(super) mu: Option<NonNegative>,
    pub(super) restitution: Option<NonNegative>,
    pub(super) iterations: Option<Count>,
    pub(super) pgs_tolerance: Option<Positive>,
    pub(super) order: Option<ContactOrder>,
    pub(super) seed: Option<u64>,
    pub(super) pgs_local_solve: Option<LocalSolve>,
    pub(super) warm_start: Option<bool>,
    pub(super) post_stabilization: Option<bool>,
    pub(super) slop: Option<NonNegative>,
    pub(super) contact_model: Option<ContactModel>,
    pub(super) white_threshold: Option<NonNegative>,
    pub(super) max_travel: Option<Positive>,
    pub(super) shock_propagation: Option<bool>,
    pub(super) solver: Option<Solver>,
    pub(super) threads: Option<Count>,
    pub(super) detection_cache: Option<bool>,
    pub(super) check_detection: Option<bool>,
    pub(super) inertia: Option<InertiaRule>,
    pub(super) disc_tree: Option<DiscTreeRule>,
    pub(super) image_reader: Option<ImageReader>,
}

#[derive(Deserialize)]
pub(super) struct ImpulseFile {
    pub(super) time: NonNegative,
    pub(super) body: usize,
    pub(super) impulse: [f64; 2],
    pub(super) point: Option<[f64; 2]>,
}

#[derive(Deserialize)]
pub(super) struct ShakeFile {
    pub(super) body: usize,
    pub(super) velocity: [f64; 2],
    #[serde(default)]
    pub(super) angular: f64,
    pub(super) frequency: NonNegative,
}

impl ParametersFile2 {
    /// The values read, as plain parameters.
    pub(super) fn plain(self) -> ParamOverrides2 {
        let p = self;
        ParamOverrides2 {
            preset: p.preset,
            step: p.step.map(|x| x.0),
            substeps: p.substeps.map(|x| x.0),
            gravity: p.gravity.map(|x| x.0),
            gravity_angle: p.gravity_angle,
            mu: p.mu.map(|x| x.0),
            restitution: p.restitution.map(|x| x.0),
            iterations: p.iterations.map(|x| x.0),
            pgs_tolerance: p.pgs_tolerance.map(|x| x.0),
            order: p.order,
            seed: p.seed,
            pgs_local_solve: p.pgs_local_solve,
            warm_start: p.warm_start,
            post_stabilization: p.post_stabilization,
            slop: p.slop.map(|x| x.0),
            contact_model: p.contact_model,
            white_threshold: p.white_threshold.map(|x| x.0),
            max_travel: p.max_travel.map(|x| x.0),
            shock_propagation: p.shock_propagation,
            solver: p.solver,
            threads: p.threads.map(|x| x.0),
            detection_cache: p.detection_cache,
            check_detection: p.check_detection,
            inertia: p.inertia,
            disc_tree: p.disc_tree,
            image_reader: p.image_reader,
        }
    }
}
