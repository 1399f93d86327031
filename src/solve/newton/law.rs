//! The contact law as the Newton iteration writes it: per contact, Alart and Curnier's function
//! F_k(λ_k, w_k) and the blocks of its generalized Jacobian (the module documentation of
//! [`super`]).

use super::*;

/// The contact law of one constraint, with its scales.
#[derive(Clone, Copy, Debug)]
pub(super) enum Law {
    /// Normal row plus friction rows each in [−μλn, μλn] (box, and the 2D interval).
    Box { mu: f64 },
    /// Normal row plus the pair of friction rows in the disk of radius μλn, with scale ρ.
    Disk { mu: f64, rho: f64 },
    /// Every row free: w = 0.
    Free,
}

/// One contact's F and its derivative blocks: ∂F_k = D_λ dλ_k + D_w dw_k.
pub(super) struct Linearised<const R: usize> {
    pub(super) f: SVector<f64, R>,
    pub(super) d_lambda: SMatrix<f64, R, R>,
    pub(super) d_w: SMatrix<f64, R, R>,
}

/// The largest eigenvalue of rows and columns 1..R of a symmetric block (the tangent block);
/// 1 where it is at or below `floor` (kg⁻¹: round-off of a zero block, [`System::of`]).
pub(super) fn tangent_scale<const R: usize>(w: &SMatrix<f64, R, R>, floor: f64) -> f64 {
    let largest = match R {
        0 | 1 => 0.0,
        2 => w[(1, 1)],
        _ => {
            let (p, d, o) = (w[(1, 1)], w[(2, 2)], w[(1, 2)]);
            0.5 * (p + d) + (0.25 * (p - d) * (p - d) + o * o).sqrt()
        }
    };
    if largest > floor { largest } else { 1.0 }
}

/// F_k and its generalized Jacobian blocks at (λ_k, w_k) for law `law` with row scales `a`.
pub(super) fn linearise<const R: usize>(
    law: Law,
    a: &SVector<f64, R>,
    lambda: &SVector<f64, R>,
    w: &SVector<f64, R>,
) -> Linearised<R> {
    let mut out = Linearised {
        f: SVector::zeros(),
        d_lambda: SMatrix::zeros(),
        d_w: SMatrix::zeros(),
    };
    let mu = match law {
        Law::Free => {
            out.f = *w;
            out.d_w = SMatrix::identity();
            return out;
        }
        Law::Box { mu } | Law::Disk { mu, .. } => mu,
    };
    // Normal row: F_n = min(a_n λn, w_n) = a_n (λn − max(0, s_n)), s_n = λn − w_n / a_n.
    let s_n = lambda[0] - w[0] / a[0];
    if s_n > 0.0 {
        out.f[0] = w[0];
        out.d_w[(0, 0)] = 1.0;
    } else {
        out.f[0] = a[0] * lambda[0];
        out.d_lambda[(0, 0)] = a[0];
    }
    // Alart and Curnier's radius μ max(0, s_n) (equal to μλn at a solution) and its derivative
    // in (λn, w_n): unlike μλn⁺ it still feels an approaching contact (w_n < 0) at λn = 0, so
    // the friction rows stay coupled to the normal row there.
    let radius = mu * s_n.max(0.0);
    let (dr_lambda, dr_w) = if s_n > 0.0 {
        (mu, -mu / a[0])
    } else {
        (0.0, 0.0)
    };
    match law {
        Law::Disk { rho, .. } if R == 3 => {
            let z = SVector::<f64, 2>::new(lambda[1] - w[1] / rho, lambda[2] - w[2] / rho);
            let norm = z.norm();
            if norm <= radius && radius > 0.0 {
                // Inside the disk: sticking, F_t = w_t.
                for r in 1..3 {
                    out.f[r] = w[r];
                    out.d_w[(r, r)] = 1.0;
                }
            } else if norm > 0.0 {
                // On the rim: F_t = ρ(λt − radius ẑ).
                let unit = z / norm;
                let g =
                    (SMatrix::<f64, 2, 2>::identity() - unit * unit.transpose()) * (radius / norm);
                for r in 1..3 {
                    out.f[r] = rho * (lambda[r] - radius * unit[r - 1]);
                    out.d_lambda[(r, 0)] = -rho * dr_lambda * unit[r - 1];
                    out.d_w[(r, 0)] = -rho * dr_w * unit[r - 1];
                    for s in 1..3 {
                        let identity = if r == s { 1.0 } else { 0.0 };
                        out.d_lambda[(r, s)] = rho * (identity - g[(r - 1, s - 1)]);
                        out.d_w[(r, s)] = g[(r - 1, s - 1)];
                    }
                }
            } else {
                // z = 0 with radius 0: F_t = ρ λt.
                for r in 1..3 {
                    out.f[r] = rho * lambda[r];
                    out.d_lambda[(r, r)] = rho;
                }
            }
        }
        _ => {
            // Box rows (and the 2D interval, which is both models).
            for r in 1..R {
                let s = lambda[r] - w[r] / a[r];
                if s > radius {
                    out.f[r] = a[r] * (lambda[r] - radius);
                    out.d_lambda[(r, r)] = a[r];
                    out.d_lambda[(r, 0)] = -a[r] * dr_lambda;
                    out.d_w[(r, 0)] = -a[r] * dr_w;
                } else if s < -radius {
                    out.f[r] = a[r] * (lambda[r] + radius);
                    out.d_lambda[(r, r)] = a[r];
                    out.d_lambda[(r, 0)] = a[r] * dr_lambda;
                    out.d_w[(r, 0)] = a[r] * dr_w;
                } else if radius > 0.0 {
                    out.f[r] = w[r];
                    out.d_w[(r, r)] = 1.0;
                } else {
                    // The tie κ = 0, z_r = 0: F_r = a_r λ_r (the clamp to [0, 0]), the piece
                    // active around it whenever κ stays 0 (s_n < 0, or μ = 0). The interior
                    // piece w_r would put W's row in the matrix, singular with redundant
                    // contacts, and is active only on the tie itself.
                    out.f[r] = a[r] * lambda[r];
                    out.d_lambda[(r, r)] = a[r];
                }
            }
        }
    }
    out
}
