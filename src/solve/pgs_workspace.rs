//! What a PGS solve keeps from solve to solve, and its set-up: each contact's entry (what a
//! sweep reads) and row scales, in visiting order; the coloured order's colours; the bodies'
//! Δu; the seeded generator of the random orders. docs/contact.md §"PGS", §"Coloured order".

use super::pgs_lanes::LaneGroup;
use super::pgs_settings::{ContactOrder, Lanes};
use super::pgs_visit::ContactRows;
use super::residual::RowScales;
use super::sweep_entry::{Entry, RowLaw};
use crate::problem::ContactProblem;
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// Buffers PGS reuses from solve to solve, so that a solve does not allocate once they have
/// grown to the problem's size; also the random generator, so a run's orders are reproducible.
#[derive(Clone, Debug)]
pub struct PgsWorkspace<const D: usize, const R: usize> {
    /// Δu per body: the velocity change the current λ causes.
    pub(super) delta_velocity: Vec<SVector<f64, D>>,
    /// Per contact, what a sweep reads, in problem order.
    pub(super) entries: Vec<Entry<D, R>>,
    /// Row scales per contact (the full block, for the exact local solve and the residuals).
    pub(super) scales: Vec<RowScales<R>>,
    /// The visiting order.
    pub(super) order: Vec<usize>,
    /// Where each contact's entry is in `entries` (the visiting order for the coloured order,
    /// else the problem order).
    pub(super) slot: Vec<usize>,
    /// With the coloured order: where each colour starts in `order` (the end appended), and
    /// the colouring's scratch.
    pub(super) colour_starts: Vec<usize>,
    pub(super) colour_masks: Vec<u64>,
    pub(super) colour_of: Vec<usize>,
    /// Per body: whether its inverse mass is not zero (a pinned body's Δu never changes).
    pub(super) moving: Vec<bool>,
    /// Threads a coloured sweep runs on ([`PgsWorkspace::set_threads`]; 1 by default).
    pub(super) threads: usize,
    /// Threads the last solve's sweeps ran on.
    pub(super) last_threads: usize,
    /// Whether a coloured sweep, row by row, takes its colours' contacts four at a time
    /// ([`PgsWorkspace::set_lanes`]; natively by default).
    pub(super) lanes: Lanes,
    /// With four contacts at a time: the groups, colour by colour, colour c's being
    /// `groups[group_starts[c]..group_starts[c + 1]]`; empty when the last solve went one
    /// contact at a time.
    pub(super) groups: Vec<LaneGroup<D, R>>,
    pub(super) group_starts: Vec<usize>,
    pub(super) rng: ChaCha8Rng,
    /// With the random coloured order: the random permutation of the contacts the solve's
    /// colouring takes them in, and each sweep's order of the colours (sweep s's being
    /// `sweep_colours[s * colours..(s + 1) * colours]`); empty otherwise.
    pub(super) shuffled: Vec<usize>,
    pub(super) sweep_colours: Vec<usize>,
    /// Exact visits of the current solve that took the local solve's best candidate because no
    /// case was exact to round-off ([`super::local::solve_local`]).
    pub(super) local_fallbacks: u32,
}

/// A contact of the body form with the bodies' Δu, borrowed apart.
pub(super) struct BodyRows<'a, const D: usize, const R: usize> {
    entry: &'a Entry<D, R>,
    delta_velocity: &'a mut [SVector<f64, D>],
}

impl<const D: usize, const R: usize> ContactRows<R> for BodyRows<'_, D, R> {
    #[inline(always)]
    fn velocity(&self, r: usize) -> f64 {
        self.entry.velocity(self.delta_velocity, r)
    }
    #[inline(always)]
    fn apply(&mut self, r: usize, delta: f64) {
        self.entry.apply(self.delta_velocity, r, delta);
    }
}

/// A contact of the body form with copies of its two bodies' Δu: a visit reads them once, its
/// rows update the copies, and [`PgsWorkspace::store`] writes them back once (the same
/// arithmetic as [`BodyRows`], so the same bits; the copies stay in registers between the rows
/// instead of going through memory). Only for a contact between two different bodies.
pub(super) struct CachedRows<'a, const D: usize, const R: usize> {
    pub(super) entry: &'a Entry<D, R>,
    pub(super) delta_velocity: [SVector<f64, D>; 2],
}

impl<const D: usize, const R: usize> ContactRows<R> for CachedRows<'_, D, R> {
    #[inline(always)]
    fn velocity(&self, r: usize) -> f64 {
        let e = self.entry;
        let mut w = e.b[r];
        for s in 0..2 {
            if e.bodies[s].is_some() {
                w += e.jacobian_t[s].column(r).dot(&self.delta_velocity[s]);
            }
        }
        w
    }
    #[inline(always)]
    fn apply(&mut self, r: usize, delta: f64) {
        let e = self.entry;
        for s in 0..2 {
            if e.bodies[s].is_some() {
                let column = e.inverse_mass_jacobian_t[s].column(r);
                self.delta_velocity[s].axpy(delta, &column, 1.0);
            }
        }
    }
}

impl<const D: usize, const R: usize> PgsWorkspace<D, R> {
    /// An empty workspace whose random orders come from `seed`.
    pub fn new(seed: u64) -> Self {
        PgsWorkspace {
            delta_velocity: Vec::new(),
            entries: Vec::new(),
            scales: Vec::new(),
            order: Vec::new(),
            slot: Vec::new(),
            colour_starts: Vec::new(),
            colour_masks: Vec::new(),
            colour_of: Vec::new(),
            moving: Vec::new(),
            threads: 1,
            last_threads: 1,
            lanes: Lanes::Native,
            groups: Vec::new(),
            group_starts: Vec::new(),
            rng: ChaCha8Rng::seed_from_u64(seed),
            shuffled: Vec::new(),
            sweep_colours: Vec::new(),
            local_fallbacks: 0,
        }
    }

    /// Δu of body `i` after the last solve: add it to the body's velocity.
    pub fn delta_velocity(&self, i: usize) -> &SVector<f64, D> {
        &self.delta_velocity[i]
    }

    /// Builds the entries for `problem`. With a coloured order the contacts are coloured
    /// first and the entries laid out in visiting order (`slot[k]` is contact k's place), so a
    /// sweep reads them front to back; otherwise in problem order.
    pub(super) fn prepare(&mut self, problem: &ContactProblem<D, R>, order: ContactOrder) {
        self.delta_velocity.clear();
        self.delta_velocity
            .resize(problem.bodies.len(), SVector::zeros());
        self.entries.clear();
        self.scales.clear();
        self.order.clear();
        self.colour_starts.clear();
        self.sweep_colours.clear();
        self.local_fallbacks = 0;
        let count = problem.contacts.len();
        if order.is_coloured() {
            self.colour(problem, order);
        } else {
            self.order.extend(0..count);
        }
        self.scales
            .resize(count, RowScales::of_block(SMatrix::zeros()));
        self.slot.clear();
        self.slot.resize(count, 0);
        for i in 0..count {
            let k = self.order[i];
            self.slot[k] = i;
            let c = &problem.contacts[k];
            let side = |s: usize| match c.bodies[s] {
                Some(b) => problem.bodies[b].inverse_mass * c.jacobian[s].transpose(),
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
            self.scales[k] = RowScales::of_block(block);
            let scales = self.scales[k];
            self.entries.push(Entry {
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
            });
        }
    }

    /// Contact `k`'s entry.
    #[inline(always)]
    pub(super) fn entry(&self, k: usize) -> &Entry<D, R> {
        &self.entries[self.slot[k]]
    }

    /// Contact `k`'s entry, to change (shock propagation holds sides fixed).
    pub(super) fn entry_mut(&mut self, k: usize) -> &mut Entry<D, R> {
        let i = self.slot[k];
        &mut self.entries[i]
    }

    /// Puts the contacts in the coloured order ([`ContactOrder::Coloured`]: coloured in problem
    /// order; [`ContactOrder::RandomColoured`]: in a fresh random permutation from the
    /// workspace's generator): a body moves when its inverse mass is not zero.
    pub(super) fn colour(&mut self, problem: &ContactProblem<D, R>, kind: ContactOrder) {
        let PgsWorkspace {
            order,
            colour_starts,
            colour_masks,
            colour_of,
            moving,
            shuffled,
            rng,
            ..
        } = self;
        moving.clear();
        moving.extend((problem.bodies.iter()).map(|b| b.inverse_mass.iter().any(|&m| m != 0.0)));
        let count = problem.contacts.len();
        shuffled.clear();
        shuffled.extend(0..count);
        if kind == ContactOrder::RandomColoured {
            shuffled.shuffle(rng);
        }
        super::colour::colour_contacts_in(
            count,
            |i| shuffled[i],
            |k| problem.contacts[k].bodies,
            moving,
            colour_masks,
            colour_of,
            order,
            colour_starts,
        );
    }

    /// With the random coloured order, draws each of `sweeps` sweeps' order of the colours
    /// from the workspace's generator (before the sweeps, so that the orders do not depend on
    /// the threads); otherwise every sweep takes the colours in turn.
    pub(super) fn draw_sweep_colours(&mut self, order: ContactOrder, sweeps: u32) {
        self.sweep_colours.clear();
        if order != ContactOrder::RandomColoured {
            return;
        }
        let colours = self.colours();
        for _ in 0..sweeps {
            let start = self.sweep_colours.len();
            self.sweep_colours.extend(0..colours);
            self.sweep_colours[start..].shuffle(&mut self.rng);
        }
    }

    /// The `i`-th colour sweep `sweep` visits.
    #[inline(always)]
    pub(super) fn colour_at(&self, sweep: usize, i: usize) -> usize {
        colour_at(&self.sweep_colours, self.colours(), sweep, i)
    }

    /// The contacts in the order the last solve's sweep `sweep` visited them, colour by colour
    /// (one list for the problem and random orders; the random order's is its last sweep's,
    /// drawn afresh each sweep). For checking an order, not for a hot loop: it allocates.
    pub fn sweep_colours(&self, sweep: usize) -> Vec<Vec<usize>> {
        if self.colour_starts.is_empty() {
            return vec![self.order.clone()];
        }
        (0..self.colours())
            .map(|i| {
                let c = self.colour_at(sweep, i);
                self.order[self.colour_starts[c]..self.colour_starts[c + 1]].to_vec()
            })
            .collect()
    }

    /// Runs the sweeps of coloured solves on `threads` threads (at least 1): bit for bit the
    /// one-thread result, for any number (docs/contact.md §"Coloured order"). Other orders, and
    /// the exact local solve, stay on one thread.
    pub fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    /// The threads the last solve's sweeps ran on: 1 unless it was a coloured solve, row by
    /// row, of at least [`MIN_CONTACTS_PER_THREAD`] contacts per thread and colour.
    pub fn last_threads(&self) -> usize {
        self.last_threads
    }

    /// Whether and how a coloured solve, row by row, visits its colours' contacts four at a
    /// time (docs/contact.md §"Four contacts per lane"): the same bits in every case;
    /// [`Lanes::Native`] by default, [`Lanes::Off`] to compare.
    pub fn set_lanes(&mut self, lanes: Lanes) {
        self.lanes = lanes;
    }

    /// The groups of four the last solve's sweeps visited (0 when they went one at a time).
    pub fn last_groups(&self) -> usize {
        self.groups.len()
    }

    /// The number of colours of the last coloured solve.
    pub fn colours(&self) -> usize {
        self.colour_starts.len().saturating_sub(1)
    }

    /// Asks the processor to start loading the entry of contact `k` (a visit two ahead, in a
    /// random order that its own prefetcher cannot guess). Only a hint: it changes no value.
    #[inline(always)]
    pub(super) fn prefetch(&self, k: usize) {
        #[cfg(target_arch = "x86_64")]
        {
            let entry = self.entry(k) as *const Entry<D, R> as *const i8;
            let bytes = std::mem::size_of::<Entry<D, R>>();
            for offset in (0..bytes).step_by(64) {
                // SAFETY: a prefetch never faults and reads nothing into the program; the
                // addresses are inside contact k's entry anyway.
                unsafe {
                    std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                        entry.add(offset),
                    )
                };
            }
        }
    }

    /// The rows of contact `k` with the bodies' Δu, borrowed apart.
    #[inline(always)]
    pub(super) fn rows(&mut self, k: usize) -> BodyRows<'_, D, R> {
        BodyRows {
            entry: &self.entries[self.slot[k]],
            delta_velocity: &mut self.delta_velocity,
        }
    }

    /// Contact `k`'s rows with copies of its bodies' Δu (zeros for the static world), or `None`
    /// when both sides are the same body (then the copies would not see each other's writes).
    #[inline(always)]
    pub(super) fn cached_rows(&self, k: usize) -> Option<CachedRows<'_, D, R>> {
        let entry = self.entry(k);
        if entry.bodies[0].is_some() && entry.bodies[0] == entry.bodies[1] {
            return None;
        }
        let copy = |s: usize| entry.bodies[s].map_or(SVector::zeros(), |b| self.delta_velocity[b]);
        Some(CachedRows {
            entry,
            delta_velocity: [copy(0), copy(1)],
        })
    }

    /// w_r = b_r + J₁,r Δu₁ + J₂,r Δu₂ for row `r` of contact `k` (without compliance).
    pub(super) fn row_velocity(&self, k: usize, r: usize) -> f64 {
        self.entry(k).velocity(&self.delta_velocity, r)
    }

    /// Changes λ_r of contact `k` by `delta` and updates the bodies' Δu to match.
    pub(super) fn apply(&mut self, k: usize, r: usize, delta: f64) {
        self.rows(k).apply(r, delta);
    }
}

/// The `i`-th of `colours` colours sweep `sweep` visits: `sweep_colours`' entry, or `i` where
/// it is empty (every order but the random coloured one).
#[inline(always)]
pub(super) fn colour_at(sweep_colours: &[usize], colours: usize, sweep: usize, i: usize) -> usize {
    if sweep_colours.is_empty() {
        i
    } else {
        sweep_colours[sweep * colours + i]
    }
}
