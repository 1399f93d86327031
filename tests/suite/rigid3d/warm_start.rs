//! The 3D warm start's store (docs/contact.md §"Warm starting", "Finding the key"): its answer
//! is a map's, the impulse stored last under a key or none, whatever the order of the stored
//! contacts and of the look-ups; and detection lists contacts in the order its cursor walks.

use crate::common;

use proptest::prelude::*;
use rigidref::common::warm_store::WarmKey;
use rigidref::rigid3d::collide::{Contact, Feature};
use rigidref::rigid3d::frame::ContactFrame;
use rigidref::rigid3d::scene::load_scene;
use rigidref::rigid3d::warm_start::{ContactKey, WarmCursor, WarmStart};
use rigidref::rigid3d::world::World;
use std::collections::HashMap;

/// A contact with this key and the frame of the unit normal at angles (`a`, `b`).
fn contact(key: ContactKey, (a, b): (f64, f64)) -> Contact {
    let n = nalgebra::Vector3::new(a.cos() * b.cos(), b.sin(), a.sin() * b.cos());
    Contact {
        body1: key.0,
        body2: key.1,
        feature: key.2,
        point: nalgebra::Vector3::zeros(),
        frame: ContactFrame::from_normal(&n),
        depth: 0.01,
    }
}

/// Keys from few bodies and features, the ground among them, so that groups and whole keys
/// repeat (and a pair's contacts name either body as body 1).
fn keys() -> impl Strategy<Value = Vec<ContactKey>> {
    let feature = prop_oneof![
        (0..3usize).prop_map(Feature::Vertex),
        Just(Feature::Surface),
        (0..2u32, 0..2u32).prop_map(|(p, f)| Feature::Manifold {
            piece1: p,
            piece2: 0,
            feature1: f,
            feature2: 1,
        }),
    ];
    let body2 = prop_oneof![Just(None), (0..5usize).prop_map(Some)];
    proptest::collection::vec((0..5usize, body2, feature), 0..40)
}

/// Stored contacts in group order (sorted by group; repeated keys kept) or as drawn; look-ups
/// of stored and unstored keys, in group order with one cursor and in the drawn order with one
/// cursor: every λ₀ the bits of a `HashMap` of world impulses filled in the stored order, put in
/// the looking-up contact's frame.
#[test]
fn the_3d_warm_store_answers_as_a_map_in_any_order_of_look_ups() {
    proptest!(common::seeded(200), |(
        mut stored in keys(),
        sort in any::<bool>(),
        angles in proptest::collection::vec((-3.2..3.2f64, -1.5..1.5f64), 80),
        lambda in proptest::collection::vec((0.0..5.0f64, -2.0..2.0f64, -2.0..2.0f64), 40),
        extra in keys(),
    )| {
        if sort {
            // Stable: repeated keys keep their order, so "stored last" is well defined.
            stored.sort_by_key(|k| k.group());
        }
        let contacts: Vec<Contact> = (stored.iter().zip(&angles))
            .map(|(k, a)| contact(*k, *a))
            .collect();
        let impulses: Vec<nalgebra::SVector<f64, 3>> = (lambda.iter())
            .map(|(n, t1, t2)| nalgebra::SVector::<f64, 3>::new(*n, *t1, *t2))
            .collect();
        let mut warm = WarmStart::new(true);
        warm.store(&contacts, &impulses[..contacts.len()]);
        let mut map = HashMap::new();
        for (c, l) in contacts.iter().zip(&impulses) {
            let p = c.frame.n * l[0] + c.frame.t1 * l[1] + c.frame.t2 * l[2];
            map.insert((c.body1, c.body2, c.feature), p);
        }
        let mut queries: Vec<ContactKey> = stored.iter().chain(&extra).copied().collect();
        let drawn = queries.clone();
        queries.sort_by_key(|k| k.group());
        for order in [queries, drawn] {
            let mut cursor = WarmCursor::default();
            for (q, a) in order.iter().zip(angles.iter().rev().cycle()) {
                // Looked up in a frame of its own (the contact has turned since).
                let c = contact(*q, *a);
                let got = warm.initial_impulse(&c, &mut cursor).map(f64::to_bits);
                let want = map.get(q).map_or(nalgebra::SVector::<f64, 3>::zeros(), |p| {
                    nalgebra::SVector::<f64, 3>::new(c.frame.n.dot(p), c.frame.t1.dot(p), c.frame.t2.dot(p))
                }).map(f64::to_bits);
                prop_assert_eq!(got, want, "key {:?}", q);
            }
        }
        // Switched off, every start is zero.
        let mut off = WarmStart::new(false);
        off.store(&contacts, &impulses[..contacts.len()]);
        for q in &stored {
            let got = off.initial_impulse(&contact(*q, (0.3, 0.2)), &mut WarmCursor::default());
            prop_assert_eq!(got, nalgebra::SVector::<f64, 3>::zeros());
        }
    });
}

/// The cursor walks forward only where detection lists contacts in group order (the ground
/// contacts body by body, then each body pair's together, pairs increasing); elsewhere the
/// store falls back to a map, with the same answers but a hash look-up per contact. Every
/// substep's contacts of resting and falling scenes, with the vertex rule and with
/// `collision: complete`, are in group order.
#[test]
fn detection_lists_contacts_in_the_warm_stores_group_order() {
    for (name, complete) in [
        ("touching_pyramid.json", false),
        ("touching_pyramid.json", true),
        ("box_stack.json", false),
        ("cube_stack.json", true),
        ("tee_on_box.json", false),
        ("touching_ten_cubes.json", true),
    ] {
        let mut scene = load_scene(&common::project_root().join("scenes").join(name)).unwrap();
        if complete {
            scene.params.collision = rigidref::rigid3d::collide::CollisionMethod::Complete;
        }
        let mut world = World::new(&scene).unwrap();
        let mut checked = 0;
        for _ in 0..40 {
            world.step().unwrap();
            for solve in &world.solves {
                let groups: Vec<_> = (solve.contacts.iter())
                    .map(|c| (c.body1, c.body2, c.feature).group())
                    .collect();
                assert!(
                    groups.windows(2).all(|w| w[0] <= w[1]),
                    "{name} (complete: {complete}): contacts out of group order: {groups:?}"
                );
                checked += groups.len();
            }
        }
        assert!(checked > 0, "{name}: no contacts in 40 frames");
    }
}
