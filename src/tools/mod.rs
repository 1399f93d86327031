//! Tools built on the two systems, as library code that commands and tests call alike.
//!
//! - [`factory`]: random bodies dropped into a 2D container (the stress test), and the Tetris tube;
//! - [`scaling`]: PGS solve time against contacts, re-timed side by side, fitted and plotted;
//! - [`nuts`]: where the heaviest nuts of the nut bag are (the shaking challenge);
//! - [`render2d`]: PNG frames of a 2D world.

pub mod factory;
pub mod nuts;
pub mod render2d;
pub mod scaling;
