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
/// phase, on a uniform grid. docs/contact.md §"Broad phase".
///
/// The cell side is the median of the boxes' largest sides. A box is entered in every cell it
/// covers; two boxes in one cell are tested, and a pair that overlaps is reported by one cell
/// only, the cell holding the smallest corner of their intersection (so no pair is found twice).
/// A box covering more than [`MAX_CELLS`] cells (a container, the ground) is tested against every
/// other box instead. Boxes that are empty (a smallest corner beyond the largest) or not a number
/// overlap nothing. The same pairs as [`sweep_and_prune_pairs`] and as testing all pairs; the cost
/// is O(n log n + k) for n boxes and k pairs sharing a cell, where a sweep along one axis pays
/// for every pair overlapping along that axis (a column of a grid of stacks, a strip of a pile).
pub fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(usize, usize)> {
    let sides: Vec<f64> = boxes
        .iter()
        .filter(|b| is_finite(b) && !is_empty(b))
        .map(|b| (b.max - b.min).max())
        .collect();
    let cell = super::stats::median(sides)
        .filter(|c| *c > 0.0)
        .unwrap_or(1.0);
    let cell_of =
        |p: &Vector3<f64>| -> [i64; 3] { [0, 1, 2].map(|k| (p[k] / cell).floor() as i64) };
    let (mut entries, mut wide) = (Vec::new(), Vec::new());
    for (i, b) in boxes.iter().enumerate() {
        if is_empty(b) {
            continue;
        }
        let covered: f64 = (0..3)
            .map(|k| (b.max[k] / cell).floor() - (b.min[k] / cell).floor() + 1.0)
            .product();
        if !is_finite(b) || covered > MAX_CELLS as f64 {
            wide.push(i);
            continue;
        }
        let (lo, hi) = (cell_of(&b.min), cell_of(&b.max));
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    entries.push((cell_key([x, y, z]), [x, y, z], i));
                }
            }
        }
    }
    // Sorted by a hash of the cell (one integer compare): two cells that share a hash share a
    // run of the list, and the cell itself is compared before a pair is tested.
    entries.sort_unstable_by_key(|e| e.0);
    let mut pairs = Vec::new();
    for group in entries.chunk_by(|a, b| a.0 == b.0) {
        for (n, &(_, home, i)) in group.iter().enumerate() {
            for &(_, cell, j) in &group[n + 1..] {
                let (a, b) = (&boxes[i], &boxes[j]);
                if cell == home && a.overlaps(b) && cell_of(&a.min.sup(&b.min)) == home {
                    pairs.push((i.min(j), i.max(j)));
                }
            }
        }
    }
    for (n, &i) in wide.iter().enumerate() {
        for (j, b) in boxes.iter().enumerate() {
            // Another wide box is tested once, from the first of the two.
            let other_wide = wide.binary_search(&j).is_ok();
            if j != i && !(other_wide && wide[..=n].contains(&j)) && boxes[i].overlaps(b) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// A cell's place in the sorted list: its coordinates hashed ([`crate::common::hash`]).
fn cell_key(cell: [i64; 3]) -> u64 {
    use std::hash::Hasher;
    let mut h = crate::common::hash::WordHasher::default();
    for c in cell {
        h.write_u64(c as u64);
    }
    h.finish()
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
