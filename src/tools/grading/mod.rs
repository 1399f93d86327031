//! Grading: another simulator's output against the reference's (docs/grading.md).
//!
//! - [`compare`]: two traces, trajectory by trajectory or by outcome;
//! - [`compare_problem`]: two contact-problem files for the same state, up to the tangent basis;
//! - [`grade`]: a folder of submissions against fresh reference runs, one report;
//! - [`table`]: the report as CSV and Markdown, names byte for byte and escaped;
//! - [`shard`]: a folder graded in shares (a job array) and the shares' reports merged.

pub mod compare;
pub mod compare_problem;
pub mod grade;
pub mod shard;
pub mod table;
