//! The simulation parameters of a 3D scene (`sim_parameters[0]`) and the project's defaults.

use crate::problem::FrictionModel;
use crate::rigid3d::body::AngularIntegrator;
use crate::rigid3d::collide::{CollisionMethod, Culling};
use crate::solve::{ContactOrder, LocalSolve, Solver};
use nalgebra::Vector3;

/// Simulation parameters: the first entry of the scene's `sim_parameters`, with the starter's
/// defaults for missing keys.
#[derive(Clone, Debug, PartialEq)]
pub struct SimParameters {
    /// `preset`: `default` or `starter` (the Python starter's own behaviour: no warm start, no
    /// Baumgarte stabilisation, its collision detection and tangents), what the other keys
    /// override (default `default`).
    pub preset: crate::common::preset::Preset,
    /// Scene name (`name`; default: the file's stem).
    pub name: String,
    /// Frame step `dt`, s (default 0.01). One trace step is one frame.
    pub dt: f64,
    /// `gravity`, m/s² (default zero).
    pub gravity: Vector3<f64>,
    /// Friction coefficient `mu` (default 0).
    pub mu: f64,
    /// `substeps` per frame (default 1); the integration step is h = dt / substeps.
    pub substeps: u32,
    /// `check_collisions` (default true).
    pub check_collisions: bool,
    /// `stop_on_contact` (default false).
    pub stop_on_contact: bool,
    /// `pgs_iterations` (default 100, the assignment's).
    pub pgs_iterations: u32,
    /// `integrator` (this project's key; default `spatial`).
    pub integrator: AngularIntegrator,
    /// `friction_model`: `box` (default, the assignment's) or `cone`.
    pub friction_model: FrictionModel,
    /// `compliance` c ≥ 0 on each contact's normal row, kg⁻¹ (default 0: rigid contacts).
    pub compliance: f64,
    /// `stabilization`: Baumgarte factor β ∈ [0, 1], the fraction of the penetration beyond the
    /// slop pushed out per step (default [`DEFAULT_STABILIZATION`]; the starter preset's 0).
    pub stabilization: f64,
    /// `stabilization_slop`: penetration left alone by stabilisation, m (default
    /// [`DEFAULT_SLOP`]).
    pub stabilization_slop: f64,
    /// `stabilization_max_speed`: the largest push-out velocity β e / h of one contact, m/s
    /// (default [`DEFAULT_MAX_PUSH_SPEED`]): bodies written overlapping are pushed apart at most
    /// this fast, not launched (docs/contact.md §"Stabilisation").
    pub stabilization_max_speed: f64,
    /// `warm_start`: start each solve from the previous substep's impulses (default true; the
    /// starter preset's false).
    pub warm_start: bool,
    /// `pgs_tolerance`: stop PGS once its residual is at or below this, m/s (default none: run
    /// all `pgs_iterations`).
    pub pgs_tolerance: Option<f64>,
    /// `pgs_order`: `sequential` (default; also `found`: the order detection found the
    /// contacts in), `random` (a fresh seeded permutation per sweep) or `coloured` (no two
    /// consecutive contacts of a colour share a moving body; docs/contact.md §"Coloured order").
    pub pgs_order: ContactOrder,
    /// `pgs_seed`: seed of the random contact order (default 0).
    pub pgs_seed: u64,
    /// `threads`: threads the coloured order's sweeps run on (default 1); the result is bit for
    /// bit the same for any number. Other orders run on one thread.
    pub threads: u32,
    /// `pgs_local_solve`: `rows` (default, the assignment's row-by-row update) or `exact` (each
    /// visit solves its contact's 3 × 3 problem exactly; docs/contact.md §"Exact local solve").
    pub pgs_local_solve: LocalSolve,
    /// `solver`: `pgs` (default, the assignment's projected Gauss–Seidel) or `newton` (the exact
    /// solver; docs/contact.md §"Newton solver").
    pub solver: Solver,
    /// `collision`: `vertices` (default, the assignment's), `complete` or `starter` (the Python
    /// starter's `collision.py`; the starter preset's).
    pub collision: CollisionMethod,
    /// `tangents`: `orthonormal` (default) or `starter` (the Python starter's `contact.py`: not
    /// normalised, its axis choice; the starter preset's). docs/contact.md §"Contact frame".
    pub tangents: crate::rigid3d::frame::Tangents,
    /// `culling`: `bvh` (default) or `sphere_tree`: how a mesh's vertices are culled before the
    /// signed-distance query against another mesh (the same contacts either way).
    pub culling: Culling,
    /// `detection_cache`: keep each body pair's candidates from step to step (default true):
    /// the same contacts, found faster (docs/contact.md §"Temporal coherence").
    pub detection_cache: bool,
    /// `persistent_manifolds`: with `collision: complete` and the detection cache, keep each
    /// convex piece pair's separating-axis features between substeps and re-derive its manifold
    /// from them while they serve (default false; docs/contact.md §"Persistent manifolds"):
    /// faster, but then a manifold is not always fresh detection's.
    pub persistent_manifolds: bool,
    /// `check_detection`: run fresh detection beside the cached one every substep and count any
    /// difference (default false): the cache's debug check.
    pub check_detection: bool,
}

/// Default Baumgarte factor β: removes a fifth of the excess penetration per step, fast enough
/// to undo a landing's penetration in a few tenths of a second, slow enough not to launch bodies.
pub const DEFAULT_STABILIZATION: f64 = 0.2;
/// Default stabilisation slop, m: penetration this small is left alone, so resting contacts do
/// not jitter (a few millimetres against bodies of a metre).
pub const DEFAULT_SLOP: f64 = 0.005;
/// Default bound on the push-out velocity, m/s: above the largest any assignment or canonical
/// scene asks for (0.90 m/s, the assignment's scene7), far below what an overlap written into a
/// scene asks for (6–36 m/s for the overlaps of issue 46).
pub const DEFAULT_MAX_PUSH_SPEED: f64 = 1.0;

impl SimParameters {
    /// The integration step h = dt / substeps, s.
    pub fn h(&self) -> f64 {
        self.dt / self.substeps as f64
    }
}
