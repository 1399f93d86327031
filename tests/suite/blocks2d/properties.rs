//! 2D images to bodies, minimum enclosing circles and bounding-disc trees, checked against
//! brute force (docs/blocks2d.md).

use crate::common;
use common::blocks::{blob, body_of};

use nalgebra::Vector2;
use proptest::prelude::*;
use rigidref::blocks2d::body::Body2;
use rigidref::blocks2d::collide::{brute_force_contacts, detect_contacts};
use rigidref::blocks2d::disc_tree::BLOCK_RADIUS;
use rigidref::blocks2d::image::{Block, BlockGroup, ImageSettings, block_mass, load_image};
use rigidref::blocks2d::mec::{brute_force_enclosing_circle, min_enclosing_circle};

#[test]
fn every_assignment_image_loads_with_the_documented_bodies() {
    let Some(dir) = common::blocks2d_assignment() else {
        return;
    };
    let mut images = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "png") {
            continue;
        }
        let groups = load_image(&path, &ImageSettings::default()).unwrap();
        let pinned = groups.iter().filter(|g| g.pinned).count();
        println!(
            "{}: {} bodies, {} pinned",
            path.file_name().unwrap().to_string_lossy(),
            groups.len(),
            pinned
        );
        for g in &groups {
            // Pinned exactly when every block is a shade of blue (r = g < b), as 8-bit values.
            let blue = g.blocks.iter().all(|b| {
                let c = b.colour.map(|x| (x * 255.0).round() as u8);
                c[0] == c[1] && c[1] < c[2]
            });
            assert_eq!(g.pinned, blue);
            for b in &g.blocks {
                assert!((b.mass - block_mass(b.colour)).abs() < 1e-15 && b.mass > 0.0);
            }
        }
        images += 1;
    }
    assert!(images >= 18, "{images} images");
    // ../shared/README.md: "In these images the pinned grounds are RGB (0, 0, 163)". That holds
    // for the tower and wall images; the others' grounds are other shades of blue (delicate
    // (0, 0, 217), nuts3 (0, 0, 128), simple* (0, 0, 230), lcp (0, 0, 125), mini (0, 0, 240) and
    // (0, 0, 255), the Tetris tube a gradient from (0, 0, 119) to (242, 242, 248)), all r = g < b
    // and so pinned, as checked above.
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.extension().is_some_and(|e| e == "png")
            && (name.starts_with("tower") || name.starts_with("wall"))
        {
            let groups = load_image(&path, &ImageSettings::default()).unwrap();
            for g in groups.iter().filter(|g| g.pinned) {
                assert!(
                    g.blocks
                        .iter()
                        .all(|b| b.colour == [0.0, 0.0, 163.0 / 255.0]),
                    "{}: a pinned body is not RGB (0, 0, 163)",
                    path.display()
                );
            }
        }
    }
    // The README's facts about tower100: 100 black 8×2 bodies of mass 16 and one pinned ground
    // of RGB (0, 0, 163).
    let groups = load_image(&dir.join("tower100.png"), &ImageSettings::default()).unwrap();
    assert_eq!(groups.len(), 101);
    let (ground, boxes): (Vec<_>, Vec<_>) = groups.iter().partition(|g| g.pinned);
    assert_eq!(ground.len(), 1);
    assert!(
        ground[0]
            .blocks
            .iter()
            .all(|b| b.colour == [0.0, 0.0, 163.0 / 255.0])
    );
    for g in boxes {
        assert_eq!(g.blocks.len(), 16);
        assert!(
            g.blocks
                .iter()
                .all(|b| b.colour == [0.0, 0.0, 0.0] && b.mass == 1.0)
        );
        let xs: Vec<f64> = g.blocks.iter().map(|b| b.pixel.x).collect();
        let ys: Vec<f64> = g.blocks.iter().map(|b| b.pixel.y).collect();
        let extent = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
                + 1.0
        };
        assert_eq!((extent(&xs), extent(&ys)), (8.0, 2.0));
    }
    // A bad file is a clear error naming it.
    let err = load_image(&dir.join("assignment.txt"), &ImageSettings::default()).unwrap_err();
    assert!(err.contains("assignment.txt"), "{err}");
}

#[test]
fn one_block_body_has_the_unit_square_inertia() {
    let colour = [0.0, 0.0, 0.0];
    let g = BlockGroup {
        blocks: vec![Block {
            pixel: Vector2::new(3.0, 4.0),
            colour,
            mass: 1.0,
        }],
        pinned: false,
        boundary: None,
    };
    let b = Body2::from_group(&g);
    assert_eq!(b.mass, 1.0);
    assert!((b.inertia - 2.0 / 12.0).abs() < 1e-15, "m (1² + 1²) / 12");
    assert_eq!(b.x, Vector2::new(3.0, 4.0));
    let pinned = Body2::from_group(&BlockGroup { pinned: true, ..g });
    assert_eq!((pinned.inv_mass, pinned.inv_inertia), (0.0, 0.0));
}

fn points() -> impl Strategy<Value = Vec<Vector2<f64>>> {
    proptest::collection::vec(
        (-10.0..10.0f64, -10.0..10.0f64).prop_map(|(x, y)| Vector2::new(x, y)),
        1..9,
    )
}

#[test]
fn minimum_enclosing_circle_contains_every_point_and_matches_brute_force() {
    proptest!(common::seeded(1000), |(p in points())| {
        let c = min_enclosing_circle(&p).unwrap();
        for q in &p {
            prop_assert!(c.contains(q));
        }
        let b = brute_force_enclosing_circle(&p).unwrap();
        // The smallest enclosing circle is unique: same radius and centre, to round-off.
        prop_assert!((c.radius - b.radius).abs() <= 1e-9 * (1.0 + b.radius), "{c:?} vs {b:?}");
        prop_assert!((c.centre - b.centre).norm() <= 1e-6 * (1.0 + b.radius), "{c:?} vs {b:?}");
    });
}

/// Every overlapping pair of block discs of different bodies (not both pinned), testing all
/// blocks, interior ones included: the all-pairs oracle, as (body, block, body, block) with the
/// lower body first.
fn all_block_pairs(bodies: &[Body2]) -> Vec<(usize, usize, usize, usize)> {
    let mut out = Vec::new();
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            if bodies[i].pinned && bodies[j].pinned {
                continue;
            }
            for (a, ba) in bodies[i].blocks.iter().enumerate() {
                for (b, bb) in bodies[j].blocks.iter().enumerate() {
                    let d = bodies[i].to_world(&ba.local) - bodies[j].to_world(&bb.local);
                    if d.norm() < 2.0 * BLOCK_RADIUS && d.norm() > 0.0 {
                        out.push((i, a, j, b));
                    }
                }
            }
        }
    }
    out.sort();
    out
}

/// Whether some block centre of one body lies inside a cell of another (a deep overlap, which
/// the step's contacts push apart long before it happens).
fn centre_inside_another_body(bodies: &[Body2]) -> bool {
    bodies.iter().enumerate().any(|(i, bi)| {
        bodies.iter().enumerate().any(|(j, bj)| {
            i != j
                && bi.blocks.iter().any(|block| {
                    let p = bi.to_world(&block.local) - bj.x;
                    let (c, s) = (bj.theta.cos(), bj.theta.sin());
                    let local = Vector2::new(c * p.x + s * p.y, -s * p.x + c * p.y);
                    bj.blocks
                        .iter()
                        .any(|o| (local - o.local).abs().max() < 0.5)
                })
        })
    })
}

/// The trees find exactly the pairs of boundary blocks that testing every pair finds.
#[test]
fn disc_tree_finds_exactly_the_block_pairs_the_brute_force_test_finds() {
    proptest!(common::seeded(300), |(
        shapes in proptest::collection::vec((blob(), -6.0..6.0f64, -6.0..6.0f64, -3.2..3.2f64, any::<bool>()), 2..6)
    )| {
        let bodies: Vec<Body2> = shapes.iter().map(|(cells, x, y, theta, pinned)| {
            let mut b = body_of(cells, *pinned);
            b.x = Vector2::new(*x, *y);
            b.theta = *theta;
            b
        }).collect();
        let mut fast = Vec::new();
        detect_contacts(&bodies, &mut fast);
        let key = |c: &rigidref::blocks2d::collide::Contact2| (c.body1, c.block1, c.body2, c.block2);
        let mut a: Vec<_> = fast.iter().map(key).collect();
        let mut b: Vec<_> = brute_force_contacts(&bodies).iter().map(key).collect();
        a.sort();
        b.sort();
        prop_assert_eq!(a, b);
    });
}

/// Where no block centre is inside another body, the pairs of *all* blocks, interior ones
/// included, that overlap are exactly the pairs the step finds among boundary blocks: an interior
/// block's disc lies within its own 3 × 3 neighbourhood, so only boundary blocks need collide.
/// This checks each body's boundary (a block with a missing neighbour, of 8) against the
/// definition of contact itself.
#[test]
fn boundary_blocks_find_every_touching_pair_unless_a_centre_is_inside_another_body() {
    let compared = std::cell::Cell::new(0usize);
    proptest!(common::seeded(3000), |(
        a in blob(), b in blob(),
        offset in (-7.0..7.0f64, -7.0..7.0f64), theta in -3.2..3.2f64, pinned in any::<bool>(),
    )| {
        let first = body_of(&a, false);
        let mut second = body_of(&b, pinned);
        second.x = first.x + Vector2::new(offset.0, offset.1);
        second.theta = theta;
        let bodies = vec![first, second];
        if centre_inside_another_body(&bodies) {
            return Ok(());
        }
        let mut found = Vec::new();
        detect_contacts(&bodies, &mut found);
        let found: std::collections::BTreeSet<_> = found
            .iter()
            .map(|c| if c.body1 < c.body2 { (c.body1, c.block1, c.body2, c.block2) } else { (c.body2, c.block2, c.body1, c.block1) })
            .collect();
        let all: std::collections::BTreeSet<_> = all_block_pairs(&bodies).into_iter().collect();
        if !all.is_empty() {
            compared.set(compared.get() + 1);
        }
        prop_assert_eq!(found, all);
    });
    // Touching configurations must have been compared, not skipped throughout.
    println!("{} touching configurations compared", compared.get());
    assert!(compared.get() >= 300, "{}", compared.get());
}
