//! Submissions as untrusted input (issue 47, found 6; docs/grading.md §"Untrusted
//! submissions"): names kept byte for byte and escaped, folders that link out, files that are
//! not files, a time beyond the maximum.

use crate::common;

use common::rigidref;
use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;

fn projectile() -> String {
    common::project_root()
        .join("scenes/projectile.json")
        .display()
        .to_string()
}

/// The projectile's 1 s reference trace in `dir` as `good.jsonl`, and a copy with gravity's
/// effect removed from every record after the first (its velocity frozen), `bad.jsonl`, which
/// fails trajectory mode.
fn traces(dir: &Path) {
    common::assert_success(&rigidref(
        &[
            "run",
            &projectile(),
            "--time",
            "1",
            "-q",
            "--out",
            "good.jsonl",
        ],
        dir,
    ));
    let text = std::fs::read_to_string(dir.join("good.jsonl")).unwrap();
    let mut lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let v0 = lines[1]["bodies"][0]["v"].clone();
    let x0: Vec<f64> = serde_json::from_value(lines[1]["bodies"][0]["x"].clone()).unwrap();
    for r in lines.iter_mut().skip(1) {
        let t = r["t"].as_f64().unwrap();
        let v: Vec<f64> = serde_json::from_value(v0.clone()).unwrap();
        r["bodies"][0]["v"] = v0.clone();
        r["bodies"][0]["x"] =
            serde_json::json!([x0[0] + v[0] * t, x0[1] + v[1] * t, x0[2] + v[2] * t]);
    }
    let out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    std::fs::write(dir.join("bad.jsonl"), out.join("\n") + "\n").unwrap();
}

/// `grade subs --scenes projectile --time 1 --out out` in `dir`: its grade.csv rows and grade.md.
fn grade(dir: &Path, extra: &[&str]) -> (Vec<Vec<String>>, String) {
    let p = projectile();
    let mut args = vec![
        "grade", "subs", "--scenes", &p, "--time", "1", "--out", "out",
    ];
    args.extend_from_slice(extra);
    let o = rigidref(&args, dir);
    common::assert_success(&o);
    let mut reader = csv::Reader::from_path(dir.join("out/grade.csv")).unwrap();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (
        rows,
        std::fs::read_to_string(dir.join("out/grade.md")).unwrap(),
    )
}

/// Two folders whose names differ only in a byte that is not UTF-8 (`x\xff` passing, `x\xfe`
/// failing) are two submissions, each with its own verdict (they used to merge into one row,
/// "fail"); a `|` and a newline in a name do not break the Markdown table; a name that is a
/// spreadsheet formula (`=HYPERLINK(…)`, `+1`, `-1`, `@SUM(…)`) is not one in the CSV; a
/// backslash keeps `x\\xff` (typed) apart from `x\xff` (the byte).
#[test]
fn grade_keeps_names_byte_for_byte_and_escapes_them_in_markdown_and_csv() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    traces(dir);
    let subs = dir.join("subs");
    let names: [(&[u8], &str); 8] = [
        (b"x\xff", "good.jsonl"),
        (b"x\xfe", "bad.jsonl"),
        (b"x\\xff", "good.jsonl"),
        (b"a|b", "good.jsonl"),
        (b"line\nbreak", "good.jsonl"),
        (b"=HYPERLINK(\"evil.example\",\"x\")", "good.jsonl"),
        (b"+1", "bad.jsonl"),
        (b"@SUM(A1)", "good.jsonl"),
    ];
    for (name, trace) in names {
        let folder = subs.join(OsStr::from_bytes(name));
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::copy(dir.join(trace), folder.join("projectile.jsonl")).unwrap();
    }
    let (rows, markdown) = grade(dir, &[]);
    let verdict = |name: &str| -> String {
        let mine: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == name).collect();
        assert!(!mine.is_empty(), "no rows for {name:?}: {rows:?}");
        if mine.iter().any(|r| r[3] == "fail") {
            "fail"
        } else {
            "pass"
        }
        .to_string()
    };
    assert_eq!(verdict("x\\xff"), "pass");
    assert_eq!(verdict("x\\xfe"), "fail");
    assert_eq!(verdict("x\\\\xff"), "pass");
    assert_eq!(verdict("a|b"), "pass");
    assert_eq!(verdict("line\\nbreak"), "pass");
    // In the CSV, a formula's first character is preceded by a quote.
    assert_eq!(verdict("'=HYPERLINK(\"evil.example\",\"x\")"), "pass");
    assert_eq!(verdict("'+1"), "fail");
    assert_eq!(verdict("'@SUM(A1)"), "pass");
    assert!(
        rows.iter()
            .all(|r| r.iter().all(|c| !c.starts_with(['=', '+', '-', '@']))),
        "{rows:?}"
    );
    // The Markdown: one line per submission, the pipe escaped.
    let table: Vec<&str> = markdown
        .lines()
        .take_while(|l| !l.is_empty())
        .skip(2)
        .collect();
    assert_eq!(table.len(), 8, "{markdown}");
    for line in &table {
        assert_eq!(
            line.matches('|').count() - line.matches("\\|").count(),
            3,
            "{line}"
        );
    }
    assert!(markdown.contains("| a\\|b | pass |"), "{markdown}");
    assert!(markdown.contains("| x\\xff | pass |"), "{markdown}");
    assert!(markdown.contains("| x\\xfe | fail |"), "{markdown}");
    assert!(markdown.contains("| line\\nbreak | pass |"), "{markdown}");
}

/// A submission folder is judged like a file: a symbolic link to a folder outside the
/// submissions folder is refused for every scene without being read (one to /etc made grade
/// look for /etc/projectile.jsonl), a link to another folder inside is followed, and the other
/// submissions are graded.
#[test]
fn grade_refuses_a_submission_folder_that_links_out_of_the_submissions_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    traces(dir);
    let subs = dir.join("subs");
    for name in ["good", "outside"] {
        std::fs::create_dir_all(if name == "outside" {
            dir.join(name)
        } else {
            subs.join(name)
        })
        .unwrap();
    }
    std::fs::copy(dir.join("good.jsonl"), subs.join("good/projectile.jsonl")).unwrap();
    std::fs::copy(dir.join("good.jsonl"), dir.join("outside/projectile.jsonl")).unwrap();
    std::os::unix::fs::symlink(dir.join("outside"), subs.join("link_out")).unwrap();
    std::os::unix::fs::symlink("/etc", subs.join("etc")).unwrap();
    std::os::unix::fs::symlink("good", subs.join("link_in")).unwrap();
    let (rows, _) = grade(dir, &[]);
    for name in ["link_out", "etc"] {
        let mine: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == name).collect();
        assert_eq!(mine.len(), 1, "{rows:?}");
        assert_eq!(mine[0][3], "refused");
        assert!(
            mine[0][4].contains(
                "the submission folder is a symbolic link leaving the submissions folder"
            ),
            "{:?}",
            mine[0]
        );
    }
    for name in ["good", "link_in"] {
        assert!(
            rows.iter()
                .filter(|r| r[0] == name)
                .all(|r| r[3] == "pass" || r[3] == "note"),
            "{rows:?}"
        );
    }
}

/// `compare` reads its files by grade's rules: a FIFO is refused without being opened for
/// reading (it used to hang), /dev/zero without being read (5 GB in 10 s before), each with exit
/// status 2 and the reason; a file whose metadata gives no size but which holds more than the
/// limit (/proc/self/maps, size 0) is stopped by counting what is read.
#[test]
fn compare_refuses_a_fifo_and_dev_zero_unread_and_counts_what_it_reads() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    traces(dir);
    let made = std::process::Command::new("mkfifo")
        .arg(dir.join("fifo.jsonl"))
        .status()
        .unwrap();
    assert!(made.success());
    for other in ["fifo.jsonl", "/dev/zero"] {
        let start = std::time::Instant::now();
        let o = rigidref(&["compare", "good.jsonl", other], dir);
        let stderr = common::stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{other}: {stderr}");
        assert!(
            stderr.contains("not a regular file (a FIFO, a device or a folder); not read"),
            "{stderr}"
        );
        // Refused from its metadata: no wait for a writer, no reading.
        assert!(start.elapsed().as_secs() < 30, "{other}");
    }
    // The reference is judged the same way.
    let o = rigidref(&["compare", "fifo.jsonl", "good.jsonl"], dir);
    assert_eq!(o.status.code(), Some(2));
    let o = rigidref(
        &[
            "compare",
            "/proc/self/maps",
            "good.jsonl",
            "--max-input-mb",
            "0",
        ],
        dir,
    );
    let stderr = common::stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("more than the limit of 0 bytes was read (raise it with --max-input-mb)"),
        "{stderr}"
    );
}

/// `grade --time` is bounded (the reference keeps every step in memory): 1e9 s is refused at
/// once with the maximum named; `help compare` lists the input limits under their own heading,
/// not the 2D scenes'.
#[test]
fn grade_refuses_a_time_beyond_its_maximum_and_help_names_the_input_limits() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::create_dir_all(dir.join("subs/a")).unwrap();
    let p = projectile();
    let start = std::time::Instant::now();
    let o = rigidref(
        &[
            "grade", "subs", "--scenes", &p, "--time", "1e9", "--out", "out",
        ],
        dir,
    );
    let stderr = common::stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("projectile: --time 1000000000 is ")
            && stderr.contains("steps of 0.01; grade runs a scene for at most 200000 steps"),
        "{stderr}"
    );
    assert!(start.elapsed().as_secs() < 30);
    let o = rigidref(&["help", "compare"], dir);
    let help = String::from_utf8_lossy(&o.stdout).to_string();
    let heading = help
        .lines()
        .take_while(|l| !l.contains("--max-input-mb"))
        .filter(|l| !l.starts_with(' ') && l.ends_with(':'))
        .last()
        .unwrap_or_default()
        .to_string();
    assert_eq!(heading, "Input limits (every command):", "{help}");
    assert!(!help.contains("2D scenes"), "{help}");
}
