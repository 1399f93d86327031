//! The test suite, one binary, by layer: the shared core (`solver`), the two systems (`rigid3d`,
//! `blocks2d`), the checks around them (`verify`) and the command line (`cli`), with one set of
//! helpers (`common`). Tests are named for the property they check.

mod blocks2d;
mod cli;
mod common;
mod rigid3d;
mod solve;
mod verify;

/// Counts the heap allocations made on each thread, for the steady-state allocation test
/// (`rigid3d::allocations`); otherwise the system allocator, unchanged.
#[global_allocator]
static ALLOCATOR: common::CountingAllocator = common::CountingAllocator;
