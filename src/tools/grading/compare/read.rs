//! Reading a trace to compare, of either system, as an untrusted file (docs/grading.md
//! §"Untrusted submissions", §"Refused traces"): a regular file only, counted against a byte
//! limit while it is read, its dimension taken from its header.

use super::two::Trace2;
use crate::rigid3d::trace::{Trace, read_trace};

/// A trace of either system, as read for a comparison.
#[derive(Clone, Debug)]
pub enum AnyTrace {
    /// A 3D trace (mesh bodies).
    Three(Trace),
    /// A 2D trace (the image-block system).
    Two(Trace2),
}

impl AnyTrace {
    /// 3 or 2.
    pub fn dimension(&self) -> u64 {
        match self {
            AnyTrace::Three(_) => 3,
            AnyTrace::Two(_) => 2,
        }
    }
}

/// Reads the trace at `path`: only a regular file (after symbolic links: a FIFO, a device or a
/// folder is an error, unread) of at most `limit` bytes, counted as it is read (`option` raises
/// the limit); a 3D or a 2D trace by its header's `dimension`. Errors name the file and what is
/// wrong (a byte-order mark, a second header, a line that is not a record, …).
pub fn read_trace_any(
    path: &std::path::Path,
    limit: u64,
    option: &'static str,
) -> Result<AnyTrace, String> {
    let name = path.display().to_string();
    let text = crate::common::input::read_regular_text(path, limit, option).map_err(|e| {
        if e.kind() == std::io::ErrorKind::InvalidData && e.to_string().contains("stream did not") {
            format!("{name}: the file is not UTF-8 text: not a trace")
        } else {
            format!("{name}: {e}")
        }
    })?;
    let first = text.lines().next().unwrap_or_default();
    if text.trim().is_empty() {
        return Err(format!("{name}: empty file; not a rigidref trace"));
    }
    let header = crate::common::trace::header_value(first, &name)?;
    match header.get("dimension").and_then(serde_json::Value::as_u64) {
        Some(3) => read_trace(std::io::Cursor::new(text.as_bytes()), &name).map(AnyTrace::Three),
        Some(2) => {
            let mut warnings = Vec::new();
            match crate::tools::viewing::view::read_run_trace(&text, &name, &mut warnings)? {
                crate::tools::viewing::view::RunTrace::Two { header, records } => {
                    Ok(AnyTrace::Two(Trace2 { header, records }))
                }
                crate::tools::viewing::view::RunTrace::Three { .. } => {
                    Err(crate::common::trace::wrong_dimension(&name, 3, 2))
                }
            }
        }
        _ => Err(format!(
            "{name}:1: the header's \"dimension\" must be 2 or 3"
        )),
    }
}

/// The trace at `path` ([`read_trace_any`]) as a trace of `wanted` dimensions (3 or 2); one of
/// the other system is an error saying so (`because` says why that system is wanted: "the
/// scene is 3D", "the reference is 2D").
pub fn read_trace_of(
    path: &std::path::Path,
    wanted: u64,
    because: &str,
    limit: u64,
    option: &'static str,
) -> Result<AnyTrace, String> {
    let trace = read_trace_any(path, limit, option)?;
    if trace.dimension() != wanted {
        let name = path.display().to_string();
        let found = trace.dimension();
        return Err(format!(
            "{}: {because}",
            crate::common::trace::wrong_dimension(&name, found, wanted)
        ));
    }
    Ok(trace)
}

/// Reads a 2D trace within the input limit (`--max-input-mb`); a 3D one, a malformed one or one
/// cut off anywhere but in its last line is an error naming the file (a cut last line is
/// dropped, as the viewer does).
pub fn read_trace2_file(path: &std::path::Path) -> Result<Trace2, String> {
    let limit = crate::common::input::max_input_bytes();
    match read_trace_of(path, 2, "the reference is 2D", limit, "--max-input-mb")? {
        AnyTrace::Two(t) => Ok(t),
        AnyTrace::Three(_) => unreachable!("read_trace_of checked the dimension"),
    }
}

/// Reads a 3D trace within the input limit (`--max-input-mb`), as a regular file.
pub fn read_trace3_file(path: &std::path::Path) -> Result<Trace, String> {
    let limit = crate::common::input::max_input_bytes();
    match read_trace_of(path, 3, "the reference is 3D", limit, "--max-input-mb")? {
        AnyTrace::Three(t) => Ok(t),
        AnyTrace::Two(_) => unreachable!("read_trace_of checked the dimension"),
    }
}
