//! Whether a trace's positions follow its velocities, record to record (docs/grading.md
//! §"Positions follow velocities"): a body cannot move without velocity, nor jump and come back.
//! Both modes judge every record of the candidate with this, so that outcome mode, which
//! compares the end, cannot be passed by a trace that teleports in between, and trajectory mode
//! checks the records it does not sample.
//!
//! Between two records Δ apart, with velocities v_a and v_b, any update of the Euler family over
//! one step (x += h v before or after the velocity update, any substeps with velocities between
//! the two) moves a body by Δ v for a v between v_a and v_b; so the displacement Δx must lie
//! within Δ |v_b − v_a| / 2 of Δ (v_a + v_b) / 2. What lies beyond is the *unexplained*
//! displacement, e = max(0, |Δx − Δ v̄| − Δ |Δv| / 2), the same for the rotation (θ in 2D; the
//! rotation vector of R_b R_aᵀ against ω in 3D, at a lever of one unit: 1 m, 1 block). A
//! simulator may legitimately move bodies beyond their velocities: post-stabilisation pushes
//! them out of penetration. The allowance is therefore a scale of the reference's own motion:
//! [`ALLOWANCE_STEPS`] of the reference's steps at its top speed, per reference step the
//! interval spans.

use super::Outcome;

/// The allowance per reference step, in reference steps travelled at the reference's top speed
/// S = max |v| + max |ω| · 1 unit + |g| dt (the speed of its fastest body, of a point one unit
/// from the centre of its fastest-turning body, and one step of gravity). Measured on
/// rigidref's own runs (the largest unexplained displacement per step, as a fraction of
/// dt · S): 3D, 14 scenes of scenes/ and the assignment's scene2–7, at most 1.5e-5 (round-off
/// of the rotations of a stack at rest; the 3D system moves bodies by their velocities only);
/// 2D with the default settings (post-stabilisation on), at most 0.15 (wallWideSparseHigh;
/// tower25 0.13, simple 0.06); 2D with post-stabilisation, 10 sweeps and one substep (the
/// starter preset before issue 47), at most 2.0 (delicate, where a pile's overlaps reach 0.75
/// block). Four steps leave room above all of them; a body teleported by tens of units, or to
/// 1e308, is far beyond it.
pub const ALLOWANCE_STEPS: f64 = 4.0;

/// One body's state at a record as the check reads it, in three components (2D: z = 0, and
/// the angular velocity ω as (ω, 0, 0)).
#[derive(Clone, Copy, Debug)]
pub(super) struct Moving {
    /// Centre of mass.
    pub x: [f64; 3],
    /// Velocity of the centre of mass.
    pub v: [f64; 3],
    /// Angular velocity.
    pub omega: [f64; 3],
}

fn norm(a: impl Iterator<Item = f64>) -> f64 {
    a.map(|x| x * x).sum::<f64>().sqrt()
}

/// The displacement `d` over `delta` that velocities `a` and `b` at its two ends do not
/// account for: max(0, |d − delta (a + b)/2| − delta |b − a|/2).
pub(super) fn unexplained(d: &[f64], a: &[f64], b: &[f64], delta: f64) -> f64 {
    let off = norm((0..d.len()).map(|k| d[k] - delta * (a[k] + b[k]) / 2.0));
    let spread = delta * norm((0..d.len()).map(|k| b[k] - a[k])) / 2.0;
    let e = off - spread;
    // NaN (a state of 1e308 minus another: inf − inf) counts as unexplained.
    if e.is_nan() {
        f64::INFINITY
    } else {
        e.max(0.0)
    }
}

/// The rotation vector (axis × angle, rad) of R_b R_aᵀ, the rotation from orientation `a` to
/// `b` in the world frame: the angle from atan2(sin, cos), exact near 0 and never NaN for a
/// matrix a round-off away from a rotation; near π the axis from the symmetric part.
pub(super) fn rotation_vector(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [f64; 3] {
    let ra = nalgebra::Matrix3::from_fn(|i, j| a[i][j]);
    let rb = nalgebra::Matrix3::from_fn(|i, j| b[i][j]);
    let r = rb * ra.transpose();
    // R − Rᵀ = 2 sin θ [axis]×; trace R = 1 + 2 cos θ.
    let w = nalgebra::Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) / 2.0;
    let (sin, cos) = (w.norm(), (r.trace() - 1.0) / 2.0);
    let angle = sin.atan2(cos);
    if !angle.is_finite() {
        return [f64::NAN; 3];
    }
    if sin > 1e-6 || cos > 0.0 {
        // Away from a half turn: the axis from the skew part (θ / sin θ → 1 at 0).
        let scale = if sin > 0.0 { angle / sin } else { 1.0 };
        return [w.x * scale, w.y * scale, w.z * scale];
    }
    // Near a half turn: (R + Rᵀ)/2 − cos θ I = (1 − cos θ) axis axisᵀ; the largest diagonal
    // entry's column gives the axis (its sign is immaterial at π: nearest_turn takes the turn).
    let s = (r + r.transpose()) / 2.0 - nalgebra::Matrix3::identity() * cos;
    let k = (0..3)
        .max_by(|&i, &j| s[(i, i)].total_cmp(&s[(j, j)]))
        .unwrap_or(0);
    let axis = s.column(k).into_owned();
    let n = axis.norm();
    if n == 0.0 {
        return [0.0; 3];
    }
    let sign = if axis.dot(&w) < 0.0 { -1.0 } else { 1.0 };
    let v = axis * (sign * angle / n);
    [v.x, v.y, v.z]
}

/// The rotation `r` (a rotation vector, or (Δθ, 0, 0) in 2D) plus the whole turns about its
/// axis that bring it nearest to `expected`: a rotation vector's angle is read modulo 2π (and a
/// 2D angle may be written wrapped into (−π, π]), a spin between records is not.
pub(super) fn nearest_turn(r: [f64; 3], expected: [f64; 3]) -> [f64; 3] {
    let angle = norm(r.iter().copied());
    let axis: [f64; 3] = if angle > 0.0 {
        std::array::from_fn(|c| r[c] / angle)
    } else {
        let e = norm(expected.iter().copied());
        if e == 0.0 {
            return r;
        }
        std::array::from_fn(|c| expected[c] / e)
    };
    let along = |k: f64| -> [f64; 3] {
        std::array::from_fn(|c| r[c] + k * std::f64::consts::TAU * axis[c])
    };
    let off = |v: [f64; 3]| norm((0..3).map(|c| v[c] - expected[c]));
    // The whole turns about the axis nearest to the expected rotation's component along it.
    let projected: f64 = (0..3).map(|c| (expected[c] - r[c]) * axis[c]).sum();
    let k = (projected / std::f64::consts::TAU).round();
    if !k.is_finite() {
        return r;
    }
    [k - 1.0, k, k + 1.0]
        .into_iter()
        .map(along)
        .min_by(|a, b| off(*a).total_cmp(&off(*b)))
        .unwrap_or(r)
}

/// The reference's top speed S (module documentation), in units per reference time unit.
pub(super) fn speed_scale(speeds: impl Iterator<Item = (f64, f64)>, gravity: f64, dt: f64) -> f64 {
    let (v, w) = speeds.fold((0.0_f64, 0.0_f64), |(v, w), (a, b)| (v.max(a), w.max(b)));
    v + w + gravity * dt
}

/// What the allowance is made of: the reference's step `dt`, its top speed S (`speed`) and the
/// length unit of the messages ("m", "block").
#[derive(Clone, Copy, Debug)]
pub(super) struct Scale {
    /// Length unit.
    pub unit: &'static str,
    /// Speed unit ("m/s", "block/t").
    pub speed_unit: &'static str,
    /// The reference's step.
    pub dt: f64,
    /// The reference's top speed S, units per time unit.
    pub speed: f64,
}

/// Judges every interval between the candidate's records: `times` the records' times,
/// `bodies` the bodies judged, `state(k, i)` body i at record k, `turned(k, i)` its rotation
/// from record k − 1 to k (θ_k − θ_{k−1} in 2D, the rotation vector of R_k R_{k−1}ᵀ in 3D);
/// `label(i)` names body i; `reference` gives the reference's step, top speed S and units. One
/// row: passes when no body's unexplained displacement (or rotation, at one unit from its
/// centre) exceeds [`ALLOWANCE_STEPS`] · dt · S per reference step of the interval; it names the
/// worst.
pub(super) fn motion_row(
    times: &[f64],
    bodies: &[usize],
    state: &dyn Fn(usize, usize) -> Moving,
    turned: &dyn Fn(usize, usize) -> [f64; 3],
    label: &dyn Fn(usize) -> String,
    reference: Scale,
) -> Outcome {
    let Scale {
        unit,
        speed_unit,
        dt,
        speed: scale,
    } = reference;
    let per_step = ALLOWANCE_STEPS * dt * scale.max(f64::MIN_POSITIVE);
    let (mut worst, mut text) = (
        0.0_f64,
        "every body moves as its velocities say".to_string(),
    );
    for k in 1..times.len() {
        let delta = times[k] - times[k - 1];
        let steps = (delta / dt).round().max(1.0);
        let allowed = steps * per_step;
        for &i in bodies {
            let (a, b) = (state(k - 1, i), state(k, i));
            let d: [f64; 3] = std::array::from_fn(|c| b.x[c] - a.x[c]);
            let moved = unexplained(&d, &a.v, &b.v, delta);
            let mean: [f64; 3] = std::array::from_fn(|c| delta * (a.omega[c] + b.omega[c]) / 2.0);
            let rotated = unexplained(&nearest_turn(turned(k, i), mean), &a.omega, &b.omega, delta);
            let ratio = moved.max(rotated) / allowed;
            if ratio > worst {
                worst = ratio;
                let what = if moved >= rotated {
                    format!("moves {moved:.4e} {unit}")
                } else {
                    format!("turns {rotated:.4e} rad")
                };
                text = format!(
                    "{} {what} between t = {} and {} beyond what its velocities account for \
                     ({ratio:.3} of the allowance)",
                    label(i),
                    super::time_text(times[k - 1]),
                    super::time_text(times[k])
                );
            }
        }
    }
    if worst > 0.0 && worst <= 1.0 {
        text = format!("largest: {text}");
    }
    Outcome {
        name: "positions follow velocities (every record)".into(),
        reference: "—".into(),
        other: text,
        difference: worst,
        tolerance: format!(
            "{per_step:.3e} {unit} per reference step ({ALLOWANCE_STEPS} steps at the reference's top speed {scale:.3e} {speed_unit})"
        ),
        passed: worst <= 1.0,
    }
}
