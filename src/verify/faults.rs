//! Deliberate bugs for the teeth tests (docs/verification.md §"Teeth"): the curated
//! [`Faults`] and [`with_faults`], which switches them on for the current thread. Compiled only
//! with the `fault-injection` feature; the switch the simulation reads is
//! [`crate::common::faults`].

pub use crate::common::faults::{Faults, active, with_faults};
