//! The exact local solve: one contact's own R × R problem solved exactly, normal and friction
//! together, for the current impulses of all the others. docs/contact.md §"Exact local solve".
//!
//! With the other contacts' impulses frozen, contact k's velocity is affine in its own impulse,
//!
//!   w = A λ + q,   A = A_kk + c e₀e₀ᵀ (its Delassus block with compliance),
//!   q = w_now − A λ_now (everything the other contacts and b contribute),
//!
//! and the contact law is one of a few closed-form cases. Each case fixes which constraints are
//! active, which turns the law into a small linear (or, for sliding in the disk, a
//! one-dimensional) equation; a case's candidate is a solution exactly when the contact's own
//! residual ([`contact_residual`]) is zero. The cases are tried in a fixed order and the first
//! whose candidate is a solution is taken:
//!
//! 1. separate: λ = 0, valid when q_n ≥ 0;
//! 2. stick: every row active (w = 0), valid when λ is inside the friction set;
//! 3. slide. Box friction: each friction row either free (w_r = 0) or at a bound ±μλn, the 3^(R−1)
//!    − 1 remaining patterns in a fixed order. Disk (R = 3): λt = −μλn d with d = (cos θ, sin θ)
//!    the unit sliding direction, w_n = 0 and w_t parallel to d; one equation in θ, whose roots
//!    are bracketed on a grid and bisected to round-off. Where the caller passes the contact's
//!    current impulse, a few Newton steps from its direction are tried first
//!    ([`disk_slide_from`]), and the scan runs only if their root is not a solution.
//!
//! In 2D (R = 2) the disk is the interval [−μλn, μλn], so both friction models take the box path.

use super::residual::{RowScales, contact_residual};
use crate::problem::FrictionModel;
use nalgebra::{SMatrix, SVector};

/// How a PGS visit updates one contact (scene key `pgs_local_solve`).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "snake_case")]
pub enum LocalSolve {
    /// Row by row: the normal row, then the friction rows with the bound from the new λn (the
    /// assignment's projected Gauss–Seidel).
    #[default]
    Rows,
    /// The contact's whole R × R problem solved exactly ([`solve_local`]).
    Exact,
}

impl LocalSolve {
    /// The scene-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            LocalSolve::Rows => "rows",
            LocalSolve::Exact => "exact",
        }
    }
}

/// Grid cells on which the sliding direction's equation is bracketed (disk friction). Its
/// left-hand side is a trigonometric polynomial of degree 2 in θ, so it has at most four roots;
/// two roots closer than 2π/256 with no sign change between them (a near-tangency) are the only
/// ones the grid can miss, and then the candidate with the smallest residual is taken.
const SLIDE_GRID: usize = 256;

/// A candidate is taken when the contact's residual at it is at most this times the scale of
/// q (m/s): a few hundred ulps, round-off in a 3 × 3 elimination of a well-scaled block.
const ACCEPT: f64 = 1e-13;

/// Solves one contact's problem w = A λ + q exactly (module documentation). `a` is the contact's
/// Delassus block with compliance on the normal row (kg⁻¹), `q` in m/s, `scales` the row scales
/// the residual measures with. Returns the first case's λ (N·s) whose residual is zero to
/// round-off and `true`, else the candidate with the smallest residual and `false` (a fallback,
/// which PGS counts and reports: `SolveReport::local_fallbacks`). Separation is always a candidate,
/// so there is always an answer: for a contact its own impulse cannot move (A = 0, every system
/// singular) it is λ = 0, and the residual keeps the violation.
///
/// `warm` is the contact's current impulse λ_now (N·s), or `None`. For the disk's sliding case
/// it gives the starting direction of a few Newton steps ([`disk_slide_from`]) tried before the
/// full scan; with `None` the scan alone runs, as it did before the warm start existed.
/// docs/contact.md §"Exact local solve", **Warm start**.
pub fn solve_local<const R: usize>(
    a: &SMatrix<f64, R, R>,
    q: &SVector<f64, R>,
    mu: f64,
    friction: FrictionModel,
    scales: &RowScales<R>,
    warm: Option<&SVector<f64, R>>,
) -> (SVector<f64, R>, bool) {
    let tolerance = ACCEPT * q.amax().max(f64::MIN_POSITIVE);
    let mut best: Option<(f64, SVector<f64, R>)> = None;
    let mut consider = |lambda: SVector<f64, R>| -> bool {
        let w = a * lambda + q;
        let r = contact_residual(friction, mu, &lambda, &w, scales);
        if best.is_none_or(|(b, _)| r < b) {
            best = Some((r, lambda));
        }
        r <= tolerance
    };

    // 1. Separate.
    if consider(SVector::zeros()) {
        return (SVector::zeros(), true);
    }
    // 2. Stick: every row active, A λ = −q.
    if let Some(lambda) = solve_linear(a, &(-q))
        && consider(lambda)
    {
        return (lambda, true);
    }
    // 3. Slide.
    if friction == FrictionModel::Cone && R == 3 {
        // The warm-started root first (a few Newton steps), then, if it is not a solution,
        // the full scan.
        if let Some(warm) = warm
            && let Some(lambda) = disk_slide_from(a, q, mu, warm)
            && consider(lambda)
        {
            return (lambda, true);
        }
        for lambda in disk_slides(a, q, mu) {
            if consider(lambda) {
                return (lambda, true);
            }
        }
    } else {
        // Pattern digits per friction row: 0 free, 1 at +μλn, 2 at −μλn; pattern 0 is stick.
        let patterns = 3usize.pow(R as u32 - 1);
        for pattern in 1..patterns {
            if let Some(lambda) = box_pattern(a, q, mu, pattern)
                && consider(lambda)
            {
                return (lambda, true);
            }
        }
    }
    // Separation was considered first, so `best` is set.
    (best.map_or(SVector::zeros(), |(_, lambda)| lambda), false)
}

/// The candidate of one box pattern: λn > 0 with w_n = 0, each friction row free (w_r = 0) or
/// fixed at s_r μ λn. Unknowns are λn and the free rows' λ_r; a fixed row's equation is replaced
/// by "its own unknown is 0" so the system stays R × R.
fn box_pattern<const R: usize>(
    a: &SMatrix<f64, R, R>,
    q: &SVector<f64, R>,
    mu: f64,
    pattern: usize,
) -> Option<SVector<f64, R>> {
    // sign[r]: 0 free, +1 or −1 at that bound.
    let mut sign = [0.0; R];
    let mut digits = pattern;
    for s in sign.iter_mut().skip(1) {
        *s = match digits % 3 {
            0 => 0.0,
            1 => 1.0,
            _ => -1.0,
        };
        digits /= 3;
    }
    // λ = λn g + Σ_free λ_r e_r, g = e₀ + Σ_fixed s_r μ e_r.
    let mut g = SVector::<f64, R>::zeros();
    g[0] = 1.0;
    for r in 1..R {
        g[r] = sign[r] * mu;
    }
    let ag = a * g;
    let mut m = SMatrix::<f64, R, R>::identity();
    let mut rhs = SVector::<f64, R>::zeros();
    for row in 0..R {
        if row > 0 && sign[row] != 0.0 {
            continue; // the identity row: this unknown is 0
        }
        m[(row, 0)] = ag[row];
        for col in 1..R {
            m[(row, col)] = if sign[col] == 0.0 { a[(row, col)] } else { 0.0 };
        }
        rhs[row] = -q[row];
    }
    let x = solve_linear(&m, &rhs)?;
    let mut lambda = g * x[0];
    for r in 1..R {
        if sign[r] == 0.0 {
            lambda[r] = x[r];
        }
    }
    Some(lambda)
}

/// cos θ_i and sin θ_i at the grid points θ_i = i 2π / [`SLIDE_GRID`], i = 0..=SLIDE_GRID,
/// computed once per process: the same values `(i as f64 * step).cos()` gives at each call, so
/// the bracketing below is unchanged bit for bit, without two `sin`/`cos` pairs per cell.
/// docs/contact.md §"Exact local solve", **Cost**.
fn slide_grid() -> &'static [(f64, f64); SLIDE_GRID + 1] {
    static GRID: std::sync::OnceLock<[(f64, f64); SLIDE_GRID + 1]> = std::sync::OnceLock::new();
    GRID.get_or_init(|| {
        let step = std::f64::consts::TAU / SLIDE_GRID as f64;
        std::array::from_fn(|i| {
            let theta = i as f64 * step;
            (theta.cos(), theta.sin())
        })
    })
}

/// The sliding candidates of disk friction (R = 3), in increasing θ ∈ [0, 2π).
///
/// With d = (cos θ, sin θ) and g(θ) = (1, −μ cos θ, −μ sin θ), λ = λn g: w_n = 0 gives
/// λn = −q_n / (A g)_n, and w_t = λn (A g)_t + q_t must be parallel to d. Multiplied by
/// (A g)_n, the parallelism is F(θ) = ((A g)_n q_t − q_n (A g)_t) × d = 0, smooth in θ.
/// F is evaluated once per grid point (cell i's upper end is cell i + 1's lower end) from the
/// tabulated cos and sin ([`slide_grid`]); only the bisection calls `sin` and `cos`.
pub fn disk_slides<const R: usize>(
    a: &SMatrix<f64, R, R>,
    q: &SVector<f64, R>,
    mu: f64,
) -> impl Iterator<Item = SVector<f64, R>> {
    let a = *a;
    let q = *q;
    let g = move |(cos, sin): (f64, f64)| {
        let mut g = SVector::<f64, R>::zeros();
        g[0] = 1.0;
        g[1] = -mu * cos;
        g[2] = -mu * sin;
        g
    };
    let f = move |(cos, sin): (f64, f64)| {
        let ag = a * g((cos, sin));
        let u1 = ag[0] * q[1] - q[0] * ag[1];
        let u2 = ag[0] * q[2] - q[0] * ag[2];
        u1 * sin - u2 * cos
    };
    let at = |theta: f64| (theta.cos(), theta.sin());
    let grid = slide_grid();
    let values: [f64; SLIDE_GRID + 1] = std::array::from_fn(|i| f(grid[i]));
    let step = std::f64::consts::TAU / SLIDE_GRID as f64;
    (0..SLIDE_GRID).filter_map(move |i| {
        let (mut lo, mut hi) = (i as f64 * step, (i + 1) as f64 * step);
        let (mut f_lo, f_hi) = (values[i], values[i + 1]);
        let root = if f_lo == 0.0 {
            grid[i]
        } else if f_lo * f_hi >= 0.0 {
            return None; // no sign change in this cell (a root at hi is the next cell's lo)
        } else {
            // Bisection to the last bit: the interval halves until it cannot.
            loop {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                let f_mid = f(at(mid));
                if f_mid == 0.0 {
                    lo = mid;
                    break;
                }
                if f_lo * f_mid < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                    f_lo = f_mid;
                }
            }
            at(lo)
        };
        let gr = g(root);
        let normal = (a * gr)[0];
        if normal <= 0.0 {
            return None;
        }
        let lambda_n = -q[0] / normal;
        (lambda_n > 0.0).then(|| gr * lambda_n)
    })
}

/// Newton steps on F at most, from the warm start ([`disk_slide_from`]). F's root is simple
/// where the scan can bracket it, and Newton's error squares each step: from an error of 0.1 rad,
/// five steps reach round-off; the rest are a margin for poorer starts. A start that has not
/// converged within them is left to the scan.
const SLIDE_NEWTON_STEPS: usize = 12;

/// A Newton step of at most this much (radians) is the last: the next would be below round-off
/// (the error after a step is about the square of the step times F''/(2F'), and F''/F' is of
/// order one for a trigonometric polynomial of degree 2 unless F' nearly vanishes, when the
/// residual check rejects an inaccurate root and the scan takes over).
const SLIDE_NEWTON_DONE: f64 = 1e-9;

/// The largest Newton step (radians): a safeguard, so that a step taken where F' is nearly zero
/// does not jump across several roots; a full turn is 2π, the grid cell 2π/256.
const SLIDE_NEWTON_MAX_STEP: f64 = 0.5;

/// The disk's sliding candidate nearest the warm start, by Newton's method on F (R = 3; the
/// equation of [`disk_slides`]). docs/contact.md §"Exact local solve", **Warm start**.
///
/// The starting direction d₀: opposite the current tangential impulse where λ_now slides or
/// sticks with λn > 0 and λt ≠ 0 (λt = −μλn d), else along the current tangential velocity
/// w_t = (A λ_now + q)_t; `None` when both are zero. With d = (c, s) = (cos θ, sin θ) and
/// A g = a₀ − μ c a₁ − μ s a₂ (a_j A's columns), the two components
/// u_r = (A g)_n q_r − q_n (A g)_r (r = t1, t2) are affine in (c, s),
///
///   u₁ = α₁ + β₁ c + γ₁ s,   u₂ = α₂ + β₂ c + γ₂ s,
///
/// so F = u₁ s − u₂ c = α₁ s − α₂ c + (β₁ − γ₂) c s + γ₁ s² − β₂ c² and
/// F' = dF/dθ = α₁ c + α₂ s + (β₁ − γ₂)(c² − s²) + 2 (γ₁ + β₂) c s: six numbers formed once,
/// then each step costs a few multiplications. A step δ = −F/F' (at most
/// [`SLIDE_NEWTON_MAX_STEP`]) turns d by atan δ: d ← (d + δ d⊥)/√(1 + δ²), no `sin` or `cos`
/// (atan δ = δ − δ³/3 + …, so the step is Newton's to third order and keeps its quadratic
/// convergence). After a step of at most [`SLIDE_NEWTON_DONE`] the root is returned as the scan
/// returns its roots: λ = λn g with λn = −q_n/(A g)_n, `None` unless (A g)_n > 0 and λn > 0, or
/// when F' vanishes or the steps run out. The caller checks it with the contact's residual like
/// every other candidate.
pub fn disk_slide_from<const R: usize>(
    a: &SMatrix<f64, R, R>,
    q: &SVector<f64, R>,
    mu: f64,
    warm: &SVector<f64, R>,
) -> Option<SVector<f64, R>> {
    if R != 3 {
        return None;
    }
    // The starting direction.
    let (mut c, mut s) = if warm[0] > 0.0 && (warm[1] != 0.0 || warm[2] != 0.0) {
        (-warm[1], -warm[2])
    } else {
        let w = a * warm + q;
        (w[1], w[2])
    };
    let length = c.hypot(s);
    if !(length > 0.0 && length.is_finite()) {
        return None;
    }
    (c, s) = (c / length, s / length);
    // The coefficients of F (doc comment).
    let alpha1 = a[(0, 0)] * q[1] - q[0] * a[(1, 0)];
    let beta1 = -mu * (a[(0, 1)] * q[1] - q[0] * a[(1, 1)]);
    let gamma1 = -mu * (a[(0, 2)] * q[1] - q[0] * a[(1, 2)]);
    let alpha2 = a[(0, 0)] * q[2] - q[0] * a[(2, 0)];
    let beta2 = -mu * (a[(0, 1)] * q[2] - q[0] * a[(2, 1)]);
    let gamma2 = -mu * (a[(0, 2)] * q[2] - q[0] * a[(2, 2)]);
    let cross = beta1 - gamma2;
    let mut converged = false;
    for _ in 0..SLIDE_NEWTON_STEPS {
        let f = alpha1 * s - alpha2 * c + cross * c * s + gamma1 * s * s - beta2 * c * c;
        let slope =
            alpha1 * c + alpha2 * s + cross * (c * c - s * s) + 2.0 * (gamma1 + beta2) * c * s;
        let step = -f / slope;
        if !step.is_finite() {
            return None;
        }
        let step = step.clamp(-SLIDE_NEWTON_MAX_STEP, SLIDE_NEWTON_MAX_STEP);
        let length = (1.0 + step * step).sqrt();
        (c, s) = ((c - step * s) / length, (s + step * c) / length);
        if step.abs() <= SLIDE_NEWTON_DONE {
            converged = true;
            break;
        }
    }
    if !converged {
        return None;
    }
    let mut g = SVector::<f64, R>::zeros();
    g[0] = 1.0;
    g[1] = -mu * c;
    g[2] = -mu * s;
    let normal = (a * g)[0];
    if normal <= 0.0 {
        return None;
    }
    let lambda_n = -q[0] / normal;
    (lambda_n > 0.0).then(|| g * lambda_n)
}

/// Solves m x = rhs by Gaussian elimination with partial pivoting (R ≤ 3 here: no library
/// factorisation is generic over the size); `None` when a pivot is zero against the matrix's
/// largest entry to round-off (the system is singular: the case has no single candidate).
pub(crate) fn solve_linear<const R: usize>(
    m: &SMatrix<f64, R, R>,
    rhs: &SVector<f64, R>,
) -> Option<SVector<f64, R>> {
    let (mut m, mut x) = (*m, *rhs);
    let tiny = 1e-14 * m.amax();
    for col in 0..R {
        let pivot = (col..R).max_by(|&i, &j| m[(i, col)].abs().total_cmp(&m[(j, col)].abs()))?;
        if m[(pivot, col)].abs() <= tiny || m[(pivot, col)].is_nan() {
            return None;
        }
        m.swap_rows(col, pivot);
        x.swap_rows(col, pivot);
        for row in col + 1..R {
            let factor = m[(row, col)] / m[(col, col)];
            for c in col..R {
                m[(row, c)] -= factor * m[(col, c)];
            }
            x[row] -= factor * x[col];
        }
    }
    for row in (0..R).rev() {
        let mut sum = x[row];
        for c in row + 1..R {
            sum -= m[(row, c)] * x[c];
        }
        x[row] = sum / m[(row, row)];
    }
    Some(x)
}
