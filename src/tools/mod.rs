//! Tools built on the two systems, as library code that commands and tests call alike, in three
//! rooms by purpose:
//!
//! - [`grading`]: another simulator's traces and contact problems against the reference's, one
//!   submission or a batch (docs/grading.md);
//! - [`viewing`]: the quantities of a run over time, the HTML viewer, plots, PNG frames and
//!   video (docs/viewing.md);
//! - [`experiments`]: the 2D factory (the stress test) and its scaling, the nut bag, the
//!   benchmark against rapier3d, and the library of standard contact problems
//!   (docs/performance.md, docs/problem-library.md);
//! - [`validation`]: other engines (rapier, MuJoCo, PyBullet, Drake) on the known-answer scenes,
//!   judged against the closed forms and rigidref's exact run (docs/validation.md).

pub mod experiments;
pub mod grading;
pub mod validation;
pub mod viewing;
