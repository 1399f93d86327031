//! The warm-start maps' hasher: the keys are a few small integers (body and feature indices),
//! looked up once per contact per substep, where the standard library's SipHash (built to resist
//! chosen keys from the network) was 4% of a 2D factory step. This is the multiply-rotate hash
//! of the Rust compiler's own tables ("FxHash"): one rotate, xor and multiply per word. It is
//! not seeded, so a map's layout is the same on every run (no map here is iterated in an order
//! that reaches the output, but nothing depends on that either).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A hash map with [`WordHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<WordHasher>>;

/// Multiply-rotate hashing of machine words.
#[derive(Clone, Copy, Debug, Default)]
pub struct WordHasher {
    hash: u64,
}

/// An odd constant with well-mixed bits (2⁶⁴ / φ, rounded to odd).
const MULTIPLIER: u64 = 0x9e37_79b9_7f4a_7c15;

impl WordHasher {
    fn add(&mut self, word: u64) {
        self.hash = (self.hash.rotate_left(5) ^ word).wrapping_mul(MULTIPLIER);
    }
}

impl Hasher for WordHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }
    fn write_u8(&mut self, i: u8) {
        self.add(u64::from(i));
    }
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
    fn finish(&self) -> u64 {
        self.hash
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_with_the_word_hasher_finds_every_key_it_holds_and_no_other() {
        let mut map: FastMap<(usize, Option<usize>, u32), usize> = FastMap::default();
        for i in 0..2000 {
            map.insert((i % 37, (i % 3 != 0).then_some(i % 11), i as u32), i);
        }
        assert_eq!(map.len(), 2000);
        for i in 0..2000 {
            assert_eq!(
                map.get(&(i % 37, (i % 3 != 0).then_some(i % 11), i as u32)),
                Some(&i)
            );
        }
        assert_eq!(map.get(&(0, None, 1)), None);
        // Nearby keys spread: the low bits (a table's bucket) differ.
        let h = |k: usize| {
            let mut s = WordHasher::default();
            s.write_usize(k);
            s.finish() >> 57
        };
        let buckets: std::collections::HashSet<u64> = (0..64).map(h).collect();
        assert!(buckets.len() > 32, "{}", buckets.len());
    }
}
