//! Deliberate bugs, for showing that the verification checks have teeth
//! (tests/teeth.rs; docs/verification.md §"Teeth"). Every flag is off unless a test turns it on;
//! no scene key or command-line option reaches them.

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
