//! Near-duplicate contacts ("twins") left out: the Newton solver, restarted from its own answer,
//! and where it still stalls, the same problem without one contact of each near-duplicate pair
//! that carries the error, the answer judged on the whole problem. docs/contact.md
//! §"Near-duplicate contacts left out".
//!
//! Two contacts whose normal rows of W are parallel to round-off (the same normal through the
//! same bodies at nearly the same point, as a mesh's coincident vertices give) leave one
//! combination of their impulses with no effect on any velocity: the answer is not isolated, and
//! the iteration cannot settle which of the two carries the load (RockPile_tob1,
//! docs/problem-library.md §"RockPile_tob1"). A contact left out with λ_k = 0 satisfies its law
//! exactly where its normal velocity w_n,k ≥ 0, for the cone and the box law, whatever μ; so an
//! exact answer of the problem without it, extended by zeros, is exact for the whole problem
//! wherever the contacts left out end with w_n ≥ 0. Of each pair the contact left out first is
//! the one moving apart faster at the stalled answer (larger w_n): its twin is the one pressed
//! into contact. Where one left out ends with w_n < 0 (it would penetrate), the two of that pair
//! swap, and the reduced problem is solved again, until a choice is exact on the whole problem,
//! repeats, or the rounds run out.

use super::newton::{NewtonSettings, solve_newton_local_until};
use super::residual::siconos_share;
use crate::problem::{FrictionModel, LocalProblem, RowBounds, SolveReport};
use nalgebra::SVector;

/// How the twin reduction runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwinSettings {
    /// Each Newton run's settings (its fallbacks included).
    pub newton: NewtonSettings,
    /// Newton runs from the best answer so far, after the first, before any contact is left out
    /// (default 1).
    pub restarts: u32,
    /// Twins: normal rows of W with cosine above 1 − this (default 1e-8).
    pub cosine: f64,
    /// Pairs are looked for among the contacts that carry this fraction of the squared error
    /// at the stalled answer, largest first (default 0.99).
    pub share: f64,
    /// Reduced problems solved at most (default 8).
    pub rounds: u32,
    /// Every stage stops where the caller's error of the whole problem is at or below this
    /// (default 1e-8).
    pub tolerance: f64,
}

impl Default for TwinSettings {
    fn default() -> Self {
        TwinSettings {
            newton: NewtonSettings::default(),
            restarts: 1,
            cosine: 1e-8,
            share: 0.99,
            rounds: 8,
            tolerance: 1e-8,
        }
    }
}

/// What the twin reduction did.
#[derive(Clone, Debug, PartialEq)]
pub struct TwinReport {
    /// Newton runs on the whole problem (the first and its restarts).
    pub whole_runs: u32,
    /// The near-duplicate pairs found at the stalled answer (contact numbers, ascending).
    pub pairs: Vec<(usize, usize)>,
    /// Reduced problems solved.
    pub rounds: u32,
    /// The contacts left out in the returned answer (empty where it is a Newton run's on the
    /// whole problem), ascending.
    pub left_out: Vec<usize>,
    /// Newton iterations of every run together, fallbacks included.
    pub iterations: u32,
    /// The report of the run that produced the returned answer; its residuals and `converged`
    /// (rigidref's residual at most the Newton solver's tolerance, m/s) are the whole
    /// problem's.
    pub report: SolveReport,
}

/// The twin reduction (module documentation) on a local problem from its `lambda0`, every stage
/// stopped where `error(λ)` of the whole problem is at most `settings.tolerance`. On return
/// `lambda` holds the answer with the lowest error found, one impulse per contact (N·s).
/// docs/contact.md §"Near-duplicate contacts left out".
pub fn solve_twins_local_until<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &TwinSettings,
    error: &mut dyn FnMut(&[SVector<f64, R>]) -> f64,
    lambda: &mut Vec<SVector<f64, R>>,
) -> TwinReport {
    let tolerance = settings.tolerance;
    let mut iterations = 0;
    let mut start: Vec<SVector<f64, R>> = problem.contacts.iter().map(|c| c.lambda0).collect();
    let mut best: Option<(f64, Vec<SVector<f64, R>>, SolveReport)> = None;
    let mut whole_runs = 0;
    // The whole problem: the first run and its restarts, each from the best answer so far.
    while whole_runs <= settings.restarts {
        let (warm, _) = problem.without(&vec![false; problem.contacts.len()], &start);
        let mut stop = |l: &[SVector<f64, R>]| error(l) <= tolerance;
        let mut answer = Vec::new();
        let report = solve_newton_local_until(&warm, &settings.newton, &mut stop, &mut answer);
        whole_runs += 1;
        iterations += report.iterations;
        let e = error(&answer);
        let better = best.as_ref().is_none_or(|(b, _, _)| e < *b);
        if better {
            start.clone_from(&answer);
            best = Some((e, answer, report));
        }
        // Solved, or a restart that did not improve (the next would repeat it).
        if e <= tolerance || !better {
            break;
        }
    }
    let (best_error, best_answer, best_report) = best.expect("one run at least");
    let mut reduction = Reduction {
        rounds: 0,
        left_out: Vec::new(),
        error: best_error,
        report: best_report,
    };
    let mut pairs = Vec::new();
    *lambda = best_answer;
    if best_error > tolerance {
        pairs = twin_pairs(problem, lambda, settings.share, settings.cosine);
        let choice = first_choice(&pairs, &problem.velocity(lambda));
        let base = lambda.clone();
        let reduced = solve_without_twins(problem, settings, &pairs, choice, &base, error, lambda);
        iterations += reduced.iterations();
        // A reduced answer replaces the whole run's only where it is better.
        if !reduced.left_out.is_empty() {
            reduction = reduced;
        } else {
            reduction.rounds = reduced.rounds;
        }
    }
    // The residuals, and `converged` by the Newton solver's own test, of the whole problem.
    let residual = super::residual::residual(problem, lambda);
    let report = SolveReport {
        iterations,
        residual,
        converged: residual <= settings.newton.tolerance,
        coulomb_residual: (problem.friction == FrictionModel::Cone)
            .then(|| super::residual::coulomb_residual(problem, lambda)),
        ..reduction.report
    };
    TwinReport {
        whole_runs,
        pairs,
        rounds: reduction.rounds,
        left_out: reduction.left_out,
        iterations,
        report,
    }
}

/// The first choice of the contacts left out, one per pair (in the pairs' order): the contact
/// moving apart faster at the velocities `w` (the larger w_n, m/s; ties: the later one, b of
/// (a, b)). Its twin is the one pressed into contact, so the one that should carry the load.
/// docs/contact.md §"Near-duplicate contacts left out", step 3.
pub fn first_choice<const R: usize>(pairs: &[(usize, usize)], w: &[SVector<f64, R>]) -> Vec<usize> {
    pairs
        .iter()
        .map(|&(a, b)| if w[a][0] > w[b][0] { a } else { b })
        .collect()
}

/// What [`solve_without_twins`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct Reduction {
    /// Reduced problems solved.
    pub rounds: u32,
    /// The contacts left out in the answer returned, ascending (empty where no reduced answer
    /// was better than the start).
    pub left_out: Vec<usize>,
    /// The caller's error of the answer returned, on the whole problem.
    pub error: f64,
    /// The Newton report of the run that produced it (iterations: every round's together).
    pub report: SolveReport,
}

impl Reduction {
    /// Newton iterations of every round together.
    pub fn iterations(&self) -> u32 {
        self.report.iterations
    }
}

/// The rounds of the twin reduction from a first `choice` (one contact of each of `pairs`, in
/// their order), each reduced problem warm-started from `base` (then from the last reduced
/// answer) and stopped where the whole problem's `error` is at most the tolerance, or where
/// the reduced problem is solved to the Newton solver's own tolerance. After each round, the
/// pairs whose contact left out ends with w_n < 0 swap. `lambda` ends as the best of `base` and
/// every round's answer (N·s). docs/contact.md §"Near-duplicate contacts left out".
pub fn solve_without_twins<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &TwinSettings,
    pairs: &[(usize, usize)],
    mut choice: Vec<usize>,
    base: &[SVector<f64, R>],
    error: &mut dyn FnMut(&[SVector<f64, R>]) -> f64,
    lambda: &mut Vec<SVector<f64, R>>,
) -> Reduction {
    let tolerance = settings.tolerance;
    let n = problem.contacts.len();
    lambda.clear();
    lambda.extend_from_slice(base);
    let mut best = Reduction {
        rounds: 0,
        left_out: Vec::new(),
        error: error(base),
        report: SolveReport::default(),
    };
    let mut iterations = 0;
    let mut tried: Vec<Vec<usize>> = Vec::new();
    let mut base = base.to_vec();
    while !pairs.is_empty() && best.rounds < settings.rounds && best.error > tolerance {
        let mut sorted = choice.clone();
        sorted.sort_unstable();
        if tried.contains(&sorted) {
            break;
        }
        tried.push(sorted.clone());
        let mut left_out = vec![false; n];
        for &k in &choice {
            left_out[k] = true;
        }
        let (reduced, kept) = problem.without(&left_out, &base);
        let extend = |part: &[SVector<f64, R>]| {
            let mut full = vec![SVector::<f64, R>::zeros(); n];
            for (i, &k) in kept.iter().enumerate() {
                full[k] = part[i];
            }
            full
        };
        // Stop where the whole problem is solved, or else where the reduced one is (to the
        // Newton solver's own tolerance, m/s), so that the contacts left out can be judged.
        let mut stop = |part: &[SVector<f64, R>]| {
            error(&extend(part)) <= tolerance
                || super::residual::residual(&reduced, part) <= settings.newton.tolerance
        };
        let mut part = Vec::new();
        let report = solve_newton_local_until(&reduced, &settings.newton, &mut stop, &mut part);
        best.rounds += 1;
        iterations += report.iterations;
        let answer = extend(&part);
        let e = error(&answer);
        let w = problem.velocity(&answer);
        if e < best.error {
            best.error = e;
            best.left_out = sorted;
            best.report = report;
            lambda.clone_from(&answer);
        }
        // The next choice: swap each pair whose contact left out would penetrate.
        let mut swapped = false;
        for (c, &(a, b)) in choice.iter_mut().zip(pairs) {
            if w[*c][0] < 0.0 {
                *c = if *c == a { b } else { a };
                swapped = true;
            }
        }
        if !swapped {
            break;
        }
        base = answer;
    }
    best.report.iterations = iterations;
    best
}

/// The near-duplicate pairs that carry the error at `lambda`: the contacts whose terms of
/// Siconos' error ([`siconos_share`]) make up `share` of its square, largest first, each paired
/// with the contact (a contact, not a joint, not already paired) whose normal row of W is most
/// nearly parallel to its own, where their cosine is above 1 − `cosine`. Pairs ascending within
/// and in the order found. docs/contact.md §"Near-duplicate contacts left out", step 2.
pub fn twin_pairs<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    share: f64,
    cosine: f64,
) -> Vec<(usize, usize)> {
    let n = problem.contacts.len();
    let w = problem.velocity(lambda);
    let terms: Vec<f64> = (0..n)
        .map(|k| {
            let c = &problem.contacts[k];
            siconos_share(c.bounds, c.mu, &lambda[k], &w[k])
        })
        .collect();
    let total: f64 = terms.iter().sum();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| terms[b].total_cmp(&terms[a]).then(a.cmp(&b)));
    let norms: Vec<f64> = (0..n).map(|k| normal_dot(problem, k, k).sqrt()).collect();
    let mut paired = vec![false; n];
    let mut pairs = Vec::new();
    let mut carried = 0.0;
    for &k in &order {
        if carried >= share * total || terms[k] == 0.0 {
            break;
        }
        carried += terms[k];
        if paired[k] || problem.contacts[k].bounds != RowBounds::Contact || norms[k] == 0.0 {
            continue;
        }
        let mut twin = None;
        let mut most = 1.0 - cosine;
        for j in 0..n {
            if j == k || paired[j] || problem.contacts[j].bounds != RowBounds::Contact {
                continue;
            }
            let c = normal_dot(problem, k, j) / (norms[k] * norms[j]);
            if c > most {
                most = c;
                twin = Some(j);
            }
        }
        if let Some(j) = twin {
            paired[k] = true;
            paired[j] = true;
            pairs.push((k.min(j), k.max(j)));
        }
    }
    pairs
}

/// The dot product of contacts `a`'s and `b`'s normal rows of W (row 0 of each block row),
/// kg⁻².
fn normal_dot<const R: usize>(problem: &LocalProblem<R>, a: usize, b: usize) -> f64 {
    let (ra, rb) = (&problem.contacts[a].row, &problem.contacts[b].row);
    let (mut i, mut j, mut sum) = (0, 0, 0.0);
    while i < ra.len() && j < rb.len() {
        match ra[i].0.cmp(&rb[j].0) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                for c in 0..R {
                    sum += ra[i].1[(0, c)] * rb[j].1[(0, c)];
                }
                i += 1;
                j += 1;
            }
        }
    }
    sum
}
