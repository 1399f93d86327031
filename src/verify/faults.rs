//! Deliberate bugs, for showing that the verification checks have teeth
//! (tests/suite/verify/teeth.rs; docs/verification.md §"Teeth").
//!
//! Compiled only with the `fault-injection` feature, which the tests turn on (Cargo.toml's
//! dev-dependency on this crate) and nothing else does: no settings struct, body or world carries
//! a fault, and no scene key or command-line option reaches one. A test switches faults on for
//! the code it runs with [`with_faults`]; they hold on that thread only, so tests running in
//! parallel do not see each other's bugs.

use std::cell::Cell;

/// Which deliberate bugs are switched on.
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
}

impl Faults {
    /// No bug: the simulator as it is.
    pub const NONE: Faults = Faults {
        jacobian_sign_flip: false,
        stale_friction_bound: false,
        no_gyroscopic_term: false,
        transposed_world_inertia: false,
    };
}

thread_local! {
    static ACTIVE: Cell<Faults> = const { Cell::new(Faults::NONE) };
}

/// The faults switched on for this thread (the code under test reads them through
/// `crate::verify::fault!`).
pub fn active() -> Faults {
    ACTIVE.with(Cell::get)
}

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
