//! The convergence residual: zero exactly at a solution of the contact problem.
//! docs/contact.md §"Residual".
//!
//! Per contact, with a_r = (A + C)_rr the row's diagonal and w = (A + C) λ + b:
//!
//! - normal row: a_n |λn − max(0, λn − w_n / a_n)| = |min(a_n λn, w_n)|, the natural map of the
//!   complementarity 0 ≤ λn ⊥ w_n ≥ 0 in velocity units;
//! - box friction row r: a_r |λ_r − clamp(λ_r − w_r / a_r, ±μ λn)|;
//! - cone friction: ρ ‖λt − proj_disk(λt − w_t / ρ, μ λn)‖, one scalar ρ for the pair (a
//!   per-row scale would move the fixed point off the disk's true solution);
//! - a joint's (free) row r: |w_r|, the natural map of an unbounded row.
//!
//! The residual is the largest of these over all rows, in m/s: "how fast some constraint is still
//! being violated, or how far from its bound an impulse is, measured as a velocity".

use crate::problem::{FrictionModel, ProblemView, RowBounds};
use nalgebra::{SMatrix, SVector};

/// A diagonal entry of W at or below this fraction of W's largest diagonal entry is round-off of
/// zero (the sums that build W err by a few ε times its entries), and the row is taken as one no
/// impulse of its own can move: a scale of 1e-18 kg⁻¹ would let the residual accept an impulse
/// of 1e7 N·s on a separating contact as 1e-11 m/s.
pub const ROUND_OFF_DIAGONAL: f64 = 64.0 * f64::EPSILON;

/// The largest diagonal entry of `problem`'s W (compliance included) times
/// [`ROUND_OFF_DIAGONAL`], kg⁻¹: diagonal entries at or below it count as zero. 0 for a problem
/// whose diagonal is all zero (or that has no constraints).
pub fn diagonal_floor<const R: usize, P: ProblemView<R> + ?Sized>(problem: &P) -> f64 {
    let largest = (0..problem.count())
        .map(|k| problem.block(k).diagonal().max())
        .fold(0.0, f64::max);
    ROUND_OFF_DIAGONAL * largest
}

/// The scales of one contact's rows that PGS steps with and the residual measures with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowScales<const R: usize> {
    /// a_r = (A + C)_rr per row, kg⁻¹ (a contact's compliance on its normal row only, a
    /// joint's on every row).
    pub diagonal: SVector<f64, R>,
    /// ρ = the largest eigenvalue of the friction rows' block A_tt, kg⁻¹; the cone step is 1/ρ.
    /// For one friction row (2D) it is that row's diagonal. An eigenvalue, not a bound such as
    /// Gershgorin's row sums, because it does not change when (t1, t2) is turned about n:
    /// A_tt turns by a similarity, so PGS's λ after any number of sweeps turns with it.
    pub tangent_rho: f64,
    /// The contact's Delassus block A_kk with its compliance on the normal row, kg⁻¹: the
    /// matrix of the exact local solve ([`super::local::solve_local`]).
    pub block: SMatrix<f64, R, R>,
}

/// The largest eigenvalue of the friction rows' block A_tt of a symmetric R × R block `a`
/// (rows and columns 1..R), kg⁻¹: exact for R ≤ 3 (the closed form of a symmetric 2 × 2),
/// Gershgorin's bound above (no system here has more than two friction rows).
pub fn tangent_eigenvalue<const R: usize>(a: &SMatrix<f64, R, R>) -> f64 {
    match R {
        0 | 1 => 0.0,
        2 => a[(1, 1)].max(0.0),
        3 => {
            let (p, d, o) = (a[(1, 1)], a[(2, 2)], a[(1, 2)]);
            let mean = 0.5 * (p + d);
            let half_gap = 0.5 * (p - d);
            (mean + (half_gap * half_gap + o * o).sqrt()).max(0.0)
        }
        _ => (1..R)
            .map(|r| (1..R).map(|s| a[(r, s)].abs()).sum::<f64>())
            .fold(0.0, f64::max),
    }
}

impl<const R: usize> RowScales<R> {
    /// The scales of a constraint whose diagonal block (compliance included) is `block`: its
    /// diagonal, and ρ from the block's symmetric part (the block itself where it is symmetric,
    /// as every block of a run's problem is; a local problem's W need not be).
    pub fn of_block(block: SMatrix<f64, R, R>) -> RowScales<R> {
        RowScales {
            diagonal: block.diagonal(),
            tangent_rho: tangent_eigenvalue(&((block + block.transpose()) * 0.5)),
            block,
        }
    }

    /// These scales with every diagonal entry at or below `floor` (kg⁻¹, [`diagonal_floor`])
    /// set to 0, and ρ too where it is at or below it: the rows the residual then measures as
    /// rows no impulse of their own can move. The block is kept.
    pub fn without_round_off(mut self, floor: f64) -> RowScales<R> {
        for d in self.diagonal.iter_mut() {
            if *d <= floor {
                *d = 0.0;
            }
        }
        if self.tangent_rho <= floor {
            self.tangent_rho = 0.0;
        }
        self
    }
}

/// The row scales of constraint `k` of `problem` (either form).
pub fn row_scales<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    k: usize,
) -> RowScales<R> {
    RowScales::of_block(problem.block(k))
}

/// One contact's residual (m/s) for impulse `lambda` and constraint velocity `w`.
pub fn contact_residual<const R: usize>(
    friction: FrictionModel,
    mu: f64,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
    scales: &RowScales<R>,
) -> f64 {
    contact_residual_of_rows(
        friction,
        mu,
        lambda,
        w,
        &scales.diagonal,
        scales.tangent_rho,
    )
}

/// [`contact_residual`] from what it reads of the row scales: the diagonal a (kg⁻¹) and ρ
/// (kg⁻¹). PGS's groups keep these two per lane, so its residual pass reads them there.
/// docs/contact.md §"Residual".
pub fn contact_residual_of_rows<const R: usize>(
    friction: FrictionModel,
    mu: f64,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
    a: &SVector<f64, R>,
    tangent_rho: f64,
) -> f64 {
    // A row with a zero diagonal cannot be moved by its own impulse (both bodies pinned);
    // it counts only as far as it is violated.
    let normal = if a[0] > 0.0 {
        (a[0] * lambda[0]).min(w[0]).abs()
    } else {
        lambda[0].min(w[0]).abs()
    };
    let bound = mu * lambda[0].max(0.0);
    let friction = match friction {
        FrictionModel::Box => (1..R)
            .map(|r| {
                if a[r] > 0.0 {
                    a[r] * (lambda[r] - (lambda[r] - w[r] / a[r]).clamp(-bound, bound)).abs()
                } else {
                    (lambda[r].abs() - bound).max(0.0)
                }
            })
            .fold(0.0, f64::max),
        FrictionModel::Cone => {
            let rho = tangent_rho;
            if rho > 0.0 {
                let mut trial = *lambda;
                for r in 1..R {
                    trial[r] = lambda[r] - w[r] / rho;
                }
                let projected = super::projection::project_disk(&trial, bound);
                rho * (1..R)
                    .map(|r| (lambda[r] - projected[r]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            } else {
                0.0
            }
        }
    };
    normal.max(friction)
}

/// A free (joint) constraint's residual (m/s): the natural map of an unbounded row is
/// a_r |λ_r − (λ_r − w_r / a_r)| = |w_r|, so the largest |w_r|.
pub fn free_residual<const R: usize>(w: &SVector<f64, R>) -> f64 {
    w.amax()
}

/// One constraint's residual (m/s): [`contact_residual`] for a contact, [`free_residual`] for a
/// joint.
pub fn constraint_residual<const R: usize>(
    friction: FrictionModel,
    bounds: RowBounds,
    mu: f64,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
    scales: &RowScales<R>,
) -> f64 {
    match bounds {
        RowBounds::Contact => contact_residual(friction, mu, lambda, w, scales),
        RowBounds::Free => free_residual(w),
    }
}

/// The residual of impulses `lambda` for `problem` (m/s, either form): the largest row
/// residual, 0 for a problem without contacts. Allocates; PGS computes the same number from its
/// workspace.
pub fn residual<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> f64 {
    let w = problem.constraint_velocity(lambda);
    let floor = diagonal_floor(problem);
    (0..problem.count())
        .map(|k| {
            constraint_residual(
                problem.friction(),
                problem.bounds(k),
                problem.mu(k),
                &lambda[k],
                &w[k],
                &row_scales(problem, k).without_round_off(floor),
            )
        })
        .fold(0.0, f64::max)
}

/// Projects (λn, λt) onto the second-order cone K_μ = {‖λt‖ ≤ μ λn}: itself inside, 0 in the
/// polar cone (μ‖λt‖ ≤ −λn), else onto the nearest boundary ray.
pub fn project_cone<const R: usize>(lambda: &SVector<f64, R>, mu: f64) -> SVector<f64, R> {
    let n = lambda[0];
    let s = (1..R).map(|r| lambda[r] * lambda[r]).sum::<f64>().sqrt();
    // The polar cone first: with μ = 0, (n < 0, s = 0) also passes the inside test below
    // (0 ≤ μ n = −0), though its projection onto K₀ = {λt = 0, λn ≥ 0} is 0.
    if mu * s <= -n {
        return SVector::zeros();
    }
    if s <= mu * n {
        return *lambda;
    }
    // Here s > 0 (s = 0 is one of the cases above) and n + μ s > 0.
    let n_new = (n + mu * s) / (1.0 + mu * mu);
    let mut p = *lambda * (mu * n_new / s);
    p[0] = n_new;
    p
}

/// One contact's exact Coulomb residual (m/s): De Saxcé's natural map,
///
///   r = ρ ‖λ − proj_K(λ − ŵ/ρ)‖,   ŵ = w + μ‖w_t‖ e_n,
///
/// with K the cone ‖λt‖ ≤ μ λn and ρ > 0 a scale (kg⁻¹). It is zero exactly when λ ∈ K, ŵ is in
/// the dual cone and λ·ŵ = 0: separation (λ = 0, w_n ≥ 0), sticking (w = 0) or sliding with
/// λt = −μλn w_t/‖w_t‖ and w_n = 0. docs/contact.md §"The exact Coulomb residual".
pub fn contact_coulomb_residual<const R: usize>(
    mu: f64,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
    rho: f64,
) -> f64 {
    let wt = (1..R).map(|r| w[r] * w[r]).sum::<f64>().sqrt();
    let mut w_hat = *w;
    w_hat[0] += mu * wt;
    let projected = project_cone(&(lambda - w_hat / rho), mu);
    rho * (lambda - projected).norm()
}

/// The scale ρ of a contact's Coulomb residual: the trace of its Delassus block with compliance
/// (kg⁻¹), which does not change when (t1, t2) is turned about n and lies between the block's
/// largest eigenvalue and R times it; 1 kg⁻¹ for a contact no impulse of its own can move (a
/// zero trace, or every diagonal entry taken as round-off by [`RowScales::without_round_off`]).
pub fn coulomb_scale<const R: usize>(scales: &RowScales<R>) -> f64 {
    let trace = scales.block.trace();
    if trace > 0.0 && scales.diagonal.iter().any(|&d| d > 0.0) {
        trace
    } else {
        1.0
    }
}

/// The exact Coulomb law's residual of impulses `lambda` for `problem` (m/s, either form): the
/// largest [`contact_coulomb_residual`] over the contacts, whatever the problem's friction model
/// (for box friction it says how far the box answer is from Coulomb's law). Allocates.
pub fn coulomb_residual<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> f64 {
    let w = problem.constraint_velocity(lambda);
    let floor = diagonal_floor(problem);
    (0..problem.count())
        .map(|k| {
            if problem.bounds(k) == RowBounds::Free {
                return free_residual(&w[k]);
            }
            let scales = row_scales(problem, k).without_round_off(floor);
            contact_coulomb_residual(problem.mu(k), &lambda[k], &w[k], coulomb_scale(&scales))
        })
        .fold(0.0, f64::max)
}

/// Siconos' error of impulses `lambda` for `problem` (either form): Siconos 4.4's
/// `fc3d_compute_error` and `fc2d_compute_error` called with norm = ‖q‖, as its solvers call
/// them (docs/problem-library.md §"Siconos' error measure"; Siconos 4.1–4.3 divide by ‖q‖
/// alone): with w = W λ + q and ŵ De Saxcé's velocity per contact,
///
///   error = √(Σ_k ‖λ_k − proj_K(λ_k − ŵ_k)‖²) / max(‖q‖, ‖λ‖, ‖w‖)
///
/// (the unit-scale natural map, summed in the 2-norm, relative; not divided where the
/// denominator is below machine epsilon). A joint's rows count with ‖w_k‖². Dimensionless only
/// where λ and w are of comparable size: it mixes N·s and m/s, as Siconos does.
pub fn siconos_error<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> f64 {
    siconos_error_measures(problem, lambda).relative()
}

/// The three ways Siconos' error has been normalised (docs/problem-library.md §"Siconos' error
/// measure"): the absolute natural-map norm and the two denominators.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SiconosErrorMeasures {
    /// √(Σ_k ‖λ_k − proj_K(λ_k − ŵ_k)‖²), not divided (mixed N·s and m/s, as Siconos').
    pub absolute: f64,
    /// ‖q‖ (m/s), Siconos 4.1–4.3's denominator.
    pub q_norm: f64,
    /// max(‖q‖, ‖λ‖, ‖w‖), Siconos 4.4's denominator.
    pub scale: f64,
}

impl SiconosErrorMeasures {
    /// Siconos 4.4's error: absolute / max(‖q‖, ‖λ‖, ‖w‖) (not divided below machine epsilon).
    pub fn relative(&self) -> f64 {
        divided(self.absolute, self.scale)
    }

    /// Siconos 4.1–4.3's error: absolute / ‖q‖ (not divided below machine epsilon); at least
    /// [`Self::relative`], by up to max(‖λ‖, ‖w‖)/‖q‖.
    pub fn q_normalised(&self) -> f64 {
        divided(self.absolute, self.q_norm)
    }
}

fn divided(error: f64, by: f64) -> f64 {
    if by > f64::EPSILON { error / by } else { error }
}

/// [`siconos_error`]'s numerator and both denominators, for reporting the error in Siconos'
/// 4.4 measure, the older ‖q‖-normalised one and unnormalised.
pub fn siconos_error_measures<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
) -> SiconosErrorMeasures {
    siconos_error_measures_given(problem, lambda, problem.dense_b().norm())
}

/// [`siconos_error_measures`] with ‖q‖ given (`q_norm`, m/s, as `problem.dense_b().norm()`
/// computes it), for a caller that evaluates the error at every iterate of one problem.
pub fn siconos_error_measures_given<const R: usize, P: ProblemView<R> + ?Sized>(
    problem: &P,
    lambda: &[SVector<f64, R>],
    q_norm: f64,
) -> SiconosErrorMeasures {
    let w = problem.constraint_velocity(lambda);
    let mut sum = 0.0;
    for k in 0..problem.count() {
        sum += siconos_share(problem.bounds(k), problem.mu(k), &lambda[k], &w[k]);
    }
    let norm = |v: &[SVector<f64, R>]| v.iter().map(|x| x.norm_squared()).sum::<f64>().sqrt();
    SiconosErrorMeasures {
        absolute: sum.sqrt(),
        q_norm,
        scale: q_norm.max(norm(lambda)).max(norm(&w)),
    }
}

/// One constraint's term of [`siconos_error`]'s numerator, squared: for a contact
/// ‖λ_k − proj_K(λ_k − ŵ_k)‖² with ŵ_k = w_k + μ‖w_T,k‖ e_n, for a joint ‖w_k‖² (λ_k in N·s,
/// w_k in m/s, mixed as Siconos does). The error's square sums these over the constraints.
/// docs/contact.md §"Near-duplicate contacts left out" (zero for λ_k = 0 exactly where w_n ≥ 0).
pub fn siconos_share<const R: usize>(
    bounds: RowBounds,
    mu: f64,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
) -> f64 {
    match bounds {
        RowBounds::Free => w.norm_squared(),
        RowBounds::Contact => {
            let wt = (1..R).map(|r| w[r] * w[r]).sum::<f64>().sqrt();
            let mut w_hat = *w;
            w_hat[0] += mu * wt;
            (lambda - project_cone(&(lambda - w_hat), mu)).norm_squared()
        }
    }
}
