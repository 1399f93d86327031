//! The assignment's four demonstration images come to rest and are not glued; README's render
//! lines use the documented settings (docs/blocks2d.md §"Demonstration settings").

use crate::common;

use nalgebra::Vector2;
use rigidref::blocks2d::disc_tree::BLOCK_RADIUS;
use rigidref::blocks2d::image::{ImageSettings, load_image};
use rigidref::blocks2d::params::Params2;
use rigidref::blocks2d::world::{ScriptedImpulse, World2};

/// Kinetic energy below which a body counts as at rest (docs/blocks2d.md §"Demonstration
/// settings"; also the render's solid circles and `run`'s summary): a black 8 × 2 bar (mass 16)
/// moving at 0.011 blocks per time unit, under a sixth of a block per second of the starter's
/// time, or turning at 0.005 rad per time unit.
const REST: f64 = 1e-3;

/// Runs one of the assignment's demonstration images with [`Params2::demonstration`] and checks
/// what the assignment's videos must show:
///
/// - rest: from `rest_by` on, through `hold` more time units, every body's kinetic energy stays
///   below [`REST`] at every step (coming to rest and staying there, not a quiet moment);
/// - no interpenetration: at rest no two blocks of different bodies overlap by more than 10% of
///   a block disc's diameter, nor by more than twice post-stabilisation's slop (0.01);
/// - standing: no body has moved sideways by more than two blocks (tower100: and its levels keep
///   their order);
/// - not glued: a sideways strike (Δv = 5 blocks per time unit) on body `struck`, chosen to have
///   bodies above it, moves it by more than a block and moves most of the bodies above it (centre
///   higher, within its horizontal extent) by more than 0.1 block, within 2 time units.
///
/// Returns the world after the strike, for checks particular to the image.
fn demonstrate(
    name: &str,
    rest_by: f64,
    hold: f64,
    struck: usize,
) -> Option<(World2, Vec<Vector2<f64>>)> {
    let dir = common::blocks2d_assignment()?;
    let groups = load_image(&dir.join(format!("{name}.png")), &ImageSettings::default()).unwrap();
    let mut world = World2::new(&groups, Params2::demonstration());
    let start: Vec<Vector2<f64>> = world.bodies.iter().map(|b| b.x).collect();
    let max_ke = |w: &World2| {
        w.bodies
            .iter()
            .map(|b| b.kinetic_energy())
            .fold(0.0, f64::max)
    };
    let mut moving_until = 0.0;
    let mut held_max: f64 = 0.0;
    common::run_until(&mut world, u64::MAX, |world, _| {
        let ke = max_ke(world);
        if ke >= REST {
            moving_until = world.time();
        }
        if world.time() >= rest_by {
            held_max = held_max.max(ke);
        }
        world.time() >= rest_by + hold - 1e-9
    });
    let overlap = world.deepest_overlap();
    let drift = world
        .bodies
        .iter()
        .zip(&start)
        .map(|(b, x0)| (b.x.x - x0.x).abs())
        .fold(0.0, f64::max);
    println!(
        "{name}: every body below KE {REST} from t = {moving_until:.2} on (required by {rest_by}, held to {}); largest KE while held {held_max:.2e}; deepest disc overlap {overlap:.4}; largest sideways drift {drift:.3}",
        rest_by + hold
    );
    assert!(
        moving_until < rest_by,
        "{name}: a body still moved (KE ≥ {REST}) at t = {moving_until}"
    );
    assert!(
        overlap <= 0.1 * 2.0 * BLOCK_RADIUS,
        "{name}: overlap {overlap}"
    );
    // The assignment's bound above is met even without post-stabilisation (tower100 rests at
    // 0.115 then); with it the overlap stays at its slop (measured 0.010).
    assert!(
        overlap <= 2.0 * world.params.slop,
        "{name}: overlap {overlap} beyond twice the post-stabilisation slop"
    );
    assert!(
        drift < 2.0,
        "{name}: a body drifted {drift} blocks sideways"
    );

    let before: Vec<Vector2<f64>> = world.bodies.iter().map(|b| b.x).collect();
    let extent = world.bodies[struck]
        .blocks
        .iter()
        .map(|b| world.bodies[struck].to_world(&b.local).x)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
    let above: Vec<usize> = (0..world.bodies.len())
        .filter(|&k| {
            !world.bodies[k].pinned
                && before[k].y < before[struck].y - 1.0
                && (extent.0..=extent.1).contains(&before[k].x)
        })
        .collect();
    assert!(
        !above.is_empty(),
        "{name}: body {struck} has nothing above it"
    );
    let m = world.bodies[struck].mass;
    world.impulses.push(ScriptedImpulse {
        time: world.time(),
        body: struck,
        impulse: Vector2::new(5.0 * m, 0.0),
        point: None,
    });
    common::run(&mut world, 40, |_, _| {});
    let moved = |k: usize| (world.bodies[k].x - before[k]).norm();
    let moved_above = above.iter().filter(|&&k| moved(k) > 0.1).count();
    println!(
        "{name}: struck body {struck} at ({:.1}, {:.1}) moved {:.3}; {moved_above} of the {} bodies above it moved more than 0.1",
        before[struck].x,
        before[struck].y,
        moved(struck),
        above.len()
    );
    assert!(moved(struck) > 1.0, "{name}: the struck body barely moved");
    assert!(
        2 * moved_above > above.len(),
        "{name}: only {moved_above} of the {} bodies above the struck one moved",
        above.len()
    );
    Some((world, before))
}

// Measured with `cargo test --release --test blocks2d -- --nocapture demonstration`: every body
// is at rest from t = 3.95 (delicate), 4.9 (both walls), 11.2 (tower100: its levels first close
// the one-pixel gaps between them, the top falling 58 blocks). The limits leave a margin; the
// hold shows the rest lasts.

#[test]
fn demonstration_delicate_comes_to_rest_and_is_not_glued() {
    // Body 12: the second bar from the top (48 blocks), under the top structure.
    demonstrate("delicate", 10.0, 10.0, 12);
}

#[test]
fn demonstration_wall_wide_sparse_high_comes_to_rest_and_is_not_glued() {
    // Body 17: the middle brick of the third row from the top.
    demonstrate("wallWideSparseHigh", 10.0, 10.0, 17);
}

#[test]
fn demonstration_wall_wide_dense_high_comes_to_rest_and_is_not_glued() {
    // Body 16: the middle brick of the third row from the top.
    demonstrate("wallWideDenseHigh", 10.0, 10.0, 16);
}

#[test]
fn demonstration_tower100_comes_to_rest_stands_and_is_not_glued() {
    // Body 10: the eleventh level from the top.
    let Some((world, before)) = demonstrate("tower100", 20.0, 10.0, 10) else {
        return;
    };
    // The levels keep their order from the top (body 0) to the bottom.
    for k in 1..100 {
        assert!(
            before[k - 1].y < before[k].y,
            "levels {} and {k} swapped",
            k - 1
        );
    }
    // The level under the struck one stays behind: it was held by friction, not glue.
    let moved = |k: usize| (world.bodies[k].x - before[k]).norm();
    println!(
        "tower100: the level below the struck one moved {:.3}",
        moved(11)
    );
    assert!(
        moved(11) < 0.5 * moved(10),
        "the level below moved with it: glued?"
    );
}

/// The README's render commands for the four images use the documented settings.
#[test]
fn readme_renders_the_demonstration_images_with_the_documented_settings() {
    let readme = std::fs::read_to_string(common::project_root().join("README.md")).unwrap();
    let p = Params2::demonstration();
    let flags = format!(
        "--substeps {} --iterations {} --order random",
        p.substeps, p.iterations
    );
    for image in [
        "delicate",
        "wallWideSparseHigh",
        "wallWideDenseHigh",
        "tower100",
    ] {
        assert!(readme.contains(image), "README does not render {image}");
    }
    let renders: Vec<&str> = readme
        .lines()
        .filter(|l| l.contains("-- render ../shared/assignments/blocks2d/"))
        .collect();
    assert_eq!(
        renders.len(),
        4,
        "one render command per demonstration image"
    );
    for line in renders {
        assert!(line.contains(&flags), "{line} does not use {flags}");
    }
}

/// Runs `rigidref run IMAGE --time 20` with `extra` options and returns, over the non-pinned
/// bodies, the largest sideways displacement of a centre of mass from t = 0 to t = 20 (blocks =
/// pixels) and the largest kinetic energy of a body at t = 20 (from the summary's rest count).
fn run_twenty(dir: &std::path::Path, image: &str, extra: &[&str]) -> (f64, usize, usize) {
    let tmp = tempfile::tempdir().unwrap();
    let path = dir.join(image);
    let mut args = vec!["run", path.to_str().unwrap(), "--time", "20"];
    args.extend(extra);
    let out = common::rigidref(&args, tmp.path());
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{image}: {stderr}");
    let text = std::fs::read_to_string(tmp.path().join("trace.jsonl")).unwrap();
    // The default trace (every step, contacts counted, not listed) of a 30-time-unit run stays
    // under 20 MB: measured here over 20 and scaled (records are the same size throughout).
    let per_30 = text.len() as f64 * 30.0 / 20.0;
    println!(
        "{image} {extra:?}: default trace {:.1} MB per 30 time units",
        per_30 / 1e6
    );
    assert!(
        per_30 < 20e6,
        "{image}: {:.1} MB per 30 time units",
        per_30 / 1e6
    );
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let (header, first, last) = (&lines[0], &lines[1], lines.last().unwrap());
    assert_eq!(last["t"].as_f64().unwrap(), 20.0);
    let (mut sideways, mut turned): (f64, f64) = (0.0, 0.0);
    for (i, info) in header["bodies"].as_array().unwrap().iter().enumerate() {
        if info["pinned"].as_bool().unwrap() {
            continue;
        }
        let x = |r: &serde_json::Value| r["bodies"][i]["x"][0].as_f64().unwrap();
        let theta = |r: &serde_json::Value| r["bodies"][i]["theta"].as_f64().unwrap();
        sideways = sideways.max((x(last) - x(first)).abs());
        turned = turned.max((theta(last) - theta(first)).abs());
    }
    let overlap = last["deepest_overlap"].as_f64().unwrap();
    println!("{image} {extra:?}: turned {turned:.4} rad, deepest overlap {overlap:.4} at t = 20");
    if extra.is_empty() {
        // Standing, not toppling or sinking into one another: no body turned (a falling bar
        // turns by radians) and no two block discs overlap by more than five times the
        // post-stabilisation slop (0.01; measured 0.010).
        assert!(turned <= 0.05, "{image}: a body turned by {turned} rad");
        assert!(overlap <= 0.05, "{image}: discs overlap by {overlap}");
    }
    // "at rest        R of M bodies below kinetic energy 0.001"
    let rest = stderr
        .lines()
        .find(|l| l.starts_with("at rest"))
        .unwrap_or_else(|| panic!("{image}: no rest line: {stderr}"));
    let words: Vec<&str> = rest.split_whitespace().collect();
    let (resting, moving) = (words[2].parse().unwrap(), words[4].parse().unwrap());
    println!("{image} {extra:?}: sideways {sideways:.4} blocks, {resting} of {moving} at rest");
    (sideways, resting, moving)
}

/// `rigidref run IMAGE.png` with no physics options keeps each demonstration image standing for
/// 20 time units: no body moves sideways by more than 2 px (measured: at most 0.009), and every
/// body is at rest at the end, no body has turned by more than 0.05 rad and no two block discs
/// overlap by more than 0.05 (measured: 0.0004 rad, 0.010): standing, not toppling or sinking.
/// Bodies do settle downwards, by the disc model's 2 − √2 per one-pixel gap (tower100's top: 59
/// px; docs/blocks2d.md §"Demonstration settings"). Its default trace stays under 20 MB per 30
/// time units (measured:
/// 12.4 MB for wallWideSparseHigh, which wrote 127 MB with every contact listed). Bodies do move down: the assignment's block discs (radius √2/2)
/// rest with block centres √2 apart, so every gap between stacked bodies closes by about 0.6 px
/// and the top of tower100 settles 59 px (docs/blocks2d.md §"Demonstration settings").
#[test]
fn default_settings_keep_the_demonstration_images_standing() {
    let Some(dir) = common::blocks2d_assignment() else {
        return;
    };
    for image in [
        "tower100.png",
        "delicate.png",
        "wallWideSparseHigh.png",
        "wallWideDenseHigh.png",
    ] {
        let (sideways, resting, moving) = run_twenty(&dir, image, &[]);
        assert!(
            sideways <= 2.0,
            "{image}: a body moved {sideways} px sideways"
        );
        assert_eq!(
            resting, moving,
            "{image}: not every body is at rest at t = 20"
        );
    }
}

/// `--preset starter` is the Java starter's behaviour (1 substep, 10 sweeps in order, no warm start,
/// no post-stabilisation, docs/blocks2d.md §"The starter preset"), under which tower100 collapses
/// (measured: 43.4 px sideways, kinetic energy 6.6e4 at t = 20): the defaults are what keeps it
/// standing.
#[test]
fn the_starter_preset_lets_tower100_collapse() {
    let Some(dir) = common::blocks2d_assignment() else {
        return;
    };
    let (sideways, resting, moving) = run_twenty(&dir, "tower100.png", &["--preset", "starter"]);
    assert!(
        sideways > 2.0 && resting < moving,
        "{sideways} {resting}/{moving}"
    );
}
