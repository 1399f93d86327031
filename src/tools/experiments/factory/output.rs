//! Every file a factory run writes, in one place: the CSV solve log (and its re-timing), the
//! viewer page.

use super::*;

/// The viewer page of a factory run (docs/viewing.md): the final world's bodies, each drawn
/// from the record where it was dropped on; the plots of the run.
pub(super) fn write_view_page(
    world: &World2,
    records: &[crate::blocks2d::trace::Record2],
    path: &Path,
) -> Result<(), String> {
    use crate::tools::viewing::view::{DEFAULT_MAX_FRAMES, html, view_data_2d};
    let header =
        crate::blocks2d::trace::TraceHeader2::for_world(world, "factory", "rigidref factory");
    let pinned: Vec<bool> = world.bodies.iter().map(|b| b.pinned).collect();
    let omega = crate::tools::viewing::series::default_omega_bodies(&pinned);
    let data = view_data_2d(&header, records, world, &[], DEFAULT_MAX_FRAMES, &omega);
    std::fs::write(path, html(&data)).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Creates `path` for writing, naming it in the error.
pub(super) fn create(path: &Path) -> Result<std::io::BufWriter<std::fs::File>, String> {
    std::fs::File::create(path)
        .map(std::io::BufWriter::new)
        .map_err(|e| format!("{}: cannot create: {e}", path.display()))
}

/// What the run measures of its solves: the per-step CSV, the in-run points, the problems kept
/// for re-timing.
pub(super) struct SolveLog {
    pub(super) csv: std::io::BufWriter<std::fs::File>,
    pub(super) csv_path: std::path::PathBuf,
    pub(super) keep_every: u64,
    pub(super) kept: Vec<ContactProblem2>,
    pub(super) in_run_wall: Vec<(f64, f64)>,
    pub(super) in_run_cpu: Vec<(f64, f64)>,
    pub(super) max_contacts: usize,
    pub(super) pgs_seconds: f64,
    pub(super) pgs_cpu_seconds: f64,
    /// The world's phase clocks after each of the last [`STEP_TIMES_KEPT`] steps, and before
    /// them (oldest first; the clocks start at zero with the world).
    pub(super) recent_phases: std::collections::VecDeque<[f64; 6]>,
}

/// Steps whose times are kept for the run's steps per second at its end.
pub const STEP_TIMES_KEPT: usize = 200;

impl SolveLog {
    pub(super) fn create(out: &Path, keep_every: u64) -> Result<SolveLog, String> {
        let csv_path = out.join("scaling.csv");
        let mut csv = create(&csv_path)?;
        writeln!(
            csv,
            "step,t,bodies,contacts,pgs_seconds,pgs_cpu_seconds,step_seconds"
        )
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
            recent_phases: std::collections::VecDeque::from([[0.0; 6]]),
        })
    }

    /// Step k's solves, summed over its substeps (one solve each), so that time and contacts
    /// match. Returns the step's contacts.
    pub(super) fn record(&mut self, w: &World2, k: u64) -> Result<usize, String> {
        let totals = SolveTotals::of(&w.solves);
        let (contacts, wall, cpu) = (
            totals.contacts,
            totals.solve_seconds,
            totals.solve_cpu_seconds,
        );
        self.max_contacts = self.max_contacts.max(totals.most_contacts);
        self.pgs_seconds += wall;
        self.pgs_cpu_seconds += cpu;
        // The step's own work: its phase clocks (detect, assemble, solve, apply, integrate,
        // post-stabilisation), not this log or the progress bar.
        let total: f64 = w.phase_times.as_array().iter().sum();
        let before: f64 = self.recent_phases.back().map_or(0.0, |p| p.iter().sum());
        let step_seconds = total - before;
        if self.recent_phases.len() == STEP_TIMES_KEPT + 1 {
            self.recent_phases.pop_front();
        }
        self.recent_phases.push_back(w.phase_times.as_array());
        writeln!(
            self.csv,
            "{},{},{},{},{wall:.9},{cpu:.9},{step_seconds:.9}",
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

    /// Steps per second over the last [`STEP_TIMES_KEPT`] steps (their phase clocks' total).
    pub(super) fn steps_per_second_at_end(&self) -> f64 {
        if self.recent_phases.len() < 2 {
            return 0.0;
        }
        1e3 / self.phases_ms_at_end().iter().sum::<f64>().max(1e-9)
    }

    /// The mean time per step of each phase (detect, assemble, solve, apply, integrate,
    /// post-stabilisation) over the last [`STEP_TIMES_KEPT`] steps, ms.
    pub(super) fn phases_ms_at_end(&self) -> [f64; 6] {
        match (self.recent_phases.front(), self.recent_phases.back()) {
            (Some(first), Some(last)) if self.recent_phases.len() > 1 => {
                let steps = (self.recent_phases.len() - 1) as f64;
                [0, 1, 2, 3, 4, 5].map(|k| (last[k] - first[k]) * 1e3 / steps)
            }
            _ => [0.0; 6],
        }
    }

    /// Re-times the kept problems side by side, writes retimed.csv, scaling.svg and scaling.png
    /// (the plot as a 2D scene image), and returns
    /// the fit and how many problems were re-timed.
    pub(super) fn write_fit(
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
                crate::tools::experiments::scaling::scene_png(&retimed, f, &png)?;
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
