//! Golden traces: the canonical scenes' traces as committed in golden/, and the comparison of a
//! fresh run with them. docs/verification.md §"Golden traces" says when regenerating them
//! (`rigidref golden --update`) is legitimate.

use crate::rigid3d::scene::{Scene, load_scene};
use crate::rigid3d::trace::{
    Trace, TraceFormat, TraceHeader, TraceRecord, TraceWriter, read_trace,
};
use crate::rigid3d::world::World;
use crate::sim::{Flow, drive, is_recorded, steps_in};
use std::path::{Path, PathBuf};

/// Simulated time of a golden trace, s.
pub const GOLDEN_TIME: f64 = 5.0;
/// A golden trace records every this-many frames (and the last).
pub const GOLDEN_EVERY: u64 = 5;

/// The canonical scenes: every `*.json` in `scenes_dir`, sorted.
pub fn canonical_scenes(scenes_dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(scenes_dir)
        .map_err(|e| format!("{}: cannot read: {e}", scenes_dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    paths.sort();
    Ok(paths)
}

/// The golden file of a scene: `golden/NAME.jsonl`.
pub fn golden_path(golden_dir: &Path, scene_path: &Path) -> PathBuf {
    let stem = scene_path.file_stem().unwrap_or_default().to_string_lossy();
    golden_dir.join(format!("{stem}.jsonl"))
}

/// Runs `scene` for [`GOLDEN_TIME`], recording every [`GOLDEN_EVERY`]-th
/// frame. `source` is what the header names as the scene's origin.
pub fn record(scene: &Scene, source: &str) -> Result<Trace, String> {
    let mut world = World::new(scene)?;
    let steps = steps_in(GOLDEN_TIME, scene.params.dt, "").map_err(|e| format!("{source}: {e}"))?;
    let header = TraceHeader::for_world(&world, source);
    let mut records = vec![TraceRecord::of_world(&world)];
    drive(&mut world, steps, |w, k| {
        if is_recorded(k, steps, GOLDEN_EVERY) {
            records.push(TraceRecord::of_world(w));
        }
        Ok::<_, String>(Flow::Continue)
    })
    .map_err(|e| format!("{source}: {e}"))?;
    Ok(Trace {
        header,
        records,
        notes: Vec::new(),
    })
}

/// Records the golden trace of the scene at `scene_path` (its source named relative to the
/// project, e.g. `scenes/box_stack.json`) and writes it to `out`.
pub fn write_golden(scene_path: &Path, source: &str, out: &Path) -> Result<(), String> {
    let scene = load_scene(scene_path).map_err(|e| e.0)?;
    let trace = record(&scene, source)?;
    let file =
        std::fs::File::create(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let mut writer = TraceWriter::new(
        Box::new(std::io::BufWriter::new(file)),
        TraceFormat::Jsonl,
        &trace.header,
    )
    .map_err(|e| format!("{}: {e}", out.display()))?;
    for r in &trace.records {
        writer
            .write(r.clone())
            .map_err(|e| format!("{}: {e}", out.display()))?;
    }
    writer
        .flush()
        .map_err(|e| format!("{}: {e}", out.display()))
}

/// Reads a golden trace.
pub fn read_golden(path: &Path) -> Result<Trace, String> {
    let file = std::fs::File::open(path)
        .map_err(|e| format!("{}: cannot open golden trace: {e}", path.display()))?;
    read_trace(std::io::BufReader::new(file), &path.display().to_string())
}

/// Per-quantity tolerances: a value v matches its golden g when |v − g| ≤ tol · (1 + |g|).
///
/// The simulator is deterministic, so on the machine and toolchain that wrote golden/ a fresh
/// trace is bitwise identical; the tolerances leave room only for another CPU or libm rounding
/// differently (a few ulps, grown by the scenes' sensitivity over 5 s), while any change of the
/// method moves values by far more (docs/verification.md §"Golden traces").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Positions (m), rotation entries, velocities (m/s), angular velocities (rad/s).
    pub state: f64,
    /// Energies (J) and momenta.
    pub diagnostics: f64,
    /// Contact points, normals, depths and impulses.
    pub contacts: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            state: 1e-8,
            diagnostics: 1e-8,
            contacts: 1e-6,
        }
    }
}

/// One value that differs from its golden.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    /// Frame of the record.
    pub step: u64,
    /// Which quantity, e.g. `bodies[2].x[1]`.
    pub quantity: String,
    /// The golden value.
    pub golden: f64,
    /// The fresh value.
    pub fresh: f64,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "step {}: {} is {:.12e}, golden {:.12e} (difference {:.3e})",
            self.step,
            self.quantity,
            self.fresh,
            self.golden,
            self.fresh - self.golden
        )
    }
}

/// Every quantity of `fresh` that differs from `golden` beyond the tolerances (records matched
/// by position; a different number of records or contacts is itself a mismatch).
pub fn compare(golden: &Trace, fresh: &Trace, tol: &Tolerances) -> Vec<Mismatch> {
    let mut out = Vec::new();
    let mut check = |step: u64, quantity: String, g: f64, v: f64, t: f64| {
        let within = (v - g).abs() <= t * (1.0 + g.abs());
        let both_nan = g.is_nan() && v.is_nan();
        let differs = !(within || both_nan);
        if differs {
            out.push(Mismatch {
                step,
                quantity,
                golden: g,
                fresh: v,
            });
        }
    };
    check(
        0,
        "number of records".into(),
        golden.records.len() as f64,
        fresh.records.len() as f64,
        0.0,
    );
    for (g, f) in golden.records.iter().zip(&fresh.records) {
        let step = g.step;
        check(step, "step".into(), g.step as f64, f.step as f64, 0.0);
        if let (Some(gp), Some(fp)) = (g.penetration, f.penetration) {
            check(step, "penetration".into(), gp, fp, tol.contacts);
        }
        for (i, (gb, fb)) in g.bodies.iter().zip(&f.bodies).enumerate() {
            for k in 0..3 {
                check(
                    step,
                    format!("bodies[{i}].x[{k}]"),
                    gb.x[k],
                    fb.x[k],
                    tol.state,
                );
                check(
                    step,
                    format!("bodies[{i}].v[{k}]"),
                    gb.v[k],
                    fb.v[k],
                    tol.state,
                );
                check(
                    step,
                    format!("bodies[{i}].omega[{k}]"),
                    gb.omega[k],
                    fb.omega[k],
                    tol.state,
                );
                for m in 0..3 {
                    check(
                        step,
                        format!("bodies[{i}].R[{k}][{m}]"),
                        gb.rotation[k][m],
                        fb.rotation[k][m],
                        tol.state,
                    );
                }
            }
        }
        let (ge, fe) = (&g.energy, &f.energy);
        for (name, a, b) in [
            (
                "energy.kinetic_linear",
                ge.kinetic_linear,
                fe.kinetic_linear,
            ),
            (
                "energy.kinetic_angular",
                ge.kinetic_angular,
                fe.kinetic_angular,
            ),
            ("energy.potential", ge.potential, fe.potential),
            ("energy.total", ge.total, fe.total),
        ] {
            check(step, name.into(), a, b, tol.diagnostics);
        }
        for k in 0..3 {
            check(
                step,
                format!("momentum.linear[{k}]"),
                g.momentum.linear[k],
                f.momentum.linear[k],
                tol.diagnostics,
            );
            check(
                step,
                format!("momentum.angular[{k}]"),
                g.momentum.angular[k],
                f.momentum.angular[k],
                tol.diagnostics,
            );
        }
        check(
            step,
            "number of contacts".into(),
            g.contacts.len() as f64,
            f.contacts.len() as f64,
            0.0,
        );
        if g.contacts.len() == f.contacts.len() {
            for (c, (gc, fc)) in g.contacts.iter().zip(&f.contacts).enumerate() {
                check(
                    step,
                    format!("contacts[{c}].bodies[0]"),
                    gc.bodies[0] as f64,
                    fc.bodies[0] as f64,
                    0.0,
                );
                check(
                    step,
                    format!("contacts[{c}].bodies[1]"),
                    gc.bodies[1] as f64,
                    fc.bodies[1] as f64,
                    0.0,
                );
                check(
                    step,
                    format!("contacts[{c}].depth"),
                    gc.depth,
                    fc.depth,
                    tol.contacts,
                );
                for k in 0..3 {
                    check(
                        step,
                        format!("contacts[{c}].p[{k}]"),
                        gc.p[k],
                        fc.p[k],
                        tol.contacts,
                    );
                    check(
                        step,
                        format!("contacts[{c}].n[{k}]"),
                        gc.n[k],
                        fc.n[k],
                        tol.contacts,
                    );
                    check(
                        step,
                        format!("contacts[{c}].lambda[{k}]"),
                        gc.lambda[k],
                        fc.lambda[k],
                        tol.contacts,
                    );
                }
            }
        }
    }
    out
}
