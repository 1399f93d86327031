//! Solving a library of contact problems in local form (Siconos `.dat`, rigidref's own problem
//! files of either form), each with several solvers, judged alike: `rigidref solve-problems`.
//! docs/problem-library.md.
//!
//! Every solver stops on the same criterion, Siconos' error measure
//! ([`crate::solve::residual::siconos_error`], Siconos ≥ 4.4's) at or below the tolerance,
//! checked after every PGS sweep, at every Newton iterate and at each centre of the proximal
//! fallback, so that iterations and times compare like with like. The comparison is summed up by a Dolan–Moré
//! performance profile: for solver s, ρ_s(τ) is the fraction of problems it solved within τ
//! times the fastest solver's time on that problem.

use crate::problem::SolveReport;
use crate::problem::local_json::AnyProblemFile;
use crate::problem::siconos::{AnyLocalProblem, read_dat};
use crate::problem::{ContactCriteria, FrictionModel, LocalProblem, RowBounds};
use crate::solve::auto::{AutoSettings, solve_auto_local_until};
use crate::solve::criteria::criteria;
use crate::solve::residual::{
    coulomb_residual, residual, siconos_error_measures, siconos_error_measures_given,
};
use crate::solve::twins::{TwinSettings, solve_twins_local_until};
use crate::solve::{
    ContactOrder, LocalSolve, NewtonSettings, PgsSettings, Regularisation,
    solve_newton_local_until, solve_pgs_local_until,
};
use nalgebra::SVector;
use std::path::Path;
use std::time::Instant;

/// A solver of the comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum LibrarySolver {
    /// PGS with row-by-row visits (the assignment's), in problem order.
    Pgs,
    /// PGS with exact local solves (Siconos' NSGS), in problem order.
    PgsExact,
    /// The Newton solver (semismooth Newton on the Alart–Curnier function with its fallbacks).
    Newton,
    /// The Newton solver with its plain runs' matrix regularised by ε = (‖F‖∞ / max|b|)^1.5
    /// (docs/contact.md §"Newton solver", **Regularisation following ‖F‖**).
    NewtonRegularised,
    /// The automatic choice: NSGS while its rate promises the tolerance soon, then Newton
    /// warm-started from its λ (docs/contact.md §"Automatic choice: NSGS, then Newton").
    Auto,
    /// The Newton solver restarted once from its own answer, then, where it still stalls, the
    /// problem without one contact of each near-duplicate pair that carries the error, judged
    /// on the whole problem (docs/contact.md §"Near-duplicate contacts left out").
    NewtonTwins,
}

impl LibrarySolver {
    /// The spelling in tables and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            LibrarySolver::Pgs => "pgs",
            LibrarySolver::PgsExact => "pgs-exact",
            LibrarySolver::Newton => "newton",
            LibrarySolver::NewtonRegularised => "newton-regularised",
            LibrarySolver::Auto => "auto",
            LibrarySolver::NewtonTwins => "newton-twins",
        }
    }
}

/// Limits of each solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LibrarySettings {
    /// Converged where Siconos' error is at or below this (relative, dimensionless).
    pub tolerance: f64,
    /// PGS sweeps at most (default 20 000, as the reference runs of Siconos' NSGS).
    pub sweeps: u32,
    /// Newton iterations at most per run before its fallbacks (default 200).
    pub newton_iterations: u32,
}

impl Default for LibrarySettings {
    fn default() -> Self {
        LibrarySettings {
            tolerance: 1e-8,
            sweeps: 20_000,
            newton_iterations: 200,
        }
    }
}

/// One solver's result on one problem.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Attempt {
    /// Which solver.
    pub solver: LibrarySolver,
    /// Siconos' error at or below the tolerance.
    pub converged: bool,
    /// PGS sweeps, or Newton iterations (fallbacks included).
    pub iterations: u32,
    /// Wall time of the solve, s (the problem's reading excluded).
    pub seconds: f64,
    /// Siconos' error of the answer (relative), the measure every solver stops on.
    pub error: f64,
    /// Siconos' error divided by ‖q‖ alone (Siconos 4.1–4.3's measure; box friction: as
    /// `error`, whose measure is rigidref's own).
    pub q_normalised_error: f64,
    /// Siconos' error not divided (its natural-map norm, mixed N·s and m/s; box friction: the
    /// box residual, m/s).
    pub absolute_error: f64,
    /// rigidref's residual of the answer, m/s (docs/contact.md §"Residual").
    pub residual: f64,
    /// The exact Coulomb residual of the answer, m/s.
    pub coulomb_residual: f64,
    /// The worst physical criteria over the contacts (docs/contact.md §"Physical criteria").
    pub criteria: ContactCriteria,
    /// For Newton: `newton` or `proximal` (which produced the answer); for the automatic
    /// choice its path: `nsgs`, `nsgs+newton` or `nsgs+proximal`; for newton-twins `newton` or
    /// `proximal` on the whole problem, `twins` where contacts are left out.
    pub method: &'static str,
    /// For the automatic choice: the NSGS sweeps of its first phase (the rest of `iterations`
    /// are Newton iterations); 0 for the other solvers.
    pub sweeps: u32,
    /// For newton-twins: the contacts its answer leaves out (zero impulse, each with w_n ≥ 0
    /// where the answer is exact), ascending; empty otherwise.
    pub left_out: Vec<usize>,
}

/// One problem of the library and every solver's attempt.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LibraryEntry {
    /// The file's name.
    pub name: String,
    /// Rows per contact (3 or 2).
    pub dimension: usize,
    /// Contacts.
    pub contacts: usize,
    /// Blocks of W stored.
    pub blocks: usize,
    /// max |W − Wᵀ| / max |W|.
    pub asymmetry: f64,
    /// One per solver asked for, in that order.
    pub attempts: Vec<Attempt>,
}

/// Reads a problem for the library: a Siconos `.dat` file, or a rigidref problem file (JSON,
/// either form; the body form converted by [`crate::problem::ContactProblem::to_local`]).
/// Errors name the file.
pub fn load(path: &Path) -> Result<AnyLocalProblem, String> {
    let name = path.display();
    crate::common::input::check_size(path).map_err(|e| format!("{name}: {e}"))?;
    match path.extension().and_then(|e| e.to_str()) {
        Some("dat") => read_dat(path),
        Some("json") => {
            let file = AnyProblemFile::read(path)?;
            match file.rows_per_contact() {
                3 => file.to_local::<3>().map(AnyLocalProblem::Three),
                2 => file.to_local::<2>().map(AnyLocalProblem::Two),
                r => Err(format!("rows_per_contact {r}: 3 (3D) or 2 (2D)")),
            }
            .map_err(|e| {
                if e.starts_with(&name.to_string()) {
                    e
                } else {
                    format!("{name}: {e}")
                }
            })
        }
        Some("hdf5" | "h5") => read_hdf5(path),
        _ => Err(format!(
            "{name}: not a problem file rigidref reads (.dat: Siconos' text; .json: rigidref's \
             contact-problem file)"
        )),
    }
}

/// An FCLIB file's local problem (a global one converted through the body form).
#[cfg(feature = "fclib")]
fn read_hdf5(path: &Path) -> Result<AnyLocalProblem, String> {
    use crate::problem::fclib::{FclibProblem, read_fclib};
    match read_fclib(path)? {
        FclibProblem::Local { problem, .. } => Ok(problem),
        FclibProblem::Global(problem) => Ok(AnyLocalProblem::Three(problem.to_local())),
    }
}

/// Without the feature `fclib`: says how to get it.
#[cfg(not(feature = "fclib"))]
fn read_hdf5(path: &Path) -> Result<AnyLocalProblem, String> {
    Err(format!(
        "{}: FCLIB HDF5 files need rigidref built with `--features fclib` (and libhdf5-dev): \
         docs/problem-library.md §\"FCLIB\"",
        path.display()
    ))
}

/// Writes a problem (either dimension) to `path` by its extension: `.json` (rigidref's
/// local-form file), `.dat` (Siconos' text) or, with the feature `fclib`, `.hdf5`/`.h5` (FCLIB
/// local). `source` names where it came from (the file's `source`, FCLIB's `info/title`).
/// Siconos and FCLIB describe contacts under the Coulomb cone only: a problem with joint rows
/// (`bounds: free`) is refused for them, since they would become contacts; box friction (3D) is
/// written with a warning, since another solver will answer for the cone. The warnings are
/// returned.
pub fn write(problem: &AnyLocalProblem, source: &str, path: &Path) -> Result<Vec<String>, String> {
    let name = path.display();
    let text =
        |s: String| std::fs::write(path, s).map_err(|e| format!("{name}: cannot write: {e}"));
    let extension = path.extension().and_then(|e| e.to_str());
    let mut warnings = Vec::new();
    if matches!(extension, Some("dat" | "hdf5" | "h5")) {
        let (joint, friction, rows, warm) = match problem {
            AnyLocalProblem::Three(p) => facts(p),
            AnyLocalProblem::Two(p) => facts(p),
        };
        if let Some(k) = joint {
            return Err(format!(
                "{name}: constraint {k} is a joint (bounds \"free\"): Siconos' and FCLIB's formats \
                 have contacts only, so it would be solved as a contact; keep this problem as .json"
            ));
        }
        if friction == FrictionModel::Box && rows == 3 {
            warnings.push(format!(
                "{name}: the problem has box friction; Siconos and FCLIB readers solve the \
                 Coulomb cone, whose answer differs wherever a contact slides off the tangent axes"
            ));
        }
        if warm && extension == Some("dat") {
            warnings.push(format!(
                "{name}: the warm start is not written (Siconos' .dat format has none)"
            ));
        }
    }
    match extension {
        Some("json") => {
            let mut file = match problem {
                AnyLocalProblem::Three(p) => crate::problem::local_json::LocalProblemFile::new(p),
                AnyLocalProblem::Two(p) => crate::problem::local_json::LocalProblemFile::new(p),
            };
            file.source = Some(source.to_string());
            text(serde_json::to_string(&file).map_err(|e| format!("{name}: {e}"))? + "\n")?
        }
        Some("dat") => text(match problem {
            AnyLocalProblem::Three(p) => crate::problem::siconos::write_dat(p),
            AnyLocalProblem::Two(p) => crate::problem::siconos::write_dat(p),
        })?,
        #[cfg(feature = "fclib")]
        Some("hdf5" | "h5") => match problem {
            AnyLocalProblem::Three(p) => crate::problem::fclib::write_fclib(p, source, None, path),
            AnyLocalProblem::Two(p) => crate::problem::fclib::write_fclib(p, source, None, path),
        }?,
        _ => {
            return Err(format!(
                "{name}: write .json (rigidref's local form), .dat (Siconos) or, built with \
                 `--features fclib`, .hdf5 (FCLIB)"
            ));
        }
    }
    Ok(warnings)
}

/// A problem's first joint (free rows), friction model, rows per contact and whether it has a
/// warm start.
fn facts<const R: usize>(p: &LocalProblem<R>) -> (Option<usize>, FrictionModel, usize, bool) {
    let joint = p.contacts.iter().position(|c| c.bounds == RowBounds::Free);
    let warm = p
        .contacts
        .iter()
        .any(|c| c.lambda0.iter().any(|x| *x != 0.0));
    (joint, p.friction, R, warm)
}

/// Solves `problem` with every solver of `solvers` and records what each did.
pub fn solve_entry(
    name: &str,
    problem: &AnyLocalProblem,
    solvers: &[LibrarySolver],
    settings: &LibrarySettings,
) -> LibraryEntry {
    match problem {
        AnyLocalProblem::Three(p) => entry(name, p, solvers, settings),
        AnyLocalProblem::Two(p) => entry(name, p, solvers, settings),
    }
}

fn entry<const R: usize>(
    name: &str,
    problem: &LocalProblem<R>,
    solvers: &[LibrarySolver],
    settings: &LibrarySettings,
) -> LibraryEntry {
    LibraryEntry {
        name: name.to_string(),
        dimension: R,
        contacts: problem.contacts.len(),
        blocks: problem.blocks(),
        asymmetry: problem.asymmetry(),
        attempts: solvers
            .iter()
            .map(|&s| attempt(problem, s, settings))
            .collect(),
    }
}

/// The error every solver stops on: Siconos' measure for the Coulomb cone
/// ([`crate::solve::residual::siconos_error`]); for a box-friction problem, whose law that measure does not describe,
/// rigidref's residual of the box law (m/s, docs/contact.md §"Residual") made relative in the
/// same way, divided by max(‖q‖, ‖w‖) (not where that is below machine epsilon).
pub fn library_error<const R: usize>(problem: &LocalProblem<R>, lambda: &[SVector<f64, R>]) -> f64 {
    library_error_given(problem, lambda, problem.dense_q().norm())
}

/// [`library_error`] with ‖q‖ given (`q_norm`, m/s, as `problem.dense_q().norm()` computes
/// it): the same bits, without gathering q again at every iterate.
pub fn library_error_given<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    q_norm: f64,
) -> f64 {
    if problem.friction == FrictionModel::Cone || R < 3 {
        return siconos_error_measures_given(problem, lambda, q_norm).relative();
    }
    let w = problem.velocity(lambda);
    let norm = |v: &[SVector<f64, R>]| v.iter().map(|x| x.norm_squared()).sum::<f64>().sqrt();
    let q = q_norm;
    let scale = q.max(norm(&w));
    let r = residual(problem, lambda);
    if scale > f64::EPSILON { r / scale } else { r }
}

/// The answer's error in the ‖q‖-normalised and absolute measures (issue 48 item 2: an answer
/// near the tolerance reads differently in each): Siconos' measure for the Coulomb cone
/// ([`siconos_error_measures`]); for box friction, the box residual (m/s) and it over ‖q‖.
pub fn other_error_measures<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
) -> (f64, f64) {
    if problem.friction == FrictionModel::Cone || R < 3 {
        let m = siconos_error_measures(problem, lambda);
        return (m.q_normalised(), m.absolute);
    }
    let r = residual(problem, lambda);
    let q = problem.dense_q().norm();
    (if q > f64::EPSILON { r / q } else { r }, r)
}

/// One solver on one problem, stopped on [`library_error`].
pub fn attempt<const R: usize>(
    problem: &LocalProblem<R>,
    solver: LibrarySolver,
    settings: &LibrarySettings,
) -> Attempt {
    let tolerance = settings.tolerance;
    // ‖q‖ once: the error is evaluated at every sweep or iterate.
    let q_norm = problem.dense_q().norm();
    let mut stop =
        |lambda: &[SVector<f64, R>]| library_error_given(problem, lambda, q_norm) <= tolerance;
    let mut lambda = Vec::new();
    let started = Instant::now();
    let mut sweeps = 0;
    let mut path = None;
    let mut left_out = Vec::new();
    let report = match solver {
        LibrarySolver::Pgs | LibrarySolver::PgsExact => {
            let pgs = PgsSettings {
                max_iterations: settings.sweeps,
                tolerance: None,
                order: ContactOrder::Sequential,
                local: if solver == LibrarySolver::Pgs {
                    LocalSolve::Rows
                } else {
                    LocalSolve::Exact
                },
            };
            solve_pgs_local_until(problem, &pgs, 0, &mut stop, &mut lambda)
        }
        LibrarySolver::Newton | LibrarySolver::NewtonRegularised => {
            let newton = NewtonSettings {
                max_iterations: settings.newton_iterations,
                regularisation: (solver == LibrarySolver::NewtonRegularised)
                    .then_some(Regularisation::MEASURED),
                ..NewtonSettings::default()
            };
            solve_newton_local_until(problem, &newton, &mut stop, &mut lambda)
        }
        LibrarySolver::Auto => {
            let auto = AutoSettings {
                newton: NewtonSettings {
                    max_iterations: settings.newton_iterations,
                    ..NewtonSettings::default()
                },
                tolerance,
                ..AutoSettings::default()
            };
            let mut error = |l: &[SVector<f64, R>]| library_error_given(problem, l, q_norm);
            let done = solve_auto_local_until(problem, &auto, &mut error, &mut lambda);
            sweeps = done.sweeps;
            path = Some(done.path.name());
            SolveReport {
                iterations: done.sweeps + done.newton_iterations,
                ..done.report
            }
        }
        LibrarySolver::NewtonTwins => {
            let twins = TwinSettings {
                newton: NewtonSettings {
                    max_iterations: settings.newton_iterations,
                    ..NewtonSettings::default()
                },
                tolerance,
                ..TwinSettings::default()
            };
            let mut error = |l: &[SVector<f64, R>]| library_error_given(problem, l, q_norm);
            let done = solve_twins_local_until(problem, &twins, &mut error, &mut lambda);
            if !done.left_out.is_empty() {
                path = Some("twins");
            }
            left_out = done.left_out;
            done.report
        }
    };
    let seconds = started.elapsed().as_secs_f64();
    let error = library_error(problem, &lambda);
    let (q_normalised_error, absolute_error) = other_error_measures(problem, &lambda);
    Attempt {
        solver,
        converged: error <= tolerance,
        iterations: report.iterations,
        seconds,
        error,
        q_normalised_error,
        absolute_error,
        residual: residual(problem, &lambda),
        coulomb_residual: coulomb_residual(problem, &lambda),
        criteria: criteria(problem, &lambda).1,
        method: path.unwrap_or(report.method.name()),
        sweeps,
        left_out,
    }
}

/// The largest of an answer's three physical parts (Signorini, cone boundary, maximum
/// dissipation; docs/contact.md §"Physical criteria"), J: zero at a Coulomb solution.
pub fn physical(criteria: &ContactCriteria) -> f64 {
    criteria
        .signorini
        .max(criteria.cone_boundary)
        .max(criteria.max_dissipation)
}

/// The entries as a Markdown table: per problem its size and, per solver, converged or not,
/// iterations, time, Siconos' error and the largest physical criterion ([`physical`]); then
/// per solver how many it solved.
pub fn markdown_table(entries: &[LibraryEntry], solvers: &[LibrarySolver]) -> String {
    let mut s = String::from("| problem | contacts | asymmetry |");
    for solver in solvers {
        s += &format!(
            " {} | iter | time (s) | error | criteria (J) |",
            solver.name()
        );
    }
    s += "\n|---|---:|---:|";
    for _ in solvers {
        s += "---|---:|---:|---:|---:|";
    }
    s += "\n";
    for e in entries {
        s += &format!("| {} | {} | {:.0e} |", e.name, e.contacts, e.asymmetry);
        for a in &e.attempts {
            let iterations = if a.solver == LibrarySolver::Auto {
                format!(
                    "{} ({}: {} sweeps + {})",
                    a.iterations,
                    a.method,
                    a.sweeps,
                    a.iterations - a.sweeps
                )
            } else if !a.left_out.is_empty() {
                format!("{} (without {:?})", a.iterations, a.left_out)
            } else {
                a.iterations.to_string()
            };
            s += &format!(
                " {} | {} | {:.3e} | {:.1e} | {:.1e} |",
                if a.converged { "yes" } else { "**no**" },
                iterations,
                a.seconds,
                a.error,
                physical(&a.criteria)
            );
        }
        s += "\n";
    }
    s += &format!("| **solved** | {} problems | |", entries.len());
    for (i, _) in solvers.iter().enumerate() {
        let solved = entries.iter().filter(|e| e.attempts[i].converged).count();
        s += &format!(" **{solved}** | | | | |");
    }
    s + "\n"
}

/// A Dolan–Moré performance profile: per solver, the ratios r_p = t_p / min_s t_p,s of the
/// problems it solved, sorted (∞ for the ones it did not solve are left out), and the number of
/// problems. ρ_s(τ) = #{p : r_p ≤ τ} / problems.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Profile {
    /// Problems in the profile (those some solver solved count; the others count as failures
    /// of every solver).
    pub problems: usize,
    /// Per solver (in the order asked), its sorted ratios.
    pub ratios: Vec<(LibrarySolver, Vec<f64>)>,
}

impl Profile {
    /// The profile of `entries` (times below 1 µs count as 1 µs, so that a solve too fast to
    /// time does not make every other one infinitely slower).
    pub fn of(entries: &[LibraryEntry], solvers: &[LibrarySolver]) -> Profile {
        const FLOOR: f64 = 1e-6;
        let mut ratios: Vec<(LibrarySolver, Vec<f64>)> =
            solvers.iter().map(|&s| (s, Vec::new())).collect();
        for e in entries {
            let best = e
                .attempts
                .iter()
                .filter(|a| a.converged)
                .map(|a| a.seconds.max(FLOOR))
                .fold(f64::INFINITY, f64::min);
            for (i, a) in e.attempts.iter().enumerate() {
                if a.converged {
                    ratios[i].1.push(a.seconds.max(FLOOR) / best);
                }
            }
        }
        for (_, r) in &mut ratios {
            r.sort_by(f64::total_cmp);
        }
        Profile {
            problems: entries.len(),
            ratios,
        }
    }

    /// ρ_s(τ) for the solver at `index`.
    pub fn fraction(&self, index: usize, tau: f64) -> f64 {
        if self.problems == 0 {
            return 0.0;
        }
        let solved = self.ratios[index].1.iter().filter(|&&r| r <= tau).count();
        solved as f64 / self.problems as f64
    }

    /// The largest finite ratio (at least 2, so the plot has a width).
    pub fn largest_ratio(&self) -> f64 {
        self.ratios
            .iter()
            .flat_map(|(_, r)| r.iter().copied())
            .fold(2.0, f64::max)
    }

    /// Draws the profile as an SVG: ρ_s(τ) against log₂ τ, one step line per solver.
    pub fn svg(&self, title: &str) -> Result<String, String> {
        use plotters::prelude::*;
        let mut text = String::new();
        {
            let root = SVGBackend::with_string(&mut text, (800, 500)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| e.to_string())?;
            let top = self.largest_ratio().log2().ceil().max(1.0);
            let mut chart = ChartBuilder::on(&root)
                .caption(title, ("sans-serif", 20))
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(55)
                .build_cartesian_2d(0.0..top * 1.05, 0.0..1.02)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc("log₂ τ (time within τ × the fastest solver's)")
                .y_desc("ρ(τ): fraction of problems solved")
                .draw()
                .map_err(|e| e.to_string())?;
            for (i, (solver, ratios)) in self.ratios.iter().enumerate() {
                let colour = crate::tools::viewing::plot::COLOURS
                    [i % crate::tools::viewing::plot::COLOURS.len()];
                // A step function: it rises at each ratio.
                let mut points = vec![(0.0, self.fraction(i, 1.0))];
                for &r in ratios {
                    let x = r.log2();
                    if x > 0.0 {
                        points.push((x, points.last().map_or(0.0, |p| p.1)));
                        points.push((x, self.fraction(i, r)));
                    }
                }
                points.push((top * 1.05, self.fraction(i, f64::INFINITY)));
                let solved = ratios.len();
                chart
                    .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(format!("{} ({solved}/{})", solver.name(), self.problems))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::LowerRight)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| e.to_string())?;
            root.present().map_err(|e| e.to_string())?;
        }
        Ok(text)
    }
}
