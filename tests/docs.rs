//! The docs name the tests that check each derivation; those tests must exist.

mod common;

/// Every `tests/FILE.rs::NAME` or `src/…` unit-test reference in docs/*.md names a function that
/// exists in that file.
#[test]
fn every_test_the_docs_name_exists() {
    let root = common::project_root();
    let mut checked = 0;
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        for (at, _) in text.match_indices("tests/") {
            let rest = &text[at..];
            let Some(rs) = rest.find(".rs::") else {
                continue;
            };
            let file = &rest[..rs + 3];
            if file.contains(char::is_whitespace) {
                continue;
            }
            let name: String = rest[rs + 5..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            let source = std::fs::read_to_string(root.join(file))
                .unwrap_or_else(|_| panic!("{}: names missing file {file}", path.display()));
            assert!(
                source.contains(&format!("fn {name}(")),
                "{}: names {file}::{name}, which does not exist",
                path.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 10, "only {checked} references found");
}

/// Every `src/FILE.rs::ITEM` (or `src/FILE.rs::TYPE::METHOD`) a doc names as the implementation of
/// a derivation exists in that file, as a function, type or constant.
#[test]
fn every_function_the_docs_name_exists() {
    let root = common::project_root();
    let mut checked = 0;
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        for (at, _) in text.match_indices("src/") {
            let rest = &text[at..];
            let Some(rs) = rest.find(".rs::") else {
                continue;
            };
            let file = &rest[..rs + 3];
            if file.contains(|c: char| c.is_whitespace() || c == '`') {
                continue;
            }
            let path_text: String = rest[rs + 5..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            let Some(name) = path_text.trim_end_matches(':').rsplit("::").next() else {
                continue;
            };
            let source = std::fs::read_to_string(root.join(file))
                .unwrap_or_else(|_| panic!("{}: names missing file {file}", path.display()));
            let defined = ["fn", "struct", "enum", "const", "type", "trait"]
                .iter()
                .any(|kind| {
                    source.contains(&format!("{kind} {name}("))
                        || source.contains(&format!("{kind} {name}<"))
                        || source.contains(&format!("{kind} {name} "))
                        || source.contains(&format!("{kind} {name}:"))
                        || source.contains(&format!("{kind} {name};"))
                });
            assert!(
                defined,
                "{}: names {file}::{path_text}, which does not exist",
                path.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 20, "only {checked} references found");
}

/// docs/verification.md's table lists every test function in tests/ (the other direction, that
/// every test it names exists, is `every_test_the_docs_name_exists`).
#[test]
fn verification_table_lists_every_test() {
    let root = common::project_root();
    let table = std::fs::read_to_string(root.join("docs/verification.md")).unwrap();
    let mut missing = Vec::new();
    let mut count = 0;
    for entry in std::fs::read_dir(root.join("tests")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
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
            if !table.contains(&format!("tests/{file}::{name}`")) {
                missing.push(format!("tests/{file}::{name}"));
            }
        }
    }
    assert!(count >= 80, "found only {count} tests");
    assert!(
        missing.is_empty(),
        "docs/verification.md does not list: {missing:#?}"
    );
}
