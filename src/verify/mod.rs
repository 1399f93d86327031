//! The checks around the simulator: nothing in a simulation step calls these.
//!
//! - [`convergence`]: a scene at several step sizes, each observable's observed order;
//! - [`crosscheck`]: every contact problem solved by PGS and by clarabel, compared;
//! - [`detection`]: 3D detection's contacts against the separating-axis oracle, over random and
//!   degenerate poses (the campaign);
//! - [`golden`]: the canonical scenes' golden traces and the comparison with a fresh run;
//! - [`snapshots`]: the rounded run summaries the insta snapshot tests keep;
//! - [`references`]: independent references (a rapier3d mirror, RK4 on Euler's equations,
//!   the no-slip rolling ellipsoid);
//! - `faults`: deliberate bugs for the teeth tests, compiled only with the `fault-injection`
//!   feature (the tests turn it on; docs/verification.md §"Teeth"); the switch the simulation
//!   reads is the leaf module [`crate::common::faults`].

pub mod convergence;
pub mod crosscheck;
pub mod detection;
#[cfg(feature = "fault-injection")]
pub mod faults;
pub mod golden;
pub mod references;
pub mod snapshots;
