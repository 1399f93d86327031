//! The factory: random bodies dropped into a container at an interval, for stress tests and the
//! scaling report; and the Tetris variant. docs/blocks2d.md §"Challenges".

use super::body::Body2;
use super::collide::tree_contacts;
use super::image::{Block, BlockGroup, block_mass};
use super::world::World2;
use nalgebra::Vector2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The kind of bodies the factory makes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Pieces {
    /// Random polyominoes of 3 to 9 blocks, in random dark colours.
    #[default]
    Random,
    /// The seven tetrominoes, in their usual colours.
    Tetris,
    /// Bricks: rectangles 2 to 8 blocks long and 1 to 3 high, in random dark colours, like the
    /// assignment's wall images. Lying flat on one another they touch along whole edges, so a
    /// pile of bricks has more contacts per body than a pile of polyominoes (measured: 4 against
    /// 3).
    Bricks,
}

impl Pieces {
    /// The mean number of blocks of a piece whose cells are `scale` × `scale` blocks.
    pub fn mean_blocks(self, scale: usize) -> f64 {
        let cells = match self {
            Pieces::Random => 6.0,  // 3 to 9 cells, uniform
            Pieces::Tetris => 4.0,  // four cells
            Pieces::Bricks => 10.0, // (2 to 8) × (1 to 3), uniform: 5 × 2
        };
        cells * (scale * scale) as f64
    }
}

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

/// A tetromino: its four cells and its colour.
type Tetromino = ([(i64, i64); 4], [f64; 3]);

const TETROMINOES: [Tetromino; 7] = [
    ([(0, 0), (1, 0), (2, 0), (3, 0)], [0.0, 0.55, 0.55]), // I
    ([(0, 0), (1, 0), (0, 1), (1, 1)], [0.75, 0.65, 0.0]), // O
    ([(0, 0), (1, 0), (2, 0), (1, 1)], [0.5, 0.0, 0.5]),   // T
    ([(1, 0), (2, 0), (0, 1), (1, 1)], [0.0, 0.5, 0.0]),   // S
    ([(0, 0), (1, 0), (1, 1), (2, 1)], [0.7, 0.0, 0.0]),   // Z
    ([(0, 0), (0, 1), (1, 1), (2, 1)], [0.1, 0.1, 0.45]),  // J (dark, not pure blue: not pinned)
    ([(2, 0), (0, 1), (1, 1), (2, 1)], [0.8, 0.4, 0.0]),   // L
];

/// Makes bodies from a seeded generator.
pub struct Factory {
    rng: ChaCha8Rng,
    /// What it makes.
    pub pieces: Pieces,
    /// Each cell of a piece is `scale` × `scale` blocks (the Tetris tube's pieces are 4 × 4).
    pub scale: usize,
}

impl Factory {
    /// A factory with a seed.
    pub fn new(seed: u64, pieces: Pieces) -> Factory {
        Factory {
            rng: ChaCha8Rng::seed_from_u64(seed),
            pieces,
            scale: 1,
        }
    }

    /// The next body, its centre of mass at `at`, at rest, turned by a random multiple of 90°.
    pub fn make(&mut self, at: Vector2<f64>) -> Body2 {
        let (cells, colour): (Vec<(i64, i64)>, [f64; 3]) = match self.pieces {
            Pieces::Tetris => {
                let (c, col) = TETROMINOES[self.rng.random_range(0..7)];
                (c.to_vec(), col)
            }
            Pieces::Bricks => {
                let (w, h) = (self.rng.random_range(2..=8), self.rng.random_range(1..=3));
                let cells = (0..w * h).map(|k| (k % w, k / w)).collect();
                (cells, self.dark_colour())
            }
            Pieces::Random => {
                let n = self.rng.random_range(3..=9);
                let mut cells = vec![(0i64, 0i64)];
                while cells.len() < n {
                    let (x, y) = cells[self.rng.random_range(0..cells.len())];
                    let (dx, dy) = [(1, 0), (-1, 0), (0, 1), (0, -1)][self.rng.random_range(0..4)];
                    if !cells.contains(&(x + dx, y + dy)) {
                        cells.push((x + dx, y + dy));
                    }
                }
                (cells, self.dark_colour())
            }
        };
        let turns = self.rng.random_range(0..4);
        let s = self.scale.max(1) as i64;
        let blocks = cells
            .iter()
            .flat_map(|&(x, y)| {
                let (mut x, mut y) = (x, y);
                for _ in 0..turns {
                    (x, y) = (-y, x);
                }
                (0..s * s).map(move |k| {
                    let p = Vector2::new((x * s + k % s) as f64, (y * s + k / s) as f64);
                    Block {
                        pixel: p,
                        colour,
                        mass: block_mass(colour),
                    }
                })
            })
            .collect();
        let mut body = Body2::from_group(&BlockGroup {
            blocks,
            pinned: false,
        });
        body.x = at;
        body
    }

    /// A random dark colour that is never a shade of blue (that would pin the body): the red
    /// channel is the highest.
    fn dark_colour(&mut self) -> [f64; 3] {
        let r = self.rng.random_range(0.2..0.6);
        [
            r,
            self.rng.random_range(0.0..r),
            self.rng.random_range(0.0..r),
        ]
    }

    /// A uniform random number in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.rng.random_range(lo..hi)
    }

    /// Drops up to `n` new bodies into `world`: one per slot of `zone` (a random offset within
    /// the slot), each placed with its lowest point about four blocks above the pile
    /// ([`DropZone::pile_top`]) and moving down (+y) at `speed`. Dropping onto the pile, not from
    /// the rim, keeps the impact speed low however deep the container: a body falling the depth
    /// of a deep container would move more than a block-disc radius per step at the starter's
    /// step and could pass through a one-block floor or a one-block body. A body whose block
    /// discs would overlap another body's is not placed (the next drop tries again): spawning
    /// bodies inside one another starts them with overlaps no contact model resolves
    /// gracefully. Returns how many were placed.
    pub fn drop_batch(
        &mut self,
        world: &mut World2,
        zone: &DropZone,
        n: usize,
        speed: f64,
    ) -> usize {
        let slot = (zone.x.1 - zone.x.0) / n.max(1) as f64;
        let pile_top = zone.pile_top(world);
        let mut placed = 0;
        for s in 0..n {
            let x = zone.x.0 + slot * (s as f64 + 0.5) + self.uniform(-0.25, 0.25) * slot;
            let mut body = self.make(Vector2::new(x, pile_top));
            // Lift it so that its bounding disc ends four blocks above the pile.
            let reach = body.tree.root().map_or(0.0, |r| r.centre.norm() + r.radius);
            body.x.y -= reach + 4.0;
            body.v = Vector2::new(0.0, speed);
            world.add_body(body);
            if overlaps_any_other(&world.bodies, world.bodies.len() - 1) {
                world.bodies.pop();
            } else {
                placed += 1;
            }
        }
        placed
    }
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
        for c in &world.last.contacts {
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
fn overlaps_any_other(bodies: &[Body2], i: usize) -> bool {
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
    }
}
