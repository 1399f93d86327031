//! A PGS solve's set-up of one contact: its entry (what a sweep reads of it) and row scales,
//! built from the problem, with M⁻¹Jᵀ summed over each body's nonzero columns of M⁻¹ only.
//! docs/contact.md §"PGS", §"Four contacts per lane".

use super::residual::RowScales;
use super::sweep_entry::{Entry, RowLaw};
use crate::problem::ContactProblem;
use nalgebra::SMatrix;

/// Contact `k`'s entry (what a sweep reads of it), built from the problem, and its row scales
/// into `scales`: M_s⁻¹ J_sᵀ per side (from the body's M⁻¹ and its rows' nonzero columns
/// `mass_rows`), the Delassus block from them, J_sᵀ, b and the constants.
pub(super) fn build_entry<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    mass_rows: &[[(usize, usize); D]],
    k: usize,
    scales: &mut RowScales<R>,
) -> Entry<D, R> {
    let c = &problem.contacts[k];
    let side = |s: usize| match c.bodies[s] {
        Some(b) => inverse_mass_times(
            &problem.bodies[b].inverse_mass,
            &mass_rows[b],
            &c.jacobian[s].transpose(),
        ),
        None => SMatrix::zeros(),
    };
    let sides = [side(0), side(1)];
    // The contact's Delassus block from the same per-body M⁻¹Jᵀ the updates use, once:
    // A_kk = Σ_s J_s (M_s⁻¹ J_sᵀ), symmetrised, plus compliance on its rows
    // (docs/contact.md §"Delassus operator"; `ContactProblem::delassus_block` forms
    // J M⁻¹ first, the same to round-off).
    let mut a = SMatrix::<f64, R, R>::zeros();
    for ((body, jacobian), side) in c.bodies.iter().zip(&c.jacobian).zip(&sides) {
        if body.is_some() {
            a += jacobian * side;
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

/// Per row i of `m`, the columns (first, end) outside of which m_ij is zero (first = end = D for
/// a zero row): a 3D body's M⁻¹ = diag(m⁻¹ I₃, J⁻¹) has one column in each of its first three
/// rows and three in the others, so its contacts' M⁻¹Jᵀ take 12 products per column, not 36.
pub(super) fn nonzero_columns<const D: usize>(m: &SMatrix<f64, D, D>) -> [(usize, usize); D] {
    std::array::from_fn(|i| {
        let first = (0..D).find(|&j| m[(i, j)] != 0.0).unwrap_or(D);
        let end = (0..D)
            .rev()
            .find(|&j| m[(i, j)] != 0.0)
            .map_or(D, |j| j + 1);
        (first, end)
    })
}

/// M⁻¹ Jᵀ (D × R), each entry Σ_j m_ij (Jᵀ)_jr summed as nalgebra's product sums it (j
/// ascending, from the first product), over row i's nonzero columns `rows[i]` only. Where that
/// sum is not zero and Jᵀ is finite it is nalgebra's sum over every column to the bit: the
/// terms left out are ±0, and adding ±0 to a sum that ends nonzero changes no bit of the end
/// (a running sum differs at most in the sign of a zero, which the next nonzero term erases).
/// Elsewhere (a zero sum, whose sign the left-out zeros decide; a zero row; a non-finite Jᵀ,
/// where 0 · ∞ is NaN) the full sum is taken. docs/contact.md §"Four contacts per lane".
#[inline(always)]
pub(super) fn inverse_mass_times<const D: usize, const R: usize>(
    m: &SMatrix<f64, D, D>,
    rows: &[(usize, usize); D],
    jacobian_t: &SMatrix<f64, D, R>,
) -> SMatrix<f64, D, R> {
    let finite = jacobian_t.iter().all(|x| x.is_finite());
    let sum = |i: usize, r: usize, columns: std::ops::Range<usize>| {
        let first = columns.start;
        let mut sum = m[(i, first)] * jacobian_t[(first, r)];
        for j in first + 1..columns.end {
            sum = m[(i, j)] * jacobian_t[(j, r)] + sum;
        }
        sum
    };
    SMatrix::from_fn(|i, r| {
        let (first, end) = rows[i];
        if finite && first < end {
            let short = sum(i, r, first..end);
            if short != 0.0 {
                return short;
            }
        }
        sum(i, r, 0..D)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The set-up's M⁻¹Jᵀ over each row's nonzero columns is nalgebra's full product to the bit,
    /// signed zeros included: block-diagonal inverse masses (a 3D body's diag(m⁻¹ I₃, J⁻¹), a
    /// pinned body's zeros, −0 outside the blocks) against Jacobians with zero and −0 entries,
    /// whole zero rows, products that cancel to zero, and an infinite entry.
    #[test]
    fn inverse_mass_times_over_nonzero_columns_is_nalgebras_product_to_the_bit() {
        let mut state = 0x49u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as f64 / (1u64 << 31) as f64 * 2.0 - 1.0
        };
        let pick = |x: f64, y: f64| {
            if x < -0.6 {
                0.0
            } else if x < -0.3 {
                -0.0
            } else {
                y
            }
        };
        for case in 0..2000 {
            let mut m = SMatrix::<f64, 6, 6>::zeros();
            if case % 7 != 0 {
                for i in 0..3 {
                    m[(i, i)] = pick(next(), 0.5);
                }
                for i in 3..6 {
                    for j in 3..6 {
                        m[(i, j)] = pick(next(), next());
                    }
                }
                // −0 outside the blocks on some bodies.
                if case % 3 == 0 {
                    m[(0, 4)] = -0.0;
                    m[(5, 1)] = -0.0;
                }
            }
            let mut jt = SMatrix::<f64, 6, 3>::from_fn(|_, _| pick(next(), next()));
            if case % 11 == 0 {
                // Cancels: m₃₃ j₃ + m₃₄ j₄ = 0 where the entries allow.
                jt[(3, 0)] = m[(3, 4)];
                jt[(4, 0)] = -m[(3, 3)];
            }
            if case % 13 == 0 {
                jt[(case % 6, case % 3)] = f64::INFINITY;
            }
            let full = m * jt;
            let short = inverse_mass_times(&m, &nonzero_columns(&m), &jt);
            for (a, b) in full.iter().zip(short.iter()) {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "case {case}: {full} against {short}"
                );
            }
        }
    }
}
