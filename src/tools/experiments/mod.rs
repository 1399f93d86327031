//! Experiments and benchmarks (docs/performance.md, docs/blocks2d.md, docs/problem-library.md).
//!
//! - [`factory`]: random bodies dropped into a 2D container (the stress test), and the Tetris tube;
//! - [`scaling`]: PGS solve time against contacts, re-timed side by side, fitted and plotted;
//! - [`nuts`]: where the heaviest nuts of the nut bag are (the shaking challenge);
//! - [`bench`]: rigidref and the rapier3d mirror timed side by side;
//! - [`problem_library`]: Siconos', FCLIB's and rigidref's contact problems solved by several
//!   solvers, with a performance profile.

pub mod bench;
pub mod factory;
pub mod nuts;
pub mod problem_library;
pub mod scaling;
