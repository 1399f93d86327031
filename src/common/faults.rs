//! Deliberate bugs, for showing that the verification checks have teeth
//! (tests/suite/verify/teeth.rs; docs/verification.md §"Teeth"). The switch lives here, in a
//! leaf module the simulation can read without depending on the checks; the teeth tests use it
//! through `crate::verify::faults`.
//!
//! Compiled only with the `fault-injection` feature, which the tests turn on (Cargo.toml's
//! dev-dependency on this crate) and nothing else does: no settings struct, body or world carries
//! a fault, and no scene key or command-line option reaches one. A test switches faults on for
//! the code it runs with `with_faults`; they hold on that thread only, so tests running in
//! parallel do not see each other's bugs.

#[cfg(feature = "fault-injection")]
use std::cell::Cell;

/// Which deliberate bugs are switched on.
#[cfg(feature = "fault-injection")]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Faults {
    /// Assembly negates one Jacobian column: body 1's ω_x column of every contact.
    pub jacobian_sign_flip: bool,
    /// PGS bounds friction with the normal impulse the solve started from (the previous step's,
    /// through warm start) instead of the current one.
    pub stale_friction_bound: bool,
    /// The velocity update drops the gyroscopic term ω × Jω.
    pub no_gyroscopic_term: bool,
    /// The world inertia is computed as Rᵀ J₀ R instead of R J₀ Rᵀ.
    pub transposed_world_inertia: bool,
    /// Detection keeps every pair's candidate list however far the pair has moved
    /// (docs/contact.md §"Temporal coherence").
    pub stale_detection_cache: bool,
    /// `collision: complete` takes the face axis of greatest penetration instead of least: a
    /// normal in the contact plane, as deep as a body's width (the GJK/EPA failure of issue 46).
    pub deepest_face_axis: bool,
    /// Detection skips a candidate vertex whose last search found it on the other body's
    /// surface without checking that it still is (docs/contact.md §"Temporal coherence",
    /// "Vertices on the surface").
    pub surface_skip_unchecked: bool,
    /// Detection answers a candidate vertex on its leading triangle without checking that the
    /// vertex has moved less than half the triangle's lead since its search (docs/contact.md
    /// §"Temporal coherence", "Leading triangles").
    pub leading_motion_unchecked: bool,
    /// `collision: complete` with the detection cache answers a piece pair on its kept face axis
    /// without checking that the pair has moved less than the axis's lead since its search
    /// (docs/contact.md §"Temporal coherence", "Leading axes").
    pub axis_lead_motion_unchecked: bool,
}

#[cfg(feature = "fault-injection")]
impl Faults {
    /// No bug: the simulator as it is.
    pub const NONE: Faults = Faults {
        jacobian_sign_flip: false,
        stale_friction_bound: false,
        no_gyroscopic_term: false,
        transposed_world_inertia: false,
        stale_detection_cache: false,
        deepest_face_axis: false,
        surface_skip_unchecked: false,
        leading_motion_unchecked: false,
        axis_lead_motion_unchecked: false,
    };
}

#[cfg(feature = "fault-injection")]
thread_local! {
    static ACTIVE: Cell<Faults> = const { Cell::new(Faults::NONE) };
}

#[cfg(feature = "fault-injection")]
/// The faults switched on for this thread (the code under test reads them through
/// `crate::common::faults::fault!`).
pub fn active() -> Faults {
    ACTIVE.with(Cell::get)
}

#[cfg(feature = "fault-injection")]
/// Runs `f` with `faults` switched on for this thread, and switches them off again afterwards,
/// also when `f` panics.
pub fn with_faults<T>(faults: Faults, f: impl FnOnce() -> T) -> T {
    struct Restore(Faults);
    impl Drop for Restore {
        fn drop(&mut self) {
            ACTIVE.with(|a| a.set(self.0));
        }
    }
    let _restore = Restore(ACTIVE.with(|a| a.replace(faults)));
    f()
}

/// Whether the deliberate bug `FIELD` of [`faults::Faults`] is switched on for this thread:
/// `fault!(no_gyroscopic_term)`. Always `false`, and compiled to nothing, without the
/// `fault-injection` feature.
#[cfg(feature = "fault-injection")]
macro_rules! fault {
    ($field:ident) => {
        $crate::common::faults::active().$field
    };
}
/// Without the `fault-injection` feature no bug can be switched on.
#[cfg(not(feature = "fault-injection"))]
macro_rules! fault {
    ($field:ident) => {
        false
    };
}
pub(crate) use fault;
