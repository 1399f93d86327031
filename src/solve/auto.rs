//! The automatic choice between rigidref's solvers of a local problem, kept exact: a phase of
//! NSGS (PGS with exact local solves, in problem order: [`solve_pgs_local_until`]) while its
//! linear rate promises the tolerance within a horizon of sweeps, then the Newton solver
//! ([`solve_newton_local_until`], with all its fallbacks) warm-started from NSGS's λ.
//! docs/contact.md §"Automatic choice: NSGS, then Newton".
//!
//! Both phases stop on the caller's criterion (for `rigidref solve-problems`, Siconos' error at
//! or below the tolerance), so an answer the choice returns is accepted by the same measure as
//! Newton's alone: the choice changes the path, never the criterion. NSGS's progress is read
//! off the change of λ over a sweep, d_k = ‖λ^k − λ^{k−1}‖ (Siconos' "light" error): for a
//! linearly convergent iteration d_k ≈ C r^k, so r is estimated over a window of sweeps as
//! (d_k / d_{k−m})^{1/m}, and the sweeps still needed to bring d_k down to tol ‖λ‖ (1 − r) as
//! ln(tol ‖λ‖ (1 − r) / d_k) / ln r. Where that exceeds the horizon (or r ≥ 1), NSGS hands over
//! to Newton. The caller's criterion (a full error: one product with W) is evaluated only where
//! the light error d_k / ‖λ‖ is at or below the tolerance, as Siconos' NSGS does by default.

use super::newton::{NewtonSettings, solve_newton_local_until};
use super::pgs_delassus::solve_pgs_local_until;
use super::{ContactOrder, LocalSolve, PgsSettings, Stop};
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
    /// 300): about what a Newton solve of a hard problem costs in sweeps.
    pub horizon: f64,
    /// The light error d_k / ‖λ‖ at or below which `stop` is evaluated during the NSGS phase
    /// (default 1e-8, the caller's relative tolerance).
    pub light_tolerance: f64,
}

impl Default for AutoSettings {
    fn default() -> Self {
        AutoSettings {
            newton: NewtonSettings::default(),
            max_sweeps: 2000,
            window: 10,
            horizon: 300.0,
            light_tolerance: 1e-8,
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
/// stopped where `stop(λ)` holds. On return `lambda` holds one impulse per contact (N·s);
/// `report.converged` is the last phase's (for NSGS: whether `stop` held).
pub fn solve_auto_local_until<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &AutoSettings,
    stop: &mut Stop<R>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> AutoReport {
    let pgs = PgsSettings {
        max_iterations: settings.max_sweeps,
        tolerance: None,
        order: ContactOrder::Sequential,
        local: LocalSolve::Exact,
    };
    let window = settings.window.max(1) as usize;
    // λ of the previous sweep, and d of the last `window` + 1 sweeps (allocated once).
    let mut previous: Vec<SVector<f64, R>> = Vec::with_capacity(problem.contacts.len());
    let mut changes = vec![0.0f64; window + 1];
    let mut sweep = 0usize;
    let mut solved = false;
    let light = settings.light_tolerance;
    let mut phase = |l: &[SVector<f64, R>]| -> bool {
        sweep += 1;
        if previous.is_empty() {
            previous.extend_from_slice(l);
            // The first sweep's change is measured from its own result: no rate yet.
            return check(stop, l, &mut solved);
        }
        let mut d2 = 0.0;
        let mut n2 = 0.0;
        for (a, b) in l.iter().zip(previous.iter_mut()) {
            d2 += (a - *b).norm_squared();
            n2 += a.norm_squared();
            *b = *a;
        }
        let (d, norm) = (d2.sqrt(), n2.sqrt());
        changes[sweep % (window + 1)] = d;
        if d <= light * norm && check(stop, l, &mut solved) {
            return true;
        }
        if sweep > window + 1 {
            let old = changes[(sweep - window) % (window + 1)];
            let rate = if old > 0.0 {
                (d / old).powf(1.0 / window as f64)
            } else {
                0.0
            };
            if d > 0.0 && rate >= 1.0 {
                return true;
            }
            if d > 0.0 && rate > 0.0 {
                let target = light * norm * (1.0 - rate);
                let needed = (target / d).ln() / rate.ln();
                if needed > settings.horizon {
                    return true;
                }
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
    // The final check of the NSGS phase (its last sweep may have been gated out).
    if stop(lambda) {
        return AutoReport {
            path: AutoPath::Nsgs,
            sweeps,
            newton_iterations: 0,
            report: SolveReport {
                converged: true,
                ..first
            },
        };
    }
    let mut warm = problem.clone();
    for (c, l) in warm.contacts.iter_mut().zip(lambda.iter()) {
        c.lambda0 = *l;
    }
    let report = solve_newton_local_until(&warm, &settings.newton, stop, lambda);
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

/// `stop(λ)`, recording in `solved` whether it held.
fn check<const R: usize>(stop: &mut Stop<R>, l: &[SVector<f64, R>], solved: &mut bool) -> bool {
    *solved = stop(l);
    *solved
}
