//! The checks have teeth: each deliberate bug of `rigidref::verify::faults`, injected alone, makes at
//! least one of the project's cross-checks or snapshots fail (docs/verification.md §"Teeth").
//!
//! Checks run per bug: golden traces of the canonical scenes, the snapshot summaries, PGS against
//! clarabel on the canonical contact scenes, and the rapier3d comparison on the scenes it is
//! documented for.

use crate::common;

use rigidref::rigid3d::scene::{Scene, load_scene};
use rigidref::rigid3d::world::World;
use rigidref::sim::{Flow, NonFinite, drive};
use rigidref::verify::crosscheck::{Comparison, CrosscheckSettings, check_step};
use rigidref::verify::faults::{Faults, with_faults};
use rigidref::verify::golden::{
    Tolerances, canonical_scenes, compare, golden_path, read_golden, record,
};
use rigidref::verify::references::compare::{
    compare as compare_observables, record_rapier, record_rigidref,
};
use rigidref::verify::snapshots::summary;

fn scenes() -> Vec<(String, Scene)> {
    let root = common::project_root();
    canonical_scenes(&root.join("scenes"))
        .unwrap()
        .into_iter()
        .map(|p| {
            (
                format!("scenes/{}", p.file_name().unwrap().to_string_lossy()),
                load_scene(&p).unwrap(),
            )
        })
        .collect()
}

/// Canonical scenes whose golden trace the faulty code does not reproduce.
fn golden_failures(faults: Faults) -> Vec<String> {
    let root = common::project_root();
    scenes()
        .into_iter()
        .filter(|(source, scene)| {
            let golden = read_golden(&golden_path(
                &root.join("golden"),
                std::path::Path::new(source),
            ))
            .unwrap();
            match with_faults(faults, || record(scene, source)) {
                Ok(fresh) => !compare(&golden, &fresh, &Tolerances::default()).is_empty(),
                Err(_) => true, // a run that blows up certainly differs
            }
        })
        .map(|(s, _)| s)
        .collect()
}

/// Canonical scenes whose snapshot summary changes.
fn snapshot_failures(faults: Faults) -> Vec<String> {
    scenes()
        .into_iter()
        .filter(|(_, scene)| {
            with_faults(faults, || summary(scene, 5)).ok() != summary(scene, 5).ok()
        })
        .map(|(s, _)| s)
        .collect()
}

/// Canonical contact scenes where, on some problem of the first second, the scene's solver (with
/// the faults: PGS run to convergence, or the step's Newton answer) and clarabel disagree, or
/// the answer does not reach the residual tolerance (the unmodified solvers reach it on every
/// problem of these scenes: `the_unmodified_code_passes_every_check`); this is
/// `rigidref crosscheck --strict`. The scenes written exactly touching are solved here by the
/// exact solver: on their aligned stacks PGS run to convergence stalls (200 000 sweeps leave a
/// residual up to 4e-5 m/s on touching_three_cubes, where Newton solves every problem; docs/contact.md
/// §"Speculative contacts"), so PGS could not verify their problems either way.
fn crosscheck_failures(faults: Faults) -> Vec<String> {
    scenes()
        .into_iter()
        .filter(|(_, scene)| scene.params.check_collisions)
        .map(|(name, mut scene)| {
            if name.starts_with("scenes/touching_") {
                scene.params.solver = rigidref::solve::Solver::Newton;
            }
            (name, scene)
        })
        .filter(|(_, scene)| {
            let settings = CrosscheckSettings {
                solver: scene.params.solver,
                ..CrosscheckSettings::default()
            };
            with_faults(faults, || {
                let mut world = World::new(scene).unwrap();
                // Stops at the first problem where the two disagree; a run that blows up certainly
                // differs.
                let mut disagree = false;
                let ran = drive(&mut world, 100, |world, _| {
                    for solve in &world.solves {
                        let step = Some((solve.lambda.as_slice(), &solve.report));
                        let c = check_step(&solve.problem, &settings, step).unwrap();
                        disagree |= c.residual_answer > 1e-10
                            || match c.comparison {
                                Comparison::Lambda => c.lambda_difference > 1e-5,
                                Comparison::Objective => c.objective_gap > 1e-8,
                            };
                    }
                    Ok::<_, NonFinite>(if disagree { Flow::Stop } else { Flow::Continue })
                });
                ran.is_err() || disagree
            })
        })
        .map(|(s, _)| s)
        .collect()
}

/// Scenes documented for the rapier comparison whose observables disagree.
fn rapier_failures(faults: Faults) -> Vec<String> {
    scenes()
        .into_iter()
        .filter(|(s, _)| {
            [
                "scenes/sphere_drop.json",
                "scenes/sliding_box.json",
                "scenes/box_stack.json",
                "scenes/dzhanibekov.json",
            ]
            .contains(&s.as_str())
        })
        .filter(|(s, scene)| {
            let seconds = if s.contains("dzhanibekov") { 20.0 } else { 5.0 };
            let steps = (seconds / scene.params.dt).round() as u64;
            let ours = match with_faults(faults, || record_rigidref(scene, steps)) {
                Ok(t) => t,
                Err(_) => return true,
            };
            let theirs = record_rapier(scene, steps).unwrap();
            compare_observables(scene, &ours, &theirs)
                .iter()
                .any(|o| !o.passed)
        })
        .map(|(s, _)| s)
        .collect()
}

fn report(name: &str, faults: Faults) -> usize {
    let golden = golden_failures(faults);
    let snapshots = snapshot_failures(faults);
    let crosscheck = crosscheck_failures(faults);
    let rapier = rapier_failures(faults);
    println!(
        "{name}:\n  golden: {golden:?}\n  snapshots: {snapshots:?}\n  clarabel: {crosscheck:?}\n  rapier3d: {rapier:?}"
    );
    golden.len() + snapshots.len() + crosscheck.len() + rapier.len()
}

#[test]
fn the_unmodified_code_passes_every_check() {
    assert_eq!(report("no bug", Faults::NONE), 0);
}

#[test]
fn a_sign_flip_in_one_jacobian_column_is_caught() {
    let faults = Faults {
        jacobian_sign_flip: true,
        ..Faults::NONE
    };
    assert!(!golden_failures(faults).is_empty() || !snapshot_failures(faults).is_empty());
    assert!(report("Jacobian column sign flip", faults) > 0);
}

#[test]
fn friction_bounds_from_the_previous_step_are_caught() {
    let faults = Faults {
        stale_friction_bound: true,
        ..Faults::NONE
    };
    assert!(
        !crosscheck_failures(faults).is_empty(),
        "the clarabel cross-check should catch it"
    );
    assert!(report("friction bound from the previous step's λn", faults) > 0);
}

#[test]
fn a_missing_gyroscopic_term_is_caught() {
    let faults = Faults {
        no_gyroscopic_term: true,
        ..Faults::NONE
    };
    assert!(
        !rapier_failures(faults).is_empty(),
        "rapier's flip period should catch it"
    );
    assert!(report("missing ω × Jω", faults) > 0);
}

#[test]
fn a_transposed_world_inertia_is_caught() {
    let faults = Faults {
        transposed_world_inertia: true,
        ..Faults::NONE
    };
    assert!(!golden_failures(faults).is_empty());
    assert!(report("world inertia Rᵀ J₀ R", faults) > 0);
}
