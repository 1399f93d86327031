//! The checks: clarabel cross-check, golden traces, snapshots, the rapier3d mirror, the teeth
//! tests, and the docs' references.

mod convergence;
mod crosscheck;
mod docs;
mod fuzz_regressions;
mod golden;
mod imports;
mod rapier;
mod snapshots;
mod soak;
mod teeth;
mod validation;
