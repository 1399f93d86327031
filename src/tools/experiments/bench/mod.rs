//! `rigidref bench`: the same scenes in rigidref and in the rapier3d mirror, timed side by side in
//! one process, interleaved, medians of rounds. docs/performance.md.
//!
//! Matched settings: the same scene (bodies, masses, inertias, meshes as the mirror's convex
//! pieces), dt, gravity and μ; one thread; rapier's solver iterations set to the scene's PGS
//! sweeps; sleeping off in the mirror. What is measured per scene: the whole step in each, the
//! ratio, rigidref's step by phase (detection, assembly, PGS, the rest), and PGS's cost per
//! contact per sweep. Sizes grow so that the report fits how the cost grows with the bodies.
//!
//! - [`cases`]: the scenes, as families of growing size;
//! - [`runner`]: timing one case in both engines, and the solver-only rows;
//! - [`report`]: the fit of cost against bodies, the Markdown tables, the targets, the SVG.

mod cases;
mod report;
mod runner;

pub use cases::*;
pub use report::*;
pub use runner::*;

use crate::blocks2d::world::World2;
use crate::rigid3d::collide::CollisionMethod;
use crate::rigid3d::scene::{BodyDescription, Scene};
use crate::rigid3d::world::{PhaseTimes, World};
use crate::sim::Simulation;
use crate::tools::experiments::factory::{Pieces, packed_pile};
use crate::verify::references::rapier::RapierMirror;
use nalgebra::Vector3;
use std::time::Instant;
