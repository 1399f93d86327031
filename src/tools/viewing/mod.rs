//! Seeing a run (docs/viewing.md).
//!
//! - [`series`]: the quantities of a run over time, as the plots and the viewer draw them;
//! - [`view`]: the self-contained HTML viewer (bodies, contacts, synchronised plots), and the
//!   generic trace reader [`view::RunTrace`] the other commands load traces with;
//! - [`plot`]: plot files, SVG or PNG (through [`pixmap_backend`]);
//! - [`render2d`], [`render3d`], [`video`]: PNG frames of a 2D world and of 3D bodies, and MP4
//!   video through ffmpeg.

pub mod pixmap_backend;
pub mod plot;
pub mod render2d;
pub mod render3d;
pub mod series;
pub mod video;
pub mod view;
