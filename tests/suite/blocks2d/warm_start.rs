//! The 2D warm start's store (docs/blocks2d.md §"Contact problem", "Finding the key"): its
//! answer is a map's, the impulse stored last under a key or none, whatever the order of the
//! stored contacts and of the look-ups.

use crate::common;

use proptest::prelude::*;
use rigidref::blocks2d::collide::Contact2;
use rigidref::blocks2d::warm_start::{ContactKey2, WarmCursor, WarmStore2};
use std::collections::HashMap;

/// A contact with this key and a unit normal at angle `a`.
fn contact(key: ContactKey2, a: f64) -> Contact2 {
    Contact2 {
        body1: key.0,
        body2: key.1,
        block1: key.2,
        block2: key.3,
        point: nalgebra::Vector2::zeros(),
        normal: nalgebra::Vector2::new(a.cos(), a.sin()),
        depth: 0.01,
    }
}

/// Keys from few bodies and blocks, so that pairs and whole keys repeat.
fn keys() -> impl Strategy<Value = Vec<ContactKey2>> {
    proptest::collection::vec((0..6usize, 0..6usize, 0..3usize, 0..3usize), 0..40)
}

/// Stored contacts in pair order (sorted by body 1, body 2; repeated keys kept) or as drawn;
/// look-ups of stored and unstored keys, in pair order with one cursor and in the drawn order
/// with one cursor: every answer the bits of a `HashMap` filled in the stored order.
#[test]
fn the_warm_store_answers_as_a_map_in_any_order_of_look_ups() {
    proptest!(common::seeded(200), |(
        mut stored in keys(),
        sort in any::<bool>(),
        angles in proptest::collection::vec(-3.2..3.2f64, 40),
        lambda in proptest::collection::vec((0.0..5.0f64, -2.0..2.0f64), 40),
        extra in keys(),
    )| {
        if sort {
            // Stable: repeated keys keep their order, so "stored last" is well defined.
            stored.sort_by_key(|k| (k.0, k.1));
        }
        let contacts: Vec<Contact2> = (stored.iter().zip(&angles))
            .map(|(k, a)| contact(*k, *a))
            .collect();
        let impulses: Vec<nalgebra::SVector<f64, 2>> = (lambda.iter())
            .map(|(n, t)| nalgebra::SVector::<f64, 2>::new(*n, *t))
            .collect();
        let mut store = WarmStore2::default();
        store.store(&contacts, &impulses[..contacts.len()]);
        prop_assert_eq!(store.len(), contacts.len());
        let mut map = HashMap::new();
        for (c, l) in contacts.iter().zip(&impulses) {
            let t = nalgebra::Vector2::new(-c.normal.y, c.normal.x);
            map.insert((c.body1, c.body2, c.block1, c.block2), c.normal * l[0] + t * l[1]);
        }
        let mut queries: Vec<ContactKey2> = stored.iter().chain(&extra).copied().collect();
        let drawn = queries.clone();
        queries.sort_by_key(|k| (k.0, k.1));
        for order in [queries, drawn] {
            let mut cursor = WarmCursor::default();
            for q in &order {
                let got = store.find(q, &mut cursor).map(|p| [p.x.to_bits(), p.y.to_bits()]);
                let want = map.get(q).map(|p| [p.x.to_bits(), p.y.to_bits()]);
                prop_assert_eq!(got, want, "key {:?}", q);
            }
        }
    });
}
