//! No import circle (docs/architecture.md §"The tree"): no module of the library imports a module
//! that imports it back, file by file and folder by folder. The imports are read from the source
//! text: every `crate::a::b` and `super::a` path (and each head of a `::{a, b}` group) outside
//! comments and `#[cfg(test)]` code, resolved to the longest module path that exists. A module and
//! its own ancestors and descendants do not count (a folder's mod.rs re-exports its files, and
//! the files use what it declares).

use crate::common;
use std::collections::{BTreeMap, BTreeSet};

/// The library's modules by path (`rigid3d::collide::ground`), with their source. The binary's
/// `main.rs` and `cli/` use the library from outside (`rigidref::…`) and are not part of it.
fn modules() -> BTreeMap<String, String> {
    crate_modules(false)
}

/// The binary's modules (`main.rs` as the crate root, `cli::run`, `cli::render::render3d`, …):
/// its `crate::` is the binary, and the library is reached as `rigidref::`, not an edge here.
fn binary_modules() -> BTreeMap<String, String> {
    crate_modules(true)
}

/// The modules of the library (`binary` false: every file of src/ but `main.rs` and `cli/`) or
/// of the binary (`binary` true: `main.rs` and `cli/`).
fn crate_modules(binary: bool) -> BTreeMap<String, String> {
    let src = common::project_root().join("src");
    let mut out = BTreeMap::new();
    let mut folders = vec![src.clone()];
    while let Some(dir) = folders.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let rel = path
                .strip_prefix(&src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            let of_binary = rel == "main.rs" || rel == "cli" || rel.starts_with("cli/");
            if dir == src && of_binary != binary {
                continue;
            }
            if path.is_dir() {
                folders.push(path);
            } else if let Some(stem) = rel.strip_suffix(".rs") {
                let mut parts: Vec<&str> = stem.split('/').collect();
                if parts.last() == Some(&"mod") || parts == ["lib"] || parts == ["main"] {
                    parts.pop();
                }
                out.insert(parts.join("::"), std::fs::read_to_string(&path).unwrap());
            }
        }
    }
    out
}

/// The source without line comments and without its `#[cfg(test)]` tail.
fn code(source: &str) -> String {
    let source = source.split("#[cfg(test)]").next().unwrap_or("");
    source
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths after `prefix` (`crate::` or `super::`) in `code`: `a::b::c`, and for a group
/// `a::{b, c::d}` the paths `a::b` and `a::c::d`.
fn paths_after(code: &str, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (at, _) in code.match_indices(prefix) {
        if code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &code[at + prefix.len()..];
        let path: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
            .collect();
        let head = path.trim_end_matches(':').to_string();
        if path.ends_with("::") && rest[path.len()..].starts_with('{') {
            let group = &rest[path.len() + 1..];
            let group = &group[..group.find('}').unwrap_or(group.len())];
            for item in group.split(',') {
                let item: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                    .collect();
                if !item.is_empty() {
                    out.push(format!("{head}::{item}"));
                }
            }
        } else if !head.is_empty() {
            out.push(head);
        }
    }
    out
}

/// The longest prefix of `path` that is a module.
fn resolve(path: &str, modules: &BTreeMap<String, String>) -> Option<String> {
    let segments: Vec<&str> = path.split("::").collect();
    (1..=segments.len())
        .rev()
        .map(|n| segments[..n].join("::"))
        .find(|m| modules.contains_key(m))
}

/// Whether one of the two module paths is the other or contains it.
fn related(a: &str, b: &str) -> bool {
    a == b
        || a.starts_with(&format!("{b}::"))
        || b.starts_with(&format!("{a}::"))
        || a.is_empty()
        || b.is_empty()
}

/// Module → the modules it imports.
fn imports(modules: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, source) in modules {
        let code = code(source);
        // `super` is the module's parent (for a folder's mod.rs, too: the folder's parent).
        let mut parent: Vec<&str> = module.split("::").collect();
        parent.pop();
        let mut targets = BTreeSet::new();
        for path in paths_after(&code, "crate::") {
            targets.extend(resolve(&path, modules));
        }
        for path in paths_after(&code, "super::") {
            let full = parent
                .iter()
                .copied()
                .chain(path.split("::"))
                .collect::<Vec<_>>()
                .join("::");
            targets.extend(resolve(&full, modules));
        }
        edges.insert(
            module.clone(),
            targets
                .into_iter()
                .filter(|t| !related(module, t))
                .collect(),
        );
    }
    edges
}

/// The strongly connected components with more than one member (Tarjan's algorithm).
fn circles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        edges: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on_stack.insert(v);
        let edges = s.edges;
        for w in edges.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut s = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in edges.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.found
}

/// The import graph with every module replaced by its first `depth` path segments (its folder at
/// that depth; a shallower module stays itself).
fn at_depth(
    edges: &BTreeMap<String, BTreeSet<String>>,
    depth: usize,
) -> BTreeMap<String, BTreeSet<String>> {
    let cut = |m: &str| m.split("::").take(depth).collect::<Vec<_>>().join("::");
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, tos) in edges {
        let a = cut(from);
        let entry = out.entry(a.clone()).or_default();
        for to in tos {
            let b = cut(to);
            if !related(&a, &b) {
                entry.insert(b);
            }
        }
    }
    out
}

#[test]
fn no_module_imports_a_module_that_imports_it_back() {
    let modules = modules();
    assert!(modules.len() > 50, "only {} modules found", modules.len());
    let edges = imports(&modules);
    // The reader sees the imports it must: a known edge of each kind.
    assert!(
        edges["rigid3d::world"].contains("solve"),
        "{:?}",
        edges["rigid3d::world"]
    );
    assert!(edges["rigid3d::collide::ellipsoid"].contains("rigid3d::collide::vertex_contact"));
    let deepest = modules.keys().map(|m| m.split("::").count()).max().unwrap();
    let mut found = Vec::new();
    for depth in 1..=deepest {
        for circle in circles(&at_depth(&edges, depth)) {
            found.push(format!("depth {depth}: {}", circle.join(" ↔ ")));
        }
    }
    found.dedup();
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

/// The checker finds a circle when there is one: two modules that import each other, and three
/// in a ring, at file and at folder level.
#[test]
fn the_import_checker_finds_a_planted_circle() {
    let mut modules: BTreeMap<String, String> = BTreeMap::new();
    modules.insert("a".into(), "use crate::b::x;".into());
    modules.insert("b".into(), "use crate::c::{y, z};".into());
    modules.insert("c".into(), "fn f() { crate::a::g(); }".into());
    modules.insert("d".into(), "mod e;".into());
    modules.insert("d::e".into(), "use super::f::h;".into());
    modules.insert("d::f".into(), "// use crate::d::e;\nuse crate::a;".into());
    let edges = imports(&modules);
    assert_eq!(
        circles(&edges),
        vec![vec!["a".to_string(), "b".into(), "c".into()]]
    );
    assert!(edges["d::e"].contains("d::f"), "{:?}", edges["d::e"]);
    assert!(
        !edges["d::f"].contains("d::e"),
        "a comment is not an import"
    );
    // A circle between folders that no two files close: x imports d::e, d::f imports x.
    let mut folders: BTreeMap<String, String> = BTreeMap::new();
    folders.insert("x".into(), "use crate::d::e::k;".into());
    folders.insert("d".into(), "mod e; mod f;".into());
    folders.insert("d::e".into(), "pub fn k() {}".into());
    folders.insert("d::f".into(), "use crate::x;".into());
    let edges = imports(&folders);
    assert!(circles(&edges).is_empty(), "{edges:?}");
    assert_eq!(
        circles(&at_depth(&edges, 1)),
        vec![vec!["d".to_string(), "x".into()]]
    );
}

/// The binary's command-line modules have no import circle either (`cli::args` ↔ `cli::args2d`
/// and `cli::common` ↔ `cli::run` were the last two): each command's module stays a leaf of the
/// shared argument and helper modules.
#[test]
fn no_cli_module_imports_a_module_that_imports_it_back() {
    let modules = binary_modules();
    assert!(
        modules.contains_key("cli::run") && modules.contains_key("cli::render::render3d"),
        "{:?}",
        modules.keys().collect::<Vec<_>>()
    );
    let edges = imports(&modules);
    // The reader sees the binary's imports: `super::` in a file of cli/ and `crate::cli::` in a
    // file of a folder below it.
    assert!(
        edges["cli::view"].contains("cli::run"),
        "{:?}",
        edges["cli::view"]
    );
    assert!(edges["cli::render::render3d"].contains("cli::run"));
    let deepest = modules.keys().map(|m| m.split("::").count()).max().unwrap();
    let mut found = Vec::new();
    for depth in 1..=deepest {
        for circle in circles(&at_depth(&edges, depth)) {
            found.push(format!("depth {depth}: {}", circle.join(" ↔ ")));
        }
    }
    found.dedup();
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}
