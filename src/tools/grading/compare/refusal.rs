//! The checks a trace must pass before it is compared (docs/grading.md §"Refused traces"): the
//! reference's well-formedness (an error: the comparison cannot be made) and the candidate's
//! defects (a refusal: a verdict on the candidate).

use super::*;

/// The grader's own trace must be well formed: a 3D trace with records, each with the header's
/// bodies, finite states and rotations, times increasing. What is wrong is an error (the
/// comparison cannot be made: exit status 2), not a verdict on the candidate.
pub(super) fn check_reference(reference: &Trace) -> Result<(), String> {
    if reference.header.dimension != 3 {
        return Err(format!(
            "the reference trace is {}D: compare reads 3D traces",
            reference.header.dimension
        ));
    }
    match candidate_defect(reference, reference) {
        Some(r) => Err(format!("the reference trace: {}", r.message)),
        None => Ok(()),
    }
}

/// The checks of a candidate trace against the reference (docs/grading.md §"Refused traces"),
/// in order: records at all, the reference's bodies, finite numbers and rotations, strictly
/// increasing times, the reference's time span covered to one reference step at each end, and
/// records at most max(the reference's own spacing, [`MAX_GAP_STEPS`] reference steps) apart.
pub(super) fn candidate_defect(reference: &Trace, other: &Trace) -> Option<Refusal> {
    let refuse = |kind: &'static str, message: String| Some(Refusal { kind, message });
    if other.records.is_empty() {
        return refuse("empty", "the trace has no records".into());
    }
    let bodies = reference.header.bodies.len();
    if other.header.bodies.len() != bodies {
        return refuse(
            "wrong bodies",
            format!(
                "the trace has {} bodies, the reference {bodies}",
                other.header.bodies.len()
            ),
        );
    }
    for r in &other.records {
        if r.bodies.len() != bodies {
            return refuse(
                "wrong bodies",
                format!(
                    "the record at step {} has {} bodies, the header {bodies}",
                    r.step,
                    r.bodies.len()
                ),
            );
        }
        // A contact names its bodies by index (negative: the ground); found by fuzzing
        // (tests/fuzz-regressions/trace/contact-body-out-of-range): outcome mode named them.
        if let Some(c) = r
            .contacts
            .iter()
            .find(|c| c.bodies.iter().any(|&b| b >= bodies as i64))
        {
            return refuse(
                "wrong bodies",
                format!(
                    "a contact at step {} names bodies {:?}; the trace has {bodies}",
                    r.step, c.bodies
                ),
            );
        }
        if !r.t.is_finite() {
            return refuse(
                "not finite",
                format!("the time of the record at step {} is not finite", r.step),
            );
        }
        for (i, b) in r.bodies.iter().enumerate() {
            let finite = |a: &[f64; 3]| a.iter().all(|x| x.is_finite());
            if !(finite(&b.x) && finite(&b.v) && finite(&b.omega)) {
                return refuse(
                    "not finite",
                    format!("body {i} is not finite at step {} (t = {} s)", r.step, r.t),
                );
            }
            if let Some(why) = not_a_rotation(b) {
                return refuse(
                    "not a rotation",
                    format!("body {i} at step {} (t = {} s): {why}", r.step, r.t),
                );
            }
        }
    }
    let times =
        |t: &Trace| -> Vec<(u64, f64)> { t.records.iter().map(|r| (r.step, r.t)).collect() };
    time_defect(&times(reference), reference.header.dt, &times(other), " s")
}

/// The checks on a candidate's record times (both systems): strictly increasing, the
/// reference's span covered to one reference step at each end, and records at most max(the
/// reference's own spacing, [`MAX_GAP_STEPS`] reference steps) apart. `reference` and `other`
/// are (step, t) per record (the reference non-empty); `unit` follows each time in a message
/// (" s" in 3D, "" in the 2D system's time units).
pub(super) fn time_defect(
    reference: &[(u64, f64)],
    dt: f64,
    other: &[(u64, f64)],
    unit: &str,
) -> Option<Refusal> {
    let refuse = |kind: &'static str, message: String| Some(Refusal { kind, message });
    let (first, last) = (other.first()?.1, other.last()?.1);
    if let Some(w) = other.windows(2).find(|w| w[1].1 <= w[0].1) {
        if w[1].1 == w[0].1 {
            let repeats = other.iter().filter(|r| r.1 == w[0].1).count();
            return refuse(
                "repeated times",
                format!("time {}{unit} repeated {repeats} times", w[0].1),
            );
        }
        return refuse(
            "times out of order",
            format!(
                "the time goes back from {}{unit} to {}{unit} at step {}",
                w[0].1, w[1].1, w[1].0
            ),
        );
    }
    // One reference step at each end, with room for the round-off of a time written as k·dt.
    let slack = dt * (1.0 + 1e-9);
    let (start, end) = (reference.first()?.1, reference.last()?.1);
    if first > start + slack {
        return refuse(
            "late start",
            format!("starts at {first}{unit}, the reference at {start}{unit}"),
        );
    }
    if last < end - slack {
        return refuse("incomplete", format!("ends at {last}{unit} of {end}{unit}"));
    }
    let largest_gap = |t: &[(u64, f64)]| t.windows(2).map(|w| w[1].1 - w[0].1).fold(0.0, f64::max);
    let allowed = largest_gap(reference).max(MAX_GAP_STEPS * dt) * (1.0 + 1e-9);
    if let Some(w) = other.windows(2).find(|w| w[1].1 - w[0].1 > allowed) {
        return refuse(
            "too sparse",
            format!(
                "records {}{unit} apart (from t = {}{unit}); at most {allowed:.6}{unit} is compared (the reference's own spacing or {MAX_GAP_STEPS} of its steps)",
                w[1].1 - w[0].1,
                w[0].1
            ),
        );
    }
    None
}

/// The reference checked (an error), then the candidate (a refusal); the common span otherwise.
pub(super) fn check_traces(
    reference: &Trace,
    other: &Trace,
) -> Result<Result<(f64, f64), Refusal>, String> {
    check_reference(reference)?;
    if other.header.dimension != 3 {
        return Err(format!(
            "the other trace is {}D: compare reads 3D traces",
            other.header.dimension
        ));
    }
    if let Some(r) = candidate_defect(reference, other) {
        return Ok(Err(r));
    }
    let start = reference.records[0].t.max(other.records[0].t);
    let end = reference
        .records
        .last()
        .unwrap()
        .t
        .min(other.records.last().unwrap().t);
    Ok(Ok((start, end)))
}
