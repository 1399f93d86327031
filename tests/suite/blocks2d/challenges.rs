//! The factory, the penalty option, and the Tetris-tube and nut-bag challenges
//! (docs/blocks2d.md §"Challenges", §"Scaling").

use crate::common;
use common::rigidref;

use rigidref::blocks2d::disc_tree::BLOCK_RADIUS;
use rigidref::blocks2d::image::{ImageSettings, load_image};
use rigidref::blocks2d::params::Params2;
use rigidref::blocks2d::world::World2;

/// The scaling demonstration (docs/blocks2d.md §"Scaling"): `rigidref factory --pieces bricks
/// --bodies 3000` reaches at least 2 000 bodies and 10 000 contacts in a sound pile, and writes the
/// scaling report. Sound: every body dropped (the container, sized for them, never fills), none
/// escaped through the floor or walls, and at the end the deepest overlap is within 10% of a
/// block disc's diameter (a pile that exploded from bodies spawned inside one another, or
/// tunnelled through the floor, would reach the contact count too). The R² of the fit is a
/// measurement of the machine and is reported, not asserted (docs: measured 0.999).
#[test]
fn factory_reaches_two_thousand_bodies_and_ten_thousand_contacts_in_a_sound_pile() {
    let tmp = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(common::rigidref_bin())
        .args([
            "factory", "--pieces", "bricks", "--bodies", "3000", "--quiet", "--out",
        ])
        .arg(tmp.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("report.json")).unwrap())
            .unwrap();
    println!("factory report: {report}");
    assert_eq!(report["dropped"], 3000);
    assert_eq!(report["container_full"], false);
    assert!(report["bodies"].as_u64().unwrap() >= 2001);
    assert!(report["max_contacts"].as_u64().unwrap() >= 10_000);
    assert_eq!(report["outside_container_at_end"], 0);
    assert!(report["deepest_overlap_at_end"].as_f64().unwrap() <= 0.1 * 2.0 * BLOCK_RADIUS);
    // R² is measured and reported; timing is not asserted.
    assert!(report["fit"]["r_squared"].as_f64().is_some());
    assert!(report["retimed_problems"].as_u64().unwrap() >= 90);
    let csv = std::fs::read_to_string(tmp.path().join("scaling.csv")).unwrap();
    assert!(csv.starts_with("step,t,bodies,contacts,pgs_seconds,pgs_cpu_seconds\n"));
    let steps = csv.lines().count() - 1;
    assert_eq!(steps as u64, report["steps"].as_u64().unwrap());
    let retimed = std::fs::read_to_string(tmp.path().join("retimed.csv")).unwrap();
    assert_eq!(
        retimed.lines().count() - 1,
        report["retimed_problems"].as_u64().unwrap() as usize
    );
    assert!(
        std::fs::read_to_string(tmp.path().join("scaling.svg"))
            .unwrap()
            .contains("<svg")
    );
}

/// The starter's penalty springs, kept for comparison, hold the stack up too: softly (the
/// penetration is the weight over the stiffness) and without friction.
#[test]
fn penalty_contact_option_holds_the_stack_up() {
    let dir = common::project_root().join("scenes/blocks");
    let groups = load_image(&dir.join("stack.png"), &ImageSettings::default()).unwrap();
    let params = Params2 {
        contact_model: rigidref::blocks2d::params::ContactModel::Penalty,
        substeps: 10,
        ..Params2::starter()
    };
    let mut world = World2::new(&groups, params);
    common::run(&mut world, 400, |_, _| {});
    let deepest = world.deepest_overlap();
    let bottom = world
        .bodies
        .iter()
        .filter(|b| !b.pinned)
        .map(|b| b.x.y)
        .fold(f64::MIN, f64::max);
    println!("penalty: deepest overlap {deepest:.3} blocks, lowest bar at y = {bottom:.3}");
    // The ground's top row is 38; the bottom bar (rows 34–35, centre 35 − ½) may sink by the
    // springs' deflection under twelve bars (12·16·g / (8 springs · k) ≈ 0.024) plus the disc
    // gap, never through the ground.
    assert!(bottom < 38.0, "fell through");
    assert!(deepest < 0.2, "penetration {deepest}");
}

/// The challenges run: the Tetris tube fills with tetrominoes, and the nut bag's shaking writes
/// its report.
#[test]
fn tetris_tube_and_nut_bag_challenges_run() {
    let Some(dir) = common::blocks2d_assignment() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let out = rigidref(
        &[
            "factory",
            "--container",
            dir.join("tetrisTube.png").to_str().unwrap(),
            "--pieces",
            "tetris",
            "--piece-scale",
            "4",
            "--bodies",
            "20",
            "--batch",
            "1",
            "--interval",
            "2",
            "--quiet",
            "--out",
            tmp.path().to_str().unwrap(),
        ],
        &common::project_root(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("report.json")).unwrap())
            .unwrap();
    assert_eq!(report["bodies"], 8 + 20);
    assert!(report["max_contacts"].as_u64().unwrap() > 0);
    let csv = tmp.path().join("nuts.csv");
    let out = rigidref(
        &[
            "run",
            dir.join("nuts3.png").to_str().unwrap(),
            "--time",
            "2",
            "--every",
            "10",
            "--gravity",
            "10",
            "--shake",
            "0:3,0:0:1",
            "--nut-report",
            csv.to_str().unwrap(),
            "--quiet",
            "--out",
            tmp.path().join("t.jsonl").to_str().unwrap(),
        ],
        &common::project_root(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "t,mean_height_heaviest_fifth,mean_height_others,heaviest_fraction_in_upper_half"
    );
    assert_eq!(lines.len(), 1 + 4);
    // The container was shaken: its recorded velocity is not zero.
    let trace = std::fs::read_to_string(tmp.path().join("t.jsonl")).unwrap();
    let last: serde_json::Value = serde_json::from_str(trace.lines().last().unwrap()).unwrap();
    assert!(last["bodies"][0]["v"][0].as_f64().unwrap().abs() > 0.1);
}
