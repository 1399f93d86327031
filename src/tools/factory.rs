//! The factory: random bodies dropped into a container at an interval, for stress tests and the
//! scaling report; and the Tetris variant. docs/blocks2d.md §"Challenges".

use crate::blocks2d::assemble::ContactProblem2;
use crate::blocks2d::body::Body2;
use crate::blocks2d::collide::tree_contacts;
use crate::blocks2d::image::{Block, BlockGroup, block_mass};
use crate::blocks2d::image::{ImageSettings, load_image};
use crate::blocks2d::params::Params2;
use crate::blocks2d::world::World2;
use crate::sim::{Flow, SolveTotals, drive};
use crate::tools::scaling::{LinearFit, linear_fit, plot, retime};
use nalgebra::Vector2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::io::Write;
use std::path::Path;

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

/// Drops in a row that place nothing before the container counts as full.
pub const FULL_AFTER: u32 = 20;

/// Contact problems kept during the run for re-timing (spread evenly over the planned steps).
pub const RETIMED_PROBLEMS: u64 = 100;

/// The viewer page of a factory run (docs/viewing.md): the final world's bodies, each drawn
/// from the record where it was dropped on; the plots of the run.
fn write_view_page(
    world: &World2,
    records: &[crate::blocks2d::trace::Record2],
    path: &Path,
) -> Result<(), String> {
    use crate::tools::view::{DEFAULT_MAX_FRAMES, html, view_data_2d};
    let header =
        crate::blocks2d::trace::TraceHeader2::for_world(world, "factory", "rigidref factory");
    let pinned: Vec<bool> = world.bodies.iter().map(|b| b.pinned).collect();
    let omega = crate::tools::series::default_omega_bodies(&pinned);
    let data = view_data_2d(&header, records, world, &[], DEFAULT_MAX_FRAMES, &omega);
    std::fs::write(path, html(&data)).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Block discs of different bodies overlapping by more than this at the end of a factory run, in
/// blocks, mean the pile did not hold (a tenth of a disc's diameter √2; a sound pile ends near
/// the post-stabilisation slop, 0.01): a 10 000-brick run with the default 10 sweeps ends with
/// discs through each other (docs/performance.md §"Targets of issue 20").
pub const CRUSHED_OVERLAP: f64 = 0.1 * std::f64::consts::SQRT_2;

/// Rounds of re-timing: each problem's time is the median of this many solves.
pub const RETIME_ROUNDS: usize = 5;

/// What a factory run does (the `rigidref factory` options).
#[derive(Clone, Debug, PartialEq)]
pub struct FactorySettings {
    /// Bodies to drop.
    pub bodies: usize,
    /// Bodies per batch.
    pub batch: usize,
    /// Time between batches.
    pub interval: f64,
    /// Downward speed of a dropped body, blocks per time unit.
    pub drop_speed: f64,
    /// Time to run after the last drop.
    pub settle: f64,
    /// Width of the generated container, blocks (default: sized for `bodies`).
    pub width: Option<usize>,
    /// Depth of the generated container, blocks (default: sized for `bodies`).
    pub depth: Option<usize>,
    /// The container's pinned bodies from this image instead (e.g. tetrisTube.png).
    pub container: Option<std::path::PathBuf>,
    /// What to drop.
    pub pieces: Pieces,
    /// Blocks per side of a piece's cell.
    pub piece_scale: usize,
    /// Seed of the factory and of PGS's random order.
    pub seed: u64,
    /// PGS sweeps per solve.
    pub iterations: u32,
    /// Substeps per step.
    pub substeps: u32,
    /// Record the state every this many steps for the viewer page DIR/view.html (0: no page).
    pub view_every: u64,
}

impl FactorySettings {
    /// Checks every value's range; the message names the option.
    pub fn check(&self) -> Result<(), String> {
        if self.bodies == 0
            || self.batch == 0
            || self.iterations == 0
            || self.substeps == 0
            || self.piece_scale == 0
        {
            return Err(
                "--bodies, --batch, --iterations, --substeps and --piece-scale must be at least 1"
                    .into(),
            );
        }
        if !(self.interval.is_finite() && self.interval > 0.0) {
            return Err(format!(
                "--interval must be a positive number, got {}",
                self.interval
            ));
        }
        if !(self.settle.is_finite() && self.settle >= 0.0) {
            return Err(format!(
                "--settle must be a number ≥ 0, got {}",
                self.settle
            ));
        }
        if !(self.drop_speed.is_finite() && self.drop_speed >= 0.0) {
            return Err(format!(
                "--drop-speed must be a number ≥ 0, got {}",
                self.drop_speed
            ));
        }
        if self.width.is_some_and(|w| w < 10) || self.depth.is_some_and(|d| d < 5) {
            return Err("the container must be at least 10 wide and 5 deep".into());
        }
        // Far above any useful run, so that an absurd value is an error, not a run that never ends.
        if self.bodies > 1_000_000 {
            return Err(format!(
                "--bodies may be at most 1000000, got {}",
                self.bodies
            ));
        }
        if self.piece_scale > 16 {
            return Err(format!(
                "--piece-scale may be at most 16, got {}",
                self.piece_scale
            ));
        }
        Ok(())
    }
}

/// The report written to DIR/report.json.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FactoryReport {
    /// Bodies at the end (dropped plus the container's image's bodies).
    pub bodies: usize,
    /// Bodies dropped.
    pub dropped: usize,
    /// Dropping stopped early because the container was full: the pile reached its rim, or
    /// [`FULL_AFTER`] drops in a row found no free place.
    pub container_full: bool,
    /// The generated container's width and depth, blocks (none with an image container).
    pub container: Option<[usize; 2]>,
    /// Most contacts in one step.
    pub max_contacts: usize,
    /// The deepest disc overlap among the last step's contacts, blocks (the pile's health: the
    /// post-stabilisation slop is 0.01; a block disc's diameter is √2).
    pub deepest_overlap_at_end: f64,
    /// Total kinetic energy at the end.
    pub kinetic_energy_at_end: f64,
    /// The most kinetic energy the bodies can have without energy being created: each body's
    /// mass times (g times the height from the highest place a body starts or is dropped from
    /// to the container's floor, plus half the drop speed squared). A run whose final kinetic
    /// energy exceeds it has blown up.
    pub kinetic_energy_bound: f64,
    /// Moving bodies outside the container at the end (escaped through its floor or walls, or
    /// spilled over): 0 in a sound run.
    pub outside_container_at_end: usize,
    /// Which: index, centre of mass (blocks) and whether it came from the container's image.
    pub outside: Vec<(usize, [f64; 2], bool)>,
    /// Steps run.
    pub steps: u64,
    /// The scaling figure: PGS solve CPU seconds against contacts, re-timed side by side on the
    /// problems kept during the run (median of `retime_rounds` rounds each).
    pub fit: Option<LinearFit>,
    /// Problems re-timed.
    pub retimed_problems: usize,
    /// Rounds of re-timing.
    pub retime_rounds: usize,
    /// For comparison: the same fitted to the thread CPU time each step's solve took in the run.
    pub fit_in_run: Option<LinearFit>,
    /// For comparison: the same fitted to the wall time each step's solve took in the run.
    pub fit_in_run_wall: Option<LinearFit>,
    /// Total PGS wall seconds in the run.
    pub pgs_seconds: f64,
    /// Total PGS thread CPU seconds in the run.
    pub pgs_cpu_seconds: f64,
    /// Wall seconds of the whole run.
    pub wall_seconds: f64,
}

impl FactoryReport {
    /// What makes the run unsound, one line each: bodies outside the container, a pile that did
    /// not hold (discs overlapping by more than [`CRUSHED_OVERLAP`] at the end), or a kinetic
    /// energy beyond what falling could give (the run blew up). Empty for a sound run.
    pub fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.outside_container_at_end > 0 {
            let first: Vec<String> = self
                .outside
                .iter()
                .take(5)
                .map(|(i, x, from_image)| {
                    format!(
                        "body {i}{} at ({:.1}, {:.1})",
                        if *from_image { " (from the image)" } else { "" },
                        x[0],
                        x[1]
                    )
                })
                .collect();
            out.push(format!(
                "{} bodies ended outside the container (escaped or spilled), e.g. {}",
                self.outside_container_at_end,
                first.join(", ")
            ));
        }
        if self.deepest_overlap_at_end > CRUSHED_OVERLAP {
            out.push(format!(
                "the pile did not hold: block discs of different bodies overlap by {:.3} blocks at the end, more than {CRUSHED_OVERLAP:.3} (a tenth of their diameter); the solver's sweeps do not carry a pile this deep (more --iterations or --substeps, docs/performance.md)",
                self.deepest_overlap_at_end
            ));
        }
        if self.kinetic_energy_at_end > self.kinetic_energy_bound {
            out.push(format!(
                "the kinetic energy at the end, {:.3e}, exceeds {:.3e}, the most that falling into the container could give: the run blew up",
                self.kinetic_energy_at_end, self.kinetic_energy_bound
            ));
        }
        out
    }
}

/// Where a factory run is, for a progress display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FactoryProgress {
    /// Steps run.
    pub step: u64,
    /// The run's planned length, steps (it grows when drops must wait).
    pub planned: u64,
    /// Bodies now.
    pub bodies: usize,
    /// Contacts in the last step.
    pub contacts: usize,
}

/// Creates `path` for writing, naming it in the error.
fn create(path: &Path) -> Result<std::io::BufWriter<std::fs::File>, String> {
    std::fs::File::create(path)
        .map(std::io::BufWriter::new)
        .map_err(|e| format!("{}: cannot create: {e}", path.display()))
}

/// The container's bodies and, when generated, its inside's size.
fn container_of(s: &FactorySettings) -> Result<(Vec<BlockGroup>, Option<[usize; 2]>), String> {
    match &s.container {
        Some(p) => {
            let g = load_image(p, &ImageSettings::default())?;
            if !g.iter().any(|g| g.pinned) {
                return Err(format!(
                    "{}: no pinned (blue) body to use as a container",
                    p.display()
                ));
            }
            Ok((g, None))
        }
        None => {
            let (w, d) = container_size(s.bodies, s.pieces, s.piece_scale);
            let (w, d) = (s.width.unwrap_or(w), s.depth.unwrap_or(d));
            // The container is a pixel grid before it becomes a body: an absurd size is an
            // error, not an aborted allocation.
            if (w as f64) * (d as f64) > 1e8 {
                return Err(format!(
                    "a container of {w} × {d} blocks is more than the limit of 100 million blocks"
                ));
            }
            Ok((vec![container(w, d)], Some([w, d])))
        }
    }
}

/// The world of a factory run: the container (generated, or an image's pinned bodies) with the
/// factory's PGS settings, and where bodies are dropped into it.
fn factory_world(s: &FactorySettings) -> Result<(World2, DropZone, Option<[usize; 2]>), String> {
    let (groups, size) = container_of(s)?;
    let params = Params2 {
        iterations: s.iterations,
        substeps: s.substeps,
        order: crate::solve::ContactOrder::Random,
        seed: s.seed,
        ..Params2::default()
    };
    let world = World2::new(&groups, params);
    let zone = DropZone::above_pinned(&world).ok_or("no pinned body to drop into")?;
    // The pile is full when it reaches the rim: a container must have walls to fill.
    if zone.floor - zone.rim < 5.0 {
        return Err(format!(
            "{}: the pinned bodies rise only {} blocks above their lowest row; a container needs walls at least 5 blocks high",
            s.container
                .as_ref()
                .map_or("the container".to_string(), |p| p.display().to_string()),
            zone.floor - zone.rim
        ));
    }
    Ok((world, zone, size))
}

/// The drop schedule: a batch every `steps_per_drop` steps while bodies remain and the
/// container is not full, then `settle_steps` more.
struct DropSchedule<'a> {
    settings: &'a FactorySettings,
    factory: Factory,
    zone: DropZone,
    steps_per_drop: u64,
    settle_steps: u64,
    dropped: usize,
    /// Drops in a row that placed nothing; after [`FULL_AFTER`] of them the container is full.
    fruitless: u32,
    full: bool,
    settled: u64,
}

impl DropSchedule<'_> {
    /// Drops a batch if one is due before step k + 1 (k steps done); then says whether the run is
    /// done: nothing left to drop and the pile settled for `settle_steps`.
    fn before_step(&mut self, world: &mut World2, k: u64) -> bool {
        let s = self.settings;
        let dropping = self.dropped < s.bodies && !self.full;
        if dropping && k.is_multiple_of(self.steps_per_drop) {
            if self.zone.is_full(world) {
                self.full = true;
            } else {
                let n = s.batch.min(s.bodies - self.dropped);
                let placed = self.factory.drop_batch(world, &self.zone, n, s.drop_speed);
                self.dropped += placed;
                self.fruitless = if placed == 0 { self.fruitless + 1 } else { 0 };
                self.full = self.fruitless >= FULL_AFTER;
            }
        }
        if dropping {
            return false;
        }
        if self.settled >= self.settle_steps {
            return true;
        }
        self.settled += 1;
        false
    }
}

/// What the run measures of its solves: the per-step CSV, the in-run points, the problems kept
/// for re-timing.
struct SolveLog {
    csv: std::io::BufWriter<std::fs::File>,
    csv_path: std::path::PathBuf,
    keep_every: u64,
    kept: Vec<ContactProblem2>,
    in_run_wall: Vec<(f64, f64)>,
    in_run_cpu: Vec<(f64, f64)>,
    max_contacts: usize,
    pgs_seconds: f64,
    pgs_cpu_seconds: f64,
}

impl SolveLog {
    fn create(out: &Path, keep_every: u64) -> Result<SolveLog, String> {
        let csv_path = out.join("scaling.csv");
        let mut csv = create(&csv_path)?;
        writeln!(csv, "step,t,bodies,contacts,pgs_seconds,pgs_cpu_seconds")
            .map_err(|e| format!("{}: cannot write: {e}", csv_path.display()))?;
        Ok(SolveLog {
            csv,
            csv_path,
            keep_every,
            kept: Vec::new(),
            in_run_wall: Vec::new(),
            in_run_cpu: Vec::new(),
            max_contacts: 0,
            pgs_seconds: 0.0,
            pgs_cpu_seconds: 0.0,
        })
    }

    /// Step k's solves, summed over its substeps (one solve each), so that time and contacts
    /// match. Returns the step's contacts.
    fn record(&mut self, w: &World2, k: u64) -> Result<usize, String> {
        let totals = SolveTotals::of(&w.solves);
        let (contacts, wall, cpu) = (
            totals.contacts,
            totals.solve_seconds,
            totals.solve_cpu_seconds,
        );
        self.max_contacts = self.max_contacts.max(totals.most_contacts);
        self.pgs_seconds += wall;
        self.pgs_cpu_seconds += cpu;
        writeln!(
            self.csv,
            "{},{},{},{},{wall:.9},{cpu:.9}",
            w.step,
            w.time(),
            w.bodies.len(),
            contacts,
        )
        .map_err(|e| format!("{}: cannot write: {e}", self.csv_path.display()))?;
        if contacts > 0 {
            self.in_run_wall.push((contacts as f64, wall));
            self.in_run_cpu.push((contacts as f64, cpu));
            if k.is_multiple_of(self.keep_every)
                && let Some(solve) = w.solves.last()
            {
                self.kept.push(solve.problem.clone());
            }
        }
        Ok(contacts)
    }

    /// Re-times the kept problems side by side, writes retimed.csv, scaling.svg and scaling.png
    /// (the plot as a 2D scene image), and returns
    /// the fit and how many problems were re-timed.
    fn write_fit(
        &mut self,
        out: &Path,
        settings: &crate::solve::PgsSettings,
        seed: u64,
    ) -> Result<(Option<LinearFit>, usize), String> {
        self.csv
            .flush()
            .map_err(|e| format!("{}: cannot write: {e}", self.csv_path.display()))?;
        let retimed = retime(&self.kept, settings, RETIME_ROUNDS, seed);
        let retimed_path = out.join("retimed.csv");
        let mut retimed_csv = create(&retimed_path)?;
        let retimed_err =
            |e: std::io::Error| format!("{}: cannot write: {e}", retimed_path.display());
        writeln!(retimed_csv, "contacts,pgs_cpu_seconds_median").map_err(retimed_err)?;
        for (contacts, seconds) in &retimed {
            writeln!(retimed_csv, "{contacts},{seconds:.9}").map_err(retimed_err)?;
        }
        retimed_csv.flush().map_err(retimed_err)?;
        let fit = linear_fit(&retimed);
        let svg = out.join("scaling.svg");
        let png = out.join("scaling.png");
        match &fit {
            Some(f) => {
                plot(
                    &retimed,
                    &self.in_run_cpu,
                    f,
                    &svg,
                    "PGS solve CPU time (re-timed)",
                )?;
                crate::tools::scaling::scene_png(&retimed, f, &png)?;
            }
            // No line to draw: do not leave an earlier run's plot looking like this one's.
            None => {
                let _ = std::fs::remove_file(&svg);
                let _ = std::fs::remove_file(&png);
            }
        }
        Ok((fit, retimed.len()))
    }
}

/// Runs the factory: drops `bodies` in batches every `interval` into the container until all are
/// dropped or the container is full, lets them settle, and writes the scaling report into `out`
/// (scaling.csv, retimed.csv, scaling.svg, scaling.png, report.json; docs/blocks2d.md
/// §"Scaling").
/// `progress` is told where the run is after every step. A note on a full container is returned
/// with the report.
pub fn run_factory(
    s: &FactorySettings,
    out: &Path,
    mut progress: impl FnMut(&FactoryProgress),
) -> Result<(FactoryReport, Option<String>), String> {
    s.check()?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let started = std::time::Instant::now();
    let (mut world, zone, size) = factory_world(s)?;
    let image_bodies = world.bodies.len();
    // The highest a body starts (the image's own moving bodies) or is dropped from (four blocks
    // and a piece above the rim at most).
    let highest = world
        .bodies
        .iter()
        .filter(|b| !b.pinned)
        .map(|b| b.x.y - b.tree.root().map_or(0.0, |r| r.radius + r.centre.norm()))
        .fold(
            zone.rim
                - 4.0
                - 2.0
                    * Factory::new(s.seed, s.pieces)
                        .with_scale(s.piece_scale)
                        .largest_reach(),
            f64::min,
        );
    let fall = zone.floor - highest;
    let dt = world.params.dt;
    let steps_per_drop = (s.interval / dt).round().max(1.0) as u64;
    let settle = (s.settle / dt).round();
    let drops = (s.interval / dt).round() * s.bodies.div_ceil(s.batch) as f64;
    crate::sim::check_step_count(settle + drops, dt)?;
    let settle_steps = settle as u64;
    // The length of the run if every drop places a whole batch; drops that must wait (the drop
    // zone still occupied) lengthen it.
    let planned = s.bodies.div_ceil(s.batch) as u64 * steps_per_drop + settle_steps;
    let mut log = SolveLog::create(out, (planned / RETIMED_PROBLEMS).max(1))?;
    let mut factory = Factory::new(s.seed, s.pieces);
    factory.scale = s.piece_scale;
    let mut schedule = DropSchedule {
        settings: s,
        factory,
        zone,
        steps_per_drop,
        settle_steps,
        dropped: 0,
        fruitless: 0,
        full: false,
        settled: 0,
    };
    // The viewer's records: the bodies dropped so far (a prefix of the final list), without
    // contacts (31 000 contacts per record would make a page of gigabytes).
    let mut view_records = Vec::new();
    if s.view_every > 0 {
        view_records.push(crate::blocks2d::trace::Record2::of_world(&world, false));
    }
    if !schedule.before_step(&mut world, 0) {
        // An open-ended run: it stops when the schedule says it is done.
        drive(&mut world, u64::MAX, |w, k| -> Result<Flow, String> {
            let contacts = log.record(w, k)?;
            if s.view_every > 0 && k.is_multiple_of(s.view_every) {
                view_records.push(crate::blocks2d::trace::Record2::of_world(w, false));
            }
            progress(&FactoryProgress {
                step: k,
                planned: if k > planned {
                    k + settle_steps
                } else {
                    planned
                },
                bodies: w.bodies.len(),
                contacts,
            });
            Ok(if schedule.before_step(w, k) {
                Flow::Stop
            } else {
                Flow::Continue
            })
        })?;
    }
    let (dropped, full) = (schedule.dropped, schedule.full);
    let note = full.then(|| {
        format!(
            "the container is full (the pile reached its rim, or {FULL_AFTER} drops in a row found no free place): {dropped} of {} bodies were dropped",
            s.bodies
        )
    });
    let (fit, retimed_problems) = log.write_fit(out, &world.pgs_settings(), s.seed)?;
    let outside: Vec<(usize, [f64; 2], bool)> = world
        .bodies
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.pinned && zone.is_outside(b))
        .map(|(i, b)| (i, [b.x.x, b.x.y], i < image_bodies))
        .collect();
    let report = FactoryReport {
        bodies: world.bodies.len(),
        dropped,
        container_full: full,
        container: size,
        max_contacts: log.max_contacts,
        deepest_overlap_at_end: world.deepest_overlap(),
        kinetic_energy_at_end: world.energy().kinetic,
        kinetic_energy_bound: world
            .bodies
            .iter()
            .filter(|b| !b.pinned)
            .map(|b| b.mass * (world.params.gravity * fall + 0.5 * s.drop_speed * s.drop_speed))
            .sum(),
        outside_container_at_end: outside.len(),
        outside,
        steps: world.step,
        fit,
        retimed_problems,
        retime_rounds: RETIME_ROUNDS,
        fit_in_run: linear_fit(&log.in_run_cpu),
        fit_in_run_wall: linear_fit(&log.in_run_wall),
        pgs_seconds: log.pgs_seconds,
        pgs_cpu_seconds: log.pgs_cpu_seconds,
        wall_seconds: started.elapsed().as_secs_f64(),
    };
    if s.view_every > 0 {
        if view_records.last().is_none_or(|r| r.step != world.step) {
            view_records.push(crate::blocks2d::trace::Record2::of_world(&world, false));
        }
        write_view_page(&world, &view_records, &out.join("view.html"))?;
    }
    let report_path = out.join("report.json");
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    std::fs::write(&report_path, text + "\n")
        .map_err(|e| format!("{}: cannot write: {e}", report_path.display()))?;
    Ok((report, note))
}

/// A factory pile made at once, for timing the factory's step at a size without the hours of
/// drops that reach it (`rigidref bench`, docs/performance.md): `bodies` pieces from
/// `Factory::new(seed, pieces)`, set down one after another across the container a factory run
/// of `bodies` would make (deeper where the pile needs it), each as low as it goes on the pile's
/// skyline, left to right and then again from the left: a block straight above another √2 −
/// 0.001 blocks higher, one in the next column at least 0.999 higher (their discs, of diameter
/// √2, overlap by at most a thousandth of a block, less than the slop), so that the pile is in
/// contact from its first step. At rest, with the factory's default settings (10 sweeps in
/// seeded random order, 1 substep, the rest [`Params2::default`]).
pub fn packed_pile(bodies: usize, pieces: Pieces, seed: u64) -> World2 {
    let above = std::f64::consts::SQRT_2 - 1e-3;
    let beside = 1.0 - 1e-3;
    let (width, depth) = container_size(bodies, pieces, 1);
    // Lattice columns c = 0 … width − 2 at x = c + above − 1, so that a block in the outermost
    // ones is `above` from the walls' blocks (x = −1 and x = width); the floor's top row is y = 0
    // here (y grows downward) and the skyline is the highest block centre per column.
    let columns = width - 1;
    let mut skyline = vec![0.0_f64; columns];
    let mut factory = Factory::new(seed, pieces);
    let mut cursor = 0;
    let mut made = Vec::with_capacity(bodies);
    for _ in 0..bodies {
        let mut body = factory.make(Vector2::zeros());
        // The blocks' offsets from the first, whole blocks (the piece is turned by 90°s).
        let first = body.to_world(&body.blocks[0].local);
        let cells: Vec<(i64, i64)> = body
            .blocks
            .iter()
            .map(|b| {
                let d = body.to_world(&b.local) - first;
                (d.x.round() as i64, d.y.round() as i64)
            })
            .collect();
        let (lo, hi) = cells
            .iter()
            .fold((i64::MAX, i64::MIN), |(l, h), c| (l.min(c.0), h.max(c.0)));
        let span = (hi - lo) as usize;
        if cursor + span >= columns {
            cursor = 0;
        }
        let column = |dx: i64| (cursor as i64 + dx - lo) as usize;
        // The reference block's y: as low as every block's constraints allow.
        let mut y = f64::INFINITY;
        for &(dx, dy) in &cells {
            let c = column(dx);
            y = y.min(skyline[c] - above - dy as f64);
            for n in [c.wrapping_sub(1), c + 1] {
                if n < columns {
                    y = y.min(skyline[n] - beside - dy as f64);
                }
            }
        }
        for &(dx, dy) in &cells {
            let c = column(dx);
            skyline[c] = skyline[c].min(y + dy as f64);
        }
        let target = Vector2::new(column(0) as f64 + above - 1.0, y);
        body.x += target - first;
        made.push(body);
        // One column left free: a piece beside another would sit a block higher.
        cursor += span + 2;
    }
    // The container deep enough for the pile, its floor's top row at y = depth.
    let top = skyline.iter().copied().fold(0.0, f64::min);
    let depth = depth.max((-top + above).ceil() as usize + 2);
    let params = Params2 {
        iterations: 10,
        substeps: 1,
        order: crate::solve::ContactOrder::Random,
        seed,
        ..Params2::default()
    };
    let mut world = World2::new(&[container(width, depth)], params);
    for mut body in made {
        body.x.y += depth as f64;
        world.add_body(body);
    }
    world
}
