//! `compare-problem` and `grade` match bodies and contacts as `compare` matches bodies (issue 47,
//! found 3; docs/grading.md §"Comparing contact problems"): another numbering of the bodies,
//! contacts in another order, a contact's two bodies the other way round.

use crate::common;

use common::rigidref;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The 2D stack (scenes/blocks/stack.json) run for `time` in `dir`, its trace `ref.jsonl` and its
/// problems in `problems/`; the first problem with contacts and the last.
fn stack(dir: &Path, time: &str) -> (PathBuf, PathBuf) {
    let scene = common::project_root().join("scenes/blocks/stack.json");
    common::assert_success(&rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            time,
            "-q",
            "--out",
            "ref.jsonl",
            "--dump-problems",
            "problems",
        ],
        dir,
    ));
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let with_contacts: Vec<PathBuf> = files
        .into_iter()
        .filter(|p| {
            let v: Value = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
            v["contacts"].as_array().is_some_and(|c| !c.is_empty())
        })
        .collect();
    (
        with_contacts.first().unwrap().clone(),
        with_contacts.last().unwrap().clone(),
    )
}

/// The bodies' new numbers: body i becomes `order[i]`; the starter's numbering scans an image
/// column by column where rigidref scans row by row, so every body may move.
fn renumbering(n: usize) -> Vec<usize> {
    // A fixed permutation: reversed, then the first two swapped.
    let mut order: Vec<usize> = (0..n).rev().collect();
    order.swap(0, 1.min(n - 1));
    order
}

/// A problem file as another simulator might write the same state: bodies renumbered by
/// `order`, contacts in reverse order, every other contact listed with its bodies the other way
/// round (normal flipped, Jacobian blocks swapped, the tangent t = (−n_y, n_x) flipped with it:
/// the tangent rows, b_t, λ_t negated), optionally without geometry.
fn as_another_simulator(problem: &Value, order: &[usize], geometry: bool) -> Value {
    let mut out = problem.clone();
    let bodies = problem["bodies"].as_array().unwrap();
    let mut renumbered = vec![Value::Null; bodies.len()];
    for (i, b) in bodies.iter().enumerate() {
        renumbered[order[i]] = b.clone();
    }
    out["bodies"] = Value::Array(renumbered);
    let mut lambda: Vec<Value> = problem["solution"]["lambda"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    let contacts = out["contacts"].as_array_mut().unwrap();
    for (k, c) in contacts.iter_mut().enumerate() {
        for side in 0..2 {
            let b = c["bodies"][side].as_i64().unwrap();
            if b >= 0 {
                c["bodies"][side] = (order[b as usize] as i64).into();
            }
        }
        if k % 2 == 1 {
            let (b0, b1) = (c["bodies"][0].clone(), c["bodies"][1].clone());
            c["bodies"] = serde_json::json!([b1, b0]);
            let (j0, j1) = (c["jacobian"][0].clone(), c["jacobian"][1].clone());
            c["jacobian"] = serde_json::json!([j1, j0]);
            for side in 0..2 {
                for v in c["jacobian"][side][1].as_array_mut().unwrap() {
                    *v = (-v.as_f64().unwrap()).into();
                }
            }
            c["b"][1] = (-c["b"][1].as_f64().unwrap()).into();
            c["lambda0"][1] = (-c["lambda0"][1].as_f64().unwrap()).into();
            if let Some(n) = c.get_mut("geometry").and_then(|g| g.get_mut("n")) {
                for v in n.as_array_mut().unwrap() {
                    *v = (-v.as_f64().unwrap()).into();
                }
            }
            if let Some(l) = lambda.get_mut(k) {
                l[1] = (-l[1].as_f64().unwrap()).into();
            }
        }
        if !geometry {
            c.as_object_mut().unwrap().remove("geometry");
        }
    }
    contacts.reverse();
    lambda.reverse();
    if let Some(solution) = out.get_mut("solution").and_then(Value::as_object_mut) {
        solution.insert("lambda".into(), Value::Array(lambda));
        solution.remove("criteria");
    }
    out
}

/// The trace `ref.jsonl` with its bodies renumbered by `order` (header and records), as
/// `other.jsonl`.
fn renumbered_trace(dir: &Path, order: &[usize]) {
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            let mut v: Value = serde_json::from_str(l).unwrap();
            let list = v["bodies"].as_array().unwrap().clone();
            let mut moved = vec![Value::Null; list.len()];
            for (i, b) in list.into_iter().enumerate() {
                moved[order[i]] = b;
            }
            v["bodies"] = Value::Array(moved);
            v.to_string()
        })
        .collect();
    std::fs::write(dir.join("other.jsonl"), out.join("\n") + "\n").unwrap();
}

/// A problem of the stack against the same state as another simulator writes it: bodies
/// renumbered, contacts reversed, every other contact's bodies the other way round. With
/// geometry the bodies are found by the contacts' points and the problems agree (the matching
/// and the swapped contacts printed); a body's inverse inertia changed by 25 % is named by the
/// reference's number. Without geometry, `--traces` matches the bodies by the image, as
/// `compare` does, and they agree. `grade` does the same with the submission's trace: a
/// renumbered trace and problem without geometry pass.
#[test]
fn compare_problem_and_grade_match_renumbered_bodies_and_contacts_listed_the_other_way_round() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (first, last) = stack(dir, "2");
    let problem: Value = serde_json::from_str(&std::fs::read_to_string(&last).unwrap()).unwrap();
    let n = problem["bodies"].as_array().unwrap().len();
    assert!(n >= 3 && problem["contacts"].as_array().unwrap().len() >= 3);
    let order = renumbering(n);
    let write = |name: &str, v: &Value| std::fs::write(dir.join(name), v.to_string()).unwrap();
    write("other.json", &as_another_simulator(&problem, &order, true));
    let o = rigidref(
        &["compare-problem", last.to_str().unwrap(), "other.json"],
        dir,
    );
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", common::stderr(&o));
    assert!(
        stdout.contains(
            "bodies matched by their contacts' points: reference body = other file's body: 0 = "
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains("contacts the other file lists with their two bodies the other way round"),
        "{stdout}"
    );
    // The inverse inertia of reference body `k` (a body that is not pinned) changed by 25 %.
    let in_contact = |i: usize| {
        problem["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c["bodies"][0] == i as i64 || c["bodies"][1] == i as i64)
    };
    let k = (0..n)
        .find(|&i| {
            in_contact(i) && problem["bodies"][i]["inverse_mass"][2][2].as_f64().unwrap() > 0.0
        })
        .unwrap();
    let mut changed = as_another_simulator(&problem, &order, true);
    let inertia = &mut changed["bodies"][order[k]]["inverse_mass"][2][2];
    *inertia = (inertia.as_f64().unwrap() * 1.25).into();
    write("changed.json", &changed);
    let o = rigidref(
        &["compare-problem", last.to_str().unwrap(), "changed.json"],
        dir,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains(&format!("first: body {k} inverse mass [2][2]")),
        "{}",
        common::stderr(&o)
    );
    // Without geometry: the traces' matching.
    renumbered_trace(dir, &order);
    write("bare.json", &as_another_simulator(&problem, &order, false));
    let o = rigidref(
        &[
            "compare-problem",
            last.to_str().unwrap(),
            "bare.json",
            "--traces",
            "ref.jsonl",
            "other.jsonl",
        ],
        dir,
    );
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", common::stderr(&o));
    assert!(
        stdout.contains("matched by the traces (by image)"),
        "{stdout}"
    );
    // grade: the renumbered trace and the first problem, renumbered, without geometry.
    let first: Value = serde_json::from_str(&std::fs::read_to_string(&first).unwrap()).unwrap();
    let folder = dir.join("subs/renumbered");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::copy(dir.join("other.jsonl"), folder.join("stack.jsonl")).unwrap();
    std::fs::write(
        folder.join("stack.problem.json"),
        as_another_simulator(&first, &order, false).to_string(),
    )
    .unwrap();
    let scene = common::project_root().join("scenes/blocks/stack.json");
    let o = rigidref(
        &[
            "grade",
            "subs",
            "--scenes",
            scene.to_str().unwrap(),
            "--time",
            "2",
            "--out",
            "out",
        ],
        dir,
    );
    common::assert_success(&o);
    let csv = std::fs::read_to_string(dir.join("out/grade.csv")).unwrap();
    assert!(
        csv.lines()
            .any(|l| l.starts_with("renumbered,stack,first contact problem,pass,")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("renumbered,stack,bodies matched by image,note,")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .all(|l| !l.contains(",fail,") && !l.contains(",refused,")),
        "{csv}"
    );
}

/// The case in 3D: a contact with the ground listed [ground, body] in one file and
/// [body, ground] in the other (the ground is −1) is the same contact, its normal flipped and
/// its Jacobian blocks swapped; it used to be "no contact of the other file matches it".
#[test]
fn compare_problem_matches_a_ground_contact_listed_the_other_way_round() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = common::project_root().join("scenes/box_stack.json");
    common::assert_success(&rigidref(
        &[
            "run",
            scene.to_str().unwrap(),
            "--time",
            "0.05",
            "-q",
            "--out",
            "t.jsonl",
            "--dump-problems",
            "problems",
        ],
        dir,
    ));
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let problem: Value =
        serde_json::from_str(&std::fs::read_to_string(&files[0]).unwrap()).unwrap();
    let mut other = problem.clone();
    let mut swapped = 0;
    for c in other["contacts"].as_array_mut().unwrap() {
        if c["bodies"][1] == -1 || c["bodies"][0] == -1 {
            let (b0, b1) = (c["bodies"][0].clone(), c["bodies"][1].clone());
            c["bodies"] = serde_json::json!([b1, b0]);
            let (j0, j1) = (c["jacobian"][0].clone(), c["jacobian"][1].clone());
            c["jacobian"] = serde_json::json!([j1, j0]);
            for v in c["geometry"]["n"].as_array_mut().unwrap() {
                *v = (-v.as_f64().unwrap()).into();
            }
            swapped += 1;
        }
    }
    assert!(swapped > 0);
    std::fs::write(dir.join("other.json"), other.to_string()).unwrap();
    let o = rigidref(
        &["compare-problem", files[0].to_str().unwrap(), "other.json"],
        dir,
    );
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", common::stderr(&o));
    assert!(stdout.contains("the other way round"), "{stdout}");
}
