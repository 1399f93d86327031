//! 2D collision: block discs, bounding-disc trees, sweep-and-prune between bodies.
//! docs/blocks2d.md §"Collision".

use super::body::Body2;
use super::disc_tree::{BLOCK_RADIUS, DiscTreeRule, NodeKind};
use crate::common::broad::{Aabb, overlapping_pairs};
use nalgebra::{Vector2, Vector3};

/// A contact between two overlapping block discs of different bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact2 {
    /// Body 1 and its block.
    pub body1: usize,
    /// Index of body 1's block.
    pub block1: usize,
    /// Body 2 and its block.
    pub body2: usize,
    /// Index of body 2's block.
    pub block2: usize,
    /// Midpoint of the two block centres, world frame.
    pub point: Vector2<f64>,
    /// Unit normal along the line of centres, from body 2's block to body 1's.
    pub normal: Vector2<f64>,
    /// Penetration 2r − distance, > 0, blocks.
    pub depth: f64,
}

/// The tangent of a 2D contact: n turned by +90°, t = (−n_y, n_x).
pub fn tangent(n: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-n.y, n.x)
}

/// The world box of a body's root disc (z = 0, for the shared sweep-and-prune).
fn root_box(body: &Placed) -> Option<Aabb> {
    let root = body.body.tree.root()?;
    let c = body.to_world(&root.centre);
    let r = Vector3::new(root.radius, root.radius, 0.0);
    let c = Vector3::new(c.x, c.y, 0.0);
    Some(Aabb {
        min: c - r,
        max: c + r,
    })
}

/// How much farther apart than touching two nodes' discs must be for the descent to prune them,
/// blocks: far above round-off, so that every pair of leaves whose discs overlap (as their own
/// test computes it) is reached even where a node's disc touches its children's from inside (a
/// minimum enclosing circle does), and the contacts are exactly the leaves' tests that pass
/// (which [`super::coherence`] relies on).
pub const PRUNE_SLACK: f64 = 1e-9;

/// A body with its rotation matrix computed once (a pair's traversal places many points; the
/// same arithmetic as [`Body2::to_world`], so the same bits).
pub(super) struct Placed<'a> {
    body: &'a Body2,
    rotation: nalgebra::Matrix2<f64>,
}

impl<'a> Placed<'a> {
    pub(super) fn new(body: &'a Body2) -> Placed<'a> {
        Placed {
            body,
            rotation: body.rotation(),
        }
    }

    /// With its rotation matrix already computed (`body.rotation()`, the same bits).
    pub(super) fn with_rotation(body: &'a Body2, rotation: nalgebra::Matrix2<f64>) -> Placed<'a> {
        Placed { body, rotation }
    }

    pub(super) fn to_world(&self, local: &Vector2<f64>) -> Vector2<f64> {
        self.body.x + self.rotation * local
    }
}

fn block_contact(bodies: &[Body2], i: usize, a: usize, j: usize, b: usize) -> Option<Contact2> {
    let (bi, bj) = (Placed::new(&bodies[i]), Placed::new(&bodies[j]));
    placed_block_contact((i, &bi), a, (j, &bj), b)
}

/// The contact of block a of body i and block b of body j if their discs overlap.
pub(super) fn placed_block_contact(
    (i, bi): (usize, &Placed),
    a: usize,
    (j, bj): (usize, &Placed),
    b: usize,
) -> Option<Contact2> {
    let pa = bi.to_world(&bi.body.blocks[a].local);
    let pb = bj.to_world(&bj.body.blocks[b].local);
    let d = pa - pb;
    let distance = d.norm();
    let depth = 2.0 * BLOCK_RADIUS - distance;
    // Coincident centres have no line of centres; such a pair is already hopelessly overlapped
    // and is left to the neighbouring blocks' contacts.
    (depth > 0.0 && distance > 1e-12).then(|| Contact2 {
        body1: i,
        block1: a,
        body2: j,
        block2: b,
        point: (pa + pb) / 2.0,
        normal: d / distance,
        depth,
    })
}

/// Appends the contacts of bodies `i` and `j` found by descending both trees together: a pair of
/// nodes whose discs overlap is split (the larger disc first) until both are leaves.
pub fn tree_contacts(
    bodies: &[Body2],
    i: usize,
    j: usize,
    stack: &mut Vec<(usize, usize)>,
    out: &mut Vec<Contact2>,
) {
    let (bi, bj) = (Placed::new(&bodies[i]), Placed::new(&bodies[j]));
    placed_tree_contacts((i, &bi), (j, &bj), stack, out);
}

/// [`tree_contacts`] of two placed bodies (their rotations already formed).
pub(super) fn placed_tree_contacts(
    (i, bi): (usize, &Placed),
    (j, bj): (usize, &Placed),
    stack: &mut Vec<(usize, usize)>,
    out: &mut Vec<Contact2>,
) {
    descend(bi, bj, PRUNE_SLACK, stack, |ba, bb| {
        if let Some(c) = placed_block_contact((i, bi), ba, (j, bj), bb) {
            out.push(c);
        }
    });
}

/// The descent of two bodies' trees together: from the roots, a pair of nodes whose discs,
/// grown by `grow` (blocks), overlap is split (the larger disc first) until both are leaves, and
/// `leaf(block of i, block of j)` is called for each pair of leaves reached. Which node is split
/// depends only on the radii (and, for equal ones, on body i's tree's [`DiscTreeRule`]), so growing the discs prunes less and keeps the order of the leaves
/// reached ([`super::coherence`] relies on it).
pub(super) fn descend(
    bi: &Placed,
    bj: &Placed,
    grow: f64,
    stack: &mut Vec<(usize, usize)>,
    mut leaf: impl FnMut(usize, usize),
) {
    let (ti, tj) = (&bi.body.tree, &bj.body.tree);
    if ti.nodes.is_empty() || tj.nodes.is_empty() {
        return;
    }
    stack.clear();
    stack.push((0, 0));
    while let Some((a, b)) = stack.pop() {
        let (na, nb) = (&ti.nodes[a], &tj.nodes[b]);
        let ca = bi.to_world(&na.centre);
        let cb = bj.to_world(&nb.centre);
        if (ca - cb).norm() >= na.radius + nb.radius + grow {
            continue;
        }
        match (na.kind, nb.kind) {
            (NodeKind::Leaf(ba), NodeKind::Leaf(bb)) => leaf(ba, bb),
            (NodeKind::Inner(l, r), NodeKind::Leaf(_)) => {
                stack.push((r, b));
                stack.push((l, b));
            }
            (NodeKind::Leaf(_), NodeKind::Inner(l, r)) => {
                stack.push((a, r));
                stack.push((a, l));
            }
            (NodeKind::Inner(al, ar), NodeKind::Inner(bl, br)) => {
                // The larger disc is split first; equal discs split body 1's node (rigidref's)
                // or body 2's (the starter's descent, DiscTreeRule::Starter).
                let first = match ti.rule {
                    DiscTreeRule::Median => na.radius >= nb.radius,
                    DiscTreeRule::Starter => na.radius > nb.radius,
                };
                if first {
                    stack.push((ar, b));
                    stack.push((al, b));
                } else {
                    stack.push((a, br));
                    stack.push((a, bl));
                }
            }
        }
    }
}

/// All contacts between bodies: sweep-and-prune on the root discs' boxes, then tree against
/// tree for each overlapping pair that is not two pinned bodies. Deterministic order: pairs
/// ascending, then tree order.
pub fn detect_contacts(bodies: &[Body2], out: &mut Vec<Contact2>) {
    out.clear();
    let mut stack = Vec::new();
    for (i, j) in overlapping_body_pairs(bodies, &mut Vec::new()) {
        tree_contacts(bodies, i, j, &mut stack, out);
    }
}

/// The broad phase: the pairs i < j, ascending, whose root discs' boxes overlap and that are not
/// two pinned bodies (`boxes` is a buffer).
pub fn overlapping_body_pairs(bodies: &[Body2], boxes: &mut Vec<Aabb>) -> Vec<(usize, usize)> {
    root_boxes(bodies, boxes);
    let mut pairs = overlapping_pairs(boxes);
    pairs.retain(|&(i, j)| !(bodies[i].pinned && bodies[j].pinned));
    pairs
}

/// The world boxes of the bodies' root discs into `boxes` (replaced; an empty box for a body
/// without blocks).
pub fn root_boxes(bodies: &[Body2], boxes: &mut Vec<Aabb>) {
    boxes.clear();
    boxes.extend(bodies.iter().map(|b| placed_root_box(&Placed::new(b))));
}

/// A placed body's root disc's world box (an empty box for a body without blocks).
pub(super) fn placed_root_box(body: &Placed) -> Aabb {
    root_box(body).unwrap_or(Aabb {
        min: Vector3::repeat(f64::INFINITY),
        max: Vector3::repeat(f64::NEG_INFINITY),
    })
}

/// The same contacts by testing every boundary block of every body against every boundary block
/// of every other (non-pinned-pair) body. O(blocks²); the oracle for the trees.
pub fn brute_force_contacts(bodies: &[Body2]) -> Vec<Contact2> {
    let mut out = Vec::new();
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            if bodies[i].pinned && bodies[j].pinned {
                continue;
            }
            for &a in &bodies[i].boundary {
                for &b in &bodies[j].boundary {
                    if let Some(c) = block_contact(bodies, i, a, j, b) {
                        out.push(c);
                    }
                }
            }
        }
    }
    out
}
