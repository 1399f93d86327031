//! The automatic choice between rigidref's solvers of a local problem, kept exact: a phase of
//! NSGS (PGS with exact local solves, in problem order: [`solve_pgs_local_until`]) while its
//! linear rate promises the tolerance within a horizon of sweeps, then the Newton solver
//! ([`solve_newton_local_until`], with all its fallbacks) warm-started from NSGS's λ.
//! docs/contact.md §"Automatic choice: NSGS, then Newton".
//!
//! Both phases stop where the caller's error measure e(λ) (for `rigidref solve-problems`,
//! Siconos' error) is at or below the tolerance, so an answer the choice returns is accepted by
//! the same measure as Newton's alone: the choice changes the path, never the criterion. NSGS's
//! progress is read off that same error after every sweep, e_k: for a linearly convergent
//! iteration e_k ≈ C r^k, so r is estimated over a window of m sweeps as (e_k / e_{k−m})^{1/m},
//! and the sweeps still needed to bring e_k down to the tolerance as ln(tol / e_k) / ln r. Where
//! that exceeds the horizon (or r ≥ 1), NSGS hands over to Newton.

use super::newton::{NewtonSettings, solve_newton_local_until};
use super::pgs_delassus::solve_pgs_local_until;
use super::{ContactOrder, LocalSolve, PgsSettings};
use crate::problem::{LocalProblem, SolveMethod, SolveReport};
use nalgebra::SVector;

/// How the automatic choice runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoSettings {
    /// The Newton phase's settings.
    pub newton: NewtonSettings,
    /// NSGS sweeps at most before Newton takes over (default 2000).
    pub max_sweeps: u32,
    /// Sweeps over which NSGS's rate is estimated (default 10).
    pub window: u32,
    /// NSGS goes on while the sweeps it still needs, by its rate, are at most this (default
    /// 1000): about what a Newton solve of a hard problem costs in sweeps (docs/contact.md
    /// §"Automatic choice: NSGS, then Newton", **Horizon**).
    pub horizon: f64,
    /// Both phases stop where the caller's error is at or below this (default 1e-8).
    pub tolerance: f64,
}

impl Default for AutoSettings {
    fn default() -> Self {
        AutoSettings {
            newton: NewtonSettings::default(),
            max_sweeps: 2000,
            window: 10,
            horizon: 1000.0,
            tolerance: 1e-8,
        }
    }
}

/// Which path produced the automatic choice's answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AutoPath {
    /// NSGS reached the criterion alone.
    Nsgs,
    /// NSGS handed over; the Newton iteration (or a plain Newton fallback) finished.
    NsgsNewton,
    /// NSGS handed over; Newton's proximal-point fallback finished.
    NsgsProximal,
}

impl AutoPath {
    /// The spelling in reports: `nsgs`, `nsgs+newton`, `nsgs+proximal`.
    pub fn name(self) -> &'static str {
        match self {
            AutoPath::Nsgs => "nsgs",
            AutoPath::NsgsNewton => "nsgs+newton",
            AutoPath::NsgsProximal => "nsgs+proximal",
        }
    }
}

/// What the automatic choice did.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoReport {
    /// The path that produced the answer.
    pub path: AutoPath,
    /// NSGS sweeps of the first phase.
    pub sweeps: u32,
    /// Newton iterations of the second phase (fallbacks included; 0 if it did not run).
    pub newton_iterations: u32,
    /// The last phase's report (its residuals are the answer's).
    pub report: SolveReport,
}

/// The automatic choice (module documentation) on a local problem from its `lambda0`, each phase
/// stopped where `error(λ)` is at most `settings.tolerance`. On return `lambda` holds one impulse
/// per contact (N·s); `report.converged` is the last phase's (for NSGS: whether the error met the
/// tolerance).
pub fn solve_auto_local_until<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &AutoSettings,
    error: &mut dyn FnMut(&[SVector<f64, R>]) -> f64,
    lambda: &mut Vec<SVector<f64, R>>,
) -> AutoReport {
    let pgs = PgsSettings {
        max_iterations: settings.max_sweeps,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: LocalSolve::Exact,
    };
    let window = settings.window.max(1) as usize;
    let tolerance = settings.tolerance;
    // e of the last `window` + 1 sweeps (allocated once).
    let mut errors = vec![0.0f64; window + 1];
    let mut sweep = 0usize;
    let mut solved = false;
    let mut phase = |l: &[SVector<f64, R>]| -> bool {
        sweep += 1;
        let e = error(l);
        errors[sweep % (window + 1)] = e;
        if e <= tolerance {
            solved = true;
            return true;
        }
        if sweep > window {
            let old = errors[(sweep - window) % (window + 1)];
            let rate = (e / old).powf(1.0 / window as f64);
            // r ≥ 1 (or NaN, from an error that is not a number): no progress.
            if rate.is_nan() || rate >= 1.0 {
                return true;
            }
            let needed = (tolerance / e).ln() / rate.ln();
            if needed > settings.horizon {
                return true;
            }
        }
        false
    };
    let first = solve_pgs_local_until(problem, &pgs, 0, &mut phase, lambda);
    let sweeps = first.iterations;
    if solved {
        return AutoReport {
            path: AutoPath::Nsgs,
            sweeps,
            newton_iterations: 0,
            report: first,
        };
    }
    let mut warm = problem.clone();
    for (c, l) in warm.contacts.iter_mut().zip(lambda.iter()) {
        c.lambda0 = *l;
    }
    let mut stop = |l: &[SVector<f64, R>]| error(l) <= tolerance;
    let report = solve_newton_local_until(&warm, &settings.newton, &mut stop, lambda);
    AutoReport {
        path: if report.method == SolveMethod::Proximal {
            AutoPath::NsgsProximal
        } else {
            AutoPath::NsgsNewton
        },
        sweeps,
        newton_iterations: report.iterations,
        report,
    }
}
