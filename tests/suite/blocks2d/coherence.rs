//! Temporal coherence in 2D detection (docs/blocks2d.md §"Temporal coherence"): the kept
//! candidate block pairs find the same contacts as fresh detection, bit for bit, on every
//! substep of the canonical scenes and of a factory's drops, and the debug check can fail.

use crate::common;

use rigidref::blocks2d::image::{ImageSettings, load_image};
use rigidref::blocks2d::params::Params2;
use rigidref::blocks2d::scene::load_scene2;
use rigidref::blocks2d::world::World2;
use rigidref::tools::experiments::factory::{DropZone, Factory, Pieces, container};
use rigidref::verify::faults::{Faults, with_faults};

/// Runs `steps` steps of `world` with the cache's check on; panics on a difference.
fn run_checked(
    name: &str,
    mut world: World2,
    steps: u64,
) -> rigidref::common::pair_cache::CacheStats {
    world.params.detection_cache = true;
    world.params.check_detection = true;
    let mut substeps = 0;
    common::run(&mut world, steps, |w, _| {
        substeps += u64::from(w.substeps_in_step)
    });
    let stats = world.detection_stats();
    assert_eq!(
        stats.checked, substeps,
        "{name}: not every substep was checked"
    );
    assert_eq!(
        stats.mismatches, 0,
        "{name}: cached detection differed from fresh"
    );
    eprintln!(
        "{name}: {} substeps checked, pair lists kept {} / found {}",
        stats.checked, stats.reused, stats.refreshed
    );
    stats
}

/// A container 40 × 30 with `drops` batches of 8 pieces dropped into it, one every 10 steps,
/// and `after` steps more; the world after it, with the check on throughout.
fn factory_run(pieces: Pieces, drops: u64, after: u64) -> World2 {
    let mut world = World2::new(
        &[container(40, 30)],
        Params2 {
            iterations: 10,
            substeps: 1,
            order: rigidref::solve::ContactOrder::Random,
            check_detection: true,
            ..Params2::default()
        },
    );
    let zone = DropZone::above_pinned(&world).unwrap();
    let mut factory = Factory::new(3, pieces);
    common::run(&mut world, drops * 10 + after, |w, k| {
        if k % 10 == 0 && k / 10 < drops {
            factory.drop_batch(w, &zone, 8, 5.0);
        }
    });
    world
}

#[test]
fn cached_detection_finds_the_fresh_contacts_on_every_substep_of_the_canonical_scenes() {
    let (mut reused, mut all) = (0, 0);
    let dir = common::project_root().join("scenes/blocks");
    for name in ["dominoes", "pendulum", "pyramid", "seesaw", "stack"] {
        let scene = load_scene2(&dir.join(format!("{name}.json"))).unwrap();
        let stats = run_checked(name, scene.world, 200);
        reused += stats.reused;
        all += stats.reused + stats.refreshed;
    }
    if let Some(dir) = common::blocks2d_assignment() {
        // The demonstration images at their defaults, a tenth of their demonstration time each
        // (the landing and the first settling, where pairs come and go).
        for name in [
            "tower100",
            "delicate",
            "wallWideDenseHigh",
            "wallWideSparseHigh",
            "nuts3",
        ] {
            let groups =
                load_image(&dir.join(format!("{name}.png")), &ImageSettings::default()).unwrap();
            let world = World2::new(&groups, Params2::default());
            let stats = run_checked(name, world, 40);
            reused += stats.reused;
            all += stats.reused + stats.refreshed;
        }
    }
    assert!(all > 10_000, "only {all} pair visits in all the scenes");
    assert!(
        reused * 2 > all,
        "the lists served only {reused} of {all} pair visits"
    );
}

#[test]
fn cached_detection_finds_the_fresh_contacts_while_a_factory_drops_bodies() {
    // Bodies falling at the drop speed refresh their lists every step or two, landing ones keep
    // them: both paths on every substep.
    for pieces in [Pieces::Bricks, Pieces::Random] {
        let world = factory_run(pieces, 12, 100);
        let stats = world.detection_stats();
        assert_eq!(
            stats.checked, world.step,
            "{pieces:?}: not every step was checked"
        );
        assert_eq!(
            stats.mismatches, 0,
            "{pieces:?}: cached detection differed from fresh"
        );
        assert!(
            stats.reused > 1000 && stats.refreshed > 100,
            "{pieces:?}: {stats:?}"
        );
    }
}

#[test]
fn the_check_catches_lists_kept_after_the_bodies_have_moved() {
    // Teeth: with the lists never refreshed, bodies landing on a pile must show differences.
    let faults = Faults {
        stale_detection_cache: true,
        ..Faults::NONE
    };
    let world = with_faults(faults, || factory_run(Pieces::Bricks, 6, 40));
    let stats = world.detection_stats();
    assert!(
        stats.mismatches > 0,
        "stale lists went unnoticed over {} checked steps",
        stats.checked
    );
}

#[test]
fn the_detection_cache_on_and_off_give_the_same_trace_bit_for_bit() {
    let dir = common::project_root().join("scenes/blocks");
    for name in ["dominoes.json", "pyramid.json"] {
        let path = dir.join(name);
        let run = |set: &[&str]| common::trace_records(&path, "5", set);
        let cached = run(&[]);
        let fresh = run(&["--set", "detection_cache=false"]);
        assert!(cached.len() > 50);
        assert!(cached == fresh, "{name}: the traces differ");
    }
}
