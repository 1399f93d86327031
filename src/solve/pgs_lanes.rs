//! The coloured sweep four contacts at a time: the contacts of one colour share no moving body,
//! so four of them can take the same steps side by side, one per lane, with every quantity of
//! the four stored lane by lane (struct of arrays within a group of four, as Box2D v3's wide
//! constraints). docs/contact.md §"Four contacts per lane".
//!
//! Each lane takes exactly the steps of the one-contact visit ([`super::pgs_visit::solve_contact`] with
//! its bodies' Δu copied once and written back once): the same products, summed in the same
//! order as nalgebra's dot product, the same branches taken as selects, so every lane's result is
//! the one-contact visit's, bit for bit, and the sweep's result is the coloured sweep's. What
//! changes is only that the processor computes four lanes with one instruction where it can.

// Loops over side s, row r, component d and lane l index several arrays by the same subscript,
// as the derivation writes them.
#![allow(clippy::needless_range_loop)]

use super::prefetch::prefetch_object;
use super::sweep_entry::{Entry, RowLaw, Shared};
pub(super) use super::wide::LANES;
use super::wide::{Mask, Wide};
use crate::problem::FrictionModel;
use nalgebra::{SMatrix, SVector};

/// A group of four contacts of one colour as a visit reads them, each quantity lane by lane
/// (lane l is the group's l-th contact): where these contacts' entries are kept, each written
/// into its lane once by the solve's set-up ([`super::pgs_workspace::PgsWorkspace::prepare`]).
#[derive(Clone, Debug)]
pub(super) struct LaneGroup<const D: usize, const R: usize> {
    /// The contacts' indices in the problem (for λ).
    contact: [usize; LANES],
    /// Per side, the body of each lane (0 where the side is the static world).
    body: [[usize; LANES]; 2],
    /// Per side, set in the lanes whose side is a body, clear where it is the static world (a
    /// bit mask, so that the processor selects with it lane by lane).
    present: [Mask; 2],
    /// Per side, whether each lane's side is a body that moves (a pinned body's Δu is only
    /// read; the static world's is not a body's).
    moving: [[bool; LANES]; 2],
    /// J_sᵀ: [side][row][component], lane by lane.
    jacobian_t: [[[Wide; D]; R]; 2],
    /// m_s⁻¹ per side, kg⁻¹: M_s⁻¹ J_sᵀ's linear rows (the first [`linear_components`]) are
    /// m_s⁻¹ J_sᵀ's, equal as numbers (`set_lane` checks it; a zero's sign may differ, which no
    /// update can tell); 0 for the static world and a side held fixed.
    inverse_mass: [Wide; 2],
    /// M_s⁻¹ J_sᵀ's angular rows, both sides in one row of D: [row][s · A + a] is component
    /// L + a of side s (L = [`linear_components`], A = D − L, and 2A ≤ D), lane by lane.
    angular_inverse_mass_jacobian_t: [[Wide; D]; R],
    /// b per row, m/s.
    b: [Wide; R],
    /// a_r per row.
    diagonal: [Wide; R],
    /// ρ, the cone step's scale.
    tangent_rho: Wide,
    /// μ.
    mu: Wide,
    /// Compliance on the normal row.
    compliance: Wide,
}

/// Whether the groups can take problems of this shape: a body dimension whose dot product
/// [`sum_in_nalgebras_order`] reproduces (below 8) and at least the normal row. The caller
/// excludes joints and contacts between a body and itself (`super::pgs::solve_pgs`).
pub(super) const fn dimensions_fit<const D: usize, const R: usize>() -> bool {
    D < 8 && R >= 1
}

/// L, the leading components of a body's velocity that are linear, ⌈D / 2⌉: (v, ω) in 3D (3 of
/// 6), (v_x, v_y, ω) in 2D (2 of 3). Where a body's M⁻¹ is m⁻¹ on them and couples them to
/// nothing else (a rigid body's, about its centre of mass), M⁻¹ J_sᵀ's linear rows are m⁻¹ J_sᵀ's,
/// and a group keeps m⁻¹ instead of them (docs/contact.md §"Four contacts per lane", "One
/// inverse mass a side").
pub(super) const fn linear_components(d: usize) -> usize {
    d.div_ceil(2)
}

impl<const D: usize, const R: usize> LaneGroup<D, R> {
    /// A group with every lane empty (all zero; no side a body), to be filled lane by lane with
    /// [`LaneGroup::set_lane`] where it is stored: made only when the groups grow, since
    /// `set_lane` overwrites a reused group's lane whole.
    pub(super) fn empty() -> Self {
        let zero = Wide::splat(0.0);
        LaneGroup {
            contact: [0; LANES],
            body: [[0; LANES]; 2],
            present: [Mask::NONE; 2],
            moving: [[false; LANES]; 2],
            jacobian_t: [[[zero; D]; R]; 2],
            inverse_mass: [zero; 2],
            angular_inverse_mass_jacobian_t: [[zero; D]; R],
            b: [zero; R],
            diagonal: [zero; R],
            tangent_rho: zero,
            mu: zero,
            compliance: zero,
        }
    }

    /// Puts contact `k`'s entry `e` in lane `l`: every quantity of the lane written, each from
    /// the entry, the static world's side as zeros, so that a group reused from an earlier
    /// solve keeps nothing of it once its four lanes are set. `moving[b]`: whether body b's
    /// inverse mass is not zero; `inverse_mass[s]`: side s's body's m⁻¹ (M⁻¹'s first diagonal
    /// entry; anything for the static world).
    ///
    /// Returns whether the lane holds the entry whole: whether (J_sᵀ)_dr is finite and
    /// m_s⁻¹ (J_sᵀ)_dr equals the entry's (M_s⁻¹ J_sᵀ)_dr on every linear row d of both sides
    /// (as numbers: ±0 alike, which an update cannot tell apart, [`apply`]). Where it does not
    /// (a body whose M⁻¹ is not a rigid body's), the solve must not use the groups
    /// (`PgsWorkspace::prepare` lays the contacts out one at a time instead).
    pub(super) fn set_lane(
        &mut self,
        l: usize,
        k: usize,
        e: &Entry<D, R>,
        moving: &[bool],
        inverse_mass: [f64; 2],
    ) -> bool {
        let linear = linear_components(D);
        let angular = D - linear;
        let mut whole = true;
        self.contact[l] = k;
        for s in 0..2 {
            // The static world's side is zero (its Δu is zero and never written).
            let body = e.bodies[s];
            self.body[s][l] = body.unwrap_or(0);
            self.present[s].assign(l, body.is_some());
            self.moving[s][l] = body.is_some_and(|b| moving[b]);
            let (j, mj, m) = match body {
                Some(_) => (
                    e.jacobian_t[s],
                    e.inverse_mass_jacobian_t[s],
                    inverse_mass[s],
                ),
                None => (SMatrix::zeros(), SMatrix::zeros(), 0.0),
            };
            self.inverse_mass[s].0[l] = m;
            for r in 0..R {
                for d in 0..D {
                    self.jacobian_t[s][r][d].0[l] = j[(d, r)];
                    if d < linear {
                        // J finite too, so that a side held fixed (m = 0) has 0 · J = ±0.
                        whole &= j[(d, r)].is_finite() && m * j[(d, r)] == mj[(d, r)];
                    } else {
                        self.angular_inverse_mass_jacobian_t[r][s * angular + d - linear].0[l] =
                            mj[(d, r)];
                    }
                }
            }
        }
        for r in 0..R {
            self.b[r].0[l] = e.b[r];
            self.diagonal[r].0[l] = e.law.diagonal[r];
        }
        self.tangent_rho.0[l] = e.law.tangent_rho;
        self.mu.0[l] = e.law.mu;
        self.compliance.0[l] = e.law.compliance;
        whole
    }

    /// The contact in lane `l` (its index in the problem).
    #[inline(always)]
    pub(super) fn contact(&self, l: usize) -> usize {
        self.contact[l]
    }

    /// Lane `l`'s body on side `s` (`None`: the static world).
    #[inline(always)]
    pub(super) fn body(&self, l: usize, s: usize) -> Option<usize> {
        self.present[s].lane(l).then_some(self.body[s][l])
    }

    /// Lane `l`'s constants as a one-at-a-time visit reads them.
    #[inline(always)]
    pub(super) fn law(&self, l: usize) -> RowLaw<R> {
        RowLaw {
            diagonal: SVector::from_fn(|r, _| self.diagonal[r].0[l]),
            tangent_rho: self.tangent_rho.0[l],
            mu: self.mu.0[l],
            compliance: self.compliance.0[l],
        }
    }

    /// Lane `l`'s row scales as shock propagation changes them (the diagonal and ρ).
    pub(super) fn set_scales(&mut self, l: usize, diagonal: &SVector<f64, R>, tangent_rho: f64) {
        for r in 0..R {
            self.diagonal[r].0[l] = diagonal[r];
        }
        self.tangent_rho.0[l] = tangent_rho;
    }

    /// Row r of J_s of lane `l` (column r of J_sᵀ), as a vector.
    #[inline(always)]
    fn jacobian_column(&self, l: usize, s: usize, r: usize) -> SVector<f64, D> {
        SVector::from_fn(|d, _| self.jacobian_t[s][r][d].0[l])
    }

    /// M_s⁻¹ J_sᵀ of lane `l` (D × R).
    pub(super) fn inverse_mass_jacobian_t(&self, l: usize, s: usize) -> SMatrix<f64, D, R> {
        SMatrix::from_fn(|d, r| inverse_mass_jacobian_t(self, s, r, d).0[l])
    }

    /// Holds side `s` of lane `l` fixed (shock propagation): its M_s⁻¹ J_sᵀ zero, so that an
    /// update does not move it.
    pub(super) fn hold_side_fixed(&mut self, l: usize, s: usize) {
        let angular = D - linear_components(D);
        self.inverse_mass[s].0[l] = 0.0;
        for r in 0..R {
            for a in 0..angular {
                self.angular_inverse_mass_jacobian_t[r][s * angular + a].0[l] = 0.0;
            }
        }
    }

    /// Lane `l`'s w_r = b_r + J₁,r u₁ + J₂,r u₂ (without compliance), u_s being side s's Δu
    /// (anything for the static world's side): [`Entry::velocity`]'s arithmetic on the same
    /// numbers (nalgebra's dot product of the same vectors), so the same bits.
    #[inline(always)]
    pub(super) fn lane_velocity(&self, l: usize, u: &[SVector<f64, D>; 2], r: usize) -> f64 {
        let mut w = self.b[r].0[l];
        for s in 0..2 {
            if self.present[s].lane(l) {
                w += self.jacobian_column(l, s, r).dot(&u[s]);
            }
        }
        w
    }

    /// Lane `l`'s λ_r changes by `delta`: u_s += (M_s⁻¹ J_sᵀ)_r δ for each side that is a body,
    /// as [`Entry::apply`] computes it.
    #[inline(always)]
    pub(super) fn lane_apply(&self, l: usize, u: &mut [SVector<f64, D>; 2], r: usize, delta: f64) {
        for s in 0..2 {
            if self.present[s].lane(l) {
                let column =
                    SVector::<f64, D>::from_fn(|d, _| inverse_mass_jacobian_t(self, s, r, d).0[l]);
                u[s].axpy(delta, &column, 1.0);
            }
        }
    }
}

/// The number of contacts of a colour of `n` that go in groups.
pub(super) fn grouped(n: usize) -> usize {
    n / LANES * LANES
}

/// Σ_d p_d in the order nalgebra's dot product sums a D-vector's products (left to right for
/// D = 2 and 3, (p₀ + p₂) + (p₁ + p₃) for 4, one by one from +0 for the other D below 8), lane
/// by lane: so that a lane's J_s,r · Δu_s is the one-contact visit's to the bit.
#[inline(always)]
fn sum_in_nalgebras_order<const D: usize>(p: &[Wide; D]) -> Wide {
    match D {
        2 => p[0] + p[1],
        3 => p[0] + p[1] + p[2],
        4 => (p[0] + p[2]) + (p[1] + p[3]),
        _ => {
            let mut sum = Wide::splat(0.0);
            for &term in p {
                sum += term;
            }
            sum
        }
    }
}

/// w_r = b_r + J₁,r Δu₁ + J₂,r Δu₂ per lane (without compliance), a side adding its term only
/// where it is a body.
#[inline(always)]
fn velocity<const D: usize, const R: usize>(
    g: &LaneGroup<D, R>,
    u: &[[Wide; D]; 2],
    r: usize,
) -> Wide {
    let mut w = g.b[r];
    for s in 0..2 {
        let mut products = [Wide::splat(0.0); D];
        for d in 0..D {
            products[d] = g.jacobian_t[s][r][d] * u[s][d];
        }
        let dot = sum_in_nalgebras_order(&products);
        w = g.present[s].select(w + dot, w);
    }
    w
}

/// (M_s⁻¹ J_sᵀ)_dr per lane: m_s⁻¹ (J_sᵀ)_dr on a linear row d (the same bits as the entry's
/// product, up to the sign of a zero: `LaneGroup::set_lane` checks it), else the angular rows
/// kept.
#[inline(always)]
fn inverse_mass_jacobian_t<const D: usize, const R: usize>(
    g: &LaneGroup<D, R>,
    s: usize,
    r: usize,
    d: usize,
) -> Wide {
    let linear = linear_components(D);
    if d < linear {
        g.inverse_mass[s] * g.jacobian_t[s][r][d]
    } else {
        g.angular_inverse_mass_jacobian_t[r][s * (D - linear) + d - linear]
    }
}

/// λ_r changes by `delta` per lane: Δu_s += (M_s⁻¹ J_sᵀ)_r δ per side. A lane whose row does not
/// move passes δ = +0, which changes nothing: 0 · x is ±0 and Δu is never −0 (it starts at +0
/// and a sum is −0 only when both terms are), so Δu + (±0) is Δu to the bit; and the static
/// world's side is zero and never written back. For the same reason a column entry of −0
/// where the entry had +0 (m⁻¹ J on a linear row) changes nothing either.
#[inline(always)]
fn apply<const D: usize, const R: usize>(
    g: &LaneGroup<D, R>,
    u: &mut [[Wide; D]; 2],
    r: usize,
    delta: Wide,
) {
    for s in 0..2 {
        for d in 0..D {
            u[s][d] += delta * inverse_mass_jacobian_t(g, s, r, d);
        }
    }
}

/// One visit of the group's four contacts, each lane the steps of
/// [`super::pgs_visit::solve_contact`]: normal row, then the friction rows bounded by μ times the
/// normal impulse just computed (box or disk).
///
/// # Safety
/// As [`visit_groups`].
#[inline(always)]
unsafe fn visit_group<const D: usize, const R: usize>(
    friction: FrictionModel,
    g: &LaneGroup<D, R>,
    shared: &Shared<D, R>,
) {
    let zero = Wide::splat(0.0);
    // The bodies' Δu and the contacts' λ, read once.
    let mut u = [[zero; D]; 2];
    for s in 0..2 {
        for l in 0..LANES {
            if g.present[s].lane(l) {
                // SAFETY: the caller's contract.
                let v = unsafe { &*shared.delta_velocity.add(g.body[s][l]) };
                for d in 0..D {
                    u[s][d].0[l] = v[d];
                }
            }
        }
    }
    let mut lam = [zero; R];
    for l in 0..LANES {
        // SAFETY: the caller's contract.
        let contact = unsafe { *shared.lambda.add(g.contact[l]) };
        for r in 0..R {
            lam[r].0[l] = contact[r];
        }
    }

    // Normal row: λn ← max(0, λn − w_n / a_n) where a_n > 0 (elsewhere λn stays and δ = 0).
    let moves = g.diagonal[0].gt(zero);
    let w_n = velocity(g, &u, 0) + g.compliance * lam[0];
    let lambda_n = (lam[0] - w_n / g.diagonal[0]).positive_part();
    apply(g, &mut u, 0, moves.select(lambda_n - lam[0], zero));
    lam[0] = moves.select(lambda_n, lam[0]);

    // Friction rows, bounded by μ λn. Where the bound is 0, each nonzero friction impulse is
    // taken back to 0 (a zero one stays as it is, −0 included).
    let bound = g.mu * lam[0];
    let zero_bound = bound.eq(zero);
    match friction {
        FrictionModel::Box => {
            // Row by row: λ_r ← clamp(λ_r − w_r / a_r, ±bound) where a_r > 0, else clamped.
            for r in 1..R {
                let old = lam[r];
                let w = velocity(g, &u, r);
                let stepped = (old - w / g.diagonal[r]).clamp(-bound, bound);
                let moves = g.diagonal[r].gt(zero);
                let nonzero = old.ne(zero);
                let delta = moves.select(stepped - old, zero);
                let delta = zero_bound.select(nonzero.select(-old, zero), delta);
                apply(g, &mut u, r, delta);
                let next = moves.select(stepped, old.clamp(-bound, bound));
                lam[r] = zero_bound.select(nonzero.select(zero, old), next);
            }
        }
        FrictionModel::Cone => {
            // One projected-gradient step on the pair with the scalar step 1/ρ (every row's
            // velocity before any update), then onto the disk (projection::project_disk).
            let rho = g.tangent_rho;
            let mut trial = lam;
            for r in 1..R {
                let w = velocity(g, &u, r);
                trial[r] = rho.gt(zero).select(lam[r] - w / rho, lam[r]);
            }
            let mut squares = Wide::splat(-0.0);
            for row in &trial[1..] {
                squares += *row * *row;
            }
            let norm = squares.sqrt();
            let scale = norm.gt(zero).select(bound / norm, zero);
            let outside = norm.gt(bound);
            for row in &mut trial[1..] {
                *row = outside.select(*row * scale, *row);
            }
            for r in 1..R {
                let old = lam[r];
                let nonzero = old.ne(zero);
                let delta = zero_bound.select(nonzero.select(-old, zero), trial[r] - old);
                apply(g, &mut u, r, delta);
                lam[r] = zero_bound.select(nonzero.select(zero, old), trial[r]);
            }
        }
    }

    // Written back once: λ, and the moving bodies' Δu.
    for l in 0..LANES {
        let contact = SVector::<f64, R>::from_fn(|r, _| lam[r].0[l]);
        // SAFETY: the caller's contract.
        unsafe { *shared.lambda.add(g.contact[l]) = contact };
    }
    for s in 0..2 {
        for l in 0..LANES {
            if g.moving[s][l] {
                // SAFETY: the caller's contract.
                let v = unsafe { &mut *shared.delta_velocity.add(g.body[s][l]) };
                for d in 0..D {
                    v[d] = u[s][d].0[l];
                }
            }
        }
    }
}

/// Visits `groups` in turn: grouped contacts of one colour (any order within a colour gives
/// the same bits, the contacts being independent). `native`, on a processor with AVX2: four
/// lanes per instruction; else the same code compiled for the baseline processor (two lanes per
/// instruction on x86-64), to the same bits (no fused multiply-add either way).
///
/// # Safety
/// `shared` points at every body's Δu and every contact's λ of the problem the groups were laid
/// out from, and while this runs nothing else reads or writes the groups' contacts' λ or their
/// moving bodies' Δu, and nothing writes a pinned body's Δu.
pub(super) unsafe fn visit_groups<const D: usize, const R: usize>(
    friction: FrictionModel,
    groups: &[LaneGroup<D, R>],
    shared: &Shared<D, R>,
    native: bool,
) {
    #[cfg(target_arch = "x86_64")]
    if native && std::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above; the rest is the caller's
        // contract.
        unsafe { visit_groups_avx2(friction, groups, shared) };
        return;
    }
    for i in 0..groups.len() {
        prefetch_group_ahead(groups, i);
        // SAFETY: the caller's contract.
        unsafe { visit_group(friction, &groups[i], shared) };
    }
}

/// [`visit_groups`] compiled for AVX2 (four f64 lanes per instruction).
///
/// # Safety
/// As [`visit_groups`], on a processor with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn visit_groups_avx2<const D: usize, const R: usize>(
    friction: FrictionModel,
    groups: &[LaneGroup<D, R>],
    shared: &Shared<D, R>,
) {
    for i in 0..groups.len() {
        prefetch_group_ahead(groups, i);
        // SAFETY: the caller's contract.
        unsafe { visit_group(friction, &groups[i], shared) };
    }
}

/// How many groups ahead of the one being visited [`visit_groups`] asks the processor to load
/// (docs/contact.md §"Four contacts per lane", "Loaded ahead"; measured in docs/performance.md
/// §"Issue 49: the groups loaded ahead").
const PREFETCH_AHEAD: usize = 2;

/// Asks the processor to start loading group `i` + [`PREFETCH_AHEAD`], if there is one, while
/// group `i` is visited. Only a hint: it reads nothing into the program and changes no value.
#[inline(always)]
fn prefetch_group_ahead<const D: usize, const R: usize>(groups: &[LaneGroup<D, R>], i: usize) {
    if let Some(ahead) = groups.get(i + PREFETCH_AHEAD) {
        prefetch_object(ahead);
    }
}

#[cfg(test)]
mod tests {
    use super::LaneGroup;

    /// The sizes docs/contact.md §"Four contacts per lane", "One inverse mass a side", gives
    /// (and the cache arithmetic of "Loaded ahead" uses): 3D, 2D with friction, 2D normal rows.
    #[test]
    fn a_group_takes_the_bytes_the_docs_give() {
        assert_eq!(std::mem::size_of::<LaneGroup<6, 3>>(), 2272);
        assert_eq!(std::mem::size_of::<LaneGroup<3, 2>>(), 1056);
        assert_eq!(std::mem::size_of::<LaneGroup<3, 1>>(), 704);
    }
}
