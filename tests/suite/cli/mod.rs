//! The command-line program: every command as a user runs it, and bad input.

mod bad_input;
mod commands;
mod grading;
mod problem_library;
mod viewing;
