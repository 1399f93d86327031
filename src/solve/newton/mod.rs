//! The exact solver: a semismooth Newton method on the Alart–Curnier function, independent of
//! PGS (it shares the problem and nothing else). docs/contact.md §"Newton solver".
//!
//! With W = A + C the Delassus operator with compliance (kg⁻¹) and w = W λ + b, each contact's
//! law is written as an equation F_k(λ_k, w_k) = 0 in velocity units (m/s), Alart and Curnier's
//! function with the radius μ max(0, s_n), s_n = λn − w_n / a_n:
//!
//!   F_n = a_n (λn − max(0, s_n)) = min(a_n λn, w_n)             (0 ≤ λn ⊥ w_n ≥ 0)
//!   F_r = a_r (λ_r − clamp(λ_r − w_r / a_r, ±μ max(0, s_n)))    (box row r)
//!   F_t = ρ (λt − proj_disk(λt − w_t / ρ, μ max(0, s_n)))        (disk, the pair of rows)
//!   F_r = w_r                                                   (a joint's free row)
//!
//! with a_r = W_rr and ρ the largest eigenvalue of the contact's tangent block. F = 0 exactly at
//! the solutions (there s_n = λn whenever λn > 0, and the radius is 0 when λn = 0). Newton solves
//! F(λ) = 0 with the generalized Jacobian ∂F = D_λ + D_w W (D_λ, D_w block diagonal, read off
//! the branch each row is on), regularised as ∂F + D_w H with H = ε diag(W) (a proximal term
//! centred at the current iterate, so the equation is unchanged; it makes the system solvable
//! where W's rank deficiency alone would make it singular; ε held at 1e-12 and raised only after
//! a failed step), globalised by a non-monotone Armijo line search on θ = ½‖F‖² (against the
//! largest θ of the last five iterations). Where that stalls (the best law norm not halved in
//! [`STALL`] iterations, and, for a run from the start, not recovered to convergence by
//! [`STALL_EXTENDED`]) or runs out of iterations, a run from λ = 0 follows (when the start was
//! warm), then the proximal-point loop (docs/contact.md §"Proximal-point globalisation"): each
//! subproblem has W + H and b − H λ_c, H = η diag(W), about a centre λ_c, is solved by the same
//! Newton iteration to a tenth of the law norm at the centre, and η = σ ‖F(λ_c)‖ / max|b| follows
//! the residual (× 10 after a failed subproblem); a fixed point is a solution of the original
//! problem. Where that loop fails too, a plain run from the start without the stall rule and then
//! the tenfold loop from its end (η from 1, ÷ 10 per solved subproblem: the fallback before the
//! adaptive loop) follow, kept where better. The report says which produced the answer.
//!
//! The linear systems are solved densely (nalgebra's LU with partial pivoting) up to
//! [`DENSE_ROWS`] rows, and above that by faer's sparse LU on the block pattern of W (contacts
//! that share a body), whose symbolic factorisation is computed once per solve and whose numeric
//! factors, values and scratch memory are written in place by every iteration.

mod law;
mod system;

use law::*;
use system::*;

use crate::problem::{
    ContactProblem, FrictionModel, LocalProblem, ProblemView, RowBounds, SolveMethod, SolveReport,
};
use crate::solve::residual::{coulomb_residual, residual};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// Rows up to which the Newton system is factorised densely; above, by faer's sparse LU.
pub const DENSE_ROWS: usize = 120;

/// How long the Newton solver runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Newton iterations at most, before the proximal fallback (default 50).
    pub max_iterations: u32,
    /// Converged when the residual (docs/contact.md §"Residual") and, for cone friction, the
    /// exact Coulomb residual of the answer are both at or below this, m/s (default 1e-10, the
    /// level at which `rigidref crosscheck` counts a solve as converged), or, where the
    /// iteration stalls above it, at or below the round-off floor [`round_off_floor`] of the
    /// answer when that floor is above it.
    pub tolerance: f64,
    /// Proximal-point iterations at most in the fallback (default 60).
    pub proximal_iterations: u32,
    /// Rows up to which the Newton system is factorised densely; above, by the sparse LU
    /// (default [`DENSE_ROWS`]; the two give the same answer to round-off, which a test checks).
    pub dense_rows: usize,
    /// A Newton matrix regularised by ε following the law norm in the plain runs (`None`, the
    /// default: ε starts at 10⁻¹² every iteration). docs/contact.md §"Newton solver",
    /// **Regularisation following ‖F‖**.
    pub regularisation: Option<Regularisation>,
}

/// The regularisation ε = c (‖F‖∞ / max|b|)^δ of the Newton matrix W + ε diag(W) in the plain
/// runs' iterations (the one-step proximal matrix centred at the iterate; F stays the original
/// problem's, so an answer is as exact as without it). docs/contact.md §"Newton solver",
/// **Regularisation following ‖F‖**.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Regularisation {
    /// c, dimensionless.
    pub factor: f64,
    /// δ, dimensionless.
    pub exponent: f64,
}

impl Regularisation {
    /// c = 1, δ = 1.5: the best of the values measured on Siconos' test data (so chosen on the
    /// folder it is then measured on; docs/contact.md §"Newton solver").
    pub const MEASURED: Regularisation = Regularisation {
        factor: 1.0,
        exponent: 1.5,
    };

    /// ε for law norm `norm` (m/s) and velocity scale `scale` = max|b| (m/s), within
    /// [10⁻¹², 10⁸].
    pub fn epsilon(&self, norm: f64, scale: f64) -> f64 {
        (self.factor * (norm / scale).powf(self.exponent)).clamp(EPS_FLOOR, ETA_MAX)
    }
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            max_iterations: 50,
            tolerance: 1e-10,
            proximal_iterations: 60,
            dense_rows: DENSE_ROWS,
            regularisation: None,
        }
    }
}

/// Buffers the Newton solver keeps between solves.
#[derive(Clone, Debug, Default)]
pub struct NewtonWorkspace<const D: usize> {
    /// Δu per body after the last solve: M⁻¹ Jᵀ λ.
    delta_velocity: Vec<SVector<f64, D>>,
}

impl<const D: usize> NewtonWorkspace<D> {
    /// Δu of body `i` after the last solve: add it to the body's velocity.
    pub fn delta_velocity(&self, i: usize) -> &SVector<f64, D> {
        &self.delta_velocity[i]
    }
}

/// The factor of the round-off floor [`round_off_floor`]: sums of a few terms per row, and the
/// exact Coulomb residual's scale (a block's trace, up to three times its largest diagonal
/// entry) and De Saxcé's term μ‖w_t‖ on top; 16 left the Coulomb residual of a problem with
/// impulses of 1e9 N·s at 2.3 times the floor.
pub const ROUND_OFF_FACTOR: f64 = 64.0;

/// The largest round-off floor accepted, as a fraction of the problem's largest |q_r|.
pub const ROUND_OFF_CAP: f64 = 1e-6;

/// The velocity error w = W λ + q carries from rounding alone, m/s: [`ROUND_OFF_FACTOR`] ε
/// max_r W_rr ‖λ‖∞ (W's largest diagonal entry stands for its norm). Below it no residual can
/// be told from zero: with impulses of 10⁹ N·s and W of order 1 kg⁻¹ it is 1.4e-5 m/s, far above
/// the default tolerance. 0 where it is above [`ROUND_OFF_CAP`] times the largest |q_r|: there
/// the size of λ, not rounding, is what is wrong (an iteration running off along a direction
/// in which W is singular, on a problem without a solution, reaches impulses of 10¹⁴ N·s whose
/// "floor" would pass a contact approaching at 0.2 m/s).
pub fn round_off_floor<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> f64 {
    let largest_diagonal = crate::solve::residual::diagonal_floor(problem)
        / crate::solve::residual::ROUND_OFF_DIAGONAL;
    let largest_impulse = lambda.iter().map(|l| l.amax()).fold(0.0, f64::max);
    let floor = ROUND_OFF_FACTOR * f64::EPSILON * largest_diagonal * largest_impulse;
    let largest_q = problem.dense_b().amax();
    if floor <= ROUND_OFF_CAP * largest_q {
        floor
    } else {
        0.0
    }
}

/// Armijo's constant: a step is taken when θ falls by at least this fraction of its linear
/// prediction.
const ARMIJO: f64 = 1e-4;
/// Iterations whose θ a trial step is compared with (the largest of them).
const NONMONOTONE_MEMORY: usize = 5;
/// Halvings of the step before the line search gives up (step 2⁻¹²): a shorter step makes no
/// progress worth its cost, and the iteration tries a better-conditioned system instead.
const LINE_SEARCH_HALVINGS: u32 = 12;
/// The Jacobian's regularisation ε diag(W) starts at this ε and grows 10⁴-fold per failed step
/// (1e-12, 1e-8, 1e-4, 1).
const EPS_FLOOR: f64 = 1e-12;

/// A run of Newton iterations stalls when its best law norm has not halved in this many
/// iterations: it is wandering, and the proximal loop takes over.
const STALL: u32 = 10;
/// A run from the problem's start that has stalled goes on until its best law norm has not
/// halved in this many iterations; if it recovers it goes on as before, if not it ends with the
/// best point of the stall ([`STALL`]): docs/contact.md §"Newton solver", **Stall rule**.
const STALL_EXTENDED: u32 = 25;

/// Which stall rule a run of iterations obeys.
#[derive(Clone, Copy, PartialEq)]
enum Stall {
    /// Ends [`STALL`] iterations after the best law norm last halved (proximal subproblems).
    Short,
    /// Stalls after [`STALL`], ends after [`STALL_EXTENDED`] iterations without halving, and
    /// then returns the best point as of the stall (runs from the start, warm or cold).
    Extended,
    /// No stall rule: only the iteration limit ends the run.
    Never,
}
/// The proximal parameter η = σ ‖F(λ_c)‖ / max|b| after a solved subproblem (Siconos' PROX
/// default σ = 5 on its relative error).
const PROXIMAL_SIGMA: f64 = 5.0;
/// Each subproblem of the adaptive loop is solved to the centre's law norm divided by this
/// (the tenfold loop's: [`TENFOLD_INNER_RATIO`]).
const PROXIMAL_INNER_RATIO: f64 = 10.0;
/// Each subproblem of the tenfold loop is solved to the centre's law norm divided by this.
const TENFOLD_INNER_RATIO: f64 = 100.0;
/// The proximal parameter's smallest value (relative to diag(W)).
pub const ETA_MIN: f64 = 1e-12;
/// The proximal parameter's largest value (relative to diag(W)).
pub const ETA_MAX: f64 = 1e8;

/// How the proximal loop sets η (docs/contact.md §"Proximal-point globalisation").
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Schedule {
    /// η = σ ‖F(λ_c)‖ / max|b| after a solved subproblem; subproblems solved to a tenth of
    /// ‖F(λ_c)‖ under the stall rule; the centre moves to any answer that lowers ‖F‖.
    Adaptive,
    /// η from 1, ÷ 10 after a solved subproblem; subproblems solved to a hundredth of ‖F(λ_c)‖
    /// without the stall rule; the centre moves to solved subproblems only. Slower, but it
    /// solves problems the adaptive loop does not (fc2d_granularflowonwall_02020 of Siconos'
    /// data, a problem of rigid3d scene 7).
    Tenfold,
}

impl Schedule {
    /// η of the loop's first subproblem (dimensionless, relative to diag(W)), from the law norm
    /// ‖F(λ_c)‖∞ (m/s) at the entry point and the velocity scale max|b| (m/s): σ ‖F‖ / max|b|
    /// clamped to [[`ETA_MIN`], [`ETA_MAX`]] (adaptive), or 1 (tenfold).
    pub fn first_eta(self, norm: f64, scale: f64) -> f64 {
        match self {
            Schedule::Adaptive => Self::adapted(norm, scale),
            Schedule::Tenfold => 1.0,
        }
    }

    /// η of the next subproblem after one with η = `eta` that was `solved` (reached its inner
    /// tolerance) or not, the centre's law norm being `norm` (m/s) and the velocity scale `scale`
    /// (m/s): after a solved one σ ‖F‖ / max|b| (adaptive) or η / 10 (tenfold), after a failed
    /// one 10 η, within [[`ETA_MIN`], [`ETA_MAX`]].
    pub fn next_eta(self, eta: f64, solved: bool, norm: f64, scale: f64) -> f64 {
        match (self, solved) {
            (Schedule::Adaptive, true) => Self::adapted(norm, scale),
            (Schedule::Tenfold, true) => (eta * 0.1).max(ETA_MIN),
            (_, false) => (eta * 10.0).min(ETA_MAX),
        }
    }

    fn adapted(norm: f64, scale: f64) -> f64 {
        (PROXIMAL_SIGMA * norm / scale).clamp(ETA_MIN, ETA_MAX)
    }
}

/// The proximal loop's parameter as the loop carries it from subproblem to subproblem: η for
/// the next subproblem and the failed subproblems in a row (docs/contact.md §"Proximal-point
/// globalisation").
#[derive(Clone, Copy, Debug)]
pub struct ProximalParameter {
    schedule: Schedule,
    /// η for the next subproblem (dimensionless, relative to diag(W)).
    pub eta: f64,
    /// Failed subproblems in a row.
    pub failures: u32,
}

impl ProximalParameter {
    /// The first subproblem's: [`Schedule::first_eta`], no failure yet.
    pub fn new(schedule: Schedule, norm: f64, scale: f64) -> Self {
        ProximalParameter {
            schedule,
            eta: schedule.first_eta(norm, scale),
            failures: 0,
        }
    }

    /// After a subproblem at η = `self.eta`, `solved` or not (the centre's law norm `norm`, the
    /// velocity scale `scale`, m/s): `false` where the loop gives up, a subproblem failed at
    /// η_max ([`ETA_MAX`]) being more than the third failure in a row; else the count and η
    /// ([`Schedule::next_eta`]) for the next subproblem, and `true`.
    pub fn after(&mut self, solved: bool, norm: f64, scale: f64) -> bool {
        if solved {
            self.failures = 0;
        } else {
            self.failures += 1;
            if self.eta >= ETA_MAX && self.failures > 3 {
                return false;
            }
        }
        self.eta = self.schedule.next_eta(self.eta, solved, norm, scale);
        true
    }
}

/// How a run of Newton iterations ended.
struct Run {
    iterations: u32,
    /// The law norm of F (with the proximal term, when given) at the end.
    norm: f64,
    reached: bool,
}

/// What ends a run of iterations: `accept(λ, law norm)`.
type Accept<'a> = dyn FnMut(&DVector<f64>, f64) -> bool + 'a;

/// Newton iterations on F (with the proximal term when given) from `lambda`, at most
/// `max_iterations`, until `accept(λ, law norm)` holds or the line search stalls.
fn iterate<const R: usize>(
    system: &System<R>,
    lambda: &mut DVector<f64>,
    proximal: Option<&Proximal>,
    max_iterations: u32,
    stall: Stall,
    accept: &mut Accept,
) -> Run {
    let (window, end) = match stall {
        Stall::Short => (STALL, STALL),
        Stall::Extended => (STALL, STALL_EXTENDED),
        Stall::Never => (u32::MAX, u32::MAX),
    };
    let n = system.rows();
    let mut w = DVector::zeros(n);
    let mut f = DVector::zeros(n);
    let mut blocks = Vec::with_capacity(system.laws.len());
    let mut trial_w = DVector::zeros(n);
    let mut trial_f = DVector::zeros(n);
    let mut trial_blocks = Vec::with_capacity(system.laws.len());
    evaluate(system, lambda, proximal, &mut w, &mut f, &mut blocks);
    let mut iterations = 0;
    // θ of the last iterations: a step is measured against the largest (a non-monotone line
    // search), so that the iteration can cross a ridge of θ on its way along a direction in
    // which W is singular, where a monotone search only creeps.
    let mut recent = [0.0f64; NONMONOTONE_MEMORY];
    // The best point so far by the law norm: the non-monotone search may end above it, and an
    // unsuccessful run returns it rather than its last iterate.
    let mut best: (f64, DVector<f64>) = (f64::INFINITY, lambda.clone());
    // The best law norm the run must halve within `window` iterations, and when it was set.
    let mut mark = (f64::INFINITY, 0);
    // The best point when the run first stalled (`window` iterations without halving), while
    // it goes on until `end` iterations without halving: what it returns unless it converges.
    let mut stalled: Option<(f64, DVector<f64>)> = None;
    let velocity_scale = system.velocity_scale();
    loop {
        let norm = law_norm(system, &f);
        if norm < best.0 {
            best = (norm, lambda.clone());
        }
        if best.0 <= 0.5 * mark.0 {
            mark = (best.0, iterations);
        }
        if accept(lambda, norm) {
            return Run {
                iterations,
                norm,
                reached: true,
            };
        }
        if stalled.is_none() && iterations - mark.1 >= window && window < end {
            stalled = Some(best.clone());
        }
        if iterations >= max_iterations || iterations - mark.1 >= end {
            let (norm, point) = stalled.unwrap_or(best);
            *lambda = point;
            return Run {
                iterations,
                norm,
                reached: false,
            };
        }
        let theta = 0.5 * f.norm_squared();
        recent[iterations as usize % NONMONOTONE_MEMORY] = theta;
        let reference = recent.iter().copied().fold(theta, f64::max);
        iterations += 1;
        // The least regularisation first: diag(W) can exceed W's smallest eigenvalue on the
        // directions that matter by 10⁶ (a heavy body on a light one), where any larger ε
        // turns the Newton step into a gradient step. More only after a failed step. With the
        // regularisation option, plain runs start at ε = c (‖F‖∞ / max|b|)^δ instead.
        let mut epsilon = match (proximal, system.regularisation) {
            (None, Some(r)) => r.epsilon(norm, velocity_scale),
            _ => EPS_FLOOR,
        };
        let mut stepped = false;
        // A failed factorisation or a failed line search retries with more regularisation (a
        // shorter, better-conditioned step), three times: one schedule for both.
        for _ in 0..4 {
            let prox = proximal.map_or(0.0, |p| p.eta);
            let h = system.scales.map(|a| (epsilon + prox) * a);
            if let Some(delta) = solve_newton_system(system, &blocks, &h, &(-&f)) {
                let mut t = 1.0;
                for _ in 0..=LINE_SEARCH_HALVINGS {
                    let trial = &*lambda + &delta * t;
                    evaluate(
                        system,
                        &trial,
                        proximal,
                        &mut trial_w,
                        &mut trial_f,
                        &mut trial_blocks,
                    );
                    if 0.5 * trial_f.norm_squared() <= reference - 2.0 * ARMIJO * t * theta {
                        *lambda = trial;
                        std::mem::swap(&mut w, &mut trial_w);
                        std::mem::swap(&mut f, &mut trial_f);
                        std::mem::swap(&mut blocks, &mut trial_blocks);
                        stepped = true;
                        break;
                    }
                    t *= 0.5;
                }
            }
            if stepped {
                break;
            }
            epsilon *= 1e4;
        }
        if !stepped {
            let (norm, point) = stalled.unwrap_or(best);
            *lambda = point;
            return Run {
                iterations,
                norm,
                reached: false,
            };
        }
    }
}

/// Solves `problem` exactly (module documentation), starting from each contact's `lambda0`. On
/// return `lambda` holds one impulse per contact (N·s) and `workspace.delta_velocity(i)` each
/// body's velocity change. The report's residuals are recomputed from the answer through the
/// bodies by [`residual`] and [`coulomb_residual`], so `converged` never rests on the
/// iteration's own bookkeeping (which works on the local form, [`ContactProblem::to_local`]).
pub fn solve_newton<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &NewtonSettings,
    workspace: &mut NewtonWorkspace<D>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    let local = problem.to_local();
    let report = newton(problem, &local, settings, None, lambda);
    let delta = problem.velocity_change(lambda);
    workspace.delta_velocity.clear();
    workspace.delta_velocity.extend(delta);
    report
}

/// Solves a problem in local form exactly, as [`solve_newton`], starting from each contact's
/// `lambda0`; the report's residuals are recomputed from the answer through W.
pub fn solve_newton_local<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &NewtonSettings,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    newton(problem, problem, settings, None, lambda)
}

/// As [`solve_newton_local`], but the iteration (and each fallback) stops where `stop(λ)`
/// holds instead of at the settings' tolerance: for `rigidref solve-problems`, which stops
/// every solver on Siconos' error measure. The report's `converged` is still the residual's.
pub fn solve_newton_local_until<const R: usize>(
    problem: &LocalProblem<R>,
    settings: &NewtonSettings,
    stop: &mut super::Stop<R>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    newton(problem, problem, settings, Some(stop), lambda)
}

/// The Newton iteration and its fallbacks on `local`, the answer judged on `judge` (the same
/// problem in the form the caller gave); `stop`, when given, replaces the tolerance as what
/// ends the iteration.
fn newton<const R: usize, P: ProblemView<R> + ?Sized>(
    judge: &P,
    local: &LocalProblem<R>,
    settings: &NewtonSettings,
    mut stop: Option<&mut super::Stop<R>>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    let mut system = System::of(local, settings.dense_rows);
    system.regularisation = settings.regularisation;
    let n = system.rows();
    let count = local.contacts.len();
    let mut x = DVector::from_iterator(
        n,
        local
            .contacts
            .iter()
            .flat_map(|c| c.lambda0.iter().copied()),
    );
    let cone = local.friction == FrictionModel::Cone;
    let tolerance = settings.tolerance;
    let stop_given = stop.is_some();
    // No contact: the empty answer at once, whatever the stop rule (there is no row to step
    // on; a step on none failed in nalgebra's slicing before this test).
    if n == 0 {
        lambda.clear();
        return SolveReport {
            iterations: 0,
            residual: residual(judge, lambda),
            converged: true,
            coulomb_residual: cone.then(|| coulomb_residual(judge, lambda)),
            method: SolveMethod::Newton,
            local_fallbacks: 0,
        };
    }
    // The answer must pass the independent measures too, not only the iteration's own F.
    let to_impulses = |x: &DVector<f64>| -> Vec<SVector<f64, R>> {
        (0..count)
            .map(|k| x.fixed_rows::<R>(R * k).into())
            .collect()
    };
    let mut accept = |x: &DVector<f64>, norm: f64| match stop.as_mut() {
        Some(stop) => stop(&to_impulses(x)),
        None => {
            norm <= tolerance && {
                let l = to_impulses(x);
                residual(judge, &l) <= tolerance
                    && (!cone || coulomb_residual(judge, &l) <= tolerance)
            }
        }
    };
    // Where the iteration stalls, its end still passes if both residuals are within the
    // round-off floor of its impulses and that floor is above the tolerance (large impulses):
    // no iteration can go below it. Checked only after a run fails, so that wherever the
    // tolerance is reachable the iteration runs exactly as it does without the floor.
    let within_floor = |x: &DVector<f64>| {
        let l = to_impulses(x);
        let floor = round_off_floor(judge, &l);
        !stop_given
            && floor > tolerance
            && residual(judge, &l) <= floor
            && (!cone || coulomb_residual(judge, &l) <= floor)
    };
    let start = x.clone();
    let first = iterate(
        &system,
        &mut x,
        None,
        settings.max_iterations,
        Stall::Extended,
        &mut accept,
    );
    let mut iterations = first.iterations;
    let mut reached = first.reached || within_floor(&x);
    let mut method = SolveMethod::Newton;
    // A warm start can put Newton where its merit function has a valley that is not a
    // solution (contacts that changed keys start cold beside warm ones, and the first steps
    // throw the rest into sliding); from zero it starts where every contact is at rest.
    if !reached && x0_is_warm(local) {
        let mut cold = DVector::zeros(n);
        let again = iterate(
            &system,
            &mut cold,
            None,
            settings.max_iterations,
            Stall::Extended,
            &mut accept,
        );
        iterations += again.iterations;
        if again.reached || again.norm < first.norm {
            x = cold;
        }
        reached = again.reached || within_floor(&x);
    }
    if !reached {
        let (extra, solved, improved) =
            proximal_point(&system, &mut x, settings, Schedule::Adaptive, &mut accept);
        iterations += extra;
        reached = solved || within_floor(&x);
        // The fallback is named only where its answer is the one returned.
        if improved {
            method = SolveMethod::Proximal;
        }
    }
    // Last: plain Newton from the start without the stall rule (a run that wanders for a while
    // and then converges; seen on spheres-in-a-box-98 of Siconos' data, which the stall rule
    // handed to a proximal loop that did not solve it), then the tenfold proximal loop from its
    // end; kept where it is better.
    if !reached {
        let mut plain = start;
        let run = iterate(
            &system,
            &mut plain,
            None,
            settings.max_iterations,
            Stall::Never,
            &mut accept,
        );
        iterations += run.iterations;
        let mut plain_method = SolveMethod::Newton;
        let mut solved = run.reached || within_floor(&plain);
        if !solved {
            let (extra, done, improved) = proximal_point(
                &system,
                &mut plain,
                settings,
                Schedule::Tenfold,
                &mut accept,
            );
            iterations += extra;
            solved = done || within_floor(&plain);
            if improved {
                plain_method = SolveMethod::Proximal;
            }
        }
        let (mut w, mut f, mut blocks) = (DVector::zeros(n), DVector::zeros(n), Vec::new());
        evaluate(&system, &x, None, &mut w, &mut f, &mut blocks);
        let norm = law_norm(&system, &f);
        evaluate(&system, &plain, None, &mut w, &mut f, &mut blocks);
        if solved || law_norm(&system, &f) < norm {
            x = plain;
            method = plain_method;
        }
    }
    lambda.clear();
    lambda.extend(to_impulses(&x));
    let residual = residual(judge, lambda);
    let coulomb = cone.then(|| coulomb_residual(judge, lambda));
    let limit = tolerance.max(round_off_floor(judge, lambda));
    SolveReport {
        iterations,
        residual,
        converged: residual <= limit && coulomb.is_none_or(|c| c <= limit),
        coulomb_residual: coulomb,
        method,
        local_fallbacks: 0,
    }
}

/// Whether any contact starts from a non-zero impulse.
fn x0_is_warm<const R: usize>(problem: &LocalProblem<R>) -> bool {
    problem
        .contacts
        .iter()
        .any(|c| c.lambda0.iter().any(|&v| v != 0.0))
}
/// The proximal-point loop (docs/contact.md §"Proximal-point globalisation"): from the centre
/// λ_c = `x`, solve the problem with W + H and b − H λ_c (H = η diag(W)) by Newton, to a fraction
/// of the law norm ‖F(λ_c)‖ of the original problem at the centre (an inexact proximal point),
/// move the centre to the answer, and set η by the `schedule` after a solved subproblem, η × 10
/// after a failed one. Returns the Newton iterations spent, whether the original problem was
/// solved, and whether `x` was replaced (by a point with a smaller law norm than the entry
/// point's; otherwise `x` is left as it came).
fn proximal_point<const R: usize>(
    system: &System<R>,
    x: &mut DVector<f64>,
    settings: &NewtonSettings,
    schedule: Schedule,
    accept: &mut Accept,
) -> (u32, bool, bool) {
    let n = system.rows();
    let (mut w, mut f, mut blocks) = (DVector::zeros(n), DVector::zeros(n), Vec::new());
    let mut original_norm = |centre: &DVector<f64>| {
        evaluate(system, centre, None, &mut w, &mut f, &mut blocks);
        law_norm(system, &f)
    };
    // The velocity scale that makes ‖F‖ relative (Siconos' PROX sets α = σ × its relative error).
    let scale = system.velocity_scale();
    let mut iterations = 0;
    let mut centre = x.clone();
    let mut norm = original_norm(&centre);
    let adaptive = schedule == Schedule::Adaptive;
    let mut parameter = ProximalParameter::new(schedule, norm, scale);
    let (inner_ratio, stall) = if adaptive {
        (PROXIMAL_INNER_RATIO, Stall::Short)
    } else {
        (TENFOLD_INNER_RATIO, Stall::Never)
    };
    // The best point by the original law norm, from the entry point on: what is returned when
    // nothing solves, and whether the loop improved on its entry at all.
    let entry_norm = norm;
    let mut best = (norm, centre.clone());
    for _ in 0..settings.proximal_iterations {
        let proximal = Proximal {
            eta: parameter.eta,
            centre: &centre,
        };
        let mut inner = centre.clone();
        let inner_tolerance = (norm / inner_ratio).max(settings.tolerance);
        let run = iterate(
            system,
            &mut inner,
            Some(&proximal),
            settings.max_iterations,
            stall,
            &mut |_, norm| norm <= inner_tolerance,
        );
        iterations += run.iterations;
        let inner_norm = original_norm(&inner);
        // A solved subproblem is the next proximal point, whether or not it lowers ‖F‖ (the
        // iteration converges in λ, not monotonically in ‖F‖); in the adaptive loop a failed one
        // is kept where it does.
        if run.reached || (adaptive && inner_norm < norm) {
            centre = inner;
            norm = inner_norm;
            if norm < best.0 {
                best = (norm, centre.clone());
            }
            if accept(&centre, norm) {
                *x = centre;
                return (iterations, true, true);
            }
        }
        if !parameter.after(run.reached, norm, scale) {
            break;
        }
    }
    // Not solved: finish with plain Newton from the best centre, and keep whichever is better.
    let mut last = best.1.clone();
    let run = iterate(
        system,
        &mut last,
        None,
        settings.max_iterations,
        Stall::Never,
        accept,
    );
    iterations += run.iterations;
    if run.reached || run.norm < best.0 {
        best = (run.norm, last);
    }
    let improved = run.reached || best.0 < entry_norm;
    if improved {
        *x = best.1;
    }
    (iterations, run.reached, improved)
}

/// The Newton function F(λ) (m/s, module documentation) and its generalized Jacobian
/// D_λ + D_w W (dense, kg⁻¹ per row scale), for inspection and tests.
pub fn newton_function<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    lambda: &[SVector<f64, R>],
) -> (DVector<f64>, DMatrix<f64>) {
    newton_function_local(&problem.to_local(), lambda, None)
}

/// [`newton_function`] for a problem in local form; with `proximal` = (η, λ_c) the function of
/// the proximal fallback's subproblem (w + H (λ − λ_c), H = η diag(W), rows scaled by W + H's
/// diagonal) and its Jacobian D_λ + D_w (W + H).
pub fn newton_function_local<const R: usize>(
    problem: &LocalProblem<R>,
    lambda: &[SVector<f64, R>],
    proximal: Option<(f64, &[SVector<f64, R>])>,
) -> (DVector<f64>, DMatrix<f64>) {
    let system = System::of(problem, DENSE_ROWS);
    let n = system.rows();
    let stack =
        |l: &[SVector<f64, R>]| DVector::from_iterator(n, l.iter().flat_map(|v| v.iter().copied()));
    let x = stack(lambda);
    let centre = proximal.map(|(_, c)| stack(c));
    let prox = proximal
        .zip(centre.as_ref())
        .map(|((eta, _), centre)| Proximal { eta, centre });
    let eta = prox.as_ref().map_or(0.0, |p| p.eta);
    let (mut w, mut f, mut blocks) = (DVector::zeros(n), DVector::zeros(n), Vec::new());
    evaluate(&system, &x, prox.as_ref(), &mut w, &mut f, &mut blocks);
    let mut jacobian = DMatrix::zeros(n, n);
    for (k, row) in system.block_rows().enumerate() {
        let (d_lambda, d_w) = &blocks[k];
        for (j, wkj) in row {
            let mut m = d_w * wkj;
            if *j == k {
                m += d_lambda;
                for r in 0..R {
                    for c in 0..R {
                        m[(r, c)] += d_w[(r, c)] * eta * system.scales[R * k + c];
                    }
                }
            }
            jacobian.view_mut((R * k, R * j), (R, R)).copy_from(&m);
        }
    }
    (f, jacobian)
}
