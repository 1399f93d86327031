//! The 2D system of the second assignment: bodies made of unit blocks from the pixels of an
//! image, bounding-disc trees for collision, and the same contact problem and PGS solver as 3D
//! (docs/blocks2d.md; how the two share one solver: docs/one-solver.md).
//!
//! - [`image`]: connected components of non-white pixels → bodies; [`starter_image`]: the same
//!   as the Java starter's reader numbers and decides them;
//! - [`body`]: a 2D rigid body and its integrator;
//! - [`mec`], [`disc_tree`]: minimum enclosing circles and bounding-disc trees;
//! - [`collide`]: block-disc contacts, tree against tree, sweep-and-prune between bodies;
//! - [`coherence`]: the same contacts from candidate lists kept between steps;
//! - [`assemble`]: the shared contact problem with 3 degrees of freedom per body;
//! - [`joints`]: springs and dampers (forces) and pins (free rows of the same problem);
//! - [`world`]: the step, [`world::World2::step`]: detect → assemble → solve → post-stabilise →
//!   integrate;
//! - [`params`], [`scene`]: parameters, 2D scene files and the one loader of images and scenes;
//! - [`diagnostics`], [`trace`]: energy and momentum, and the 2D trace.

pub mod assemble;
pub mod body;
pub mod coherence;
pub mod collide;
pub mod diagnostics;
pub mod disc_tree;
pub mod image;
pub mod joints;
pub mod mec;
pub mod params;
pub mod scene;
pub mod starter_image;
pub mod trace;
pub mod warm_start;
pub mod world;
