//! Tools built on the two systems, as library code that commands and tests call alike.
//!
//! - [`factory`]: random bodies dropped into a 2D container (the stress test), and the Tetris tube;
//! - [`scaling`]: PGS solve time against contacts, re-timed side by side, fitted and plotted;
//! - [`nuts`]: where the heaviest nuts of the nut bag are (the shaking challenge);
//! - [`render2d`], [`render3d`], [`video`]: PNG frames of a 2D world and of 3D bodies, and MP4
//!   video through ffmpeg;
//! - [`series`], [`view`], [`plot`]: the quantities of a run over time, the self-contained HTML
//!   viewer and the plot files, SVG or PNG through [`pixmap_backend`] (docs/viewing.md);
//! - [`bench`]: rigidref and the rapier3d mirror timed side by side (docs/performance.md);
//! - [`compare`], [`compare_problem`], [`grade`]: another simulator's traces and contact
//!   problems against the reference's, one submission or a batch (docs/grading.md);
//! - [`problem_library`]: a library of contact problems (Siconos', FCLIB's, rigidref's) solved
//!   by several solvers, with a performance profile (docs/problem-library.md).

pub mod bench;
pub mod compare;
pub mod compare_problem;
pub mod factory;
pub mod grade;
pub mod nuts;
pub mod pixmap_backend;
pub mod plot;
pub mod problem_library;
pub mod render2d;
pub mod render3d;
pub mod scaling;
pub mod series;
pub mod video;
pub mod view;
