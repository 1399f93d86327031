//! What the traces of both systems share: the header's format name and version
//! (docs/trace-format.md).

/// Value of the header's `format` key.
pub const FORMAT_NAME: &str = "rigidref-trace";
/// Value of the header's `version` key; raised on any incompatible change. Version 2 (issue 13):
/// 3D headers name the `collision` method, 3D records carry `penetration`, and a 3D contact's
/// point may be a manifold point rather than a vertex (`collision: complete`).
pub const FORMAT_VERSION: u32 = 2;

/// Why a JSON text could not be read, in words: what the problem is and where, never serde's
/// bare message ("expected value at line 1 column 1"), which names neither.
pub fn json_problem(e: &serde_json::Error) -> String {
    use serde_json::error::Category;
    let at = format!("line {}, column {}", e.line(), e.column());
    let message = e.to_string();
    if message.contains("recursion limit exceeded") {
        return format!(
            "its arrays and objects are nested more than 127 deep (at {at}); rigidref reads \
             at most 127 levels"
        );
    }
    match e.classify() {
        Category::Eof => format!("it ends before its JSON is complete (at {at}): cut off?"),
        Category::Syntax => format!("it is not JSON (a syntax error at {at})"),
        // What a value means is wrong (a missing key, a wrong type or length): serde names it.
        Category::Data => message,
        Category::Io => format!("it could not be read ({message})"),
    }
}

/// The header line of a trace of either system, read as far as both systems share it: no
/// UTF-8 byte-order mark, JSON of at most 127 levels, `format` [`FORMAT_NAME`], a `version`
/// from 1 to [`FORMAT_VERSION`]. Errors name `source` and line 1 and say what is wrong
/// (docs/trace-format.md §"Reading rules").
pub fn header_value(first_line: &str, source: &str) -> Result<serde_json::Value, String> {
    if first_line.starts_with('\u{feff}') {
        return Err(format!(
            "{source}:1: the file starts with a UTF-8 byte-order mark (BOM), which JSON does not \
             allow; write it without one (Python: encoding=\"utf-8\", not \"utf-8-sig\"; \
             Java: no BOM is written by default)"
        ));
    }
    let value: serde_json::Value = serde_json::from_str(first_line).map_err(|e| {
        format!(
            "{source}:1: not a rigidref trace: its first line is not a JSON header: {}",
            json_problem(&e)
        )
    })?;
    if value.get("format").and_then(serde_json::Value::as_str) != Some(FORMAT_NAME) {
        return Err(format!(
            "{source}:1: not a rigidref trace (its header has no \"format\": \"{FORMAT_NAME}\")"
        ));
    }
    let version = value.get("version").and_then(serde_json::Value::as_u64);
    if !version.is_some_and(|v| (1..=u64::from(FORMAT_VERSION)).contains(&v)) {
        let given = value
            .get("version")
            .map_or("none".to_string(), |v| v.to_string());
        return Err(format!(
            "{source}:1: trace version {given}; this rigidref reads version 1 to {FORMAT_VERSION}"
        ));
    }
    Ok(value)
}

/// Whether a line of a trace is a header line (`"format": "rigidref-trace"`): a second one in a
/// file is two traces written into one, which the readers name.
pub fn is_header_line(line: &str) -> bool {
    line.contains("\"format\"")
        && serde_json::from_str::<serde_json::Value>(line)
            .is_ok_and(|v| v.get("format").and_then(serde_json::Value::as_str) == Some(FORMAT_NAME))
}

/// The message for a second header at `line` (1-based) of `source`.
pub fn repeated_header(source: &str, line: usize) -> String {
    format!(
        "{source}:{line}: a second header line (a trace has one, its first line): two traces \
         written into one file?"
    )
}

/// The message for a trace of `found` dimensions (2 or 3) where one of `wanted` is read.
pub fn wrong_dimension(source: &str, found: u64, wanted: u64) -> String {
    format!(
        "{source}: a {found}D trace where a {wanted}D one is compared (its header says \"dimension\": {found})"
    )
}
