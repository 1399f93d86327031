//! The 2D image-block system.

mod challenges;
mod coherence;
mod commands;
mod demonstrations;
mod grading;
mod java_student;
mod java_writer;
mod joints;
mod options;
mod physics;
mod properties;
mod student;
mod warm_start;
