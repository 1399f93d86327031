//! The checks: clarabel cross-check, golden traces, snapshots, the rapier3d mirror, the teeth
//! tests, and the docs' references.

mod convergence;
mod crosscheck;
mod docs;
mod golden;
mod rapier;
mod snapshots;
mod soak;
mod teeth;
