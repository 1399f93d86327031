//! A factory run's settings, its report and its progress callback's data.

use super::*;

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
    /// PGS's contact order (random coloured, the factory's default `FACTORY_ORDER`; random,
    /// sequential or coloured: docs/contact.md §"Coloured order", §"Random coloured order").
    pub order: crate::solve::ContactOrder,
    /// Threads of the coloured order's sweeps.
    pub threads: u32,
    /// Shock propagation after each velocity solve (docs/blocks2d.md §"Shock propagation").
    pub shock_propagation: bool,
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
    /// Steps per second over the run's last 200 steps (the settling, at its full size), from the
    /// step's own phase clocks: detection, assembly, the solves, post-stabilisation and the
    /// integration, not the log or the progress bar.
    pub steps_per_second_at_end: f64,
    /// Over the same steps, ms per step of each phase: detect, assemble, solve (PGS), apply,
    /// integrate, post-stabilisation ([`crate::sim::PhaseTimes`]).
    pub phases_ms_at_end: [f64; 6],
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
