//! Outcome mode for 2D traces (the image-block system): how every body ends up, not the path
//! it took (docs/grading.md §"2D outcome mode"). Towers, walls and piles are chaotic: two
//! valid solvers part ways at the first impact shared by several contacts, but agree on which
//! bodies stand, which topple and where they rest.
//!
//! Per body that is not pinned, at the end of the span both traces cover: at rest or not; when
//! both are at rest, the rest position and the rest angle modulo the block shape's symmetry
//! (the quarter turns that map the body's blocks onto themselves, read from the image); standing
//! or toppled (turned by more than 45° from its first angle, modulo the same symmetry); and the
//! total energy at the end.

use super::two::{Trace2, angle_difference, energy_scale_2d, prepare};
use super::*;
use crate::blocks2d::body::Body2;
use crate::blocks2d::trace::State2;
use nalgebra::Vector2;
use std::f64::consts::FRAC_PI_2;

/// Tolerances and thresholds of 2D outcome mode, in the 2D system's units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutcomeTolerances2 {
    /// A body is at rest when its fastest point moves slower than this, blocks per time unit:
    /// |v| + |ω| r_max, r_max the farthest block corner from the centre of mass (1 block
    /// without the image).
    pub rest_speed: f64,
    /// Rest position, blocks.
    pub position: f64,
    /// Rest angle, rad, after the shape's symmetries.
    pub angle: f64,
    /// Total energy at the end, relative to the reference's energy scale (as for trajectories).
    pub energy: f64,
    /// Moving above this many times `rest_speed`; settling in between, which agrees with either
    /// verdict (docs/grading.md §"2D outcome mode": a margin, not a cut).
    pub settle_factor: f64,
}

impl Default for OutcomeTolerances2 {
    /// At rest below 0.05 block per time unit (1 % of the speed a body reaches after 5 time
    /// units of free fall under the default gravity of 1 block/t²), moving above twice that; a
    /// tenth of a block (the image's resolution is one block); 0.1 rad; 5 % in energy (as in
    /// 3D).
    fn default() -> Self {
        OutcomeTolerances2 {
            rest_speed: 0.05,
            position: 0.1,
            angle: 0.1,
            energy: 0.05,
            settle_factor: 2.0,
        }
    }
}

/// The quarter turns k (0 ≤ k < 4) that map a body's blocks onto themselves about its centre of
/// mass, each block to one of the same mass: the symmetry of the block shape (k = 0 always;
/// {0, 2} for a bar, {0, 1, 2, 3} for a square, {0} for an L).
pub fn quarter_turn_symmetries(body: &Body2) -> Vec<u8> {
    let turn = |p: &Vector2<f64>, k: u8| match k {
        0 => *p,
        1 => Vector2::new(-p.y, p.x),
        2 => -p,
        _ => Vector2::new(p.y, -p.x),
    };
    (0..4u8)
        .filter(|&k| {
            body.blocks.iter().all(|b| {
                let q = turn(&b.local, k);
                body.blocks
                    .iter()
                    .any(|c| (c.local - q).norm() <= 1e-9 && (c.mass - b.mass).abs() <= 1e-12)
            })
        })
        .collect()
}

/// The smallest angle between two orientations of a body, rad, over the body's symmetries
/// (quarter turns `symmetries`): min over k of |a − b − k π/2| wrapped into [0, π].
pub fn angle_after_symmetries(a: f64, b: f64, symmetries: &[u8]) -> f64 {
    symmetries
        .iter()
        .map(|&k| angle_difference(a, b + f64::from(k) * FRAC_PI_2))
        .fold(f64::INFINITY, f64::min)
}

/// The farthest a block's corner is from a body's centre of mass, blocks.
fn reach(body: &Body2) -> f64 {
    body.blocks
        .iter()
        .map(|b| b.local.norm() + std::f64::consts::FRAC_1_SQRT_2)
        .fold(0.0, f64::max)
}

/// The speed of a body's fastest point in state `s`: |v| + |ω| `reach`, blocks per time unit.
fn speed(s: &State2, reach: f64) -> f64 {
    s.v[0].hypot(s.v[1]) + s.omega.abs() * reach
}

/// Whether a body in state `s` is at rest: its fastest point below `rest_speed`.
fn at_rest(s: &State2, reach: f64, rest_speed: f64) -> bool {
    speed(s, reach) < rest_speed
}

/// The first time after which body `i` stays at rest to the end of `records`, if it is at rest
/// at the end.
fn rest_time(trace: &Trace2, i: usize, reach: f64, rest_speed: f64) -> Option<f64> {
    let records = &trace.records;
    if !at_rest(&records.last()?.bodies[i], reach, rest_speed) {
        return None;
    }
    let k = records
        .iter()
        .rposition(|r| !at_rest(&r.bodies[i], reach, rest_speed));
    Some(k.map_or(records[0].t, |k| records[(k + 1).min(records.len() - 1)].t))
}

/// The bodies of the 2D scene a reference trace came from, for their shapes: `given` (an image
/// or a 2D scene file; an error when it does not load), else the header's `source` where that
/// file exists as named or beside the reference trace; `None` when there is none or when its
/// bodies are not the trace's (another number).
pub fn outcome_scene_2d(
    reference: &Trace2,
    reference_path: &std::path::Path,
    given: Option<&std::path::Path>,
) -> Result<Option<(Vec<Body2>, std::path::PathBuf)>, String> {
    // The scene's bodies in the trace's order: the trace may number them otherwise than the
    // file loads them (a run with `--preset starter` numbers an image column by column).
    let load = |path: &std::path::Path| {
        crate::blocks2d::scene::load_2d(path, &Default::default())
            .map(|s| in_trace_order(s.world.bodies, reference))
            .map_err(|e| e.0)
    };
    if let Some(path) = given {
        let Some(bodies) = load(path)? else {
            return Err(format!(
                "{}: its bodies are not the reference trace's (another number, or blocks not \
                 where the trace's bodies start): not its scene",
                path.display(),
            ));
        };
        return Ok(Some((bodies, path.to_path_buf())));
    }
    Ok(
        super::outcome::source_candidates(&reference.header.source, reference_path)
            .find_map(|p| load(&p).ok().flatten().map(|b| (b, p))),
    )
}

/// `bodies` in the order of the trace's bodies, `None` when they are not the same bodies: each
/// trace body takes the unmatched body with its block count whose centre of mass is nearest the
/// trace's first recorded centre, within half a block (the masses are not compared: the
/// starter's image reader computes them from 32-bit colours).
fn in_trace_order(bodies: Vec<Body2>, trace: &Trace2) -> Option<Vec<Body2>> {
    let header = &trace.header.bodies;
    let first = trace.records.first()?;
    if bodies.len() != header.len() || first.bodies.len() != header.len() {
        return None;
    }
    let mut slots: Vec<Option<Body2>> = bodies.into_iter().map(Some).collect();
    let mut ordered = Vec::with_capacity(header.len());
    for (info, state) in header.iter().zip(&first.bodies) {
        let centre = Vector2::from(state.x);
        let best = (0..slots.len())
            .filter(|&k| {
                slots[k]
                    .as_ref()
                    .is_some_and(|b| b.blocks.len() == info.blocks)
            })
            .map(|k| {
                (
                    k,
                    (slots[k]
                        .as_ref()
                        .map_or(f64::INFINITY, |b| (b.x - centre).norm())),
                )
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .filter(|&(_, d)| d <= 0.5)?;
        ordered.push(slots[best.0].take()?);
    }
    Some(ordered)
}

/// Outcome mode for 2D traces (module documentation). `shapes`, the reference scene's bodies in
/// the reference trace's order, give the symmetries and reaches; without them angles are
/// compared modulo 2π only and a body's reach is taken as 1 block.
pub fn compare_outcomes_2d(
    reference: &Trace2,
    other: &Trace2,
    shapes: Option<&[Body2]>,
    tol: &OutcomeTolerances2,
) -> Result<Comparison, String> {
    let (map, start, end) = match prepare(reference, other)? {
        Ok(prepared) => prepared,
        Err(refusal) => return Ok(Comparison::refused("outcome", refusal)),
    };
    // Every record of the candidate, not only the span or the end.
    let checks = vec![super::two::motion_check_2d(reference, other, &map)];
    // Only what both traces cover: a trace that runs longer is judged at the common end.
    let within = |t: &Trace2| Trace2 {
        header: t.header.clone(),
        records: (t.records.iter())
            .filter(|r| r.t >= start && r.t <= end)
            .cloned()
            .collect(),
    };
    let (reference, other) = (&within(reference), &within(other));
    let (Some(end_r), Some(end_o)) = (reference.records.last(), other.records.last()) else {
        return Err("the traces have no record in the span both cover".into());
    };
    let (first_r, first_o) = (&reference.records[0], &other.records[0]);
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
    for (i, &j) in map.iter().enumerate() {
        if reference.header.bodies[i].pinned {
            continue;
        }
        let label = format!("body {i} ({:?})", reference.header.bodies[i].name);
        let shape = shapes.and_then(|s| s.get(i));
        let symmetries = shape.map_or(vec![0], quarter_turn_symmetries);
        let reach = shape.map_or(1.0, reach);
        let (ra, rb) = (
            rest_time(reference, i, reach, tol.rest_speed),
            rest_time(other, j, reach, tol.rest_speed),
        );
        let (sa, sb) = (&end_r.bodies[i], &end_o.bodies[j]);
        let moving_speed = tol.settle_factor * tol.rest_speed;
        // At rest (below rest_speed), settling (up to settle_factor times that: either verdict
        // agrees with it) or moving; the speeds judged are shown.
        let end = |t: Option<f64>, s: &State2| {
            let v = speed(s, reach);
            match t {
                Some(t) => (
                    0,
                    format!("at rest from t = {t:.4} (speed {v:.3e} block/t)"),
                ),
                None if v <= moving_speed => (1, format!("settling (speed {v:.3e} block/t)")),
                None => (2, format!("moving (speed {v:.3e} block/t)")),
            }
        };
        let ((ka, ta), (kb, tb)) = (end(ra, sa), end(rb, sb));
        let differ = (ka == 0 && kb == 2) || (ka == 2 && kb == 0);
        push(
            format!("{label} at rest at the end"),
            ta,
            tb,
            if differ { 1.0 } else { 0.0 },
            format!(
                "at rest below {} block/t, moving above {moving_speed} block/t (fastest point)",
                tol.rest_speed
            ),
            !differ,
        );
        if ka < 2 && kb < 2 {
            let d = (sa.x[0] - sb.x[0]).hypot(sa.x[1] - sb.x[1]);
            push(
                format!("{label} rest position"),
                format!("[{:.4}, {:.4}]", sa.x[0], sa.x[1]),
                format!("[{:.4}, {:.4}]", sb.x[0], sb.x[1]),
                d,
                format!("{} block", tol.position),
                d <= tol.position,
            );
            let angle = angle_after_symmetries(sa.theta, sb.theta, &symmetries);
            push(
                format!("{label} rest angle (after {} symmetries)", symmetries.len()),
                format!("{:.4} rad", sa.theta),
                format!("{:.4} rad ({angle:.4} from the reference)", sb.theta),
                angle,
                format!("{} rad", tol.angle),
                angle <= tol.angle,
            );
        }
        // Toppled: turned by more than 45° from the first record's angle, modulo the symmetry.
        let turned_r = angle_after_symmetries(sa.theta, first_r.bodies[i].theta, &symmetries);
        let turned_o = angle_after_symmetries(sb.theta, first_o.bodies[j].theta, &symmetries);
        let state = |turned: f64| {
            if turned > std::f64::consts::FRAC_PI_4 {
                format!("toppled ({turned:.3} rad)")
            } else {
                format!("standing ({turned:.3} rad)")
            }
        };
        let same =
            (turned_r > std::f64::consts::FRAC_PI_4) == (turned_o > std::f64::consts::FRAC_PI_4);
        push(
            format!("{label} standing or toppled"),
            state(turned_r),
            state(turned_o),
            (turned_r - turned_o).abs(),
            "toppled when turned > 0.785 rad".into(),
            same,
        );
    }
    let scale = energy_scale_2d(reference);
    let (ea, eb) = (end_r.energy.total, end_o.energy.total);
    let d = (ea - eb).abs();
    push(
        format!("total energy at t = {}", end_r.t),
        format!("{ea:.6e}"),
        format!("{eb:.6e}"),
        d,
        format!("{:.3e} mass·block²/t²", tol.energy * scale),
        d <= tol.energy * scale,
    );
    let agree = outcomes.iter().chain(&checks).all(|o| o.passed);
    Ok(Comparison {
        mode: "outcome",
        span: (start, end),
        matched_by: "image",
        matching: map,
        errors: Vec::new(),
        outcomes,
        checks,
        agree,
        refused: None,
    })
}
