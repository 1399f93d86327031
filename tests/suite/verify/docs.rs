//! The docs name the tests that check each derivation; those tests must exist.

use crate::common;

/// A reference `DIR/FILE.rs::ITEM` (or `DIR/FILE.rs::TYPE::METHOD`) in a doc.
struct Reference {
    /// The doc it is in.
    doc: std::path::PathBuf,
    /// `DIR/FILE.rs`, relative to the project root.
    file: String,
    /// What follows `::`.
    item: String,
    /// The source of `file`.
    source: String,
}

impl Reference {
    /// The last segment of `item`: the function, type or constant named.
    fn name(&self) -> &str {
        self.item.rsplit("::").next().unwrap_or(&self.item)
    }
}

/// Every reference into `dir` (`"tests/"` or `"src/"`) in docs/*.md. Panics naming the doc when
/// a referenced file does not exist.
fn references(dir: &str) -> Vec<Reference> {
    let root = common::project_root();
    let mut found = Vec::new();
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let doc = entry.unwrap().path();
        if doc.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let text = std::fs::read_to_string(&doc).unwrap();
        for (at, _) in text.match_indices(dir) {
            let rest = &text[at..];
            let Some(rs) = rest.find(".rs::") else {
                continue;
            };
            let file = &rest[..rs + 3];
            if file.contains(|c: char| c.is_whitespace() || c == '`') {
                continue;
            }
            let item: String = rest[rs + 5..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            let source = std::fs::read_to_string(root.join(file))
                .unwrap_or_else(|_| panic!("{}: names missing file {file}", doc.display()));
            found.push(Reference {
                doc: doc.clone(),
                file: file.to_string(),
                item: item.trim_end_matches(':').to_string(),
                source,
            });
        }
    }
    found
}

/// Every `tests/FILE.rs::NAME` in docs/*.md names a test function that exists in that file.
#[test]
fn every_test_the_docs_name_exists() {
    let found = references("tests/");
    for r in &found {
        assert!(
            r.source.contains(&format!("fn {}(", r.name())),
            "{}: names {}::{}, which does not exist",
            r.doc.display(),
            r.file,
            r.item
        );
    }
    assert!(found.len() >= 10, "only {} references found", found.len());
}

/// Every `src/FILE.rs::ITEM` (or `src/FILE.rs::TYPE::METHOD`) a doc names as the implementation of
/// a derivation exists in that file, as a function, type or constant.
#[test]
fn every_function_the_docs_name_exists() {
    let found = references("src/");
    for r in &found {
        let name = r.name();
        let defined = ["fn", "struct", "enum", "const", "type", "trait"]
            .iter()
            .any(|kind| {
                ["(", "<", " ", ":", ";"]
                    .iter()
                    .any(|after| r.source.contains(&format!("{kind} {name}{after}")))
            });
        assert!(
            defined,
            "{}: names {}::{}, which does not exist",
            r.doc.display(),
            r.file,
            r.item
        );
    }
    assert!(found.len() >= 20, "only {} references found", found.len());
}

/// docs/verification.md's table lists every test function under tests/ (the other direction, that
/// every test it names exists, is `every_test_the_docs_name_exists`).
#[test]
fn verification_table_lists_every_test() {
    let root = common::project_root();
    let table = std::fs::read_to_string(root.join("docs/verification.md")).unwrap();
    let mut missing = Vec::new();
    let mut count = 0;
    let mut files = Vec::new();
    let mut folders = vec![root.join("tests")];
    while let Some(dir) = folders.pop() {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    for path in files {
        let file = path
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let lines: Vec<String> = std::fs::read_to_string(&path)
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        for (i, line) in lines.iter().enumerate() {
            let trimmed = line.trim_start();
            let Some(rest) = trimmed.strip_prefix("fn ") else {
                continue;
            };
            let is_test = lines[i.saturating_sub(3)..i]
                .iter()
                .any(|l| l.contains("#[test]"));
            if !is_test {
                continue;
            }
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            count += 1;
            if !table.contains(&format!("{file}::{name}`")) {
                missing.push(format!("{file}::{name}"));
            }
        }
    }
    assert!(count >= 80, "found only {count} tests");
    assert!(
        missing.is_empty(),
        "docs/verification.md does not list: {missing:#?}"
    );
}
