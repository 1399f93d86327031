//! The 2D warm start's store: the last solve's impulse of each contact, found again by the
//! contact's key (body 1, body 2, block 1, block 2). docs/blocks2d.md §"Contact problem",
//! "Finding the key".
//!
//! The answer is a map's: the impulse stored last under the key, or none. Detection lists a
//! substep's contacts pair by pair in increasing (body 1, body 2), so the store keeps the last
//! solve's contacts in that order and finds a key by walking a cursor forward with the
//! contacts being assembled (which come in the same order): the key's pair is at or just after
//! the cursor, and its few contacts are searched from the last one back, so that a repeated
//! key gives the impulse stored last, as a map would. Where the stored contacts are not in
//! pair order (a caller's own list), the store keeps a map instead.

use super::collide::{Contact2, tangent};
use crate::common::hash::FastMap;
use nalgebra::{SVector, Vector2};

/// Identifies a 2D contact across substeps: (body 1, body 2, block 1, block 2).
pub type ContactKey2 = (usize, usize, usize, usize);

/// The last solve's contacts' world impulses P = λn n + λt t, by contact key.
#[derive(Clone, Debug, Default)]
pub struct WarmStore2 {
    /// The stored contacts' keys, in the order stored.
    keys: Vec<ContactKey2>,
    /// Their world impulses λn n + λt t, mass units · blocks per time unit.
    impulses: Vec<Vector2<f64>>,
    /// Whether `keys` is in non-decreasing (body 1, body 2) order; if not, `map` holds the
    /// impulses.
    pair_order: bool,
    /// Key → impulse stored last under it; filled only where `keys` is not in pair order.
    map: FastMap<ContactKey2, Vector2<f64>>,
}

/// A key's body pair (body 1, body 2), the order the store's list is kept in.
fn pair(k: &ContactKey2) -> (usize, usize) {
    (k.0, k.1)
}

/// Where the next look-up starts: the index of the stored contacts at which the last found
/// pair began. Start each assembly at `WarmCursor::default()`.
#[derive(Clone, Copy, Debug, Default)]
pub struct WarmCursor(usize);

impl WarmStore2 {
    /// Empties the store.
    pub fn clear(&mut self) {
        self.keys.clear();
        self.impulses.clear();
        self.map.clear();
        self.pair_order = true;
    }

    /// Replaces the store with `contacts` and their impulses λ = (λn, λt).
    pub fn store(&mut self, contacts: &[Contact2], lambda: &[SVector<f64, 2>]) {
        self.clear();
        for (c, l) in contacts.iter().zip(lambda) {
            let key = (c.body1, c.body2, c.block1, c.block2);
            if let Some(last) = self.keys.last() {
                self.pair_order &= pair(last) <= pair(&key);
            }
            self.keys.push(key);
            self.impulses.push(c.normal * l[0] + tangent(&c.normal) * l[1]);
        }
        if !self.pair_order {
            self.map.extend(self.keys.iter().copied().zip(self.impulses.iter().copied()));
        }
    }

    /// The number of stored contacts.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Whether the store is empty.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// The impulse stored last under `key`, or `None`: the map's answer. `cursor` carries
    /// where the last look-up's pair began; look-ups in pair order walk it forward.
    pub fn find(&self, key: &ContactKey2, cursor: &mut WarmCursor) -> Option<Vector2<f64>> {
        if !self.pair_order {
            return self.map.get(key).copied();
        }
        let wanted = pair(key);
        let below = |k: &ContactKey2| pair(k) < wanted;
        let n = self.keys.len();
        // The first stored contact whose pair is not below the key's: from the cursor a few
        // steps forward (the usual case), else by bisection on the side the key lies.
        let mut start = cursor.0.min(n);
        if start > 0 && !below(&self.keys[start - 1]) {
            start = self.keys[..start].partition_point(below);
        } else {
            let mut steps = 0;
            while start < n && below(&self.keys[start]) && steps < 8 {
                start += 1;
                steps += 1;
            }
            if start < n && below(&self.keys[start]) {
                start += self.keys[start..].partition_point(below);
            }
        }
        cursor.0 = start;
        let end = start + (self.keys[start..].iter()).take_while(|k| pair(k) == wanted).count();
        (start..end)
            .rev()
            .find(|&i| self.keys[i] == *key)
            .map(|i| self.impulses[i])
    }
}
