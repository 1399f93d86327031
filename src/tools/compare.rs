//! Comparing a simulator's 3D trace with the reference's: trajectories (every quantity over time,
//! aligned by time) or outcomes (what happened: first contact, rest, where and how bodies rest,
//! energy at the end, Dzhanibekov flips). docs/grading.md.

use crate::rigid3d::diagnostics::sign_changes;
use crate::rigid3d::scene::Scene;
use crate::rigid3d::trace::{BodyState, Trace, TraceRecord};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// Tolerances of trajectory mode, each an absolute bound on an error over time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrajectoryTolerances {
    /// Position of a centre of mass, m.
    pub position: f64,
    /// Orientation: the angle of R_refᵀ R_other, rad.
    pub angle: f64,
    /// Velocity, m/s.
    pub velocity: f64,
    /// Angular velocity, rad/s.
    pub omega: f64,
    /// Energy terms, relative to the reference's energy scale: the largest of its largest
    /// kinetic energy, the range of its potential energy and the energy of lifting every body by
    /// 1 cm.
    pub energy: f64,
    /// Momenta, relative to the largest |momentum| of the reference, or to the total mass
    /// × 1 m/s (× 1 m for angular momentum) when that is larger.
    pub momentum: f64,
}

impl Default for TrajectoryTolerances {
    /// 1 mm, 1 mrad, 1 mm/s, 1 mrad/s, 1e-3 relative: far above round-off and the interpolation
    /// error of records a few frames apart, far below any modelling difference.
    fn default() -> Self {
        TrajectoryTolerances {
            position: 1e-3,
            angle: 1e-3,
            velocity: 1e-3,
            omega: 1e-3,
            energy: 1e-3,
            momentum: 1e-3,
        }
    }
}

impl TrajectoryTolerances {
    /// Every tolerance `t` (in each quantity's own unit, or relative): what `rigidref compare
    /// --tolerance t` and the Python module's `compare_traces(tolerance=t)` ask for.
    pub fn uniform(t: f64) -> Self {
        TrajectoryTolerances {
            position: t,
            angle: t,
            velocity: t,
            omega: t,
            energy: t,
            momentum: t,
        }
    }
}

/// One quantity's error over time.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct QuantityError {
    /// What, e.g. `body 1 ("cube") position` or `energy.total`.
    pub quantity: String,
    /// Unit of the error.
    pub unit: &'static str,
    /// The largest error.
    pub max_error: f64,
    /// When it occurred, s.
    pub at: f64,
    /// The first time it exceeded the tolerance, s, if it did.
    pub first_exceeded: Option<f64>,
    /// The tolerance.
    pub tolerance: f64,
}

/// The result of a comparison: every quantity's error (trajectory mode) or every observable
/// (outcome mode), and the verdict.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Comparison {
    /// `trajectory` or `outcome`.
    pub mode: &'static str,
    /// The times compared, s: from the later start to the earlier end of the two traces.
    pub span: (f64, f64),
    /// How the bodies were matched: `name` or `index`.
    pub matched_by: &'static str,
    /// Trajectory mode: the errors, in body order then system quantities.
    pub errors: Vec<QuantityError>,
    /// Outcome mode: the observables.
    pub outcomes: Vec<Outcome>,
    /// True when nothing exceeds its tolerance (false when the candidate was refused).
    pub agree: bool,
    /// Why the candidate trace was not compared at all, when it was refused (a trace that stops
    /// early, repeats or reorders its times, is too sparse, has other bodies or non-finite
    /// numbers); then `errors` and `outcomes` are empty. docs/grading.md §"Refused traces".
    pub refused: Option<Refusal>,
}

/// Why a candidate trace is refused before any comparison: its own verdict.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Refusal {
    /// `empty`, `wrong bodies`, `not finite`, `not a rotation`, `repeated times`,
    /// `times out of order`, `late start`, `incomplete` or `too sparse`.
    pub kind: &'static str,
    /// What is wrong, in one line, e.g. "ends at 0.5 s of 2 s".
    pub message: String,
}

/// How far apart a candidate's records may be, in reference steps (dt), where the reference
/// itself records more often: the comparison samples at the sparser trace's record times, so a
/// trace of a handful of records would otherwise be judged on a handful of states.
pub const MAX_GAP_STEPS: f64 = 10.0;

impl Comparison {
    fn refused(mode: &'static str, refusal: Refusal) -> Comparison {
        Comparison {
            mode,
            span: (f64::NAN, f64::NAN),
            matched_by: "",
            errors: Vec::new(),
            outcomes: Vec::new(),
            agree: false,
            refused: Some(refusal),
        }
    }

    /// The first failing quantity or observable, as a sentence.
    pub fn first_failure(&self) -> Option<String> {
        if let Some(r) = &self.refused {
            return Some(format!("refused ({}): {}", r.kind, r.message));
        }
        let by_time = self
            .errors
            .iter()
            .filter_map(|e| e.first_exceeded.map(|t| (t, e)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((t, e)) = by_time {
            return Some(format!(
                "{} exceeds {:.3e} {} first at t = {t} s (largest {:.3e} {} at t = {} s)",
                e.quantity, e.tolerance, e.unit, e.max_error, e.unit, e.at
            ));
        }
        self.outcomes.iter().find(|o| !o.passed).map(|o| {
            format!(
                "{}: reference {}, other {} (tolerance {})",
                o.name, o.reference, o.other, o.tolerance
            )
        })
    }
}

/// One observable of outcome mode.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Outcome {
    /// What, e.g. `body 0 ("cube") rest position`.
    pub name: String,
    /// The reference's value, as text (a number, `never`, `yes`).
    pub reference: String,
    /// The other trace's value.
    pub other: String,
    /// The difference measured (NaN when not numeric).
    pub difference: f64,
    /// The tolerance, as text.
    pub tolerance: String,
    /// Whether the two agree.
    pub passed: bool,
}

/// A body's state at a time, interpolated between records.
#[derive(Clone, Copy, Debug)]
struct State {
    x: Vector3<f64>,
    rotation: UnitQuaternion<f64>,
    v: Vector3<f64>,
    omega: Vector3<f64>,
}

fn v3(a: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn rotation_of(b: &BodyState) -> UnitQuaternion<f64> {
    // The traces were checked to hold rotations (orthonormal within 1e-6), so the direct
    // conversion (no iteration) applies; the quaternion is normalised.
    let m = Matrix3::from_fn(|i, j| b.rotation[i][j]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// Why `b.rotation` is not a rotation matrix (non-finite, not orthonormal within 1e-6, or a
/// reflection), if it is not.
fn not_a_rotation(b: &BodyState) -> Option<String> {
    let m = Matrix3::from_fn(|i, j| b.rotation[i][j]);
    if !m.iter().all(|x| x.is_finite()) {
        return Some("R is not finite".into());
    }
    let error = (m.transpose() * m - Matrix3::identity()).norm();
    if error > 1e-6 {
        return Some(format!("R is not orthonormal (‖RᵀR − I‖ = {error:.3e})"));
    }
    if m.determinant() < 0.0 {
        return Some("R is a reflection (det R < 0)".into());
    }
    None
}

fn state_of(b: &BodyState) -> State {
    State {
        x: v3(&b.x),
        rotation: rotation_of(b),
        v: v3(&b.v),
        omega: v3(&b.omega),
    }
}

/// The trace's records bracketing `t` and the fraction of the way from the first to the second.
fn bracket(records: &[TraceRecord], t: f64) -> (usize, usize, f64) {
    let k = records.partition_point(|r| r.t <= t);
    if k == 0 {
        return (0, 0, 0.0);
    }
    if k >= records.len() {
        let last = records.len() - 1;
        return (last, last, 0.0);
    }
    let (a, b) = (&records[k - 1], &records[k]);
    if a.t == t {
        // A record at exactly this time: itself, not an interpolation that could round.
        return (k - 1, k - 1, 0.0);
    }
    let s = if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    };
    (k - 1, k, s)
}

/// The angle of the rotation from `a` to `b`, rad: 2 atan2(|d_xyz|, |d_w|) for d = a⁻¹ b
/// (accurate for small angles, where acos of d_w is not); exactly 0 for equal orientations.
fn angle_between(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    if a == b {
        return 0.0;
    }
    let d = a.inverse() * b;
    2.0 * d.imag().norm().atan2(d.w.abs())
}

fn lerp(a: f64, b: f64, s: f64) -> f64 {
    a + (b - a) * s
}

/// Body `i`'s state at time `t`: linear interpolation of x, v, ω and slerp of the orientation.
fn body_at(records: &[TraceRecord], i: usize, t: f64) -> State {
    let (a, b, s) = bracket(records, t);
    let (p, q) = (
        state_of(&records[a].bodies[i]),
        state_of(&records[b].bodies[i]),
    );
    if a == b {
        return p;
    }
    State {
        x: p.x.lerp(&q.x, s),
        rotation: p.rotation.slerp(&q.rotation, s),
        v: p.v.lerp(&q.v, s),
        omega: p.omega.lerp(&q.omega, s),
    }
}

/// System quantities at `t`: the energy terms and momenta, interpolated linearly.
fn system_at(records: &[TraceRecord], t: f64) -> [f64; 13] {
    let (a, b, s) = bracket(records, t);
    let values = |r: &TraceRecord| {
        let e = &r.energy;
        let m = &r.momentum;
        [
            e.kinetic_linear,
            e.kinetic_angular,
            e.potential,
            e.total,
            m.linear[0],
            m.linear[1],
            m.linear[2],
            m.angular[0],
            m.angular[1],
            m.angular[2],
            m.angular_com[0],
            m.angular_com[1],
            m.angular_com[2],
        ]
    };
    let (p, q) = (values(&records[a]), values(&records[b]));
    std::array::from_fn(|k| lerp(p[k], q[k], s))
}

/// How bodies of `other` map onto the reference's: by name when both traces name the same set
/// of bodies, else by index when they have as many. `map[i]` is the other's index of reference
/// body i.
pub fn match_bodies(
    reference: &Trace,
    other: &Trace,
) -> Result<(Vec<usize>, &'static str), String> {
    let (r, o) = (&reference.header.bodies, &other.header.bodies);
    let by_name: Option<Vec<usize>> = r
        .iter()
        .map(|b| o.iter().position(|c| c.name == b.name))
        .collect();
    let names_unique = {
        let mut names: Vec<&str> = r.iter().map(|b| b.name.as_str()).collect();
        names.sort_unstable();
        names.windows(2).all(|w| w[0] != w[1])
    };
    match by_name {
        Some(map) if r.len() == o.len() && names_unique => Ok((map, "name")),
        _ if r.len() == o.len() => {
            // Matched by place: the masses must agree, or these are not the same scene's bodies.
            if let Some(i) = (0..r.len()).find(|&i| {
                (r[i].mass - o[i].mass).abs() > 1e-6 * r[i].mass.abs().max(o[i].mass.abs())
            }) {
                return Err(format!(
                    "the bodies' names differ and body {i} has mass {} kg in one trace and {} kg in the other: not the same scene",
                    r[i].mass, o[i].mass
                ));
            }
            Ok(((0..r.len()).collect(), "index"))
        }
        _ => Err(format!(
            "the traces have {} and {} bodies, and their names do not match",
            r.len(),
            o.len()
        )),
    }
}

/// The grader's own trace must be well formed: a 3D trace with records, each with the header's
/// bodies, finite states and rotations, times increasing. What is wrong is an error (the
/// comparison cannot be made: exit status 2), not a verdict on the candidate.
fn check_reference(reference: &Trace) -> Result<(), String> {
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
fn candidate_defect(reference: &Trace, other: &Trace) -> Option<Refusal> {
    let refuse = |kind: &'static str, message: String| Some(Refusal { kind, message });
    let (Some(first), Some(last)) = (other.records.first(), other.records.last()) else {
        return refuse("empty", "the trace has no records".into());
    };
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
    if let Some(w) = other.records.windows(2).find(|w| w[1].t <= w[0].t) {
        if w[1].t == w[0].t {
            let repeats = other.records.iter().filter(|r| r.t == w[0].t).count();
            return refuse(
                "repeated times",
                format!("time {} s repeated {repeats} times", w[0].t),
            );
        }
        return refuse(
            "times out of order",
            format!(
                "the time goes back from {} s to {} s at step {}",
                w[0].t, w[1].t, w[1].step
            ),
        );
    }
    let dt = reference.header.dt;
    // One reference step at each end, with room for the round-off of a time written as k·dt.
    let slack = dt * (1.0 + 1e-9);
    let (start, end) = (reference.records[0].t, reference.records.last().unwrap().t);
    if first.t > start + slack {
        return refuse(
            "late start",
            format!("starts at {} s, the reference at {start} s", first.t),
        );
    }
    if last.t < end - slack {
        return refuse("incomplete", format!("ends at {} s of {end} s", last.t));
    }
    let largest_gap = |t: &Trace| {
        t.records
            .windows(2)
            .map(|w| w[1].t - w[0].t)
            .fold(0.0, f64::max)
    };
    let allowed = largest_gap(reference).max(MAX_GAP_STEPS * dt) * (1.0 + 1e-9);
    if let Some(w) = other.records.windows(2).find(|w| w[1].t - w[0].t > allowed) {
        return refuse(
            "too sparse",
            format!(
                "records {} s apart (from t = {} s); at most {allowed:.6} s is compared (the reference's own spacing or {MAX_GAP_STEPS} of its steps)",
                w[1].t - w[0].t,
                w[0].t
            ),
        );
    }
    None
}

/// The reference checked (an error), then the candidate (a refusal); the common span otherwise.
fn check_traces(reference: &Trace, other: &Trace) -> Result<Result<(f64, f64), Refusal>, String> {
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

/// The energy scale of a trace, J: the largest of its largest kinetic energy, the range of its
/// potential energy (not |E|, which depends on where the potential is zero) and the energy of
/// lifting every body by 1 cm against gravity (|g| taken as at least 1 m/s²), so that a scene at
/// rest is not judged by round-off.
fn energy_scale(trace: &Trace) -> f64 {
    let g = trace.header.gravity;
    let g = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt().max(1.0);
    let total_mass: f64 = trace.header.bodies.iter().map(|b| b.mass).sum();
    let lift = total_mass * g * 0.01;
    let kinetic = trace
        .records
        .iter()
        .map(|r| r.energy.kinetic_linear + r.energy.kinetic_angular)
        .fold(0.0, f64::max);
    let (low, high) = trace
        .records
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
            (l.min(r.energy.potential), h.max(r.energy.potential))
        });
    kinetic.max(high - low).max(lift).max(f64::MIN_POSITIVE)
}

fn body_label(trace: &Trace, i: usize) -> String {
    format!("body {i} ({:?})", trace.header.bodies[i].name)
}

/// Trajectory mode: every quantity of `other` against `reference` at the record times of the
/// sparser of the two within the common span, the other interpolated (x, v, ω, energies and
/// momenta linearly, R by slerp).
pub fn compare_trajectories(
    reference: &Trace,
    other: &Trace,
    tol: &TrajectoryTolerances,
) -> Result<Comparison, String> {
    let span = match check_traces(reference, other)? {
        Ok(span) => span,
        Err(refusal) => return Ok(Comparison::refused("trajectory", refusal)),
    };
    let (map, matched_by) = match_bodies(reference, other)?;
    // Sample at the record times of the sparser trace (within the common span) and interpolate
    // the denser one, so that a trace recorded every K frames is compared where it has data.
    let in_span = |t: &Trace| -> Vec<f64> {
        t.records
            .iter()
            .map(|r| r.t)
            .filter(|&t| t >= span.0 && t <= span.1)
            .collect()
    };
    let (from_reference, from_other) = (in_span(reference), in_span(other));
    let times = if from_other.len() < from_reference.len() {
        from_other
    } else {
        from_reference
    };
    // Both traces at each sample time, interpolated once: every body's state, and the 13
    // system values (energy terms, momenta).
    struct Sample {
        t: f64,
        bodies: Vec<(State, State)>,
        system: ([f64; 13], [f64; 13]),
    }
    let samples: Vec<Sample> = times
        .iter()
        .map(|&t| Sample {
            t,
            bodies: map
                .iter()
                .enumerate()
                .map(|(i, &j)| {
                    (
                        body_at(&reference.records, i, t),
                        body_at(&other.records, j, t),
                    )
                })
                .collect(),
            system: (
                system_at(&reference.records, t),
                system_at(&other.records, t),
            ),
        })
        .collect();
    let mut errors = Vec::new();
    let mut track =
        |quantity: String, unit: &'static str, tolerance: f64, f: &dyn Fn(&Sample) -> f64| {
            let mut e = QuantityError {
                quantity,
                unit,
                max_error: 0.0,
                at: span.0,
                first_exceeded: None,
                tolerance,
            };
            for sample in &samples {
                let err = f(sample);
                if err > e.max_error || err.is_nan() {
                    e.max_error = if err.is_nan() { f64::INFINITY } else { err };
                    e.at = sample.t;
                }
                // NaN counts as exceeding.
                if e.first_exceeded.is_none() && (err.is_nan() || err > tolerance) {
                    e.first_exceeded = Some(sample.t);
                }
            }
            errors.push(e);
        };
    for i in 0..map.len() {
        let label = body_label(reference, i);
        track(format!("{label} position"), "m", tol.position, &|s| {
            let (a, b) = &s.bodies[i];
            (a.x - b.x).norm()
        });
        track(format!("{label} orientation"), "rad", tol.angle, &|s| {
            let (a, b) = &s.bodies[i];
            angle_between(&a.rotation, &b.rotation)
        });
        track(format!("{label} velocity"), "m/s", tol.velocity, &|s| {
            let (a, b) = &s.bodies[i];
            (a.v - b.v).norm()
        });
        track(
            format!("{label} angular velocity"),
            "rad/s",
            tol.omega,
            &|s| {
                let (a, b) = &s.bodies[i];
                (a.omega - b.omega).norm()
            },
        );
    }
    let names = [
        "energy.kinetic_linear",
        "energy.kinetic_angular",
        "energy.potential",
        "energy.total",
    ];
    let energy_scale = energy_scale(reference);
    for (k, name) in names.iter().enumerate() {
        track(name.to_string(), "J", tol.energy * energy_scale, &|s| {
            (s.system.0[k] - s.system.1[k]).abs()
        });
    }
    // Relative to the reference's largest momentum, but never less than that of the whole mass
    // moving at 1 m/s (at 1 m for angular momentum): a system at rest has zero momentum, and
    // round-off must not fail it.
    let total_mass: f64 = reference.header.bodies.iter().map(|b| b.mass).sum();
    for (k, name) in [
        "momentum.linear",
        "momentum.angular",
        "momentum.angular_com",
    ]
    .iter()
    .enumerate()
    {
        let part = |v: &[f64; 13]| Vector3::new(v[4 + 3 * k], v[5 + 3 * k], v[6 + 3 * k]);
        let of_record = |r: &TraceRecord| {
            let m = &r.momentum;
            v3([&m.linear, &m.angular, &m.angular_com][k]).norm()
        };
        let scale = reference
            .records
            .iter()
            .map(of_record)
            .fold(total_mass.max(f64::MIN_POSITIVE), f64::max);
        let unit = if k == 0 { "kg·m/s" } else { "kg·m²/s" };
        track(name.to_string(), unit, tol.momentum * scale, &|s| {
            (part(&s.system.0) - part(&s.system.1)).norm()
        });
    }
    let agree = errors.iter().all(|e| e.first_exceeded.is_none());
    Ok(Comparison {
        mode: "trajectory",
        span,
        matched_by,
        errors,
        outcomes: Vec::new(),
        agree,
        refused: None,
    })
}

/// A body is at rest when |v| < 0.05 m/s and |ω| < 0.1 rad/s (the rapier comparison's rule).
fn at_rest(b: &BodyState) -> bool {
    v3(&b.v).norm() < 0.05 && v3(&b.omega).norm() < 0.1
}

/// The rotations mapping a mesh onto itself among the 24 that permute and flip the axes of a
/// frame (identity included), tried in the body's principal frame and in the mesh's own axes
/// (a cube's or a ball's principal frame is decided by round-off, since its moments are
/// equal): the symmetries a box, a cube or a symmetric tessellation has.
fn symmetries(scene: Option<&Scene>, i: usize) -> Vec<Matrix3<f64>> {
    let Some(body) = scene.and_then(|s| s.bodies.get(i)) else {
        return vec![Matrix3::identity()];
    };
    let eigen = body.inertia.symmetric_eigen();
    let mut principal = eigen.eigenvectors;
    if principal.determinant() < 0.0 {
        principal.column_mut(2).neg_mut();
    }
    let size = body.mesh.bounding_radius();
    let mut out: Vec<Matrix3<f64>> = Vec::new();
    for frame in [principal, Matrix3::identity()] {
        for perm in [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ] {
            for signs in 0..8u32 {
                let p = Matrix3::from_fn(|r, c| {
                    if perm[r] != c {
                        0.0
                    } else if signs & (1 << r) != 0 {
                        -1.0
                    } else {
                        1.0
                    }
                });
                if p.determinant() < 0.0 {
                    continue;
                }
                let s = frame * p * frame.transpose();
                let known = out.iter().any(|q| (q - s).norm() < 1e-9);
                let maps_onto_itself = body.mesh.vertices.iter().all(|v| {
                    let w = s * v;
                    body.mesh
                        .vertices
                        .iter()
                        .any(|u| (u - w).norm() <= 1e-6 * size)
                });
                if !known && maps_onto_itself {
                    out.push(s);
                }
            }
        }
    }
    out
}

/// The first time after which the body stays at rest to the end, if it is at rest at the end.
fn rest_time(trace: &Trace, i: usize) -> Option<f64> {
    let records = &trace.records;
    if !at_rest(&records.last()?.bodies[i]) {
        return None;
    }
    let k = records.iter().rposition(|r| !at_rest(&r.bodies[i]));
    Some(k.map_or(records[0].t, |k| records[(k + 1).min(records.len() - 1)].t))
}

/// Tolerances of outcome mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutcomeTolerances {
    /// Time of first contact and of coming to rest, s.
    pub time: f64,
    /// Rest position, as a fraction of the body's bounding radius (0.05 m without a scene).
    pub position: f64,
    /// Rest orientation, rad, after the body's symmetries.
    pub angle: f64,
    /// Total energy at the end, relative to the reference's energy scale (as for trajectories).
    pub energy: f64,
    /// Dzhanibekov flip times, relative to the reference's flip period.
    pub flip: f64,
}

impl Default for OutcomeTolerances {
    /// Five frames of 0.01 s (0.25 s for coming to rest, which a threshold decides), 5% of the
    /// radius, 0.1 rad, 5% in energy, 5% of a flip period.
    fn default() -> Self {
        OutcomeTolerances {
            time: 0.05,
            position: 0.05,
            angle: 0.1,
            energy: 0.05,
            flip: 0.05,
        }
    }
}

fn number(x: Option<f64>) -> String {
    x.map_or("never".into(), |x| format!("{x:.4}"))
}

/// The scene outcome mode reads the bodies' sizes, symmetries and axes from: `given` when it is
/// given (an error when it does not load), else the scene the reference trace's header names as
/// its source, where that file exists as named or beside the reference trace (`reference_path`);
/// `None` when there is none. Returns the scene and the path it came from.
pub fn outcome_scene(
    reference: &Trace,
    reference_path: &std::path::Path,
    given: Option<&std::path::Path>,
) -> Result<Option<(Scene, std::path::PathBuf)>, String> {
    if let Some(path) = given {
        let scene = crate::rigid3d::scene::load_scene(path).map_err(|e| e.0)?;
        return Ok(Some((scene, path.to_path_buf())));
    }
    let source = std::path::Path::new(&reference.header.source);
    let beside = reference_path
        .parent()
        .map(|d| d.join(source))
        .unwrap_or_default();
    Ok([source.to_path_buf(), beside]
        .into_iter()
        .filter(|p| p.is_file())
        .find_map(|p| crate::rigid3d::scene::load_scene(&p).ok().map(|s| (s, p))))
}

/// Outcome mode: what happened, compared observable by observable. `scene` (the reference's)
/// gives the bodies' meshes and inertia, for sizes, symmetries and the Dzhanibekov axis; without
/// it rest orientations are compared without symmetries and no flips are sought.
pub fn compare_outcomes(
    reference: &Trace,
    other: &Trace,
    scene: Option<&Scene>,
    tol: &OutcomeTolerances,
) -> Result<Comparison, String> {
    let span = match check_traces(reference, other)? {
        Ok(span) => span,
        Err(refusal) => return Ok(Comparison::refused("outcome", refusal)),
    };
    let (map, matched_by) = match_bodies(reference, other)?;
    // Only what both traces cover: a trace that runs longer must not count flips, contacts or
    // rest the other could not show.
    let within = |t: &Trace| Trace {
        notes: Vec::new(),
        header: t.header.clone(),
        records: t
            .records
            .iter()
            .filter(|r| r.t >= span.0 && r.t <= span.1)
            .cloned()
            .collect(),
    };
    let (reference, other) = (&within(reference), &within(other));
    let mut outcomes = Vec::new();
    let mut push =
        |name: String, a: String, b: String, difference: f64, tolerance: String, passed: bool| {
            outcomes.push(Outcome {
                name,
                reference: a,
                other: b,
                difference,
                tolerance,
                passed,
            })
        };
    // First contact of each pair of bodies (or body and ground) that touches in either trace,
    // with the other trace's bodies renamed to the reference's.
    let reported = other.records.iter().any(|r| !r.contacts.is_empty());
    if reported {
        let mut back = vec![usize::MAX; map.len()];
        for (i, &j) in map.iter().enumerate() {
            back[j] = i;
        }
        let pair_of = |bodies: [i64; 2], rename: bool| {
            let name = |b: i64| {
                if b < 0 || !rename {
                    b
                } else {
                    back.get(b as usize).map_or(b, |&i| i as i64)
                }
            };
            let (p, q) = (name(bodies[0]), name(bodies[1]));
            (p.max(q), p.min(q))
        };
        let firsts = |t: &Trace, rename: bool| {
            let mut out: Vec<((i64, i64), f64)> = Vec::new();
            for r in &t.records {
                for c in &r.contacts {
                    let pair = pair_of(c.bodies, rename);
                    if !out.iter().any(|(p, _)| *p == pair) {
                        out.push((pair, r.t));
                    }
                }
            }
            out
        };
        let (fa, fb) = (firsts(reference, false), firsts(other, true));
        let mut pairs: Vec<(i64, i64)> = fa.iter().chain(&fb).map(|(p, _)| *p).collect();
        pairs.sort_unstable();
        pairs.dedup();
        for pair in pairs {
            let find =
                |f: &[((i64, i64), f64)]| f.iter().find(|(p, _)| *p == pair).map(|(_, t)| *t);
            let (a, b) = (find(&fa), find(&fb));
            let d = match (a, b) {
                (Some(a), Some(b)) => (a - b).abs(),
                _ => f64::INFINITY,
            };
            let who = |b: i64| {
                if b < 0 {
                    "the ground".to_string()
                } else {
                    body_label(reference, b as usize)
                }
            };
            push(
                format!("first contact of {} with {}", who(pair.0), who(pair.1)),
                number(a),
                number(b),
                d,
                format!("{} s", tol.time),
                d <= tol.time,
            );
        }
    } else {
        push(
            "first contacts".into(),
            "recorded".into(),
            "not reported (the trace lists no contacts)".into(),
            f64::NAN,
            "—".into(),
            true,
        );
    }
    let end_r = reference
        .records
        .iter()
        .rev()
        .find(|r| r.t <= span.1)
        .unwrap();
    let end_o = other.records.iter().rev().find(|r| r.t <= span.1).unwrap();
    for (i, &j) in map.iter().enumerate() {
        let label = body_label(reference, i);
        let (ra, rb) = (rest_time(reference, i), rest_time(other, j));
        let d = match (ra, rb) {
            (Some(a), Some(b)) => (a - b).abs(),
            (None, None) => 0.0,
            _ => f64::INFINITY,
        };
        let rest_tol = 5.0 * tol.time;
        push(
            format!("{label} comes to rest at"),
            number(ra),
            number(rb),
            d,
            format!("{rest_tol} s"),
            d <= rest_tol,
        );
        if ra.is_some() && rb.is_some() {
            let scale = scene
                .and_then(|s| s.bodies.get(i))
                .map_or(1.0, |b| b.mesh.bounding_radius());
            let (xa, xb) = (v3(&end_r.bodies[i].x), v3(&end_o.bodies[j].x));
            let d = (xa - xb).norm();
            push(
                format!("{label} rest position"),
                format!("[{:.4}, {:.4}, {:.4}]", xa.x, xa.y, xa.z),
                format!("[{:.4}, {:.4}, {:.4}]", xb.x, xb.y, xb.z),
                d,
                format!("{:.4} m", tol.position * scale),
                d <= tol.position * scale,
            );
            let (qa, qb) = (rotation_of(&end_r.bodies[i]), rotation_of(&end_o.bodies[j]));
            let (ma, mb) = (
                qa.to_rotation_matrix().into_inner(),
                qb.to_rotation_matrix().into_inner(),
            );
            // The smallest angle between the two orientations over the body's symmetries S
            // (body frame): angle of R_aᵀ R_b S.
            let angle = symmetries(scene, i)
                .iter()
                .map(|s| {
                    let r = ma.transpose() * mb * s;
                    ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
                })
                .fold(f64::INFINITY, f64::min);
            push(
                format!("{label} rest orientation (after symmetries)"),
                "—".into(),
                format!("{angle:.4} rad from the reference"),
                angle,
                format!("{} rad", tol.angle),
                angle <= tol.angle,
            );
        }
    }
    let scale = energy_scale(reference);
    let (ea, eb) = (end_r.energy.total, end_o.energy.total);
    let d = (ea - eb).abs();
    push(
        format!("total energy at t = {}", end_r.t),
        format!("{ea:.6e} J"),
        format!("{eb:.6e} J"),
        d,
        format!("{:.3e} J", tol.energy * scale),
        d <= tol.energy * scale,
    );
    if let Some(scene) = scene
        && scene.bodies.len() == 1
        && scene.params.gravity.norm() == 0.0
    {
        {
            let flips = |t: &Trace| {
                let body = &scene.bodies[0];
                let eigen = body.inertia.symmetric_eigen();
                let mut order: Vec<usize> = (0..3).collect();
                order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
                let axis = eigen.eigenvectors.column(order[1]).into_owned();
                let samples: Vec<(f64, f64)> = t
                    .records
                    .iter()
                    .map(|r| {
                        let b = &r.bodies[0];
                        let rot = Matrix3::from_fn(|i, j| b.rotation[i][j]);
                        (r.t, (rot.transpose() * v3(&b.omega)).dot(&axis))
                    })
                    .collect();
                sign_changes(&samples)
            };
            let (fa, fb) = (flips(reference), flips(other));
            if fa.len() >= 2 {
                // Two sign changes of the intermediate-axis spin per period.
                let period = 2.0 * (fa[fa.len() - 1] - fa[0]) / (fa.len() - 1) as f64;
                let n = fa.len().min(fb.len());
                let worst = if fb.len() < fa.len() {
                    f64::INFINITY
                } else {
                    (0..n).map(|k| (fa[k] - fb[k]).abs()).fold(0.0, f64::max)
                };
                push(
                    "Dzhanibekov flip times".into(),
                    format!("{} sign changes, period {period:.4} s", fa.len()),
                    format!("{} sign changes", fb.len()),
                    worst,
                    format!("{:.4} s", tol.flip * period),
                    worst <= tol.flip * period,
                );
            }
        }
    }
    let agree = outcomes.iter().all(|o| o.passed);
    Ok(Comparison {
        mode: "outcome",
        span,
        matched_by,
        errors: Vec::new(),
        outcomes,
        agree,
        refused: None,
    })
}
