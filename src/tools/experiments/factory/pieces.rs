//! What the factory drops: random blobs of blocks, bricks or tetrominoes (the Tetris tube).

use super::*;

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

pub(super) const TETROMINOES: [Tetromino; 7] = [
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
    pub(super) rng: ChaCha8Rng,
    /// What it makes.
    pub pieces: Pieces,
    /// Each cell of a piece is `scale` × `scale` blocks (the Tetris tube's pieces are 4 × 4).
    pub scale: usize,
}

impl Factory {
    /// The largest distance from a piece's centre of mass to the edge of its bounding disc,
    /// blocks: a bound for every piece this factory makes.
    pub fn largest_reach(&self) -> f64 {
        let cells = match self.pieces {
            Pieces::Tetris => 4.0,
            Pieces::Bricks => 8.0,
            Pieces::Random => 9.0,
        };
        (cells * self.scale.max(1) as f64) + 1.0
    }

    /// The same factory making pieces of `scale` blocks per cell.
    pub fn with_scale(mut self, scale: usize) -> Factory {
        self.scale = scale;
        self
    }

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
            boundary: None,
        });
        body.x = at;
        body
    }

    /// A random dark colour that is never a shade of blue (that would pin the body): the red
    /// channel is the highest.
    pub(super) fn dark_colour(&mut self) -> [f64; 3] {
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
        let pile_top = zone.pile_top(world);
        // Inside the container's walls at the height bodies are placed at: a container whose
        // walls are not vertical (the Tetris tube's funnel) is narrower below its rim than its
        // pinned bodies' whole extent, and a body placed beside the tube falls outside it.
        let band = (pile_top - 4.0 - 2.0 * self.largest_reach(), pile_top);
        let (lo, hi, walled) = match zone.interior(world, band) {
            Some((l, r)) if l > zone.x.0 || r < zone.x.1 => {
                (l.max(zone.x.0), r.min(zone.x.1), true)
            }
            _ => (zone.x.0, zone.x.1, false),
        };
        let slot = (hi - lo) / n.max(1) as f64;
        let mut placed = 0;
        for s in 0..n {
            let x = lo + slot * (s as f64 + 0.5) + self.uniform(-0.25, 0.25) * slot;
            let mut body = self.make(Vector2::new(x, pile_top));
            // Lift it so that its bounding disc ends four blocks above the pile.
            let reach = body.tree.root().map_or(0.0, |r| r.centre.norm() + r.radius);
            body.x.y -= reach + 4.0;
            if walled {
                // Keep its bounding disc off the walls where there is room for it.
                let (a, b) = (lo + reach, hi - reach);
                body.x.x = if a < b {
                    body.x.x.clamp(a, b)
                } else {
                    0.5 * (lo + hi)
                };
            }
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
