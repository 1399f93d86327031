//! The 2D image-block system.

mod properties;
mod physics;
mod demonstrations;
mod challenges;
mod commands;
