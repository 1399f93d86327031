//! JSON Lines traces: read, then compare with itself in both modes (the candidate checks run on
//! it). Nothing may panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::rigid3d::trace::read_trace;
use rigidref::tools::grading::compare::{
    OutcomeTolerances, TrajectoryTolerances, compare_outcomes, compare_trajectories,
};

fuzz_target!(|data: &[u8]| {
    let Ok(trace) = read_trace(std::io::Cursor::new(data), "fuzz.jsonl") else { return };
    if trace.records.len() > 500 {
        return;
    }
    let _ = compare_trajectories(&trace, &trace, &TrajectoryTolerances::default());
    let _ = compare_outcomes(&trace, &trace, None, &OutcomeTolerances::default());
});
