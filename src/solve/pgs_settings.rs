//! What a PGS solve is asked to do: the contact order of its sweeps, whether a coloured sweep
//! takes four contacts at a time, and how long it runs. docs/contact.md §"PGS", §"Coloured
//! order", §"Four contacts per lane".

use super::local::LocalSolve;


/// The order in which a sweep visits the contacts.
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
pub enum ContactOrder {
    /// Problem order, every sweep: the contacts in the order detection found them (the
    /// assignment's). Also read as `found`.
    #[default]
    #[serde(alias = "found")]
    #[value(alias = "found")]
    Sequential,
    /// A fresh permutation every sweep from the workspace's seeded generator (ChaCha8).
    Random,
    /// Colour by colour: contacts grouped so that no two of a group share a moving body
    /// (deterministic: src/solve/colour.rs), problem order within a group; the same order every
    /// sweep. A group's contacts are independent, so they are visited four at a time where
    /// they can be, with the same bits. Different last bits from the problem order; the same
    /// bits on any number of threads. docs/contact.md §"Coloured order".
    Coloured,
}

/// The fewest contacts per thread and colour, on average, for which a coloured solve runs its
/// sweeps on several threads ([`PgsWorkspace::set_threads`]); smaller solves stay on one.
pub const MIN_CONTACTS_PER_THREAD: usize = 64;

/// The most contacts for which a coloured solve visits its colours' contacts four at a time
/// (docs/contact.md §"Four contacts per lane"). The groups are laid out from the entries at the
/// start of each solve, one more pass over every contact's data. Measured against one contact
/// at a time: PGS about 30 % faster at 926–2 292 contacts and 13–25 % at 7 168–9 178, equal at
/// 20 480–28 672, slower at 36 568 (37.6–42.5 → 49.4–51.0 ms) and 96 322 (118.5–119.5 →
/// 149.1–153.2 ms) (docs/performance.md §"Issue 33, fourth part"). Either way the result is the
/// same bits.
pub const MAX_CONTACTS_IN_GROUPS: usize = 16_384;

/// Whether and how a coloured sweep, row by row, visits its colours' contacts four at a time
/// (docs/contact.md §"Four contacts per lane"); the same bits in every case.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lanes {
    /// One contact at a time.
    Off,
    /// Four at a time, compiled for the baseline processor (two f64 per instruction on
    /// x86-64's SSE2).
    Portable,
    /// Four at a time, with the widest instructions the processor has (AVX2's four f64 per
    /// instruction where present, else as `Portable`). The default.
    #[default]
    Native,
}

/// How long PGS runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PgsSettings {
    /// Sweeps at most (`pgs_iterations`, default 100).
    pub max_iterations: u32,
    /// Stop as soon as the residual is at or below this (m/s); `None` runs every sweep.
    pub tolerance: Option<f64>,
    /// Contact order.
    pub order: ContactOrder,
    /// How a visit updates its contact: row by row (the assignment's) or the exact local solve.
    pub local: LocalSolve,
}
