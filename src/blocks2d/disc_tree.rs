//! A body's bounding-disc tree: a binary tree whose nodes are discs containing all the block
//! discs below them. docs/blocks2d.md §"Bounding-disc tree".

use super::mec::min_enclosing_circle;
use nalgebra::Vector2;

/// Radius of a block's collision disc: the disc circumscribing the unit square, √2/2.
pub const BLOCK_RADIUS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// One node, in the body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscNode {
    /// Centre, body frame.
    pub centre: Vector2<f64>,
    /// Radius: the minimum enclosing circle of the block centres below, plus [`BLOCK_RADIUS`].
    pub radius: f64,
    /// Children (indices into the tree's nodes), or the block for a leaf.
    pub kind: NodeKind,
}

/// Inner node or leaf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NodeKind {
    /// Two children.
    Inner(usize, usize),
    /// One block (index into the body's blocks).
    Leaf(usize),
}

/// How a body's disc tree is built and how two trees are descended (scene key `disc_tree`).
/// Both descents find the same contacts; the order they list them in differs, and with a fixed
/// number of Gauss–Seidel sweeps in that order the answer depends on it.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum DiscTreeRule {
    /// rigidref's: a node's blocks sorted along the longer side of their bounding box (ties by
    /// block index) and split at the median (a balanced tree); two inner nodes of equal discs
    /// descend body 1's.
    #[default]
    Median,
    /// The Java starter's `BVNode`: a node's blocks split at the middle of their bounding box,
    /// across y when it is strictly taller than wide and across x otherwise, the blocks below the
    /// middle (in the body frame) the first child, in list order; and the descent the students
    /// write on it (the larger disc split first, children in order), which on equal discs splits
    /// body 2's node (`r1 > r2` splits body 1's, else body 2's, in the filled-in submissions read).
    Starter,
}

/// The tree; node 0 is the root.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DiscTree {
    /// The nodes.
    pub nodes: Vec<DiscNode>,
    /// How it was built, and how it is descended.
    pub rule: DiscTreeRule,
}

impl DiscTree {
    /// Builds the tree over the blocks `indices` with body-frame centres `centres[i]`: each node
    /// is split at the median along the longer side of its blocks' bounding box.
    pub fn build(centres: &[Vector2<f64>], indices: &[usize]) -> DiscTree {
        let mut tree = DiscTree {
            nodes: Vec::new(),
            rule: DiscTreeRule::Median,
        };
        if !indices.is_empty() {
            let mut work = indices.to_vec();
            tree.build_node(centres, &mut work);
        }
        tree
    }

    /// The Java starter's tree ([`DiscTreeRule::Starter`]) over the blocks `indices`, with
    /// body-frame centres `centres[i]` for the discs and image positions `pixels[i]` (whole
    /// numbers) for the splits: a node's blocks go to the first child when 2 p < min + max along
    /// the split axis, which is exact in whole numbers. (The starter compares body-frame
    /// positions with the box's middle in floating point; for a block exactly at the middle both
    /// sides are the same difference from the centre of mass, so it agrees except where the
    /// centre of mass is so far from the blocks that the subtraction rounds.)
    pub fn build_starter(
        centres: &[Vector2<f64>],
        pixels: &[Vector2<f64>],
        indices: &[usize],
    ) -> DiscTree {
        let mut tree = DiscTree {
            nodes: Vec::new(),
            rule: DiscTreeRule::Starter,
        };
        if !indices.is_empty() {
            tree.build_starter_node(centres, pixels, indices);
        }
        tree
    }

    /// A node's disc: the minimum enclosing circle of its blocks' centres, plus a block's radius;
    /// pushed as a leaf of its first block (an inner node's children are set by the caller).
    fn push_node(&mut self, centres: &[Vector2<f64>], blocks: &[usize]) -> usize {
        let points: Vec<Vector2<f64>> = blocks.iter().map(|&b| centres[b]).collect();
        let circle = min_enclosing_circle(&points).expect("non-empty");
        self.nodes.push(DiscNode {
            centre: circle.centre,
            radius: circle.radius + BLOCK_RADIUS,
            kind: NodeKind::Leaf(blocks[0]),
        });
        self.nodes.len() - 1
    }

    fn build_starter_node(
        &mut self,
        centres: &[Vector2<f64>],
        pixels: &[Vector2<f64>],
        blocks: &[usize],
    ) -> usize {
        let id = self.push_node(centres, blocks);
        if blocks.len() > 1 {
            let (mut lo, mut hi) = (pixels[blocks[0]], pixels[blocks[0]]);
            for &b in blocks {
                lo = lo.inf(&pixels[b]);
                hi = hi.sup(&pixels[b]);
            }
            let axis = if hi.y - lo.y > hi.x - lo.x { 1 } else { 0 };
            let (first, second): (Vec<usize>, Vec<usize>) = blocks
                .iter()
                .partition(|&&b| 2.0 * pixels[b][axis] < lo[axis] + hi[axis]);
            let l = self.build_starter_node(centres, pixels, &first);
            let r = self.build_starter_node(centres, pixels, &second);
            self.nodes[id].kind = NodeKind::Inner(l, r);
        }
        id
    }

    fn build_node(&mut self, centres: &[Vector2<f64>], blocks: &mut [usize]) -> usize {
        let id = self.push_node(centres, blocks);
        if blocks.len() > 1 {
            let points: Vec<Vector2<f64>> = blocks.iter().map(|&b| centres[b]).collect();
            let (mut lo, mut hi) = (points[0], points[0]);
            for p in &points {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
            let axis = if hi.x - lo.x >= hi.y - lo.y { 0 } else { 1 };
            blocks.sort_by(|&a, &b| {
                centres[a][axis]
                    .total_cmp(&centres[b][axis])
                    .then(a.cmp(&b))
            });
            let half = blocks.len() / 2;
            let (left, right) = blocks.split_at_mut(half);
            let l = self.build_node(centres, left);
            let r = self.build_node(centres, right);
            self.nodes[id].kind = NodeKind::Inner(l, r);
        }
        id
    }

    /// The root disc, if the tree has blocks.
    pub fn root(&self) -> Option<&DiscNode> {
        self.nodes.first()
    }
}

#[cfg(test)]
mod tests {
    //! Structure on small cases; that the tree finds exactly the touching block pairs is
    //! tests/suite/blocks2d/properties.rs::disc_tree_finds_exactly_the_block_pairs_the_brute_force_test_finds.

    use super::*;

    /// The blocks below node `i` (its leaves), after checking that the node's disc contains
    /// every one of their block discs (centre `centres[b]`, radius [`BLOCK_RADIUS`]).
    fn leaves(tree: &DiscTree, centres: &[Vector2<f64>], i: usize) -> Vec<usize> {
        let node = &tree.nodes[i];
        let below = match node.kind {
            NodeKind::Leaf(b) => vec![b],
            NodeKind::Inner(a, b) => {
                let mut v = leaves(tree, centres, a);
                v.extend(leaves(tree, centres, b));
                v
            }
        };
        for &b in &below {
            // Round-off only: the radius is a square root of sums of squares.
            let reach = (centres[b] - node.centre).norm() + BLOCK_RADIUS;
            assert!(
                reach <= node.radius + 1e-9,
                "node {i} does not contain block {b}"
            );
        }
        below
    }

    #[test]
    fn an_empty_body_has_no_tree_and_one_block_is_a_single_leaf() {
        assert!(DiscTree::build(&[], &[]).root().is_none());
        let tree = DiscTree::build(&[Vector2::new(2.0, 5.0)], &[0]);
        assert_eq!(tree.nodes.len(), 1);
        let root = tree.root().unwrap();
        assert_eq!(root.kind, NodeKind::Leaf(0));
        assert_eq!(
            (root.centre, root.radius),
            (Vector2::new(2.0, 5.0), BLOCK_RADIUS)
        );
    }

    #[test]
    fn every_block_is_one_leaf_and_every_disc_contains_the_block_discs_below_it() {
        let centres: Vec<Vector2<f64>> = (0..7)
            .flat_map(|i| (0..3).map(move |j| Vector2::new(i as f64, j as f64)))
            .collect();
        let indices: Vec<usize> = (0..centres.len()).collect();
        let tree = DiscTree::build(&centres, &indices);
        let mut found = leaves(&tree, &centres, 0);
        found.sort();
        assert_eq!(found, indices);
        // A full binary tree over n leaves has 2n − 1 nodes.
        assert_eq!(tree.nodes.len(), 2 * centres.len() - 1);
    }

    #[test]
    fn the_starter_tree_splits_at_the_middle_of_the_box_below_it_first() {
        // A bar of 3 blocks: the middle block is at the box's middle, not below it, so it goes
        // with the right one; a 2 × 2 square is as tall as wide, so split across x.
        let pixels: Vec<Vector2<f64>> = [(4.0, 7.0), (5.0, 7.0), (6.0, 7.0)]
            .map(|(x, y)| Vector2::new(x, y))
            .to_vec();
        let centres: Vec<Vector2<f64>> =
            pixels.iter().map(|p| p - Vector2::new(5.0, 7.0)).collect();
        let tree = DiscTree::build_starter(&centres, &pixels, &[0, 1, 2]);
        let NodeKind::Inner(l, r) = tree.nodes[0].kind else {
            panic!("the root of three blocks is inner")
        };
        assert_eq!(leaves(&tree, &centres, l), [0]);
        assert_eq!(leaves(&tree, &centres, r), [1, 2]);
        assert_eq!(tree.rule, DiscTreeRule::Starter);
        let square: Vec<Vector2<f64>> = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .map(|(x, y)| Vector2::new(x, y))
            .to_vec();
        let tree = DiscTree::build_starter(&square, &square, &[0, 1, 2, 3]);
        let NodeKind::Inner(l, _) = tree.nodes[0].kind else {
            panic!("inner")
        };
        assert_eq!(leaves(&tree, &square, l), [0, 2]);
    }
}
