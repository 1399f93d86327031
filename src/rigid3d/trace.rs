//! The trace: the contract between a run and every tool that reads it (comparison, plots,
//! snapshots, grading). JSON Lines, or a flat CSV with the same per-step quantities.
//! The format is defined in docs/trace-format.md; the structs below are its single definition in
//! code, used by both the writer and the reader.

use crate::rigid3d::diagnostics::Energy;
use crate::rigid3d::world::World;
use serde::{Deserialize, Serialize};
use std::io::{BufRead, BufWriter, Write};

pub use crate::common::trace::{FORMAT_NAME, FORMAT_VERSION};
pub use crate::sim::SolverRecord;

/// The first line of a JSON Lines trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TraceHeader {
    /// Always [`FORMAT_NAME`].
    pub format: String,
    /// [`FORMAT_VERSION`].
    pub version: u32,
    /// 3 for mesh bodies, 2 for image-block bodies.
    pub dimension: u32,
    /// The scene's `name` (descriptive: may be absent in a trace read).
    #[serde(default)]
    pub scene: String,
    /// Where the scene came from (descriptive: may be absent in a trace read).
    #[serde(default)]
    pub source: String,
    /// Parameters set on the command line (`--set KEY=VALUE`), as `KEY=VALUE`; the key is
    /// present only when some were given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<String>,
    /// Frame step, s.
    pub dt: f64,
    /// Substeps per frame (descriptive: may be absent in a trace read; then 1).
    #[serde(default = "one")]
    pub substeps: u32,
    /// Gravity, m/s².
    pub gravity: [f64; 3],
    /// The angular integrator's scene name (descriptive: may be absent in a trace read).
    #[serde(default)]
    pub integrator: String,
    /// The collision method's scene name (`vertices`, `complete` or `starter`); absent from version 1
    /// traces, which were all `vertices`.
    #[serde(default = "vertices")]
    pub collision: String,
    /// The contact tangents' scene name (`orthonormal` or `starter`); written only when not
    /// `orthonormal`, so traces of the default are unchanged.
    #[serde(default = "orthonormal", skip_serializing_if = "is_orthonormal")]
    pub tangents: String,
    /// The bodies in index order.
    pub bodies: Vec<TraceBodyInfo>,
}

/// A body's constant properties in the header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TraceBodyInfo {
    /// Name from the scene.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
}

/// One recorded step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TraceRecord {
    /// Frames completed (0 is the initial state).
    pub step: u64,
    /// Time, s.
    pub t: f64,
    /// Per-body state, in header order.
    pub bodies: Vec<BodyState>,
    /// System energy, J.
    pub energy: Energy,
    /// System momentum.
    pub momentum: MomentumRecord,
    /// Contacts found in this step (filled from issue #3 on).
    pub contacts: Vec<ContactRecord>,
    /// The penetration measure after this step, m: the deepest interpenetration of any two
    /// bodies or of a body and the ground, whatever contacts were found
    /// ([`crate::rigid3d::collide::penetration`]). `None` only when read from a version 1 trace.
    #[serde(default)]
    pub penetration: Option<f64>,
    /// What the frame's contact solves did (sweeps, worst residual); absent when it solved none,
    /// and in traces written before issue 16.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<SolverRecord>,
}

fn vertices() -> String {
    "vertices".into()
}

fn orthonormal() -> String {
    "orthonormal".into()
}

fn is_orthonormal(name: &String) -> bool {
    name == "orthonormal"
}

/// A body's state: position (m), rotation rows, velocity (m/s), angular velocity (rad/s, world).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyState {
    /// Centre of mass, m.
    pub x: [f64; 3],
    /// Rotation matrix as a list of rows.
    #[serde(rename = "R")]
    pub rotation: [[f64; 3]; 3],
    /// Linear velocity, m/s.
    pub v: [f64; 3],
    /// Angular velocity in the world frame, rad/s.
    pub omega: [f64; 3],
}

/// System momentum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MomentumRecord {
    /// Linear momentum, kg·m/s.
    pub linear: [f64; 3],
    /// Angular momentum about the world origin, kg·m²/s.
    pub angular: [f64; 3],
    /// Angular momentum about the system's centre of mass, kg·m²/s.
    pub angular_com: [f64; 3],
}

/// A contact: bodies (−1 is the ground), point (m), normal, depth (m), impulses (N·s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    /// Body indices; −1 for the ground.
    pub bodies: [i64; 2],
    /// Contact point, world frame, m.
    pub p: [f64; 3],
    /// Contact normal, world frame.
    pub n: [f64; 3],
    /// Penetration depth, m.
    pub depth: f64,
    /// Normal and two tangent impulses, N·s (force = λ / h).
    pub lambda: [f64; 3],
}

impl TraceHeader {
    /// The header for a world about to run.
    pub fn for_world(world: &World, source: &str) -> TraceHeader {
        TraceHeader {
            format: FORMAT_NAME.into(),
            version: FORMAT_VERSION,
            dimension: 3,
            scene: world.params.name.clone(),
            source: source.into(),
            overrides: Vec::new(),
            dt: world.params.dt,
            substeps: world.params.substeps,
            gravity: world.params.gravity.into(),
            integrator: world.params.integrator.name().into(),
            collision: world.params.collision.name().into(),
            tangents: world.params.tangents.name().into(),
            bodies: world
                .bodies
                .iter()
                .map(|b| TraceBodyInfo {
                    name: b.name.clone(),
                    mass: b.mass,
                })
                .collect(),
        }
    }
}

impl TraceRecord {
    /// The world's current state.
    /// Its contacts are those of the frame's last substep that had any (see
    /// [`contact_records`]).
    pub fn of_world(world: &World) -> TraceRecord {
        let momentum = world.momentum();
        let contacts = contact_records(world);
        TraceRecord {
            step: world.step,
            t: world.time(),
            bodies: world
                .bodies
                .iter()
                .map(|b| BodyState {
                    x: b.x.into(),
                    rotation: std::array::from_fn(|i| std::array::from_fn(|j| b.rotation[(i, j)])),
                    v: b.v.into(),
                    omega: b.omega.into(),
                })
                .collect(),
            energy: world.energy(),
            momentum: MomentumRecord {
                linear: momentum.linear.into(),
                angular: momentum.angular.into(),
                angular_com: momentum.angular_com.into(),
            },
            contacts,
            penetration: Some(world.deepest_penetration()),
            solver: SolverRecord::of(&world.solves),
        }
    }
}

/// The contacts of the last substep of the world's last frame that had contacts, with their
/// impulses (empty when the frame had none). docs/trace-format.md §"Contacts".
pub fn contact_records(world: &World) -> Vec<ContactRecord> {
    let Some(solve) = world.solves.last() else {
        return Vec::new();
    };
    solve
        .contacts
        .iter()
        .zip(&solve.lambda)
        .map(|(c, l)| ContactRecord {
            bodies: [c.body1 as i64, c.body2.map_or(-1, |b| b as i64)],
            p: c.point.into(),
            n: c.frame.n.into(),
            depth: c.depth,
            lambda: [l[0], l[1], l[2]],
        })
        .collect()
}

/// The two trace encodings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TraceFormat {
    /// JSON Lines: a header line, then one line per recorded step.
    Jsonl,
    /// Comma-separated values with one header row; no metadata.
    Csv,
}

#[allow(clippy::large_enum_variant)] // one per trace; the size is irrelevant
enum Sink {
    Jsonl(BufWriter<Box<dyn Write + Send>>),
    Csv(csv::Writer<Box<dyn Write + Send>>),
}

impl Sink {
    fn write(&mut self, record: &TraceRecord) -> std::io::Result<()> {
        match self {
            Sink::Jsonl(w) => {
                serde_json::to_writer(&mut *w, record)?;
                w.write_all(b"\n")
            }
            Sink::Csv(w) => Ok(w.write_record(csv_row(record))?),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::Jsonl(w) => w.flush(),
            Sink::Csv(w) => w.flush(),
        }
    }
}

/// Writes a trace record by record, formatting them on a thread of its own
/// ([`crate::common::writer::BackgroundWriter`]: the bytes are those of writing in place, in
/// order). [`TraceWriter::flush`] waits until everything given so far is written and durable
/// (also on an error path); an output error is returned by the next `write` or `flush`.
pub struct TraceWriter {
    thread: crate::common::writer::BackgroundWriter<TraceRecord>,
}

impl TraceWriter {
    /// Starts a trace on `out`, writing the header (JSON Lines) or the column names (CSV).
    pub fn new(
        out: Box<dyn Write + Send>,
        format: TraceFormat,
        header: &TraceHeader,
    ) -> std::io::Result<TraceWriter> {
        let sink = match format {
            TraceFormat::Jsonl => {
                let mut w = BufWriter::new(out);
                serde_json::to_writer(&mut w, header)?;
                w.write_all(b"\n")?;
                Sink::Jsonl(w)
            }
            TraceFormat::Csv => {
                let mut w = csv::Writer::from_writer(out);
                w.write_record(csv_columns(header.bodies.len()))?;
                Sink::Csv(w)
            }
        };
        Ok(TraceWriter {
            thread: crate::common::writer::BackgroundWriter::new(
                sink,
                |sink: &mut Sink, r: &TraceRecord| sink.write(r),
                Sink::flush,
            ),
        })
    }

    /// Appends one record (queued for the writer thread).
    pub fn write(&mut self, record: TraceRecord) -> std::io::Result<()> {
        self.thread.write(record)
    }

    /// Waits until every record given so far is written, and flushes the file or stream.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.thread.flush()
    }
}

/// CSV column names for `n` bodies (docs/trace-format.md §"CSV").
pub fn csv_columns(n: usize) -> Vec<String> {
    let mut cols: Vec<String> = vec!["step".into(), "t".into()];
    for b in 0..n {
        for q in ["x", "y", "z"] {
            cols.push(format!("b{b}_{q}"));
        }
        for i in 0..3 {
            for j in 0..3 {
                cols.push(format!("b{b}_R{i}{j}"));
            }
        }
        for q in ["vx", "vy", "vz", "wx", "wy", "wz"] {
            cols.push(format!("b{b}_{q}"));
        }
    }
    for q in ["kinetic_linear", "kinetic_angular", "potential", "total"] {
        cols.push(q.into());
    }
    for prefix in ["p", "L", "Lcom"] {
        for axis in ["x", "y", "z"] {
            cols.push(format!("{prefix}_{axis}"));
        }
    }
    cols.push("contacts".into());
    cols.push("penetration".into());
    cols
}

fn csv_row(r: &TraceRecord) -> Vec<String> {
    // Rust's `{}` for f64 prints the shortest string that reads back to the same number.
    let mut row = vec![r.step.to_string(), r.t.to_string()];
    let mut push = |xs: &[f64]| row.extend(xs.iter().map(|x| x.to_string()));
    for b in &r.bodies {
        push(&b.x);
        push(b.rotation.as_flattened());
        push(&b.v);
        push(&b.omega);
    }
    let e = &r.energy;
    push(&[e.kinetic_linear, e.kinetic_angular, e.potential, e.total]);
    push(&r.momentum.linear);
    push(&r.momentum.angular);
    push(&r.momentum.angular_com);
    row.push(r.contacts.len().to_string());
    row.push(r.penetration.map_or(String::new(), |x| x.to_string()));
    row
}

/// A trace read back from JSON Lines.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// The header line.
    pub header: TraceHeader,
    /// The records in file order.
    pub records: Vec<TraceRecord>,
    /// What the reader noticed without refusing the trace: the descriptive header keys
    /// ([`DESCRIPTIVE_KEYS`]) it lacks.
    pub notes: Vec<String>,
}

/// Header keys that only describe the run (nothing is compared from them): a trace written by
/// another simulator may leave them out, and the reader notes it instead of refusing the trace.
pub const DESCRIPTIVE_KEYS: [&str; 4] = ["scene", "source", "integrator", "substeps"];

/// Reads the JSON Lines trace in the file `path`, judged by its size first
/// ([`crate::common::input::open`]); errors name the file (and the line). The golden traces are
/// read with this; `rigidref compare`, `grade` and the Python bindings read a trace through
/// `tools::grading::compare::read_trace_any`, which reads regular files only.
pub fn read_trace_file(path: &std::path::Path) -> Result<Trace, String> {
    let file = crate::common::input::open(path)
        .map_err(|e| format!("{}: cannot open: {e}", path.display()))?;
    read_trace(std::io::BufReader::new(file), &path.display().to_string())
}

/// Reads a 3D JSON Lines trace; errors name the line and what is wrong with it: a byte-order
/// mark, a first line that is not a rigidref header, a 2D trace, a second header line, a NaN
/// (docs/trace-format.md §"Reading rules").
pub fn read_trace(reader: impl BufRead, source: &str) -> Result<Trace, String> {
    let mut lines = reader.lines().enumerate();
    let (_, first) = lines
        .next()
        .ok_or_else(|| format!("{source}: empty trace"))?;
    let first = first.map_err(|e| format!("{source}: {e}"))?;
    let given = crate::common::trace::header_value(&first, source)?;
    let dimension = given.get("dimension").and_then(serde_json::Value::as_u64);
    if dimension != Some(3) {
        return Err(match dimension {
            Some(d @ 2) => crate::common::trace::wrong_dimension(source, d, 3),
            _ => format!("{source}:1: the header's \"dimension\" must be 2 or 3"),
        });
    }
    let header: TraceHeader = serde_json::from_value(given.clone()).map_err(|e| {
        format!(
            "{source}:1: bad header: {}",
            crate::common::trace::json_problem(&e)
        )
    })?;
    let missing: Vec<&str> = DESCRIPTIVE_KEYS
        .into_iter()
        .filter(|k| given.get(k).is_none())
        .collect();
    let notes = if missing.is_empty() {
        Vec::new()
    } else {
        vec![format!(
            "{source}: the header has no {} (descriptive keys; nothing is compared from them)",
            missing.join(", ")
        )]
    };
    let mut records = Vec::new();
    for (i, line) in lines {
        let line = line.map_err(|e| format!("{source}: {e}"))?;
        if line.trim().is_empty() {
            continue; // a trailing newline too many, from a hand-written or concatenated file
        }
        records.push(serde_json::from_str(&line).map_err(|e| {
            // JSON has no NaN or Infinity; writers that print them anyway (Python's json module
            // does) get the reason, not only the column.
            if has_non_finite_token(&line) {
                format!(
                    "{source}:{}: a number is NaN or Infinity (not finite): a trace holds finite numbers",
                    i + 1
                )
            } else if crate::common::trace::is_header_line(&line) {
                crate::common::trace::repeated_header(source, i + 1)
            } else {
                format!(
                    "{source}:{}: not a record: {}",
                    i + 1,
                    crate::common::trace::json_problem(&e)
                )
            }
        })?);
    }
    Ok(Trace {
        header,
        records,
        notes,
    })
}

/// Whether a JSON line holds a bare `NaN`, `Infinity` or `-Infinity` outside strings.
fn has_non_finite_token(line: &str) -> bool {
    let mut in_string = false;
    let mut escaped = false;
    let bytes = line.as_bytes();
    for (k, &c) in bytes.iter().enumerate() {
        if in_string {
            match (escaped, c) {
                (true, _) => escaped = false,
                (false, b'\\') => escaped = true,
                (false, b'"') => in_string = false,
                _ => {}
            }
        } else if c == b'"' {
            in_string = true;
        } else if bytes[k..].starts_with(b"NaN") || bytes[k..].starts_with(b"Infinity") {
            return true;
        }
    }
    false
}

/// The default substep count of a trace header that does not give one.
fn one() -> u32 {
    1
}
