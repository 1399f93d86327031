//! The factory: random bodies dropped into a container at an interval, for stress tests and the
//! scaling report; and the Tetris variant. docs/blocks2d.md §"Challenges".
//!
//! - [`pieces`]: what is dropped (random blobs, bricks, tetrominoes);
//! - [`container`]: the container and where a piece may drop;
//! - [`settings`]: a run's settings, report and progress;
//! - [`output`]: every file a run writes (the CSV solve log, the viewer page);
//! - here: the run itself ([`run_factory`]) and a packed pile for the benchmark ([`packed_pile`]).

mod container;
mod output;
mod pieces;
mod settings;

pub use container::*;
use output::*;
pub use pieces::*;
pub use settings::*;

use crate::blocks2d::assemble::ContactProblem2;
use crate::blocks2d::body::Body2;
use crate::blocks2d::collide::tree_contacts;
use crate::blocks2d::image::{Block, BlockGroup, block_mass};
use crate::blocks2d::image::{ImageSettings, load_image};
use crate::blocks2d::params::Params2;
use crate::blocks2d::world::World2;
use crate::sim::{Flow, SolveTotals, drive};
use crate::tools::experiments::scaling::{LinearFit, linear_fit, plot, retime};
use nalgebra::Vector2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::io::Write;
use std::path::Path;

/// A tetromino: its four cells and its colour.
type Tetromino = ([(i64, i64); 4], [f64; 3]);

/// The factory's PGS sweeps per solve by default: twice the starter's 10, which let a pile of
/// 10 000 bricks give way at about 9 000 (docs/blocks2d.md §"Challenges").
pub const FACTORY_ITERATIONS: u32 = 20;

/// The factory's PGS contact order by default: the random coloured order, a fresh random
/// colouring per solve and a fresh order of the colours per sweep, whose colours' contacts go
/// four at a time (docs/blocks2d.md §"Challenges", docs/contact.md §"Random coloured order").
/// The 2D scenes keep the random order (`order: random`, the demonstration default).
pub const FACTORY_ORDER: crate::solve::ContactOrder = crate::solve::ContactOrder::RandomColoured;

/// Drops in a row that place nothing before the container counts as full.
pub const FULL_AFTER: u32 = 20;

/// Contact problems kept during the run for re-timing (spread evenly over the planned steps).
pub const RETIMED_PROBLEMS: u64 = 100;

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
        order: s.order,
        seed: s.seed,
        threads: s.threads,
        shock_propagation: s.shock_propagation,
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
        steps_per_second_at_end: log.steps_per_second_at_end(),
        phases_ms_at_end: log.phases_ms_at_end(),
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
/// contact from its first step. At rest, with the factory's default settings ([`FACTORY_ITERATIONS`] sweeps in
/// the [`FACTORY_ORDER`], 1 substep, the rest [`Params2::default`]).
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
        iterations: FACTORY_ITERATIONS,
        substeps: 1,
        order: FACTORY_ORDER,
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
