//! Fresh runs of the canonical scenes against golden/ (docs/verification.md §"Golden traces").

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::verify::golden::{
    Tolerances, canonical_scenes, compare, golden_path, read_golden, record,
};

#[test]
fn canonical_scenes_match_their_golden_traces() {
    let root = common::project_root();
    let scenes = canonical_scenes(&root.join("scenes")).unwrap();
    assert!(scenes.len() >= 10);
    let mut failures = Vec::new();
    for path in &scenes {
        let source = format!("scenes/{}", path.file_name().unwrap().to_string_lossy());
        let golden = read_golden(&golden_path(&root.join("golden"), path)).unwrap_or_else(|e| {
            panic!("{e} (run `rigidref golden --update` after adding a scene)")
        });
        let fresh = record(&load_scene(path).unwrap(), &source).unwrap();
        assert_eq!(fresh.header, golden.header, "{source}: the header differs");
        let mismatches = compare(&golden, &fresh, &Tolerances::default());
        println!(
            "{source}: {} records, {} mismatches",
            golden.records.len(),
            mismatches.len()
        );
        if let Some(first) = mismatches.first() {
            failures.push(format!(
                "{source}: {} mismatches, first {first}",
                mismatches.len()
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn golden_comparison_notices_a_change_in_any_quantity() {
    let root = common::project_root();
    let path = root.join("scenes/collision.json");
    let golden = read_golden(&golden_path(&root.join("golden"), &path)).unwrap();
    let tolerances = Tolerances::default();
    assert!(compare(&golden, &golden, &tolerances).is_empty());
    // One part in 1e6 of one coordinate, one contact impulse, one record dropped.
    let mut moved = golden.clone();
    moved.records[50].bodies[1].x[2] *= 1.0 + 1e-6;
    let m = compare(&golden, &moved, &tolerances);
    assert_eq!(m.len(), 1, "{m:?}");
    assert_eq!(m[0].quantity, "bodies[1].x[2]");
    let mut pushed = golden.clone();
    let (record, contact) = pushed
        .records
        .iter()
        .enumerate()
        .find_map(|(i, r)| {
            r.contacts
                .iter()
                .position(|c| c.lambda[0] > 1.0)
                .map(|c| (i, c))
        })
        .expect("a pressed contact");
    pushed.records[record].contacts[contact].lambda[0] *= 1.0 + 1e-4;
    assert_eq!(compare(&golden, &pushed, &tolerances).len(), 1);
    let mut short = golden.clone();
    short.records.pop();
    assert!(
        compare(&golden, &short, &tolerances)
            .iter()
            .any(|m| m.quantity == "number of records")
    );
}
