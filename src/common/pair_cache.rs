//! Temporal coherence in detection, the part both systems share: per body pair, a list of
//! candidates (block pairs in 2D; vertices and convex-piece pairs in 3D) found once with a margin
//! and kept from step to step while the two bodies have moved, relative to the poses they were
//! found at, by less than half that margin. docs/contact.md §"Temporal coherence".
//!
//! The cache only ever skips candidates that cannot be contacts: everything it keeps is tested
//! exactly as fresh detection tests it, in fresh detection's order, so the contacts found are the
//! same, bit for bit. Each system says what a candidate is, what its anchor (the poses the list
//! was found at) is, and when the anchor still holds; this file keeps the lists.

use std::ops::Range;

/// How often the cache served a pair, and what the debug check found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CacheStats {
    /// Pair visits served from a list kept from an earlier step.
    pub reused: u64,
    /// Pair visits that found their list afresh (new pairs, and pairs that moved too far).
    pub refreshed: u64,
    /// Steps (3D: substeps) whose cached detection was compared with fresh detection
    /// (`check_detection`).
    pub checked: u64,
    /// Of those, the ones whose contacts differed (must stay 0).
    pub mismatches: u64,
    /// 3D: signed-distance queries of kept candidate vertices (those inside the other body's
    /// box and sphere).
    pub queries: u64,
    /// Of those, the ones answered on a nearest triangle kept from an earlier step, without
    /// the BVH search (kept for the list's life, or leading).
    pub nearest_kept: u64,
    /// Of `nearest_kept`, the ones answered on a leading triangle: the vertex within half the
    /// triangle's lead of where its last search found it (docs/contact.md §"Temporal
    /// coherence", "Leading triangles").
    pub nearest_leading: u64,
    /// Of those, the ones answered without the search because the vertex's last search found
    /// it on the surface and it still is, within half the surface tolerance of the same
    /// triangle (no contact: docs/contact.md §"Temporal coherence", "Vertices on the surface").
    pub on_surface: u64,
    /// 3D, `collision: complete` with the cache: piece-pair manifolds re-derived from kept
    /// features (a leading axis, exactly; with persistent manifolds, within the preferences'
    /// bound).
    pub manifolds_kept: u64,
    /// 3D, `collision: complete` with the cache: piece-pair manifolds found by the full
    /// separating-axis search.
    pub manifolds_searched: u64,
    /// 3D, persistent manifolds: of the checked steps, those whose contacts differed from fresh
    /// detection's only as a kept manifold may (docs/contact.md §"Persistent manifolds"); not
    /// mismatches.
    pub kept_differs: u64,
}

impl CacheStats {
    /// Reused over all pair visits, or `None` before any.
    pub fn hit_rate(&self) -> Option<f64> {
        let all = self.reused + self.refreshed;
        (all > 0).then(|| self.reused as f64 / all as f64)
    }

    /// The share of piece-pair manifolds re-derived from kept features, or `None` when none was
    /// asked for (no `collision: complete`, or no cache).
    pub fn manifold_rate(&self) -> Option<f64> {
        let all = self.manifolds_kept + self.manifolds_searched;
        (all > 0).then(|| self.manifolds_kept as f64 / all as f64)
    }

    /// The share of kept candidates' signed-distance queries answered on a kept nearest
    /// triangle, or `None` before any (and in 2D).
    pub fn nearest_rate(&self) -> Option<f64> {
        (self.queries > 0).then(|| self.nearest_kept as f64 / self.queries as f64)
    }

    /// The counts since `before` (for a timed stretch of a run).
    pub fn since(&self, before: &CacheStats) -> CacheStats {
        CacheStats {
            reused: self.reused - before.reused,
            refreshed: self.refreshed - before.refreshed,
            checked: self.checked - before.checked,
            mismatches: self.mismatches - before.mismatches,
            queries: self.queries - before.queries,
            nearest_kept: self.nearest_kept - before.nearest_kept,
            nearest_leading: self.nearest_leading - before.nearest_leading,
            on_surface: self.on_surface - before.on_surface,
            manifolds_kept: self.manifolds_kept - before.manifolds_kept,
            manifolds_searched: self.manifolds_searched - before.manifolds_searched,
            kept_differs: self.kept_differs - before.kept_differs,
        }
    }
}

/// One pair's list: the pair (i < j), its anchor and where its candidates are.
#[derive(Clone, Debug)]
struct Entry<A> {
    pair: (u32, u32),
    anchor: A,
    items: Range<usize>,
}

/// The lists of all pairs, sorted by pair, rebuilt each detection pass by walking the pairs in
/// ascending order ([`PairCache::begin`], [`PairCache::candidates`] for each pair,
/// [`PairCache::end`]). Pairs not visited in a pass are dropped. No allocation once grown.
#[derive(Clone, Debug)]
pub struct PairCache<A, T> {
    entries: Vec<Entry<A>>,
    items: Vec<T>,
    next_entries: Vec<Entry<A>>,
    next_items: Vec<T>,
    /// The first entry of `entries` not yet passed in this pass.
    cursor: usize,
    /// The counts so far.
    pub stats: CacheStats,
}

impl<A, T> Default for PairCache<A, T> {
    fn default() -> Self {
        PairCache {
            entries: Vec::new(),
            items: Vec::new(),
            next_entries: Vec::new(),
            next_items: Vec::new(),
            cursor: 0,
            stats: CacheStats::default(),
        }
    }
}

impl<A: Clone, T: Copy> PairCache<A, T> {
    /// Starts a pass.
    pub fn begin(&mut self) {
        self.next_entries.clear();
        self.next_items.clear();
        self.cursor = 0;
    }

    /// The candidates of pair `(i, j)`, visited in ascending order within a pass: the kept list
    /// when there is one and `holds(anchor)` says its anchor still holds, else a fresh list from
    /// `fresh`, which is given the pair's last anchor (if the pair was visited in the last pass),
    /// appends the candidates and returns their anchor. Returned to change: what a system learns
    /// of a candidate while the list holds is kept with it (3D: its nearest triangle).
    pub fn candidates(
        &mut self,
        (i, j): (usize, usize),
        holds: impl FnOnce(&A) -> bool,
        fresh: impl FnOnce(Option<&A>, &mut Vec<T>) -> A,
    ) -> &mut [T] {
        let pair = (i as u32, j as u32);
        while self.cursor < self.entries.len() && self.entries[self.cursor].pair < pair {
            self.cursor += 1;
        }
        let start = self.next_items.len();
        let last = self.entries.get(self.cursor).filter(|e| e.pair == pair);
        let anchor = match last {
            Some(e) if holds(&e.anchor) => {
                self.next_items
                    .extend_from_slice(&self.items[e.items.clone()]);
                self.stats.reused += 1;
                e.anchor.clone()
            }
            _ => {
                self.stats.refreshed += 1;
                fresh(last.map(|e| &e.anchor), &mut self.next_items)
            }
        };
        let items = start..self.next_items.len();
        self.next_entries.push(Entry {
            pair,
            anchor,
            items: items.clone(),
        });
        &mut self.next_items[items]
    }

    /// Ends a pass: the lists visited in it become the kept ones.
    pub fn end(&mut self) {
        std::mem::swap(&mut self.entries, &mut self.next_entries);
        std::mem::swap(&mut self.items, &mut self.next_items);
    }

    /// Forgets every list (the next pass finds all afresh).
    pub fn clear(&mut self) {
        self.entries.clear();
        self.items.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_is_served_from_its_list_while_its_anchor_holds_and_pairs_not_visited_are_dropped() {
        let mut cache: PairCache<f64, u32> = PairCache::default();
        let mut calls = 0;
        for (pass, anchor_ok) in [(0, true), (1, true), (2, false)] {
            cache.begin();
            for pair in [(0, 1), (2, 5)] {
                if pass == 1 && pair == (0, 1) {
                    continue; // (0, 1) not overlapping in pass 1: dropped
                }
                let got = cache
                    .candidates(
                        pair,
                        |_| anchor_ok,
                        |_, out| {
                            calls += 1;
                            out.extend([pair.0 as u32, pair.1 as u32]);
                            0.0
                        },
                    )
                    .to_vec();
                assert_eq!(got, vec![pair.0 as u32, pair.1 as u32]);
            }
            cache.end();
        }
        // Pass 0: both fresh. Pass 1: (2, 5) kept. Pass 2: (0, 1) fresh (dropped in pass 1),
        // (2, 5) fresh (anchor no longer holds).
        assert_eq!(calls, 4);
        assert_eq!(cache.stats.reused, 1);
        assert_eq!(cache.stats.refreshed, 4);
        assert_eq!(cache.stats.hit_rate(), Some(0.2));
    }
}
