//! The 2D system's parameters: the defaults (the demonstration settings) and the Java
//! starter's, `--preset starter`. docs/blocks2d.md §"Demonstration settings", §"The starter
//! preset".

use super::body::InertiaRule;
use super::disc_tree::DiscTreeRule;
use super::image::ImageReader;
use crate::solve::{ContactOrder, LocalSolve};
use nalgebra::Vector2;

/// How contacts are resolved.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum ContactModel {
    /// Velocity-level complementarity solved by PGS (the assignment's objective).
    #[default]
    Pgs,
    /// The starter's penalty springs (frictionless), for comparison.
    Penalty,
}

/// Parameters of the 2D system. The defaults are the demonstration settings
/// ([`Params2::demonstration`]); [`Params2::starter`] holds the Java starter's values.
#[derive(Clone, Debug, PartialEq)]
pub struct Params2 {
    /// Step size dt, time units (scene key and option `step`; default 0.05, the starter's).
    pub dt: f64,
    /// Substeps per step (default 4; the starter's 1).
    pub substeps: u32,
    /// Gravity magnitude, blocks per time² (default 1).
    pub gravity: f64,
    /// Gravity direction, degrees from +x toward +y (default 90: toward increasing image row).
    pub gravity_angle: f64,
    /// Friction coefficient (default 0.33, the starter's).
    pub mu: f64,
    /// Coefficient of restitution (default 0).
    pub restitution: f64,
    /// PGS sweeps per solve (default 200; the starter's 10).
    pub iterations: u32,
    /// Optional early stop on the residual.
    pub tolerance: Option<f64>,
    /// Contact order in PGS (default random; the starter's sequential).
    pub order: ContactOrder,
    /// Seed of the random order.
    pub seed: u64,
    /// How a PGS visit updates its contact (scene key `pgs_local_solve`; default rows, the
    /// starter's; docs/contact.md §"Exact local solve").
    pub local_solve: LocalSolve,
    /// Warm start (default true; the starter's false).
    pub warm_start: bool,
    /// Post-stabilisation of penetration (default true; the starter's false).
    pub post_stabilization: bool,
    /// Penetration left alone by post-stabilisation, blocks (default 0.01).
    pub slop: f64,
    /// PGS (default) or penalty springs.
    pub contact_model: ContactModel,
    /// Penalty spring stiffness, per unit penetration (default 1000).
    pub penalty_stiffness: f64,
    /// Penalty damping, per unit approach speed (default 10).
    pub penalty_damping: f64,
    /// Adaptive substeps (scene key `max_travel`, blocks; default off): when set, each step takes
    /// enough substeps that the fastest body's fastest block moves at most this far per substep,
    /// never fewer than `substeps`, at most [`MAX_ADAPTIVE_SUBSTEPS`]. docs/blocks2d.md
    /// §"Adaptive substeps".
    pub max_travel: Option<f64>,
    /// Shock propagation after each velocity solve (scene key `shock_propagation`; default off).
    /// docs/blocks2d.md §"Shock propagation".
    pub shock_propagation: bool,
    /// The contact solver (scene key `solver`): `pgs` (default, the assignment's) or `newton`
    /// (the exact solver, docs/contact.md §"Newton solver"); post-stabilisation uses it too.
    pub solver: crate::solve::Solver,
    /// Threads the coloured order's sweeps run on (scene key `threads`; default 1): bit for bit
    /// the one-thread result (docs/contact.md §"Coloured order").
    pub threads: u32,
    /// Keep each body pair's candidate block pairs from step to step (scene key
    /// `detection_cache`; default true): the same contacts, found faster. docs/blocks2d.md
    /// §"Temporal coherence".
    pub detection_cache: bool,
    /// Run fresh detection beside the cached one every substep and count any difference (scene
    /// key `check_detection`; default false): the cache's debug check.
    pub check_detection: bool,
    /// How a body's rotational inertia comes from its blocks (scene key `inertia`; default
    /// `blocks`, unit squares; the starter's `block_centres`, point masses).
    pub inertia: InertiaRule,
    /// How the bodies' disc trees are built and descended (scene key `disc_tree`; default
    /// `median`; the starter's `starter`): the order contacts are found in.
    pub disc_tree: DiscTreeRule,
    /// How the image was read into bodies (scene key `image_reader`; default `rigidref`, bodies
    /// numbered row by row; the starter's `starter`, column by column). Used when loading.
    pub image_reader: ImageReader,
    /// The preset these parameters started from (the run's summary names it and what it set).
    pub preset: Preset,
}

/// The most substeps one step takes with adaptive substeps: a body faster than
/// `max_travel · 4096 / step` is stepped at that cap (and the run says so).
pub const MAX_ADAPTIVE_SUBSTEPS: u32 = 4096;

/// The named starting points of the parameters (`--preset`, or `"preset"` in a scene file's
/// parameters): [`Params2::default`] or [`Params2::starter`].
pub use crate::common::preset::Preset;

impl Preset {
    /// The parameters of the preset.
    pub fn params(self) -> Params2 {
        match self {
            Preset::Default => Params2::default(),
            Preset::Starter => Params2::starter(),
        }
    }
}

impl Default for Params2 {
    /// The defaults: [`Params2::demonstration`].
    fn default() -> Self {
        Params2::demonstration()
    }
}

impl Params2 {
    /// The Java starter code's values, everything its provided code does (docs/blocks2d.md
    /// §"The starter preset" says where each was read): step 0.05, 1 substep, gravity 1 at 90°,
    /// μ 0.33, restitution 0, 10 Gauss–Seidel sweeps over the contacts in the order found, each
    /// solve from zero (no warm start), no post-stabilisation (the assignment lists both under
    /// "other things to try"), the inertia of point-mass blocks (`RigidBody`'s), the starter's
    /// disc trees (`BVNode`) and its image reader's body numbering (`ImageBlocker`). With them
    /// tower100 collapses (docs/blocks2d.md §"Demonstration settings").
    pub fn starter() -> Params2 {
        Params2 {
            substeps: 1,
            iterations: 10,
            order: ContactOrder::Sequential,
            warm_start: false,
            post_stabilization: false,
            inertia: InertiaRule::BlockCentres,
            disc_tree: DiscTreeRule::Starter,
            image_reader: ImageReader::Starter,
            preset: Preset::Starter,
            ..Params2::demonstration()
        }
    }

    /// The settings under which the assignment's four demonstration images (delicate, tower100,
    /// wallWideSparseHigh, wallWideDenseHigh) come to rest and stay at rest, and the defaults:
    /// the starter's step 0.05 in 4 substeps, 200 PGS sweeps in seeded random order, warm start
    /// and post-stabilisation (slop 0.01), each block a unit square, rigidref's disc trees.
    /// Why these and not the starter's 10 sweeps in order: docs/blocks2d.md §"Demonstration
    /// settings".
    pub fn demonstration() -> Params2 {
        Params2 {
            dt: 0.05,
            substeps: 4,
            gravity: 1.0,
            gravity_angle: 90.0,
            mu: 0.33,
            restitution: 0.0,
            iterations: 200,
            tolerance: None,
            order: ContactOrder::Random,
            seed: 0,
            local_solve: LocalSolve::Rows,
            warm_start: true,
            post_stabilization: true,
            slop: 0.01,
            contact_model: ContactModel::Pgs,
            penalty_stiffness: 1000.0,
            penalty_damping: 10.0,
            max_travel: None,
            shock_propagation: false,
            solver: crate::solve::Solver::Pgs,
            threads: 1,
            detection_cache: true,
            check_detection: false,
            inertia: InertiaRule::Blocks,
            disc_tree: DiscTreeRule::Median,
            image_reader: ImageReader::Rigidref,
            preset: Preset::Default,
        }
    }

    /// h = dt / substeps.
    pub fn h(&self) -> f64 {
        self.dt / self.substeps as f64
    }

    /// The gravity vector. Components below 1e-15 of the magnitude are zero, so the default
    /// 90° is exactly (0, g) (cos 90° in floating point is 6e-17).
    pub fn gravity_vector(&self) -> Vector2<f64> {
        let a = self.gravity_angle.to_radians();
        let snap = |c: f64| if c.abs() < 1e-15 { 0.0 } else { c };
        Vector2::new(snap(a.cos()), snap(a.sin())) * self.gravity
    }
}

/// What a preset sets, for the run's summary (`None` for the defaults): each value it gives
/// that differs from the defaults, as the scene keys spell them.
pub fn preset_summary(preset: Preset) -> Option<String> {
    match preset {
        Preset::Default => None,
        Preset::Starter => Some(
            "starter (the Java starter's code, docs/blocks2d.md §\"The starter preset\"): substeps 1, \
             iterations 10, order sequential (as found), warm_start false, post_stabilization false, \
             inertia block_centres, image_reader starter, disc_tree starter; options given override it"
                .to_string(),
        ),
    }
}
