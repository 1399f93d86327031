//! The command-line program: every command as a user runs it, and bad input.

mod bad_input;
mod commands;
mod grading;
mod grading_checks;
mod grading_problems;
mod grading_shards;
mod grading_untrusted;
mod problem_library;
mod viewing;
