//! Broad phase: sweep-and-prune on axis-aligned bounding boxes. docs/contact.md §"Broad phase".

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

/// The pairs (i, j), i < j, whose boxes overlap, sorted. Sweep and prune along x: sort the boxes
/// by their smallest x, and compare each only with those that start before it ends. Costs
/// O(n log n + pairs along x) rather than n² box tests.
pub fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(usize, usize)> {
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
