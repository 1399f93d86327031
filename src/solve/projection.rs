//! The feasible set of one contact's impulse and the projections onto it, written once for PGS,
//! its residual and the crosscheck: λn ≥ 0, and the friction rows within the box
//! |λt_r| ≤ bound (box friction) or the disk ‖λt‖ ≤ bound (cone friction), bound = μ λn.
//! docs/contact.md §"Box and cone friction".

use crate::problem::FrictionModel;
use nalgebra::SVector;

/// Projects one contact's impulse onto its feasible set: λn ≥ 0 and the friction rows within
/// the box or disk of radius μ λn.
pub fn project_feasible<const R: usize>(
    lambda: &SVector<f64, R>,
    mu: f64,
    friction: FrictionModel,
) -> SVector<f64, R> {
    let mut p = *lambda;
    p[0] = p[0].max(0.0);
    project_friction(&p, mu * p[0], friction)
}

/// Projects the friction rows 1..R of `lambda` onto the box or disk of radius `bound` (≥ 0);
/// row 0 unchanged.
pub fn project_friction<const R: usize>(
    lambda: &SVector<f64, R>,
    bound: f64,
    friction: FrictionModel,
) -> SVector<f64, R> {
    match friction {
        FrictionModel::Box => clamp_box(lambda, bound),
        FrictionModel::Cone => project_disk(lambda, bound),
    }
}

/// Clamps each friction row 1..R of `lambda` to [−bound, bound]; row 0 unchanged.
pub fn clamp_box<const R: usize>(lambda: &SVector<f64, R>, bound: f64) -> SVector<f64, R> {
    let mut p = *lambda;
    for r in 1..R {
        p[r] = p[r].clamp(-bound, bound);
    }
    p
}

/// Scales the friction rows 1..R of `lambda` into the disk of radius `bound`; row 0 unchanged.
/// A zero bound gives zero friction rows (each times +0, so keeping its sign) even where their
/// squares underflow to a zero norm (components below ~1.5e-154).
pub fn project_disk<const R: usize>(lambda: &SVector<f64, R>, bound: f64) -> SVector<f64, R> {
    let mut p = *lambda;
    let norm = (1..R).map(|r| p[r] * p[r]).sum::<f64>().sqrt();
    if norm > bound || bound == 0.0 {
        let scale = if norm > 0.0 { bound / norm } else { 0.0 };
        for r in 1..R {
            p[r] *= scale;
        }
    }
    p
}

/// max(x, 0) with every case fixed: x where x > 0, else +0 (for −0 and NaN too). `f64::max`
/// may return either zero for max(−0, +0), so the sweep's one-contact and four-lane visits
/// both use this (docs/contact.md §"Four contacts per lane").
#[inline(always)]
pub fn positive_part(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}
