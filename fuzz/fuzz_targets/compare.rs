//! The compare path on a pair of traces (reference, candidate) separated by a 0xFF byte: both
//! modes. Nothing may panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::rigid3d::trace::read_trace;
use rigidref::tools::grading::compare::{
    OutcomeTolerances, TrajectoryTolerances, compare_outcomes, compare_trajectories,
};

fuzz_target!(|data: &[u8]| {
    let Some(cut) = data.iter().position(|&b| b == 0xFF) else { return };
    let (a, b) = (&data[..cut], &data[cut + 1..]);
    let (Ok(a), Ok(b)) = (
        read_trace(std::io::Cursor::new(a), "a.jsonl"),
        read_trace(std::io::Cursor::new(b), "b.jsonl"),
    ) else {
        return;
    };
    if a.records.len() > 500 || b.records.len() > 500 {
        return;
    }
    let _ = compare_trajectories(&a, &b, &TrajectoryTolerances::default());
    let _ = compare_outcomes(&a, &b, None, &OutcomeTolerances::default());
});
