//! rigidref: a verification-focused reference implementation of rigid-body dynamics with
//! frictional contact.
//!
//! The architecture in one picture: a shared core, two systems feeding it, checks around it.
//!
//! ```text
//!   rigid3d (meshes)  ─┐                                   ┌─ verify (crosscheck, golden,
//!                      ├─ problem::ContactProblem<D, R> ──►│  snapshots, references, faults)
//!   blocks2d (images) ─┘        │                          └─ tools (factory, scaling, render)
//!                               ▼
//!         solve::solve (PGS | Newton, one switch) ── solve::qp (clarabel, the independent check)
//! ```
//!
//! - [`problem`] and [`solve`]: the contact problem as plain data, generic over degrees of
//!   freedom per body `D` and rows per contact `R`, and its solvers;
//! - [`rigid3d`] and [`blocks2d`]: the two systems; each step reads detect → assemble → solve →
//!   integrate in one function ([`rigid3d::world::World::step`], [`blocks2d::world::World2::step`]);
//! - [`sim`]: the one simulation interface both worlds implement and the one driver loop every
//!   command and test uses;
//! - [`verify`]: the checks; [`tools`]: factory, scaling report, rendering; [`common`]: the broad
//!   phase, scene-value parsing and the stopwatch that both systems use.
//!
//! Every quantity is defined once, with its symbol and units, in `docs/` (docs/architecture.md
//! first). Units are SI in 3D (blocks and time units in 2D), y is up in 3D (image rows grow down
//! in 2D), all arithmetic is f64, and runs are deterministic: the same inputs give a
//! bitwise-identical trace.

#![warn(missing_docs)]

pub mod blocks2d;
pub mod common;
pub mod problem;
pub mod rigid3d;
pub mod sim;
pub mod solve;
pub mod tools;
pub mod verify;
