//! The warm start's store, for both systems: the last solve's impulse of each contact, found
//! again by the contact's key. docs/contact.md §"Warm starting", "Finding the key".
//!
//! The answer is a map's: the impulse stored last under the key, or none. Detection lists a
//! substep's contacts group by group in increasing order of a group the key names (2D: the body
//! pair; 3D: the ground contacts body by body, then the body pairs), so the store keeps the last
//! solve's contacts in that order and finds a key by walking a cursor forward with the contacts
//! being assembled (which come in the same order): the key's group is at or just after the
//! cursor, and its few contacts are searched from the last one back, so that a repeated key gives
//! the impulse stored last, as a map would. Where the stored contacts are not in group order (a
//! caller's own list, the starter's detection), the store keeps a map instead.

use crate::common::hash::FastMap;
use std::hash::Hash;

/// A contact's key as the store files it: the whole key, compared for equality, and the group
/// it belongs to, which detection lists in increasing order.
pub trait WarmKey: Copy + Eq + Hash {
    /// The group: the contacts of one group are listed together, the groups in increasing
    /// order.
    type Group: Ord + Copy;
    /// This key's group.
    fn group(&self) -> Self::Group;
}

/// The last solve's contacts' values (world impulses), by contact key.
#[derive(Clone, Debug)]
pub struct WarmStore<K: WarmKey, V: Copy> {
    /// The stored contacts' keys, in the order stored.
    keys: Vec<K>,
    /// Their values, in the same order.
    values: Vec<V>,
    /// Whether `keys` is in non-decreasing group order; if not, `map` holds the values.
    in_order: bool,
    /// Key → value stored last under it; filled only where `keys` is not in group order.
    map: FastMap<K, V>,
}

impl<K: WarmKey, V: Copy> Default for WarmStore<K, V> {
    fn default() -> Self {
        WarmStore {
            keys: Vec::new(),
            values: Vec::new(),
            in_order: true,
            map: FastMap::default(),
        }
    }
}

/// Where the next look-up starts: the stored contacts of the last look-up's group,
/// `start..end` (empty where none was stored). Start each assembly at `WarmCursor::default()`.
#[derive(Clone, Copy, Debug, Default)]
pub struct WarmCursor {
    start: usize,
    end: usize,
}

impl<K: WarmKey, V: Copy> WarmStore<K, V> {
    /// Empties the store.
    pub fn clear(&mut self) {
        self.keys.clear();
        self.values.clear();
        self.map.clear();
        self.in_order = true;
    }

    /// Replaces the store with `items` (key, value), in the order given.
    pub fn fill(&mut self, items: impl IntoIterator<Item = (K, V)>) {
        self.clear();
        for (key, value) in items {
            if let Some(last) = self.keys.last() {
                self.in_order &= last.group() <= key.group();
            }
            self.keys.push(key);
            self.values.push(value);
        }
        if !self.in_order {
            self.map
                .extend(self.keys.iter().copied().zip(self.values.iter().copied()));
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

    /// The value stored last under `key`, or `None`: the map's answer. `cursor` carries the
    /// last look-up's group; look-ups in group order walk it forward.
    pub fn find(&self, key: &K, cursor: &mut WarmCursor) -> Option<V> {
        if !self.in_order {
            return self.map.get(key).copied();
        }
        let wanted = key.group();
        // The last look-up's group again (a group's contacts come together): its stored
        // contacts are known.
        let same = cursor.start < cursor.end && self.keys[cursor.start].group() == wanted;
        if !same {
            *cursor = self.group_at(wanted, cursor.start);
        }
        // Searched from the last back, so that a repeated key gives the value stored last.
        (cursor.start..cursor.end)
            .rev()
            .find(|&i| self.keys[i] == *key)
            .map(|i| self.values[i])
    }

    /// The stored contacts of group `wanted` (an empty range where it has none), looked for
    /// from index `from`: a few steps forward (the usual case), else by bisection on the side
    /// the group lies.
    fn group_at(&self, wanted: K::Group, from: usize) -> WarmCursor {
        let below = |k: &K| k.group() < wanted;
        let n = self.keys.len();
        let mut start = from.min(n);
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
        let end = start
            + (self.keys[start..].iter())
                .take_while(|k| k.group() == wanted)
                .count();
        WarmCursor { start, end }
    }
}
