//! Grading: another simulator's output against the reference's (docs/grading.md).
//!
//! - [`compare`]: two traces, trajectory by trajectory or by outcome;
//! - [`compare_problem`]: two contact-problem files for the same state, up to the tangent basis;
//! - [`grade`]: a folder of submissions against fresh reference runs, one report.

pub mod compare;
pub mod compare_problem;
pub mod grade;
