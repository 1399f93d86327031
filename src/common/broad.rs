//! Broad phase: a uniform grid on axis-aligned bounding boxes (and the sweep and prune it is
//! checked against). docs/contact.md §"Broad phase".

use nalgebra::Vector3;

/// An axis-aligned box, world frame, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vector3<f64>,
    /// Largest corner.
    pub max: Vector3<f64>,
}

impl Aabb {
    /// The box around `points`.
    pub fn around(points: impl IntoIterator<Item = Vector3<f64>>) -> Aabb {
        let mut b = Aabb {
            min: Vector3::repeat(f64::INFINITY),
            max: Vector3::repeat(f64::NEG_INFINITY),
        };
        for p in points {
            b.min = b.min.inf(&p);
            b.max = b.max.sup(&p);
        }
        b
    }

    /// Whether the two boxes overlap (touching counts).
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }

    /// The length of the box's shortest side, m.
    pub fn smallest_side(&self) -> f64 {
        let side = self.max - self.min;
        side.x.min(side.y).min(side.z)
    }

    /// Whether `p` is inside the box (boundary included).
    pub fn contains(&self, p: &Vector3<f64>) -> bool {
        (0..3).all(|k| self.min[k] <= p[k] && p[k] <= self.max[k])
    }
}

/// Every pair (i, j), i < j, of `boxes` that overlap ([`Aabb::overlaps`]), sorted: the broad
/// phase, on a uniform grid ([`BroadGrid`], with working memory of its own for this one call).
/// docs/contact.md §"Broad phase".
pub fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    BroadGrid::default().pairs_into(boxes, &mut pairs);
    pairs
}

/// The broad phase on a uniform grid, with its working memory kept from call to call (no
/// allocation once grown). docs/contact.md §"Broad phase".
///
/// The cell side is the median of the boxes' largest sides, and the cells are counted from the
/// smallest corner of the finite boxes. A box is entered in every cell it covers; two boxes in
/// one cell are tested, and a pair that overlaps is reported by one cell only, the cell holding
/// the smallest corner of their intersection (so no pair is found twice).
/// A box covering more than [`MAX_CELLS`] cells (a container, the ground) is tested against every
/// other box instead. Boxes that are empty (a smallest corner beyond the largest) or not a number
/// overlap nothing. The same pairs as [`sweep_and_prune_pairs`] and as testing all pairs; the cost
/// is O(n + k) for n boxes and k pairs sharing a cell (while each box has a bounded number of
/// partners, whose short lists are sorted), where a sweep along one axis pays for
/// every pair overlapping along that axis (a column of a grid of stacks, a strip of a pile).
#[derive(Clone, Debug, Default)]
pub struct BroadGrid {
    sides: Vec<f64>,
    entries: Vec<GridEntry>,
    keys: Vec<(u32, u32)>,
    scratch: Vec<(u32, u32)>,
    sorted: Vec<GridEntry>,
    wide: Vec<usize>,
    found: Vec<(usize, usize)>,
    /// Per box i, where its partners j begin in `partners` (the counting sort of the pairs).
    starts: Vec<usize>,
    partners: Vec<usize>,
}

/// A box entered in one cell of the grid: the cell, the cell of the box's smallest corner, the
/// box and its index (laid out together so that a cell's run is read in one pass).
#[derive(Clone, Copy, Debug)]
struct GridEntry {
    cell: [i64; 3],
    lowest: [i64; 3],
    owner: usize,
    bounds: Aabb,
}

impl BroadGrid {
    /// The (box, cell) entries the last [`Self::pairs_into`] made: each box entered in the grid
    /// once per cell it covers (the grid's work grows with them).
    pub fn entered(&self) -> usize {
        self.entries.len()
    }

    /// Every pair (i, j), i < j, of `boxes` that overlap, ascending, into `pairs` (replaced):
    /// the same pairs as [`sweep_and_prune_pairs`] and as testing all pairs.
    pub fn pairs_into(&mut self, boxes: &[Aabb], pairs: &mut Vec<(usize, usize)>) {
        pairs.clear();
        // The grid's list numbers its entries in 32 bits (at most MAX_CELLS per box): beyond
        // that many boxes, the sweep, which gives the same pairs.
        if boxes.len() > u32::MAX as usize / MAX_CELLS {
            *pairs = sweep_and_prune_pairs(boxes);
            return;
        }
        self.sides.clear();
        // The grid's origin: the smallest corner of the finite boxes, so that an axis along
        // which every box lies within one cell's side of the lowest (a 2D scene's z, its boxes
        // grown by a margin about z = 0) has one cell, not two.
        let mut origin = Vector3::repeat(f64::INFINITY);
        for b in boxes.iter().filter(|b| is_finite(b) && !is_empty(b)) {
            self.sides.push((b.max - b.min).max());
            origin = origin.inf(&b.min);
        }
        let cell = super::stats::median_of(&mut self.sides)
            .filter(|c| *c > 0.0)
            .unwrap_or(1.0);
        let index = |x: f64, k: usize| floor((x - origin[k]) / cell);
        let cell_of = |p: &Vector3<f64>| -> [i64; 3] { [0, 1, 2].map(|k| index(p[k], k) as i64) };
        // Per entry: its cell's hash and the entry's index, sorted by the hash; the entries
        // then gathered in that order.
        self.entries.clear();
        self.keys.clear();
        self.wide.clear();
        for (i, b) in boxes.iter().enumerate() {
            if is_empty(b) {
                continue;
            }
            let covered: f64 = (0..3)
                .map(|k| index(b.max[k], k) - index(b.min[k], k) + 1.0)
                .product();
            // (Not a number where both ends lie beyond f64's range from the origin: wide too.)
            if !is_finite(b) || !(covered <= MAX_CELLS as f64) {
                self.wide.push(i);
                continue;
            }
            let (lo, hi) = (cell_of(&b.min), cell_of(&b.max));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        let key = cell_key([x, y, z]);
                        self.keys.push((key, self.entries.len() as u32));
                        self.entries.push(GridEntry {
                            cell: [x, y, z],
                            lowest: lo,
                            owner: i,
                            bounds: *b,
                        });
                    }
                }
            }
        }
        // Sorted by a hash of the cell: two cells that share a hash share a run of the list, and
        // the cell itself is compared before a pair is tested. Only the runs matter, not their
        // order, so the pairs do not depend on the sort.
        radix_sort_by_key(&mut self.keys, &mut self.scratch);
        self.sorted.clear();
        let entries = &self.entries;
        self.sorted
            .extend(self.keys.iter().map(|&(_, e)| entries[e as usize]));
        self.found.clear();
        let mut start = 0;
        while start < self.keys.len() {
            let key = self.keys[start].0;
            // A run is a few entries: found by walking it, not by a search of the whole list.
            let end = start + self.keys[start..].iter().take_while(|k| k.0 == key).count();
            let group = &self.sorted[start..end];
            for (n, a) in group.iter().enumerate() {
                for b in &group[n + 1..] {
                    // The smallest corner of the intersection, max(a.min, b.min), lies in the
                    // cell max(⌊a.min / s⌋, ⌊b.min / s⌋) (⌊x / s⌋ does not decrease as x grows):
                    // the cell that reports the pair.
                    if b.cell == a.cell
                        && a.bounds.overlaps(&b.bounds)
                        && (0..3).all(|k| a.lowest[k].max(b.lowest[k]) == a.cell[k])
                    {
                        let (i, j) = (a.owner, b.owner);
                        self.found.push((i.min(j), i.max(j)));
                    }
                }
            }
            start = end;
        }
        for (n, &i) in self.wide.iter().enumerate() {
            for (j, b) in boxes.iter().enumerate() {
                // Another wide box is tested once, from the first of the two.
                let other_wide = self.wide.binary_search(&j).is_ok();
                if j != i && !(other_wide && self.wide[..=n].contains(&j)) && boxes[i].overlaps(b) {
                    self.found.push((i.min(j), i.max(j)));
                }
            }
        }
        // Ascending: counted by i, each box's partners then sorted (a few each). No pair is
        // found twice, so this is the one sorted order.
        self.starts.clear();
        self.starts.resize(boxes.len() + 1, 0);
        for &(i, _) in &self.found {
            self.starts[i + 1] += 1;
        }
        for i in 0..boxes.len() {
            self.starts[i + 1] += self.starts[i];
        }
        self.partners.clear();
        self.partners.resize(self.found.len(), 0);
        for &(i, j) in &self.found {
            self.partners[self.starts[i]] = j;
            self.starts[i] += 1;
        }
        let mut begin = 0;
        for i in 0..boxes.len() {
            let end = self.starts[i];
            let partners = &mut self.partners[begin..end];
            partners.sort_unstable();
            pairs.extend(partners.iter().map(|&j| (i, j)));
            begin = end;
        }
    }
}

/// ⌊x⌋: the value of [`f64::floor`] (signed zeros, NaN and infinities included) without the
/// library call the baseline x86-64 target makes of it: through the integer truncation where
/// |x| < 2⁵² (exact there), `f64::floor` elsewhere. The grid's cells are ⌊coordinate / side⌋.
pub fn floor(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        let truncated = x as i64 as f64;
        let below = if truncated > x {
            truncated - 1.0
        } else {
            truncated
        };
        below.copysign(x)
    } else {
        x.floor()
    }
}

/// Sorts `items` by their key, stably, by four counting passes over its bytes (least
/// significant first): O(n) where a comparison sort is O(n log n).
fn radix_sort_by_key(items: &mut Vec<(u32, u32)>, scratch: &mut Vec<(u32, u32)>) {
    scratch.clear();
    scratch.resize(items.len(), (0, 0));
    for pass in 0..4 {
        let digit = |key: u32| ((key >> (8 * pass)) & 0xff) as usize;
        let mut starts = [0usize; 256];
        for &(key, _) in items.iter() {
            starts[digit(key)] += 1;
        }
        let mut sum = 0;
        for start in starts.iter_mut() {
            (*start, sum) = (sum, sum + *start);
        }
        for &item in items.iter() {
            let d = digit(item.0);
            scratch[starts[d]] = item;
            starts[d] += 1;
        }
        std::mem::swap(items, scratch);
    }
}

/// A cell's place in the sorted list: its coordinates hashed ([`crate::common::hash`]), the
/// hash's two halves folded into 32 bits (cells sharing a key share a run of the list and are
/// told apart by their coordinates).
fn cell_key(cell: [i64; 3]) -> u32 {
    use std::hash::Hasher;
    let mut h = crate::common::hash::WordHasher::default();
    for c in cell {
        h.write_u64(c as u64);
    }
    let hash = h.finish();
    (hash ^ (hash >> 32)) as u32
}

/// Cells a box may cover and still be entered in the grid (4 × 4 × 4).
pub const MAX_CELLS: usize = 64;

fn is_finite(b: &Aabb) -> bool {
    b.min.iter().chain(b.max.iter()).all(|x| x.is_finite())
}

/// Empty or not a number: overlaps nothing ([`Aabb::overlaps`] compares false).
fn is_empty(b: &Aabb) -> bool {
    (0..3).any(|k| b.min[k].partial_cmp(&b.max[k]).is_none_or(|o| o.is_gt()))
}

/// The same pairs as [`overlapping_pairs`] by a **sweep and prune along x**: the boxes sorted by
/// their smallest x, each compared with those after it until one starts beyond its largest x.
/// Kept as the plain reference the grid is tested against.
pub fn sweep_and_prune_pairs(boxes: &[Aabb]) -> Vec<(usize, usize)> {
    let mut by_start: Vec<usize> = (0..boxes.len()).collect();
    by_start.sort_by(|&a, &b| boxes[a].min.x.total_cmp(&boxes[b].min.x).then(a.cmp(&b)));
    let mut pairs = Vec::new();
    for (position, &i) in by_start.iter().enumerate() {
        for &j in &by_start[position + 1..] {
            if boxes[j].min.x > boxes[i].max.x {
                break;
            }
            if boxes[i].overlaps(&boxes[j]) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// The broad phase with temporal coherence: the pairs of the boxes grown by each body's margin,
/// kept while a body has moved by at most half its margin since its box was grown, and filtered
/// each call by the present boxes. The result is exactly [`overlapping_pairs`] of the present
/// boxes (a pair overlapping now overlapped, grown, then), in the same order.
///
/// A body that has moved further (or is new) is a **mover**: its box is grown afresh at its
/// present pose and its grown pairs found again against every other grown box, the other bodies'
/// pairs kept; when movers are more than [`MOVERS_FOR_REBUILD`] of the bodies, the grown pairs
/// are all found afresh on the grid instead. docs/contact.md §"Temporal coherence".
#[derive(Clone, Debug)]
pub struct KeptPairs<A> {
    /// Each body's pose when its grown box was made.
    anchors: Vec<A>,
    grown_pairs: Vec<(usize, usize)>,
    grown: Vec<Aabb>,
    is_mover: Vec<bool>,
    movers: Vec<usize>,
    mover_pairs: Vec<(usize, usize)>,
    merged: Vec<(usize, usize)>,
    grid: BroadGrid,
    /// Calls with no mover.
    pub kept: u64,
    /// Calls that updated the movers' pairs.
    pub updated: u64,
    /// Calls that found all grown pairs afresh.
    pub found: u64,
}

/// The share of bodies (1 in this many) above which movers make the grown pairs be found afresh
/// rather than updated: each mover is tested against every body, so the update costs
/// movers × bodies box tests against the grid's O(bodies log bodies).
pub const MOVERS_FOR_REBUILD: usize = 128;

impl<A> Default for KeptPairs<A> {
    fn default() -> Self {
        KeptPairs {
            anchors: Vec::new(),
            grown_pairs: Vec::new(),
            grown: Vec::new(),
            is_mover: Vec::new(),
            movers: Vec::new(),
            mover_pairs: Vec::new(),
            merged: Vec::new(),
            grid: BroadGrid::default(),
            kept: 0,
            updated: 0,
            found: 0,
        }
    }
}

impl<A> KeptPairs<A> {
    /// The overlapping pairs of `boxes` into `out` (replaced). `margin(k)` is body k's margin,
    /// `anchor(k)` its present pose, `moved(k, a)` a bound on how far any point of body k has
    /// moved since pose `a` (NaN fails).
    pub fn overlapping(
        &mut self,
        boxes: &[Aabb],
        margin: impl Fn(usize) -> f64,
        anchor: impl Fn(usize) -> A,
        moved: impl Fn(usize, &A) -> f64,
        out: &mut Vec<(usize, usize)>,
    ) {
        let n = boxes.len();
        let grow = |k: usize| Aabb {
            min: boxes[k].min.add_scalar(-margin(k)),
            max: boxes[k].max.add_scalar(margin(k)),
        };
        // Within half its margin (false for NaN: a body whose state is not a number moves).
        let stayed = |k: usize, a: &A| moved(k, a) <= margin(k) / 2.0;
        self.movers.clear();
        if self.anchors.len() <= n {
            self.movers
                .extend((0..self.anchors.len()).filter(|&k| !stayed(k, &self.anchors[k])));
            self.movers.extend(self.anchors.len()..n);
        }
        if self.anchors.len() > n
            || self.movers.len() * MOVERS_FOR_REBUILD > n.max(MOVERS_FOR_REBUILD)
        {
            self.found += 1;
            self.grown.clear();
            self.grown.extend((0..n).map(grow));
            self.grid.pairs_into(&self.grown, &mut self.grown_pairs);
            self.anchors.clear();
            self.anchors.extend((0..n).map(&anchor));
        } else if !self.movers.is_empty() {
            self.updated += 1;
            self.is_mover.clear();
            self.is_mover.resize(n, false);
            for &k in &self.movers {
                self.is_mover[k] = true;
                if k < self.anchors.len() {
                    self.anchors[k] = anchor(k);
                    self.grown[k] = grow(k);
                } else {
                    self.anchors.push(anchor(k));
                    self.grown.push(grow(k));
                }
            }
            // A mover's pairs against every grown box (a pair of two movers once, from the
            // first); empty boxes overlap nothing, as on the grid.
            self.mover_pairs.clear();
            for &k in &self.movers {
                if is_empty(&self.grown[k]) {
                    continue;
                }
                for j in 0..n {
                    if j == k || (self.is_mover[j] && j < k) || is_empty(&self.grown[j]) {
                        continue;
                    }
                    if self.grown[k].overlaps(&self.grown[j]) {
                        self.mover_pairs.push((k.min(j), k.max(j)));
                    }
                }
            }
            self.mover_pairs.sort_unstable();
            // The kept pairs of bodies that did not move, merged with the movers' (both sorted).
            let is_mover = &self.is_mover;
            self.merged.clear();
            let mut kept = self
                .grown_pairs
                .iter()
                .copied()
                .filter(|&(i, j)| !is_mover[i] && !is_mover[j])
                .peekable();
            let mut new = self.mover_pairs.iter().copied().peekable();
            loop {
                let next = match (kept.peek(), new.peek()) {
                    (Some(a), Some(b)) => {
                        if a < b {
                            kept.next()
                        } else {
                            new.next()
                        }
                    }
                    (Some(_), None) => kept.next(),
                    (None, _) => new.next(),
                };
                match next {
                    Some(p) => self.merged.push(p),
                    None => break,
                }
            }
            std::mem::swap(&mut self.grown_pairs, &mut self.merged);
        } else {
            self.kept += 1;
        }
        out.clear();
        out.extend(self.grown_pairs.iter().copied().filter(|&(i, j)| {
            !is_empty(&boxes[i]) && !is_empty(&boxes[j]) && boxes[i].overlaps(&boxes[j])
        }));
    }
}
