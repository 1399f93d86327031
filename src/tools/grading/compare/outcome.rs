//! Outcome mode: what happened in a trace against what happened in the reference's
//! (docs/grading.md §"Outcome mode").

use super::refusal::{check_traces, motion_check};
use super::*;
use crate::rigid3d::diagnostics::sign_changes;
use crate::rigid3d::scene::Scene;

/// A body is at rest when |v| < `tol.rest_speed` and |ω| < `tol.rest_omega` (0.05 m/s and
/// 0.1 rad/s by default: the rapier comparison's rule).
fn at_rest(b: &BodyState, tol: &OutcomeTolerances) -> bool {
    v3(&b.v).norm() < tol.rest_speed && v3(&b.omega).norm() < tol.rest_omega
}

/// A body is moving when |v| or |ω| is above `tol.settle_factor` times its rest threshold;
/// between the two it is settling, which either verdict accepts.
fn moving(b: &BodyState, tol: &OutcomeTolerances) -> bool {
    v3(&b.v).norm() > tol.settle_factor * tol.rest_speed
        || v3(&b.omega).norm() > tol.settle_factor * tol.rest_omega
}

/// A body's state at the end: at rest from a time, settling, or moving (see [`moving`]).
#[derive(Clone, Copy, Debug, PartialEq)]
enum End {
    Rest(f64),
    Settling,
    Moving,
}

fn end_of(trace: &Trace, i: usize, tol: &OutcomeTolerances) -> End {
    match (rest_time(trace, i, tol), trace.records.last()) {
        (Some(t), _) => End::Rest(t),
        (None, Some(r)) if !moving(&r.bodies[i], tol) => End::Settling,
        _ => End::Moving,
    }
}

/// An end state with the speeds judged: `2.1400 (|v| 1.2e-3 m/s, |ω| 3.0e-3 rad/s at the end)`.
fn end_text(end: End, b: &BodyState) -> String {
    let speeds = format!(
        "|v| {:.3e} m/s, |ω| {:.3e} rad/s at the end",
        v3(&b.v).norm(),
        v3(&b.omega).norm()
    );
    match end {
        End::Rest(t) => format!("{t:.4} ({speeds})"),
        End::Settling => format!("never: settling ({speeds})"),
        End::Moving => format!("never: moving ({speeds})"),
    }
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
fn rest_time(trace: &Trace, i: usize, tol: &OutcomeTolerances) -> Option<f64> {
    let records = &trace.records;
    if !at_rest(&records.last()?.bodies[i], tol) {
        return None;
    }
    let k = records.iter().rposition(|r| !at_rest(&r.bodies[i], tol));
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
    /// At rest below this speed, m/s (and below `rest_omega`).
    pub rest_speed: f64,
    /// At rest below this angular speed, rad/s (and below `rest_speed`).
    pub rest_omega: f64,
    /// Moving above this many times the rest thresholds; settling in between, which agrees
    /// with either (docs/grading.md §"Outcome mode": a margin, not a cut).
    pub settle_factor: f64,
}

impl Default for OutcomeTolerances {
    /// Five frames of 0.01 s (0.25 s for coming to rest, which a threshold decides), 5% of the
    /// radius, 0.1 rad, 5% in energy, 5% of a flip period; at rest below 0.05 m/s and
    /// 0.1 rad/s, moving above twice that.
    fn default() -> Self {
        OutcomeTolerances {
            time: 0.05,
            position: 0.05,
            angle: 0.1,
            energy: 0.05,
            flip: 0.05,
            rest_speed: 0.05,
            rest_omega: 0.1,
            settle_factor: 2.0,
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
    Ok(source_candidates(&reference.header.source, reference_path)
        .find_map(|p| crate::rigid3d::scene::load_scene(&p).ok().map(|s| (s, p))))
}

/// The files a reference trace's header `source` may name: the path as written, then the same
/// path beside the reference trace; those that exist. (Outcome mode's scene, 3D and 2D.)
pub(super) fn source_candidates(
    source: &str,
    reference_path: &std::path::Path,
) -> impl Iterator<Item = std::path::PathBuf> {
    let source = std::path::Path::new(source);
    let beside = reference_path
        .parent()
        .map(|d| d.join(source))
        .unwrap_or_default();
    [source.to_path_buf(), beside]
        .into_iter()
        .filter(|p| p.is_file())
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
    let prepared = match check_traces(reference, other)? {
        Ok(prepared) => prepared,
        Err(refusal) => return Ok(Comparison::refused("outcome", refusal)),
    };
    let (span, map, matched_by) = (prepared.span, prepared.map, prepared.matched_by);
    // Every record of the candidate, not only the span or the end.
    let checks = vec![motion_check(reference, other, &map)];
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
        let (ea, eb) = (end_of(reference, i, tol), end_of(other, j, tol));
        // At rest against moving differs; settling (between the rest threshold and twice it)
        // agrees with either; two rest times must agree to the tolerance.
        let d = match (ea, eb) {
            (End::Rest(a), End::Rest(b)) => (a - b).abs(),
            (End::Rest(_), End::Moving) | (End::Moving, End::Rest(_)) => f64::INFINITY,
            _ => 0.0,
        };
        let rest_tol = 5.0 * tol.time;
        push(
            format!("{label} comes to rest at"),
            end_text(ea, &end_r.bodies[i]),
            end_text(eb, &end_o.bodies[j]),
            d,
            format!(
                "{rest_tol} s; at rest below {} m/s and {} rad/s, moving above {} times that",
                tol.rest_speed, tol.rest_omega, tol.settle_factor
            ),
            d <= rest_tol,
        );
        if ea != End::Moving && eb != End::Moving {
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
    let agree = outcomes.iter().chain(&checks).all(|o| o.passed);
    Ok(Comparison {
        mode: "outcome",
        span,
        matched_by,
        matching: map,
        errors: Vec::new(),
        outcomes,
        checks,
        agree,
        refused: None,
    })
}
