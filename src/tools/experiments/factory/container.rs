//! The factory's container, its size for a number of bodies, and the drop zone above it.

use super::*;

/// Room for a pile, in block² of container per block of the pieces: measured piles of
/// polyominoes and of bricks dropped by the factory fill 1.4 to 1.6 (the gaps between bodies and
/// the √2-diameter collision discs); 2 leaves a margin.
pub const PILE_ROOM: f64 = 2.0;

/// The width and depth (blocks) of a generated container that holds `bodies` pieces with room to
/// spare ([`PILE_ROOM`]), five wide for three deep, at least 20 × 12.
pub fn container_size(bodies: usize, pieces: Pieces, scale: usize) -> (usize, usize) {
    let area = bodies as f64 * pieces.mean_blocks(scale) * PILE_ROOM;
    let depth = (area * 3.0 / 5.0).sqrt().ceil().max(12.0);
    let width = (area / depth).ceil().max(20.0);
    (width as usize, depth as usize)
}

/// Where the factory places new bodies: across the container, just above the pile in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DropZone {
    /// Leftmost and rightmost x at which bodies are placed, blocks.
    pub x: (f64, f64),
    /// The container's rim: the top of its pinned bodies, y (the world's y grows downward:
    /// smaller is higher), blocks.
    pub rim: f64,
    /// The container's floor: the bottom of its pinned bodies, y, blocks.
    pub floor: f64,
    /// The leftmost and rightmost x of the container's pinned bodies, blocks.
    pub sides: (f64, f64),
}

impl DropZone {
    /// The zone of the pinned bodies of `world`: across their extent less 6 blocks at each end
    /// (inside a container's walls); `None` when there is no pinned body.
    pub fn above_pinned(world: &World2) -> Option<DropZone> {
        let (mut lo, mut hi) = (
            Vector2::repeat(f64::INFINITY),
            Vector2::repeat(f64::NEG_INFINITY),
        );
        for b in world.bodies.iter().filter(|b| b.pinned) {
            for block in &b.blocks {
                let p = b.to_world(&block.local);
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
        }
        if !lo.x.is_finite() {
            return None;
        }
        Some(DropZone {
            x: (lo.x + 6.0, (hi.x - 6.0).max(lo.x + 12.0)),
            rim: lo.y,
            floor: hi.y,
            sides: (lo.x, hi.x),
        })
    }

    /// The top of the pile: the highest block (smallest y) of the moving bodies touching
    /// something in the last substep, or the floor while nothing has landed.
    pub fn pile_top(&self, world: &World2) -> f64 {
        let mut top = self.floor;
        for c in &world.contacts {
            for i in [c.body1, c.body2] {
                let b = &world.bodies[i];
                if !b.pinned {
                    for block in &b.blocks {
                        top = top.min(b.to_world(&block.local).y);
                    }
                }
            }
        }
        top
    }

    /// The free interior of the container at the heights `band` (y from, y to; y grows
    /// downward), blocks: in each row of pinned blocks in the band that is open around the
    /// container's middle, from just right of the nearest pinned block left of the middle to just
    /// left of the nearest one right of it; the narrowest over those rows. Rows closed across the
    /// middle (the floor) are passed over. `None` where no row in the band has walls on both sides
    /// (above the rim).
    pub fn interior(&self, world: &World2, band: (f64, f64)) -> Option<(f64, f64)> {
        let middle = 0.5 * (self.sides.0 + self.sides.1);
        // Per row: the nearest wall left and right of the middle.
        let mut rows: std::collections::BTreeMap<i64, (f64, f64)> = Default::default();
        for b in world.bodies.iter().filter(|b| b.pinned) {
            for block in &b.blocks {
                let p = b.to_world(&block.local);
                if p.y < band.0 - 1.0 || p.y > band.1 + 1.0 {
                    continue;
                }
                let row = rows
                    .entry(p.y.round() as i64)
                    .or_insert((f64::NEG_INFINITY, f64::INFINITY));
                if p.x < middle {
                    row.0 = row.0.max(p.x);
                } else {
                    row.1 = row.1.min(p.x);
                }
            }
        }
        rows.values()
            .filter(|(l, r)| l.is_finite() && r.is_finite() && r - l > 2.0)
            .map(|&(l, r)| (l + 1.0, r - 1.0))
            .reduce(|a, b| (a.0.max(b.0), a.1.min(b.1)))
    }

    /// Whether a body's centre has left the container: below its floor or beside its walls
    /// (such a body has escaped through them, or spilled over, and falls for ever).
    pub fn is_outside(&self, body: &Body2) -> bool {
        body.x.y > self.floor || body.x.x < self.sides.0 || body.x.x > self.sides.1
    }

    /// Whether the pile has reached the rim.
    pub fn is_full(&self, world: &World2) -> bool {
        self.pile_top(world) <= self.rim
    }
}

/// Whether any block disc of body `i` overlaps a block disc of another body (pinned or not),
/// by the same tree traversal the step uses.
pub(super) fn overlaps_any_other(bodies: &[Body2], i: usize) -> bool {
    let (mut stack, mut found) = (Vec::new(), Vec::new());
    (0..bodies.len()).filter(|&j| j != i).any(|j| {
        tree_contacts(bodies, i, j, &mut stack, &mut found);
        !found.is_empty()
    })
}

/// Thickness of a generated container's floor and walls, blocks: thick enough that the bottom
/// of a deep pile, pressed down by a solver that has not converged, cannot be pushed through.
pub const CONTAINER_WALL: usize = 3;

/// An open box of pinned blue blocks (RGB 0, 0, 163, as in the assignment's images), `width`
/// blocks inside and `depth` deep: the inside spans columns 0..width and rows 0..depth, the
/// floor and walls [`CONTAINER_WALL`] blocks thick around it.
pub fn container(width: usize, depth: usize) -> BlockGroup {
    let colour = [0.0, 0.0, 163.0 / 255.0];
    let wall = CONTAINER_WALL as i64;
    let (w, d) = (width as i64, depth as i64);
    let blocks = (0..d + wall)
        .flat_map(|i| (-wall..w + wall).map(move |j| (i, j)))
        .filter(|&(i, j)| i >= d || j < 0 || j >= w)
        .map(|(i, j)| Block {
            pixel: Vector2::new(j as f64, i as f64),
            colour,
            mass: block_mass(colour),
        })
        .collect();
    BlockGroup {
        blocks,
        pinned: true,
        boundary: None,
    }
}
