//! What a PGS sweep reads per contact, and how threads reach the state it writes: the records
//! the one-at-a-time visits of src/solve/pgs.rs and the groups of src/solve/pgs_lanes.rs are
//! built from (docs/contact.md §"PGS", §"Four contacts per lane").

use crate::problem::RowBounds;
use nalgebra::{SMatrix, SVector};

/// Contact `k` as a sweep reads it, gathered in one place (Box2D's "constraint" struct): one
/// stretch of memory per visit, wherever the order jumps, and borrowed apart from the bodies' Δu
/// that a visit changes, so that the compiler knows the one is not written through the other.
#[derive(Clone, Debug)]
pub(super) struct Entry<const D: usize, const R: usize> {
    /// The problem's bodies of its two sides (`None`: the static world).
    pub bodies: [Option<usize>; 2],
    /// J_sᵀ per side (D × R): row r of J_s is column r here, contiguous in memory.
    pub jacobian_t: [SMatrix<f64, D, R>; 2],
    /// M_s⁻¹ J_sᵀ per side (D × R), zero for the static world (and, during shock propagation,
    /// for a side held fixed).
    pub inverse_mass_jacobian_t: [SMatrix<f64, D, R>; 2],
    /// b, m/s.
    pub b: SVector<f64, R>,
    /// The constants a visit steps with.
    pub law: RowLaw<R>,
    /// The rows' bounds (a contact's, or a joint's free rows).
    pub bounds: RowBounds,
    /// The warm start λ₀ (read by the deliberate fault `stale_friction_bound`): here so that
    /// a visit reads nothing of the problem's contact, wherever the order jumps.
    pub lambda0: SVector<f64, R>,
}

/// A constraint's constants as a visit reads them.
#[derive(Clone, Copy, Debug)]
pub(super) struct RowLaw<const R: usize> {
    /// a_r = (A + C)_rr, the rows' diagonal ([`super::residual::RowScales::diagonal`]).
    pub diagonal: SVector<f64, R>,
    /// ρ, the cone step's scale ([`super::residual::RowScales::tangent_rho`]).
    pub tangent_rho: f64,
    /// μ.
    pub mu: f64,
    /// Compliance on the normal row (a joint's on every row), added to the rows' velocities
    /// by the visit; 0 where [`ContactRows::velocity`] includes it already (the local form).
    pub compliance: f64,
}

impl<const D: usize, const R: usize> Entry<D, R> {
    /// An entry of zeros, no body on either side: a place in the workspace's entries until the
    /// set-up writes the contact's entry there.
    pub fn placeholder() -> Self {
        Entry {
            bodies: [None; 2],
            jacobian_t: [SMatrix::zeros(); 2],
            inverse_mass_jacobian_t: [SMatrix::zeros(); 2],
            b: SVector::zeros(),
            law: RowLaw {
                diagonal: SVector::zeros(),
                tangent_rho: 0.0,
                mu: 0.0,
                compliance: 0.0,
            },
            bounds: RowBounds::Contact,
            lambda0: SVector::zeros(),
        }
    }

    /// w_r = b_r + J₁,r Δu₁ + J₂,r Δu₂ (without compliance).
    #[inline(always)]
    pub(super) fn velocity(&self, delta_velocity: &[SVector<f64, D>], r: usize) -> f64 {
        let mut w = self.b[r];
        for s in 0..2 {
            if let Some(b) = self.bodies[s] {
                w += self.jacobian_t[s].column(r).dot(&delta_velocity[b]);
            }
        }
        w
    }

    /// λ_r changes by `delta`: Δu_s += (M_s⁻¹ J_sᵀ)_r δ for each body.
    #[inline(always)]
    pub(super) fn apply(&self, delta_velocity: &mut [SVector<f64, D>], r: usize, delta: f64) {
        for s in 0..2 {
            if let Some(b) = self.bodies[s] {
                let column = self.inverse_mass_jacobian_t[s].column(r);
                delta_velocity[b].axpy(delta, &column, 1.0);
            }
        }
    }
}

/// What the threads of a coloured solve share: the bodies' Δu and the contacts' λ, written
/// through raw pointers ([`super::pgs_threads::sweep_in_threads`] schedules the visits).
pub(super) struct Shared<const D: usize, const R: usize> {
    pub delta_velocity: *mut SVector<f64, D>,
    pub lambda: *mut SVector<f64, R>,
}

// SAFETY: the pointers are written only at indices that one thread owns for the current colour
// (a contact's λ; its moving bodies' Δu, which no other contact of the colour touches); the
// barrier between colours orders every write before the next colour's reads; a pinned body's
// Δu is only read.
unsafe impl<const D: usize, const R: usize> Sync for Shared<D, R> {}
