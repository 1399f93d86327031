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
    let masses: Vec<(usize, f64)> = other
        .header
        .bodies
        .iter()
        .map(|b| b.mass)
        .enumerate()
        .collect();
    if let Some(r) = header_defect(other.header.dt, &masses, " s") {
        return Some(r);
    }
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
                format!("time {}{unit} repeated {repeats} times", time_text(w[0].1)),
            );
        }
        return refuse(
            "times out of order",
            format!(
                "the time goes back from {}{unit} to {}{unit} at step {}",
                time_text(w[0].1),
                time_text(w[1].1),
                w[1].0
            ),
        );
    }
    // Records at most max(the reference's own spacing, MAX_GAP_STEPS of its steps) apart, with
    // room for the round-off of times written as k·dt; the same allowance at each end, so that
    // a writer that records every K steps (K ≤ MAX_GAP_STEPS) and so misses the last step is
    // not refused for the one gap that falls at the end.
    let largest_gap = |t: &[(u64, f64)]| t.windows(2).map(|w| w[1].1 - w[0].1).fold(0.0, f64::max);
    let allowed = largest_gap(reference).max(MAX_GAP_STEPS * dt) * (1.0 + 1e-9);
    let (start, end) = (reference.first()?.1, reference.last()?.1);
    let (t, gap) = (time_text, |g: f64| time_text(g / (1.0 + 1e-9)));
    if first > start + allowed {
        return refuse(
            "late start",
            format!(
                "starts at {}{unit}, the reference at {}{unit} (at most {}{unit} later)",
                t(first),
                t(start),
                gap(allowed)
            ),
        );
    }
    if last < end - allowed {
        return refuse(
            "incomplete",
            format!(
                "ends at {}{unit} of {}{unit} (at most {}{unit} earlier)",
                t(last),
                t(end),
                gap(allowed)
            ),
        );
    }
    if let Some(w) = other.windows(2).find(|w| w[1].1 - w[0].1 > allowed) {
        return refuse(
            "too sparse",
            format!(
                "records {}{unit} apart (from t = {}{unit}); at most {}{unit} is compared (the reference's own spacing or {MAX_GAP_STEPS} of its steps)",
                time_text(w[1].1 - w[0].1),
                time_text(w[0].1),
                gap(allowed)
            ),
        );
    }
    None
}

/// What makes no sense in a header (both systems): a step dt that is not a positive number, a
/// body whose mass is not (`masses`: index and mass of each body that must have one; a 2D
/// pinned body reports its blocks' mass but is not judged by it).
pub(super) fn header_defect(dt: f64, masses: &[(usize, f64)], unit: &str) -> Option<Refusal> {
    if !(dt.is_finite() && dt > 0.0) {
        return Some(Refusal {
            kind: "bad header",
            message: format!("the header's dt is {dt}{unit}: a step must be a positive number"),
        });
    }
    masses
        .iter()
        .find(|(_, m)| !(m.is_finite() && *m > 0.0))
        .map(|(i, m)| Refusal {
            kind: "bad header",
            message: format!("body {i}'s mass in the header is {m}: a mass must be positive"),
        })
}

/// How the bodies of `other` map onto the reference's (`map[i]` is the other's index of
/// reference body i): by name when both traces name the same set of bodies (names unique);
/// else by body: each reference body takes the other trace's unmatched body of the same mass
/// (within 1e-6) whose first position is nearest (so that bodies listed in another order under
/// other names are found); a reference body with none is a refusal (`wrong bodies`) naming it.
pub(super) fn match_bodies(
    reference: &Trace,
    other: &Trace,
) -> Result<(Vec<usize>, &'static str), Refusal> {
    let (r, o) = (&reference.header.bodies, &other.header.bodies);
    let by_name: Option<Vec<usize>> = r
        .iter()
        .map(|b| o.iter().position(|c| c.name == b.name))
        .collect();
    let unique = |names: &mut Vec<&str>| {
        names.sort_unstable();
        names.windows(2).all(|w| w[0] != w[1])
    };
    let names_unique = unique(&mut r.iter().map(|b| b.name.as_str()).collect())
        && unique(&mut o.iter().map(|b| b.name.as_str()).collect());
    if let Some(map) = by_name
        && r.len() == o.len()
        && names_unique
    {
        return Ok((map, "name"));
    }
    let (r0, o0) = (&reference.records[0], &other.records[0]);
    let mut taken = vec![false; o.len()];
    let mut map = Vec::with_capacity(r.len());
    for (i, body) in r.iter().enumerate() {
        let same_mass =
            |j: usize| (o[j].mass - body.mass).abs() <= 1e-6 * body.mass.abs().max(o[j].mass.abs());
        let distance = |j: usize| (v3(&r0.bodies[i].x) - v3(&o0.bodies[j].x)).norm();
        let best = (0..o.len())
            .filter(|&j| !taken[j] && same_mass(j))
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)));
        let Some(j) = best else {
            let masses: Vec<String> = (0..o.len())
                .filter(|&j| !taken[j])
                .map(|j| format!("{:?} {} kg", o[j].name, o[j].mass))
                .collect();
            return Err(Refusal {
                kind: "wrong bodies",
                message: format!(
                    "reference body {i} ({:?}, {} kg) has no body of the trace with its mass \
                     (unmatched: {}): not the same scene's bodies",
                    body.name,
                    body.mass,
                    if masses.is_empty() {
                        "none".to_string()
                    } else {
                        masses.join(", ")
                    }
                ),
            });
        };
        taken[j] = true;
        map.push(j);
    }
    Ok((map, "body"))
}

/// What both 3D modes compare over: the span both traces cover, (start, end), the matching
/// (`map[i]`: the other's body of reference body i) and how it was made (`name` or `body`).
pub(super) struct Prepared3 {
    pub span: (f64, f64),
    pub map: Vec<usize>,
    pub matched_by: &'static str,
}

/// The reference checked (an error), then the candidate (a refusal: its defects, then the
/// matching of its bodies); the span and the matching otherwise.
pub(super) fn check_traces(
    reference: &Trace,
    other: &Trace,
) -> Result<Result<Prepared3, Refusal>, String> {
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
    let (map, matched_by) = match match_bodies(reference, other) {
        Ok(m) => m,
        Err(r) => return Ok(Err(r)),
    };
    let start = reference.records[0].t.max(other.records[0].t);
    let end = reference
        .records
        .last()
        .unwrap()
        .t
        .min(other.records.last().unwrap().t);
    Ok(Ok(Prepared3 {
        span: (start, end),
        map,
        matched_by,
    }))
}

/// The candidate's positions against its own velocities, record by record
/// ([`super::motion`]), with the reference's step and top speed; bodies are named by the
/// reference's numbers (`map[i]`: the other's body of reference body i).
pub(super) fn motion_check(reference: &Trace, other: &Trace, map: &[usize]) -> Outcome {
    let g = reference.header.gravity;
    let scale = super::motion::speed_scale(
        reference.records.iter().flat_map(|r| {
            r.bodies
                .iter()
                .map(|b| (v3(&b.v).norm(), v3(&b.omega).norm()))
        }),
        (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt(),
        reference.header.dt,
    );
    let times: Vec<f64> = other.records.iter().map(|r| r.t).collect();
    let bodies: Vec<usize> = (0..other.header.bodies.len()).collect();
    let state = |k: usize, i: usize| {
        let b = &other.records[k].bodies[i];
        super::motion::Moving {
            x: b.x,
            v: b.v,
            omega: b.omega,
        }
    };
    let turned = |k: usize, i: usize| {
        super::motion::rotation_vector(
            &other.records[k - 1].bodies[i].rotation,
            &other.records[k].bodies[i].rotation,
        )
    };
    let label = |j: usize| match map.iter().position(|&m| m == j) {
        Some(i) => body_label(reference, i),
        None => format!("the trace's body {j}"),
    };
    super::motion::motion_row(
        &times,
        &bodies,
        &state,
        &turned,
        &label,
        super::motion::Scale {
            unit: "m",
            speed_unit: "m/s",
            dt: reference.header.dt,
            speed: scale,
        },
    )
}
