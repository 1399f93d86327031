//! The viewer: one self-contained HTML file that shows a run in a browser, offline: the bodies
//! at the recorded states with play, pause, a time slider and single steps; the contacts with
//! their normals, impulses and (3D) tangent frames; the plots of [`super::series`], synchronised
//! with the slider; and the selected body's state. docs/viewing.md.
//!
//! The page is the project's own code (src/tools/viewing/view/viewer.{html,css,js}, plain WebGL and
//! canvas, no third-party script), compiled into the binary; the run's data is embedded in it as
//! JSON (the schema is in docs/viewing.md §"The page's data").

use super::series::{Plot, plots_2d, plots_3d};
use crate::blocks2d::trace::{Record2, TraceHeader2};
use crate::blocks2d::world::World2;
use crate::rigid3d::frame::ContactFrame;
use crate::rigid3d::mesh::TriMesh;
use crate::rigid3d::trace::{TraceHeader, TraceRecord};
use nalgebra::Vector3;
use serde::de::DeserializeOwned;
use serde_json::{Value, json};

/// The `format` of the page's data.
pub const VIEW_FORMAT: &str = "rigidref-view";

/// The most records a page holds by default: longer traces are thinned evenly (the first and
/// the last record always kept), which keeps a page of thousands of bodies small enough to load
/// in a second or two (`rigidref view --max-frames`).
pub const DEFAULT_MAX_FRAMES: usize = 1500;

/// A trace of either system (3D or 2D), as `view`, `plot` and `render` read it.
#[derive(Clone, Debug)]
pub enum RunTrace {
    /// A 3D trace.
    Three {
        /// Header line.
        header: TraceHeader,
        /// The complete records.
        records: Vec<TraceRecord>,
    },
    /// A 2D trace.
    Two {
        /// Header line.
        header: TraceHeader2,
        /// The complete records.
        records: Vec<Record2>,
    },
}

impl RunTrace {
    /// The `source` the header names (the scene the run read, whose geometry the page draws).
    pub fn source(&self) -> &str {
        match self {
            RunTrace::Three { header, .. } => &header.source,
            RunTrace::Two { header, .. } => &header.source,
        }
    }

    /// The bodies whose angular velocity is plotted: `chosen` when given, else the first
    /// [`super::series::MAX_OMEGA_BODIES`] that are not pinned.
    pub fn omega_bodies(&self, chosen: &[usize]) -> Vec<usize> {
        if !chosen.is_empty() {
            return chosen.to_vec();
        }
        let pinned: Vec<bool> = match self {
            RunTrace::Three { header, .. } => vec![false; header.bodies.len()],
            RunTrace::Two { header, .. } => header.bodies.iter().map(|b| b.pinned).collect(),
        };
        super::series::default_omega_bodies(&pinned)
    }

    /// How many bodies the header lists.
    pub fn body_count(&self) -> usize {
        match self {
            RunTrace::Three { header, .. } => header.bodies.len(),
            RunTrace::Two { header, .. } => header.bodies.len(),
        }
    }
}

/// Reads a trace of either system for viewing. A trace cut off in its last line (a run that
/// was stopped, a copy that was interrupted) keeps its complete records, with a warning in
/// `warnings`; any other bad line is an error naming the file and the line.
pub fn read_run_trace(
    text: &str,
    source: &str,
    warnings: &mut Vec<String>,
) -> Result<RunTrace, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, first)) = lines.next() else {
        return Err(format!("{source}: empty file; not a rigidref trace"));
    };
    let header = crate::common::trace::header_value(first, source)?;
    let rest: Vec<(usize, &str)> = lines.collect();
    match header.get("dimension").and_then(Value::as_u64) {
        Some(3) => {
            let header: TraceHeader = serde_json::from_value(header).map_err(|e| {
                let why = crate::common::trace::json_problem(&e);
                format!("{source}:1: bad 3D trace header: {why}")
            })?;
            let records = read_records(
                &rest,
                source,
                header.bodies.len(),
                warnings,
                |r: &TraceRecord| r.bodies.len(),
            )?;
            Ok(RunTrace::Three { header, records })
        }
        Some(2) => {
            let header: TraceHeader2 = serde_json::from_value(header).map_err(|e| {
                let why = crate::common::trace::json_problem(&e);
                format!("{source}:1: bad 2D trace header: {why}")
            })?;
            let records = read_records(
                &rest,
                source,
                header.bodies.len(),
                warnings,
                |r: &Record2| r.bodies.len(),
            )?;
            Ok(RunTrace::Two { header, records })
        }
        _ => Err(format!(
            "{source}:1: the header's \"dimension\" must be 2 or 3"
        )),
    }
}

/// The records of `lines` (numbered from 0), each with `bodies` bodies; an unreadable last line
/// is a cut-off record (warned about and dropped), any other is an error.
fn read_records<T: DeserializeOwned>(
    lines: &[(usize, &str)],
    source: &str,
    bodies: usize,
    warnings: &mut Vec<String>,
    count: impl Fn(&T) -> usize,
) -> Result<Vec<T>, String> {
    let mut records = Vec::with_capacity(lines.len());
    for (k, &(i, line)) in lines.iter().enumerate() {
        match serde_json::from_str::<T>(line) {
            Ok(r) if count(&r) == bodies => records.push(r),
            Ok(r) => {
                return Err(format!(
                    "{source}:{}: the record has {} bodies; the header lists {bodies}",
                    i + 1,
                    count(&r)
                ));
            }
            Err(e) if k + 1 == lines.len() && e.is_eof() => {
                warnings.push(format!(
                    "{source}:{}: the last record is incomplete (the trace was cut off); showing the {} complete records",
                    i + 1,
                    records.len()
                ));
            }
            Err(_) if crate::common::trace::is_header_line(line) => {
                return Err(crate::common::trace::repeated_header(source, i + 1));
            }
            Err(e) => {
                return Err(format!(
                    "{source}:{}: not a record: {}",
                    i + 1,
                    crate::common::trace::json_problem(&e)
                ));
            }
        }
    }
    if records.is_empty() {
        return Err(format!(
            "{source}: the trace has a header but no complete record"
        ));
    }
    Ok(records)
}

/// The indices of at most `max` records out of `n`, evenly spread, the first and the last
/// always among them (all of them when `n ≤ max`).
pub fn pick_frames(n: usize, max: usize) -> Vec<usize> {
    if n <= max || max < 2 {
        return (0..n).collect();
    }
    let mut picked: Vec<usize> = (0..max)
        .map(|k| ((k as f64) * (n - 1) as f64 / (max - 1) as f64).round() as usize)
        .collect();
    picked.dedup();
    picked
}

/// `x` to 7 significant digits: what the page shows, at about half the characters of the
/// shortest round-trip form (the trace keeps the exact value).
fn r7(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{x:.6e}").parse().unwrap_or(x)
}

fn r7s(xs: impl IntoIterator<Item = f64>) -> Vec<f64> {
    xs.into_iter().map(r7).collect()
}

/// The plots as the page's JSON, only the picked records.
fn plots_json(plots: &[Plot], picked: &[usize]) -> Value {
    Value::Array(
        plots
            .iter()
            .map(|p| {
                json!({
                    "title": p.title,
                    "unit": p.unit,
                    "log": p.log,
                    "series": p.series.iter().map(|s| json!({
                        "name": s.name,
                        "values": picked.iter().map(|&k| s.values[k].map(r7)).collect::<Vec<_>>(),
                    })).collect::<Vec<_>>(),
                })
            })
            .collect(),
    )
}

/// A body's display colour, RGB in [0, 1]: a fixed palette by index, so that a body keeps its
/// colour from page to page (and in `rigidref render`'s frames).
pub fn palette(i: usize) -> [f64; 3] {
    const COLOURS: [[f64; 3]; 8] = [
        [0.85, 0.45, 0.25],
        [0.30, 0.55, 0.85],
        [0.40, 0.70, 0.35],
        [0.80, 0.65, 0.20],
        [0.60, 0.40, 0.75],
        [0.25, 0.70, 0.70],
        [0.80, 0.35, 0.50],
        [0.55, 0.55, 0.55],
    ];
    COLOURS[i % COLOURS.len()]
}

fn mesh_json(mesh: &TriMesh) -> Value {
    json!({
        "vertices": r7s(mesh.vertices.iter().flat_map(|v| [v.x, v.y, v.z])),
        "triangles": mesh.triangles.iter().flatten().collect::<Vec<_>>(),
    })
}

/// The page's data for a 3D trace: `meshes[i]` is body i's mesh (body frame, centre of mass at
/// the origin, m); at most `max_frames` records; `omega_bodies` as in [`plots_3d`].
pub fn view_data_3d(
    header: &TraceHeader,
    records: &[TraceRecord],
    meshes: &[&TriMesh],
    warnings: &[String],
    max_frames: usize,
    omega_bodies: &[usize],
) -> Value {
    // A mesh shared by several bodies (a stack of equal cubes) is sent once.
    let mut bodies = Vec::with_capacity(meshes.len());
    for (i, (info, mesh)) in header.bodies.iter().zip(meshes).enumerate() {
        let same = (0..i).find(|&k| {
            std::ptr::eq(meshes[k], *mesh)
                || (meshes[k].vertices == mesh.vertices && meshes[k].triangles == mesh.triangles)
        });
        let mesh = match same {
            Some(k) => json!({ "same_as": k }),
            None => mesh_json(mesh),
        };
        bodies.push(json!({
            "name": info.name, "mass": info.mass, "mesh": mesh, "color": palette(i),
        }));
    }
    let picked = pick_frames(records.len(), max_frames);
    let frames: Vec<Value> = picked
        .iter()
        .map(|&k| {
            let r = &records[k];
            let pose = r7s(r.bodies.iter().flat_map(|b| {
                let m = b.rotation;
                [
                    b.x[0], b.x[1], b.x[2], m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2],
                    m[2][0], m[2][1], m[2][2],
                ]
            }));
            let vel = r7s(r
                .bodies
                .iter()
                .flat_map(|b| [b.v[0], b.v[1], b.v[2], b.omega[0], b.omega[1], b.omega[2]]));
            let contacts: Vec<Value> = r
                .contacts
                .iter()
                .map(|c| {
                    // The tangent t1 the solver used: the frame is a function of n alone
                    // (docs/contact.md §"Contact frame").
                    let t1 = ContactFrame::from_normal(&Vector3::from(c.n)).t1;
                    let mut row = vec![json!(c.bodies[0]), json!(c.bodies[1])];
                    row.extend(
                        r7s([
                            c.p[0],
                            c.p[1],
                            c.p[2],
                            c.n[0],
                            c.n[1],
                            c.n[2],
                            t1.x,
                            t1.y,
                            t1.z,
                            c.depth,
                            c.lambda[0],
                            c.lambda[1],
                            c.lambda[2],
                        ])
                        .into_iter()
                        .map(|x| json!(x)),
                    );
                    Value::Array(row)
                })
                .collect();
            json!({ "step": r.step, "t": r.t, "pose": pose, "vel": vel, "contacts": contacts })
        })
        .collect();
    let plots = plots_3d(header, records, omega_bodies);
    json!({
        "format": VIEW_FORMAT, "version": 1, "dimension": 3,
        "scene": header.scene, "source": header.source, "dt": header.dt,
        "length_unit": "m", "time_unit": "s",
        "warnings": warnings,
        "bodies": bodies,
        "frames": frames,
        "plots": plots_json(&plots, &picked),
    })
}

/// The page's data for a 2D trace, with the blocks of `world` (the scene the trace ran, as it
/// starts: the blocks' body-frame positions do not change).
pub fn view_data_2d(
    header: &TraceHeader2,
    records: &[Record2],
    world: &World2,
    warnings: &[String],
    max_frames: usize,
    omega_bodies: &[usize],
) -> Value {
    let bodies: Vec<Value> = world
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let blocks = r7s(b.blocks.iter().flat_map(|k| [k.local.x, k.local.y]));
            let colors: Vec<u8> = b
                .blocks
                .iter()
                .flat_map(|k| k.colour.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
                .collect();
            json!({
                "name": format!("body{i}"), "mass": b.mass, "pinned": b.pinned,
                "blocks": blocks, "colors": colors,
            })
        })
        .collect();
    let picked = pick_frames(records.len(), max_frames);
    // A factory run's records hold the bodies dropped so far, a prefix of the world's list:
    // the rest are padded with null and the frame says how many are `present`.
    let nb = world.bodies.len();
    let absent = |r: &Record2| nb.saturating_sub(r.bodies.len());
    let frames: Vec<Value> = picked
        .iter()
        .map(|&k| {
            let r = &records[k];
            let pad = std::iter::repeat_n(f64::NAN, 3 * absent(r));
            let pose = r7s(r
                .bodies
                .iter()
                .flat_map(|b| [b.x[0], b.x[1], b.theta])
                .chain(pad.clone()));
            let vel = r7s(r
                .bodies
                .iter()
                .flat_map(|b| [b.v[0], b.v[1], b.omega])
                .chain(pad));
            let contacts = r.contacts.as_ref().map(|cs| {
                cs.iter()
                    .map(|c| {
                        let mut row = vec![json!(c.bodies[0]), json!(c.bodies[1])];
                        row.extend(
                            r7s([
                                c.p[0],
                                c.p[1],
                                c.n[0],
                                c.n[1],
                                c.depth,
                                c.lambda[0],
                                c.lambda[1],
                            ])
                            .into_iter()
                            .map(|x| json!(x)),
                        );
                        Value::Array(row)
                    })
                    .collect::<Vec<_>>()
            });
            json!({
                "step": r.step, "t": r.t, "pose": pose, "vel": vel, "contacts": contacts,
                "present": r.bodies.len().min(nb),
            })
        })
        .collect();
    let plots = plots_2d(records, omega_bodies);
    json!({
        "format": VIEW_FORMAT, "version": 1, "dimension": 2,
        "scene": header.scene, "source": header.source, "dt": header.dt,
        "length_unit": "block", "time_unit": "time unit",
        "warnings": warnings,
        "bodies": bodies,
        "frames": frames,
        "plots": plots_json(&plots, &picked),
    })
}

const PAGE: &str = include_str!("view/viewer.html");
const STYLE: &str = include_str!("view/viewer.css");
const SCRIPT: &str = include_str!("view/viewer.js");

/// The self-contained page for `data`: the template with the style, the script and the data
/// put in place, the data last (so nothing in the style or script is scanned for its
/// placeholder). Every `<` in the data is written `\u003c`, the same string to a JSON reader
/// (a `<` can only occur inside JSON strings), so that no name in it can end or re-open the
/// script element that holds it (`</script>`, or `<!--` followed by `<script`).
pub fn html(data: &Value) -> String {
    let json = data.to_string().replace('<', "\\u003c");
    PAGE.replacen("/*RIGIDREF_CSS*/", STYLE, 1)
        .replacen("/*RIGIDREF_JS*/", SCRIPT, 1)
        .replacen("__RIGIDREF_DATA__", &json, 1)
}
