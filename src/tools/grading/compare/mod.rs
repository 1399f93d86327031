//! Comparing a simulator's 3D trace with the reference's: trajectories (every quantity over time,
//! aligned by time; [`trajectory`]) or outcomes (what happened: first contact, rest, where and
//! how bodies rest, energy at the end, Dzhanibekov flips; [`outcome`]), after the traces pass
//! the checks of [`refusal`]. docs/grading.md.
//!
//! This file holds what both modes share: the reports' types, the bodies' matching and the
//! interpolation of a trace between its records.

mod motion;
mod outcome;
mod read;
mod refusal;
mod trajectory;
mod two;
mod two_outcome;

pub use motion::ALLOWANCE_STEPS;
pub use outcome::{OutcomeTolerances, compare_outcomes, outcome_scene};
pub use read::{AnyTrace, read_trace_any, read_trace_of, read_trace2_file, read_trace3_file};
pub use trajectory::compare_trajectories;
pub use two::{Trace2, compare_trajectories_2d, match_bodies_2d};
pub use two_outcome::{
    OutcomeTolerances2, angle_after_symmetries, compare_outcomes_2d, outcome_scene_2d,
    quarter_turn_symmetries,
};

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
    /// How the bodies were matched: `name` or `body` (3D: mass and first position), `image`
    /// (2D).
    pub matched_by: &'static str,
    /// The other trace's body matched to each reference body (entry i is the other trace's
    /// index of reference body i); empty when the candidate was refused.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub matching: Vec<usize>,
    /// Trajectory mode: the errors, in body order then system quantities.
    pub errors: Vec<QuantityError>,
    /// Outcome mode: the observables.
    pub outcomes: Vec<Outcome>,
    /// Both modes: the checks of the candidate against itself, on every record: its positions
    /// follow its velocities (docs/grading.md §"Positions follow velocities").
    pub checks: Vec<Outcome>,
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
    /// `bad header`, `empty`, `wrong bodies`, `not finite`, `not a rotation`, `repeated
    /// times`, `times out of order`, `late start`, `incomplete` or `too sparse`.
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
            matching: Vec::new(),
            errors: Vec::new(),
            outcomes: Vec::new(),
            checks: Vec::new(),
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
                "{} exceeds {:.3e} {} first at t = {} s (largest {:.3e} {} at t = {} s)",
                e.quantity,
                e.tolerance,
                e.unit,
                time_text(t),
                e.max_error,
                e.unit,
                time_text(e.at)
            ));
        }
        self.outcomes
            .iter()
            .chain(&self.checks)
            .find(|o| !o.passed)
            .map(|o| {
                format!(
                    "{}: reference {}, other {} (tolerance {})",
                    o.name, o.reference, o.other, o.tolerance
                )
            })
    }
}

/// A record time as reports print it: rounded to 1e-9 (of a second or time unit), so that
/// `0.05 × 23` reads 1.15, not 1.1500000000000001; the reports' numbers stay exact in `--json`.
pub fn time_text(t: f64) -> String {
    let rounded = (t * 1e9).round() / 1e9;
    format!("{rounded}")
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

/// The records (of either system; `time` reads one's t) bracketing `t` and the fraction of
/// the way from the first to the second.
fn bracket<T>(records: &[T], time: impl Fn(&T) -> f64, t: f64) -> (usize, usize, f64) {
    let k = records.partition_point(|r| time(r) <= t);
    if k == 0 {
        return (0, 0, 0.0);
    }
    if k >= records.len() {
        let last = records.len() - 1;
        return (last, last, 0.0);
    }
    let (a, b) = (time(&records[k - 1]), time(&records[k]));
    if a == t {
        // A record at exactly this time: itself, not an interpolation that could round.
        return (k - 1, k - 1, 0.0);
    }
    let s = if b > a { (t - a) / (b - a) } else { 0.0 };
    (k - 1, k, s)
}

/// One quantity's error over the sample times: `errors` gives (t, error) in time order; the
/// largest error (a NaN counts as infinite) and when, and the first time it exceeds `tolerance`.
fn quantity_error(
    quantity: String,
    unit: &'static str,
    tolerance: f64,
    start: f64,
    errors: impl Iterator<Item = (f64, f64)>,
) -> QuantityError {
    let mut e = QuantityError {
        quantity,
        unit,
        max_error: 0.0,
        at: start,
        first_exceeded: None,
        tolerance,
    };
    for (t, err) in errors {
        if err > e.max_error || err.is_nan() {
            e.max_error = if err.is_nan() { f64::INFINITY } else { err };
            e.at = t;
        }
        // NaN counts as exceeding.
        if e.first_exceeded.is_none() && (err.is_nan() || err > tolerance) {
            e.first_exceeded = Some(t);
        }
    }
    e
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
    let (a, b, s) = bracket(records, |r: &TraceRecord| r.t, t);
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
    let (a, b, s) = bracket(records, |r: &TraceRecord| r.t, t);
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

/// The bodies of two traces of the same system matched as the comparisons match them: `map[i]`
/// is `other`'s body of reference body i, and how (`name`, `body`, `image`). An error says why
/// they cannot be matched (other systems, no records, a body without a partner). What
/// `compare-problem --traces` and `grade` match problem files' bodies with.
pub fn match_traces(
    reference: &AnyTrace,
    other: &AnyTrace,
) -> Result<(Vec<usize>, &'static str), String> {
    match (reference, other) {
        (AnyTrace::Three(r), AnyTrace::Three(o)) => {
            if r.records.is_empty() || o.records.is_empty() {
                return Err("a trace has no records".into());
            }
            if r.records[0].bodies.len() != r.header.bodies.len()
                || o.records[0].bodies.len() != o.header.bodies.len()
            {
                return Err("a trace's first record has other bodies than its header".into());
            }
            refusal::match_bodies(r, o).map_err(|e| e.message)
        }
        (AnyTrace::Two(r), AnyTrace::Two(o)) => {
            if r.records.is_empty() || o.records.is_empty() {
                return Err("a trace has no records".into());
            }
            if r.records[0].bodies.len() != r.header.bodies.len()
                || o.records[0].bodies.len() != o.header.bodies.len()
            {
                return Err("a trace's first record has other bodies than its header".into());
            }
            match_bodies_2d(r, o).map(|m| (m, "image"))
        }
        _ => Err("the traces are of different systems (2D and 3D)".into()),
    }
}
