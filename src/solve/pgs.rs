//! Projected Gauss–Seidel with delta velocities (Erleben 2007). docs/contact.md §"PGS".
//!
//! Instead of the dense w = (A + C) λ + b, each body carries Δu = M⁻¹ Jᵀ λ, the velocity change
//! that the current impulses cause. A row's velocity is then w_r = b_r + J₁,r Δu₁ + J₂,r Δu₂
//! (+ c λn on the normal row), and a change δ of λ_r costs one update Δu_s += (M_s⁻¹ J_sᵀ)_r δ per
//! body. One sweep visits every contact once: the normal row first, then its friction rows with
//! bounds from the λn just computed. A joint's rows (free bounds) are visited in the same sweep,
//! each unbounded.

use super::local::{LocalSolve, solve_local};
use super::pgs_threads::share;
use super::projection::{positive_part, project_disk, project_feasible};
use super::residual::{
    RowScales, constraint_residual, contact_coulomb_residual, coulomb_scale, free_residual,
};
pub(super) use super::sweep_entry::{Entry, RowLaw, Shared};
use crate::problem::{ContactProblem, FrictionModel, RowBounds, SolveReport};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// The order in which a sweep visits the contacts.
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
pub enum ContactOrder {
    /// Problem order, every sweep: the contacts in the order detection found them (the
    /// assignment's). Also read as `found`.
    #[default]
    #[serde(alias = "found")]
    #[value(alias = "found")]
    Sequential,
    /// A fresh permutation every sweep from the workspace's seeded generator (ChaCha8).
    Random,
    /// Colour by colour: contacts grouped so that no two of a group share a moving body
    /// (deterministic: src/solve/colour.rs), problem order within a group; the same order every
    /// sweep. A group's contacts are independent, so they are visited four at a time where
    /// they can be, with the same bits. Different last bits from the problem order; the same
    /// bits on any number of threads. docs/contact.md §"Coloured order".
    Coloured,
}

/// The fewest contacts per thread and colour, on average, for which a coloured solve runs its
/// sweeps on several threads ([`PgsWorkspace::set_threads`]); smaller solves stay on one.
pub const MIN_CONTACTS_PER_THREAD: usize = 64;

/// The most contacts for which a coloured solve visits its colours' contacts four at a time
/// (docs/contact.md §"Four contacts per lane"). The groups are laid out from the entries at the
/// start of each solve, one more pass over every contact's data. Measured against one contact
/// at a time: PGS about 30 % faster at 926–2 292 contacts and 13–25 % at 7 168–9 178, equal at
/// 20 480–28 672, slower at 36 568 (37.6–42.5 → 49.4–51.0 ms) and 96 322 (118.5–119.5 →
/// 149.1–153.2 ms) (docs/performance.md §"Issue 33, fourth part"). Either way the result is the
/// same bits.
pub const MAX_CONTACTS_IN_GROUPS: usize = 16_384;

/// Whether and how a coloured sweep, row by row, visits its colours' contacts four at a time
/// (docs/contact.md §"Four contacts per lane"); the same bits in every case.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lanes {
    /// One contact at a time.
    Off,
    /// Four at a time, compiled for the baseline processor (two f64 per instruction on
    /// x86-64's SSE2).
    Portable,
    /// Four at a time, with the widest instructions the processor has (AVX2's four f64 per
    /// instruction where present, else as `Portable`). The default.
    #[default]
    Native,
}

/// How long PGS runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PgsSettings {
    /// Sweeps at most (`pgs_iterations`, default 100).
    pub max_iterations: u32,
    /// Stop as soon as the residual is at or below this (m/s); `None` runs every sweep.
    pub tolerance: Option<f64>,
    /// Contact order.
    pub order: ContactOrder,
    /// How a visit updates its contact: row by row (the assignment's) or the exact local solve.
    pub local: LocalSolve,
}

/// Buffers PGS reuses from solve to solve, so that a solve does not allocate once they have
/// grown to the problem's size; also the random generator, so a run's orders are reproducible.
#[derive(Clone, Debug)]
pub struct PgsWorkspace<const D: usize, const R: usize> {
    /// Δu per body: the velocity change the current λ causes.
    delta_velocity: Vec<SVector<f64, D>>,
    /// Per contact, what a sweep reads, in problem order.
    pub(super) entries: Vec<Entry<D, R>>,
    /// Row scales per contact (the full block, for the exact local solve and the residuals).
    pub(super) scales: Vec<RowScales<R>>,
    /// The visiting order.
    order: Vec<usize>,
    /// Where each contact's entry is in `entries` (the visiting order for the coloured order,
    /// else the problem order).
    slot: Vec<usize>,
    /// With the coloured order: where each colour starts in `order` (the end appended), and
    /// the colouring's scratch.
    colour_starts: Vec<usize>,
    colour_masks: Vec<u64>,
    colour_of: Vec<usize>,
    /// Per body: whether its inverse mass is not zero (a pinned body's Δu never changes).
    moving: Vec<bool>,
    /// Threads a coloured sweep runs on ([`PgsWorkspace::set_threads`]; 1 by default).
    threads: usize,
    /// Threads the last solve's sweeps ran on.
    last_threads: usize,
    /// Whether a coloured sweep, row by row, takes its colours' contacts four at a time
    /// ([`PgsWorkspace::set_lanes`]; natively by default).
    lanes: Lanes,
    /// With four contacts at a time: the groups, colour by colour, colour c's being
    /// `groups[group_starts[c]..group_starts[c + 1]]`; empty when the last solve went one
    /// contact at a time.
    groups: Vec<super::pgs_lanes::LaneGroup<D, R>>,
    group_starts: Vec<usize>,
    pub(super) rng: ChaCha8Rng,
    /// Exact visits of the current solve that took the local solve's best candidate because no
    /// case was exact to round-off ([`super::local::solve_local`]).
    local_fallbacks: u32,
}

/// One constraint's rows as a visit sees them: the current velocity of a row, and the update
/// a change of one row's impulse makes. The body form reads w through the bodies' Δu
/// ([`BodyRows`]); the local form through W ([`super::pgs_delassus`]). A visit is the same
/// code for both.
pub(super) trait ContactRows<const R: usize> {
    /// w_r without compliance, m/s.
    fn velocity(&self, r: usize) -> f64;
    /// λ_r changes by `delta` (N·s): update what [`Self::velocity`] reads.
    fn apply(&mut self, r: usize, delta: f64);
}

/// A contact of the body form with the bodies' Δu, borrowed apart.
struct BodyRows<'a, const D: usize, const R: usize> {
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
struct CachedRows<'a, const D: usize, const R: usize> {
    entry: &'a Entry<D, R>,
    delta_velocity: [SVector<f64, D>; 2],
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
            local_fallbacks: 0,
        }
    }

    /// Δu of body `i` after the last solve: add it to the body's velocity.
    pub fn delta_velocity(&self, i: usize) -> &SVector<f64, D> {
        &self.delta_velocity[i]
    }

    /// Builds the entries for `problem`. With the coloured order the contacts are coloured
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
        self.local_fallbacks = 0;
        let count = problem.contacts.len();
        if order == ContactOrder::Coloured {
            self.colour(problem);
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

    /// Puts the contacts in the coloured order ([`ContactOrder::Coloured`]): a body moves when
    /// its inverse mass is not zero.
    fn colour(&mut self, problem: &ContactProblem<D, R>) {
        let PgsWorkspace {
            order,
            colour_starts,
            colour_masks,
            colour_of,
            moving,
            ..
        } = self;
        moving.clear();
        moving.extend((problem.bodies.iter()).map(|b| b.inverse_mass.iter().any(|&m| m != 0.0)));
        super::colour::colour_contacts(
            problem.contacts.len(),
            |k| problem.contacts[k].bodies,
            moving,
            colour_masks,
            colour_of,
            order,
            colour_starts,
        );
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

    /// One coloured sweep with the contacts four at a time: per colour its groups, then the
    /// rest of the colour one at a time (docs/contact.md §"Four contacts per lane").
    fn sweep_in_lanes(&mut self, problem: &ContactProblem<D, R>, lambda: &mut [SVector<f64, R>]) {
        for colour in 0..self.colours() {
            let (a, b) = (self.colour_starts[colour], self.colour_starts[colour + 1]);
            let grouped = super::pgs_lanes::grouped(b - a);
            let groups = &self.groups[self.group_starts[colour]..self.group_starts[colour + 1]];
            let shared = Shared {
                delta_velocity: self.delta_velocity.as_mut_ptr(),
                lambda: lambda.as_mut_ptr(),
            };
            // SAFETY: the groups were laid out from this problem, whose bodies' Δu and
            // contacts' λ `shared` points at; nothing else runs meanwhile.
            unsafe {
                super::pgs_lanes::visit_groups(
                    problem.friction,
                    groups,
                    &shared,
                    self.lanes == Lanes::Native,
                )
            };
            for position in a + grouped..b {
                let k = self.order[position];
                visit(problem, LocalSolve::Rows, self, k, &mut lambda[k]);
            }
        }
    }

    /// The number of colours of the last coloured solve.
    pub fn colours(&self) -> usize {
        self.colour_starts.len().saturating_sub(1)
    }

    /// Asks the processor to start loading the entry of contact `k` (a visit two ahead, in a
    /// random order that its own prefetcher cannot guess). Only a hint: it changes no value.
    #[inline(always)]
    fn prefetch(&self, k: usize) {
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
    fn rows(&mut self, k: usize) -> BodyRows<'_, D, R> {
        BodyRows {
            entry: &self.entries[self.slot[k]],
            delta_velocity: &mut self.delta_velocity,
        }
    }

    /// Contact `k`'s rows with copies of its bodies' Δu (zeros for the static world), or `None`
    /// when both sides are the same body (then the copies would not see each other's writes).
    #[inline(always)]
    fn cached_rows(&self, k: usize) -> Option<CachedRows<'_, D, R>> {
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
    fn row_velocity(&self, k: usize, r: usize) -> f64 {
        self.entry(k).velocity(&self.delta_velocity, r)
    }

    /// Changes λ_r of contact `k` by `delta` and updates the bodies' Δu to match.
    fn apply(&mut self, k: usize, r: usize, delta: f64) {
        self.rows(k).apply(r, delta);
    }

    /// The full constraint velocity w of contact `k`, compliance included.
    fn contact_velocity(
        &self,
        problem: &ContactProblem<D, R>,
        k: usize,
        lambda: &SVector<f64, R>,
    ) -> SVector<f64, R> {
        let c = &problem.contacts[k];
        SVector::<f64, R>::from_fn(|r, _| self.row_velocity(k, r) + c.row_compliance(r) * lambda[r])
    }

    fn coulomb_residual(&self, problem: &ContactProblem<D, R>, lambda: &[SVector<f64, R>]) -> f64 {
        (0..problem.contacts.len())
            .map(|k| {
                let w = self.contact_velocity(problem, k, &lambda[k]);
                if problem.contacts[k].bounds == RowBounds::Free {
                    return free_residual(&w);
                }
                let rho = coulomb_scale(&self.scales[k]);
                contact_coulomb_residual(problem.contacts[k].mu, &lambda[k], &w, rho)
            })
            .fold(0.0, f64::max)
    }

    fn residual(&self, problem: &ContactProblem<D, R>, lambda: &[SVector<f64, R>]) -> f64 {
        row_residual(
            problem,
            &self.entries,
            &self.slot,
            &self.scales,
            &self.delta_velocity,
            lambda,
        )
    }
}

/// The residual (docs/contact.md §"Residual") of λ with the bodies' Δu, m/s: the largest row
/// term over all contacts.
pub(super) fn row_residual<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    entries: &[Entry<D, R>],
    slot: &[usize],
    scales: &[RowScales<R>],
    delta_velocity: &[SVector<f64, D>],
    lambda: &[SVector<f64, R>],
) -> f64 {
    (0..problem.contacts.len())
        .map(|k| {
            let c = &problem.contacts[k];
            let w = SVector::<f64, R>::from_fn(|r, _| {
                entries[slot[k]].velocity(delta_velocity, r) + c.row_compliance(r) * lambda[k][r]
            });
            constraint_residual(problem.friction, c.bounds, c.mu, &lambda[k], &w, &scales[k])
        })
        .fold(0.0, f64::max)
}

/// Solves `problem` by projected Gauss–Seidel, starting from each contact's `lambda0` (projected
/// onto its feasible set). On return `lambda` holds one impulse per contact (N·s) and
/// `workspace.delta_velocity(i)` each body's velocity change. docs/contact.md §"PGS".
pub fn solve_pgs<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &PgsSettings,
    workspace: &mut PgsWorkspace<D, R>,
    lambda: &mut Vec<SVector<f64, R>>,
) -> SolveReport {
    workspace.prepare(problem, settings.order);
    lambda.clear();
    for (k, c) in problem.contacts.iter().enumerate() {
        let start = match c.bounds {
            RowBounds::Contact => project_feasible(&c.lambda0, c.mu, problem.friction),
            RowBounds::Free => c.lambda0,
        };
        lambda.push(SVector::zeros());
        for r in 0..R {
            workspace.apply(k, r, start[r]);
        }
        lambda[k] = start;
    }

    let mut iterations = 0;
    let mut converged = false;
    // One pass over the entries for what the threads and the groups of four exclude: a contact
    // between a body and itself, and (groups only) a joint's free rows.
    let (self_contact, joint) = (workspace.entries.iter()).fold((false, false), |(s, j), e| {
        (
            s || (e.bodies[0].is_some() && e.bodies[0] == e.bodies[1]),
            j || e.bounds == RowBounds::Free,
        )
    });
    // Threads only where a colour gives each at least MIN_CONTACTS_PER_THREAD visits on
    // average: below that, starting them and meeting at every colour's barrier costs more than
    // the visits (the result is the same bits either way).
    let colours = workspace.colours().max(1);
    let threaded = settings.order == ContactOrder::Coloured
        && settings.local == LocalSolve::Rows
        && workspace.threads > 1
        && !self_contact
        && problem.contacts.len() >= MIN_CONTACTS_PER_THREAD * workspace.threads * colours;
    workspace.last_threads = if threaded { workspace.threads } else { 1 };
    let lanes = settings.order == ContactOrder::Coloured
        && settings.local == LocalSolve::Rows
        && workspace.lanes != Lanes::Off
        && !crate::common::faults::fault!(stale_friction_bound)
        && !self_contact
        && !joint
        && problem.contacts.len() <= MAX_CONTACTS_IN_GROUPS
        && super::pgs_lanes::dimensions_fit::<D, R>();
    workspace.groups.clear();
    if lanes {
        let PgsWorkspace {
            entries,
            order,
            colour_starts,
            moving,
            groups,
            group_starts,
            ..
        } = &mut *workspace;
        super::pgs_lanes::lay_out(entries, order, colour_starts, moving, groups, group_starts);
    }
    let workspace_lanes = workspace.lanes;
    if threaded {
        let PgsWorkspace {
            entries,
            slot,
            scales,
            order,
            colour_starts,
            moving,
            delta_velocity,
            threads,
            groups,
            group_starts,
            ..
        } = &mut *workspace;
        let threads = *threads;
        let (bodies, contacts) = (delta_velocity.len(), lambda.len());
        let shared = Shared {
            delta_velocity: delta_velocity.as_mut_ptr(),
            lambda: lambda.as_mut_ptr(),
        };
        let (entries, order, moving, starts) = (&*entries, &*order, &*moving, &*colour_starts);
        let (groups, group_starts) = (&*groups, &*group_starts);
        let native = workspace_lanes == Lanes::Native;
        // The closures take `shared` whole (a reference), not its pointer fields, which are
        // not Sync on their own.
        let shared = &shared;
        let visit = |position: usize| {
            // The entries are laid out in visiting order: entry `position` is contact
            // order[position].
            let k = order[position];
            // SAFETY: see `Shared`: within a colour no other visit touches contact k's λ or
            // its moving bodies' Δu, and the threads meet at a barrier between colours.
            unsafe {
                visit_shared(
                    problem,
                    &entries[position],
                    k,
                    moving,
                    shared,
                    bodies,
                    contacts,
                )
            };
        };
        // Thread t's share of colour c: a contiguous part of its groups and of the rest (with
        // four at a time), or of its contacts.
        let visit_share = |colour: usize, t: usize| {
            let (a, b) = (starts[colour], starts[colour + 1]);
            let mut rest = a..b;
            if lanes {
                let mine = share(group_starts[colour]..group_starts[colour + 1], t, threads);
                // SAFETY: as for `visit`; the groups were laid out from this problem.
                unsafe {
                    super::pgs_lanes::visit_groups(problem.friction, &groups[mine], shared, native)
                };
                rest = a + super::pgs_lanes::grouped(b - a)..b;
            }
            share(rest, t, threads).for_each(visit);
        };
        let reached = std::sync::atomic::AtomicBool::new(false);
        let after_sweep = || {
            let Some(tolerance) = settings.tolerance else {
                return false;
            };
            // SAFETY: every other thread waits at the barrier while thread 0 runs this.
            let (dv, l) = unsafe {
                (
                    std::slice::from_raw_parts(shared.delta_velocity, bodies),
                    std::slice::from_raw_parts(shared.lambda, contacts),
                )
            };
            let done = row_residual(problem, entries, slot, scales, dv, l) <= tolerance;
            reached.store(done, std::sync::atomic::Ordering::Relaxed);
            done
        };
        iterations = super::pgs_threads::sweep_in_threads(
            settings.max_iterations,
            colour_starts.len().saturating_sub(1),
            threads,
            &visit_share,
            &after_sweep,
        );
        converged = reached.load(std::sync::atomic::Ordering::Relaxed);
    }
    while !threaded && iterations < settings.max_iterations {
        if settings.order == ContactOrder::Random {
            let PgsWorkspace { order, rng, .. } = &mut *workspace;
            order.shuffle(rng);
        }
        if lanes {
            workspace.sweep_in_lanes(problem, lambda);
        } else {
            for i in 0..problem.contacts.len() {
                let k = workspace.order[i];
                if let Some(&next) = workspace.order.get(i + 2) {
                    workspace.prefetch(next);
                }
                visit(problem, settings.local, workspace, k, &mut lambda[k]);
            }
        }
        iterations += 1;
        if let Some(tolerance) = settings.tolerance
            && workspace.residual(problem, lambda) <= tolerance
        {
            converged = true;
            break;
        }
    }
    SolveReport {
        iterations,
        residual: workspace.residual(problem, lambda),
        converged,
        coulomb_residual: (problem.friction == FrictionModel::Cone)
            .then(|| workspace.coulomb_residual(problem, lambda)),
        method: crate::problem::SolveMethod::Pgs,
        local_fallbacks: workspace.local_fallbacks,
    }
}

/// One visit of entry `k`: the update its bounds and the local-solve setting call for.
pub(super) fn visit<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    local: LocalSolve,
    workspace: &mut PgsWorkspace<D, R>,
    k: usize,
    lambda: &mut SVector<f64, R>,
) {
    let contact = &problem.contacts[k];
    let law = workspace.entry(k).law;
    if local == LocalSolve::Exact {
        // q = w_now − A λ_now: the velocity the rest of the problem gives this constraint.
        let q =
            workspace.contact_velocity(problem, k, lambda) - workspace.scales[k].block * *lambda;
        let scales = workspace.scales[k];
        let exact = visit_exactly(
            problem.friction,
            contact.bounds,
            &scales,
            &law,
            &q,
            &mut workspace.rows(k),
            lambda,
        );
        if !exact {
            workspace.local_fallbacks += 1;
        }
        return;
    }
    if let Some(mut rows) = workspace.cached_rows(k) {
        let (bounds, lambda0) = (rows.entry.bounds, rows.entry.lambda0);
        match bounds {
            RowBounds::Free => solve_free_rows(&law, &mut rows, lambda),
            RowBounds::Contact => {
                solve_contact(problem.friction, &law, &lambda0, &mut rows, lambda)
            }
        }
        let copies = rows.delta_velocity;
        let bodies = workspace.entry(k).bodies;
        for s in 0..2 {
            if let Some(b) = bodies[s] {
                workspace.delta_velocity[b] = copies[s];
            }
        }
        return;
    }
    let mut rows = workspace.rows(k);
    match contact.bounds {
        RowBounds::Free => solve_free_rows(&law, &mut rows, lambda),
        RowBounds::Contact => {
            solve_contact(problem.friction, &law, &contact.lambda0, &mut rows, lambda)
        }
    }
}

/// One constraint's exact update: its own R × R problem, W_kk λ + q with q the velocity the
/// rest of the problem gives it, solved for the others' current impulses (docs/contact.md
/// §"Exact local solve"); a joint's block solved as a linear system, left as it is where the
/// block is singular (a joint no impulse can move). Returns false where the contact's solve
/// took its best candidate because no case was exact to round-off.
pub(super) fn visit_exactly<const R: usize>(
    friction: FrictionModel,
    bounds: RowBounds,
    scales: &RowScales<R>,
    law: &RowLaw<R>,
    q: &SVector<f64, R>,
    rows: &mut impl ContactRows<R>,
    lambda: &mut SVector<f64, R>,
) -> bool {
    let (solution, exact) = match bounds {
        RowBounds::Contact => solve_local(&scales.block, q, law.mu, friction, scales),
        RowBounds::Free => match super::local::solve_linear(&scales.block, &(-q)) {
            Some(solution) => (solution, true),
            None => return true,
        },
    };
    for r in 0..R {
        rows.apply(r, solution[r] - lambda[r]);
    }
    *lambda = solution;
    exact
}

/// One joint's Gauss–Seidel update: each row in turn, unbounded, λ_r ← λ_r − w_r / a_r
/// (docs/contact.md §"Row bounds").
#[inline(always)]
pub(super) fn solve_free_rows<const R: usize>(
    law: &RowLaw<R>,
    rows: &mut impl ContactRows<R>,
    lambda: &mut SVector<f64, R>,
) {
    let diagonal = law.diagonal;
    for r in 0..R {
        if diagonal[r] > 0.0 {
            let w_r = rows.velocity(r) + law.compliance * lambda[r];
            let delta = -w_r / diagonal[r];
            rows.apply(r, delta);
            lambda[r] += delta;
        }
    }
}

/// One contact's Gauss–Seidel update: normal row, then friction rows. `start` is the contact's
/// warm start (read only by the deliberate fault `stale_friction_bound`).
#[inline(always)]
pub(super) fn solve_contact<const R: usize>(
    friction: FrictionModel,
    law: &RowLaw<R>,
    start: &SVector<f64, R>,
    rows: &mut impl ContactRows<R>,
    lambda: &mut SVector<f64, R>,
) {
    let diagonal = &law.diagonal;

    // Normal row: λn ← max(0, λn − w_n / a_n); a row with a_n = 0 cannot move anything.
    if diagonal[0] > 0.0 {
        let w_n = rows.velocity(0) + law.compliance * lambda[0];
        let lambda_n = positive_part(lambda[0] - w_n / diagonal[0]);
        rows.apply(0, lambda_n - lambda[0]);
        lambda[0] = lambda_n;
    }

    // Friction rows, bounded by μ times the normal impulse just computed.
    let bound = if crate::common::faults::fault!(stale_friction_bound) {
        // The deliberate bug: the bound from the starting λn instead of the one just computed.
        law.mu * project_feasible(start, law.mu, friction)[0]
    } else {
        law.mu * lambda[0]
    };
    if bound == 0.0 {
        // μ λn = 0 (no friction, or no normal impulse): the friction rows' bounds are [0, 0] and
        // their projection is 0, whatever their velocities.
        for r in 1..R {
            if lambda[r] != 0.0 {
                rows.apply(r, -lambda[r]);
                lambda[r] = 0.0;
            }
        }
        return;
    }
    match friction {
        FrictionModel::Box => {
            for r in 1..R {
                if diagonal[r] > 0.0 {
                    let w_r = rows.velocity(r);
                    let lambda_r = (lambda[r] - w_r / diagonal[r]).clamp(-bound, bound);
                    rows.apply(r, lambda_r - lambda[r]);
                    lambda[r] = lambda_r;
                } else {
                    lambda[r] = lambda[r].clamp(-bound, bound);
                }
            }
        }
        FrictionModel::Cone => {
            // One projected-gradient step on the pair with the scalar step 1/ρ, then onto the
            // disk: a per-row step would converge to a point that is not the disk's solution.
            let rho = law.tangent_rho;
            let mut trial = *lambda;
            if rho > 0.0 {
                for r in 1..R {
                    trial[r] = lambda[r] - rows.velocity(r) / rho;
                }
            }
            let projected = project_disk(&trial, bound);
            for r in 1..R {
                rows.apply(r, projected[r] - lambda[r]);
                lambda[r] = projected[r];
            }
        }
    }
}

/// One visit of contact `k` on a thread (row by row, as [`visit`] with [`CachedRows`]): copy its
/// bodies' Δu, update, write back the moving ones. Every operation is the one-thread visit's,
/// on the same values, so the bits are the same.
///
/// # Safety
/// No other thread reads or writes contact `k`'s λ or its moving bodies' Δu meanwhile, and
/// nothing writes a pinned body's Δu; `k` < `contacts` and its bodies < `bodies`.
unsafe fn visit_shared<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    entry: &Entry<D, R>,
    k: usize,
    moving: &[bool],
    shared: &Shared<D, R>,
    bodies: usize,
    contacts: usize,
) {
    debug_assert!(k < contacts);
    let read = |s: usize| {
        entry.bodies[s].map_or(SVector::zeros(), |b| {
            debug_assert!(b < bodies);
            // SAFETY: the caller's contract.
            unsafe { *shared.delta_velocity.add(b) }
        })
    };
    let mut rows = CachedRows {
        entry,
        delta_velocity: [read(0), read(1)],
    };
    // SAFETY: the caller's contract.
    let lambda = unsafe { &mut *shared.lambda.add(k) };
    match entry.bounds {
        RowBounds::Free => solve_free_rows(&entry.law, &mut rows, lambda),
        RowBounds::Contact => solve_contact(
            problem.friction,
            &entry.law,
            &entry.lambda0,
            &mut rows,
            lambda,
        ),
    }
    for s in 0..2 {
        if let Some(b) = entry.bodies[s]
            && moving[b]
        {
            // SAFETY: the caller's contract.
            unsafe { *shared.delta_velocity.add(b) = rows.delta_velocity[s] };
        }
    }
}
