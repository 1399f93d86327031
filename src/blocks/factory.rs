//! The factory: random bodies dropped into a container at an interval, for stress tests and the
//! scaling report; and the Tetris variant. docs/blocks2d.md §"Challenges".

use super::body::Body2;
use super::image::{Block, BlockGroup, block_mass};
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
                // Dark, and never a shade of blue (that would pin it): red channel highest.
                let r = self.rng.random_range(0.2..0.6);
                let colour = [
                    r,
                    self.rng.random_range(0.0..r),
                    self.rng.random_range(0.0..r),
                ];
                (cells, colour)
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

    /// A uniform random number in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.rng.random_range(lo..hi)
    }
}

/// An open box of pinned blue blocks: floor `width` blocks wide at row `depth`, walls `depth`
/// high at columns 0 and width − 1.
pub fn container(width: usize, depth: usize) -> BlockGroup {
    let colour = [0.0, 0.0, 163.0 / 255.0];
    let mut blocks = Vec::new();
    for j in 0..width {
        blocks.push(Block {
            pixel: Vector2::new(j as f64, depth as f64),
            colour,
            mass: block_mass(colour),
        });
    }
    for i in 0..depth {
        for j in [0, width - 1] {
            blocks.push(Block {
                pixel: Vector2::new(j as f64, i as f64),
                colour,
                mass: block_mass(colour),
            });
        }
    }
    BlockGroup {
        blocks,
        pinned: true,
    }
}
