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
    /// The coloured order made random from the workspace's seeded generator (ChaCha8): each
    /// solve colours the contacts taken in a fresh random permutation (so which contacts share
    /// a colour changes from solve to solve) and each sweep visits the colours in a fresh
    /// random order. A colour's contacts are independent, so their order within it changes no
    /// bit: they are visited in problem order, four at a time as in `coloured`, and the bits
    /// are the same on any number of threads. The 2D factory's default (docs/contact.md
    /// §"Random coloured order").
    #[serde(alias = "random-coloured")]
    #[value(alias = "random_coloured")]
    RandomColoured,
}

impl ContactOrder {
    /// Whether the sweeps go colour by colour (`coloured` and `random_coloured`): the orders
    /// whose contacts can be visited four at a time and on several threads.
    pub fn is_coloured(self) -> bool {
        matches!(self, ContactOrder::Coloured | ContactOrder::RandomColoured)
    }

    /// Whether the order is drawn from the workspace's seeded generator (`random` and
    /// `random_coloured`).
    pub fn is_random(self) -> bool {
        matches!(self, ContactOrder::Random | ContactOrder::RandomColoured)
    }
}

/// The fewest contacts per thread and colour, on average, for which a coloured solve runs its
/// sweeps on several threads ([`PgsWorkspace::set_threads`]); smaller solves stay on one.
pub const MIN_CONTACTS_PER_THREAD: usize = 64;

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
