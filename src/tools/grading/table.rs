//! The grade table as files: names shown byte for byte, CSV that a spreadsheet does not run,
//! Markdown whose table a name cannot break (docs/grading.md §"Untrusted submissions"); the
//! rows and a submission's verdict.

use std::ffi::OsStr;
use std::path::Path;

/// One row of the grade table.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GradeRow {
    /// The submission folder's name, byte for byte ([`display_name`]: a byte that is not UTF-8
    /// as `\xNN`, a backslash doubled): the submission's identity in the table.
    pub submission: String,
    /// The scene's name.
    pub scene: String,
    /// The observable or quantity (`trace` for the file as a whole).
    pub observable: String,
    /// `pass`, `fail`, `refused` (the trace is too short, degenerate or for other bodies:
    /// [`crate::tools::grading::compare::Refusal`]; or the file or folder is not opened),
    /// `missing`, `unreadable`, or `note` (what the reader should know; never a failure).
    pub result: String,
    /// The figure: the error, the observable's values, or what is wrong with the file.
    pub figure: String,
}

/// A row of the table.
pub(super) fn row(
    submission: &str,
    scene: &str,
    observable: &str,
    result: &str,
    figure: String,
) -> GradeRow {
    GradeRow {
        submission: submission.into(),
        scene: scene.into(),
        observable: observable.into(),
        result: result.into(),
        figure,
    }
}

/// A submission's verdict for a scene: `pass` when every row passes, else the worst result
/// (`missing`, `unreadable`, `refused`, `fail`).
pub fn verdict(rows: &[GradeRow], submission: &str, scene: &str) -> &'static str {
    let mine = rows
        .iter()
        .filter(|r| r.submission == submission && r.scene == scene);
    let mut verdict = "pass";
    for r in mine {
        verdict = match (verdict, r.result.as_str()) {
            (_, "missing") => "missing",
            ("missing", _) => "missing",
            (_, "unreadable") => "unreadable",
            ("unreadable", _) => "unreadable",
            (_, "refused") => "refused",
            ("refused", _) => "refused",
            (_, "fail") => "fail",
            (v, _) => v,
        };
    }
    verdict
}

/// A submission folder's name as the tables show it, and its identity: its bytes, valid UTF-8
/// as it is, a backslash as `\\`, a control character as `\n`, `\t`, `\r` or `\xNN`, a byte
/// that is not UTF-8 as `\xNN`. Two folders whose names differ keep different names (`x\xff`
/// and `x\xfe`), and a name is one line.
pub fn display_name(name: &OsStr) -> String {
    use std::fmt::Write;
    let bytes = name.as_encoded_bytes();
    let mut out = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        for c in chunk.valid().chars() {
            match c {
                '\\' => out.push_str("\\\\"),
                '\n' => out.push_str("\\n"),
                '\t' => out.push_str("\\t"),
                '\r' => out.push_str("\\r"),
                c if c.is_control() => {
                    let mut buf = [0u8; 4];
                    for b in c.encode_utf8(&mut buf).bytes() {
                        let _ = write!(out, "\\x{b:02x}");
                    }
                }
                c => out.push(c),
            }
        }
        for b in chunk.invalid() {
            let _ = write!(out, "\\x{b:02x}");
        }
    }
    out
}

/// The name a submission folder's rows carry ([`display_name`] of its last component).
pub fn submission_name(dir: &Path) -> String {
    dir.file_name()
        .map_or_else(|| display_name(dir.as_os_str()), display_name)
}

/// A cell as CSV may hold it without a spreadsheet taking it for a formula (CSV injection): a
/// text starting with `=`, `+`, `-`, `@`, a tab or a carriage return gets a leading `'`, and so
/// does one starting with `'`, so that the mark can be told from a name's own quote.
pub fn csv_cell(text: &str) -> String {
    match text.chars().next() {
        Some('=' | '+' | '-' | '@' | '\t' | '\r' | '\'') => format!("'{text}"),
        _ => text.to_string(),
    }
}

/// A cell as a Markdown table may hold it: `|` escaped, a line break as a space.
pub fn markdown_cell(text: &str) -> String {
    text.replace('|', "\\|").replace(['\n', '\r'], " ")
}

/// The table as CSV (one row per observable), every cell through [`csv_cell`].
pub fn to_csv(rows: &[GradeRow]) -> Result<String, String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["submission", "scene", "observable", "result", "figure"])
        .map_err(|e| e.to_string())?;
    for r in rows {
        w.write_record(
            [&r.submission, &r.scene, &r.observable, &r.result, &r.figure].map(|c| csv_cell(c)),
        )
        .map_err(|e| e.to_string())?;
    }
    String::from_utf8(w.into_inner().map_err(|e| e.to_string())?).map_err(|e| e.to_string())
}

/// The table as Markdown: the verdict of each submission for each scene, then every row that
/// did not pass; every cell through [`markdown_cell`].
pub fn to_markdown(rows: &[GradeRow], scenes: &[String]) -> String {
    let mut names: Vec<&str> = rows.iter().map(|r| r.submission.as_str()).collect();
    names.dedup();
    let mut out = String::from("| submission |");
    for s in scenes {
        out.push_str(&format!(" {} |", markdown_cell(s)));
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(scenes.len()));
    out.push('\n');
    for n in &names {
        out.push_str(&format!("| {} |", markdown_cell(n)));
        for s in scenes {
            out.push_str(&format!(" {} |", verdict(rows, n, s)));
        }
        out.push('\n');
    }
    let problems: Vec<&GradeRow> = rows.iter().filter(|r| r.result != "pass").collect();
    if !problems.is_empty() {
        out.push_str(
            "\n| submission | scene | observable | result | figure |\n|---|---|---|---|---|\n",
        );
        for r in problems {
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} |\n",
                markdown_cell(&r.submission),
                markdown_cell(&r.scene),
                markdown_cell(&r.observable),
                markdown_cell(&r.result),
                markdown_cell(&r.figure)
            ));
        }
    }
    out
}
