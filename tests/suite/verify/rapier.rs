//! rigidref against a rapier3d mirror of the same scene, through observables
//! (docs/verification.md §"rapier3d"; tolerances and expected differences in
//! src/verify/references/compare.rs, printed with each result).

use crate::common;

use rigidref::rigid3d::scene::load_scene;
use rigidref::verify::references::compare::{Observable, compare, record_rapier, record_rigidref};

fn observables(scene_file: &str, seconds: f64) -> Vec<Observable> {
    let scene = load_scene(&common::project_root().join("scenes").join(scene_file)).unwrap();
    let steps = (seconds / scene.params.dt).round() as u64;
    let ours = record_rigidref(&scene, steps).unwrap();
    let theirs = record_rapier(&scene, steps).unwrap();
    let out = compare(&scene, &ours, &theirs);
    for o in &out {
        println!(
            "{scene_file}: {}: rigidref {:.5}, rapier3d {:.5}, reference {:?}, tolerance {:?} → {}",
            o.name,
            o.rigidref,
            o.rapier,
            o.reference,
            o.tolerance,
            if o.passed { "ok" } else { "DIFFERS" }
        );
    }
    out
}

fn find<'a>(o: &'a [Observable], name: &str) -> &'a Observable {
    o.iter()
        .find(|o| o.name.starts_with(name))
        .unwrap_or_else(|| panic!("no {name} in {o:?}"))
}

#[test]
fn sphere_drop_first_contact_and_rest_height_agree_with_rapier() {
    let o = observables("sphere_drop.json", 5.0);
    let contact = find(&o, "time of first contact");
    assert!(contact.passed && (contact.rigidref - contact.rapier).abs() <= 0.01 + 1e-12);
    let rest = find(&o, "rest height");
    // 2% of the ball's radius (0.5 m).
    assert!(rest.passed && (rest.rigidref - rest.rapier).abs() <= 0.02 * 0.5);
}

#[test]
fn sliding_box_stopping_distance_agrees_with_rapier_and_the_formula() {
    let o = observables("sliding_box.json", 5.0);
    let slide = find(&o, "sliding distance");
    let expected = slide.reference.unwrap();
    assert!((expected - 25.0 / 9.8).abs() < 1e-12);
    for value in [slide.rigidref, slide.rapier] {
        assert!((value - expected).abs() <= 0.05 * expected, "{slide:?}");
    }
    assert!(
        (slide.rigidref - slide.rapier).abs() <= 0.05 * expected,
        "{slide:?}"
    );
}

#[test]
fn five_box_stack_stands_after_five_seconds_in_both() {
    let o = observables("box_stack.json", 5.0);
    let standing = find(&o, "stack standing");
    assert_eq!((standing.rigidref, standing.rapier), (1.0, 1.0));
}

#[test]
fn equal_cube_stack_stands_in_both_and_rest_heights_agree() {
    // scenes/cube_stack.json: four equal 0.5 m boxes, `collision: complete`; rapier's colliders
    // are the same convex pieces.
    let o = observables("cube_stack.json", 5.0);
    let standing = find(&o, "stack standing");
    assert_eq!((standing.rigidref, standing.rapier), (1.0, 1.0));
    let rest = find(&o, "rest height, the body differing most");
    // 2% of the cube's size.
    assert!(
        rest.passed && (rest.rigidref - rest.rapier).abs() <= 0.02 * 0.5,
        "{rest:?}"
    );
}

#[test]
fn dzhanibekov_flip_period_agrees_with_rapier() {
    let o = observables("dzhanibekov.json", 25.0);
    let flip = find(&o, "Dzhanibekov flip period");
    assert!(
        flip.passed && (flip.rigidref - flip.rapier).abs() <= 0.05 * flip.rigidref,
        "{flip:?}"
    );
}

#[test]
fn rapier_comparison_command_passes_on_the_documented_scenes() {
    for (scene, time) in [
        ("sphere_drop.json", "5"),
        ("sliding_box.json", "5"),
        ("box_stack.json", "5"),
        ("cube_stack.json", "5"),
        ("dzhanibekov.json", "25"),
    ] {
        let out = std::process::Command::new(common::rigidref_bin())
            .args(["crosscheck", "--rapier", "--time", time, scene])
            .current_dir(common::project_root().join("scenes"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{scene}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            common::stderr(&out)
        );
    }
}
