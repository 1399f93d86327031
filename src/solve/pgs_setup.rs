//! A PGS solve's set-up of one contact: its entry (what a sweep reads of it) and row scales,
//! built from the problem. docs/contact.md §"PGS", §"Four contacts per lane".

use super::residual::RowScales;
use super::sweep_entry::{Entry, RowLaw};
use crate::problem::ContactProblem;
use nalgebra::SMatrix;

/// Contact `k`'s entry (what a sweep reads of it), built from the problem, and its row scales
/// into `scales`: M_s⁻¹ J_sᵀ per side ([`inverse_mass_times`]), the Delassus block from them,
/// J_sᵀ, b and the constants.
pub(super) fn build_entry<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    k: usize,
    scales: &mut RowScales<R>,
) -> Entry<D, R> {
    let c = &problem.contacts[k];
    let side = |s: usize| match c.bodies[s] {
        Some(b) => inverse_mass_times(problem, k, s, b),
        None => SMatrix::zeros(),
    };
    let sides = [side(0), side(1)];
    // The contact's Delassus block from the same per-body M⁻¹Jᵀ the updates use, once:
    // A_kk = Σ_s J_s (M_s⁻¹ J_sᵀ), symmetrised, plus compliance on its rows
    // (docs/contact.md §"Delassus operator"; `ContactProblem::delassus_block` forms
    // J M⁻¹ first, the same to round-off).
    // A contact of a body with itself adds the cross terms J₁ (M⁻¹ J₂ᵀ) + J₂ (M⁻¹ J₁ᵀ).
    let mut a = SMatrix::<f64, R, R>::zeros();
    for (s, t) in crate::problem::SIDE_PAIRS {
        if c.bodies[s].is_some() && c.bodies[s] == c.bodies[t] {
            a += c.jacobian[s] * sides[t];
        }
    }
    let mut block = (a + a.transpose()) * 0.5;
    for r in 0..R {
        block[(r, r)] += c.row_compliance(r);
    }
    *scales = RowScales::of_block(block);
    Entry {
        bodies: c.bodies,
        jacobian_t: [c.jacobian[0].transpose(), c.jacobian[1].transpose()],
        inverse_mass_jacobian_t: sides,
        b: c.b,
        law: RowLaw {
            diagonal: scales.diagonal,
            tangent_rho: scales.tangent_rho,
            mu: c.mu,
            compliance: c.compliance,
        },
        bounds: c.bounds,
        lambda0: c.lambda0,
    }
}

/// M_s⁻¹ J_sᵀ (D × R) of side `s` of contact `k`, whose body is `b`: nalgebra's product of the
/// body's M⁻¹ and the side's Jᵀ, every column summed in full (for a 3D body's
/// diag(m⁻¹ I₃, J⁻¹) 36 products a column, of which 24 are by zero; summing the nonzero columns
/// alone, as the set-up did for a while, gave the same bits but took about three times the
/// instructions: docs/performance.md §"Issue 49: leading triangles and the full product").
/// Formed once per solve by the set-up; the warm start applies the entry's copy (the same bits).
#[inline(always)]
pub(super) fn inverse_mass_times<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    k: usize,
    s: usize,
    b: usize,
) -> SMatrix<f64, D, R> {
    problem.bodies[b].inverse_mass * problem.contacts[k].jacobian[s].transpose()
}
