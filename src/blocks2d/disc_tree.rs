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

/// The tree; node 0 is the root.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DiscTree {
    /// The nodes.
    pub nodes: Vec<DiscNode>,
}

impl DiscTree {
    /// Builds the tree over the blocks `indices` with body-frame centres `centres[i]`: each node
    /// is split at the median along the longer side of its blocks' bounding box.
    pub fn build(centres: &[Vector2<f64>], indices: &[usize]) -> DiscTree {
        let mut tree = DiscTree { nodes: Vec::new() };
        if !indices.is_empty() {
            let mut work = indices.to_vec();
            tree.build_node(centres, &mut work);
        }
        tree
    }

    fn build_node(&mut self, centres: &[Vector2<f64>], blocks: &mut [usize]) -> usize {
        let points: Vec<Vector2<f64>> = blocks.iter().map(|&b| centres[b]).collect();
        let circle = min_enclosing_circle(&points).expect("non-empty");
        let id = self.nodes.len();
        self.nodes.push(DiscNode {
            centre: circle.centre,
            radius: circle.radius + BLOCK_RADIUS,
            kind: NodeKind::Leaf(blocks[0]),
        });
        if blocks.len() > 1 {
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
}
