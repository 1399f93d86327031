//! What a PGS solve keeps from solve to solve, and its set-up: each contact's entry (what a
//! sweep reads) and row scales, built once, in problem order, and written where the visiting
//! order reads it: as a lane of a group of four where a coloured sweep takes four at a time and
//! as a one-contact entry elsewhere; the warm start, applied as the entries are built; the coloured
//! order's colours; the bodies' Δu; the seeded generator of the random orders.
//! docs/contact.md §"PGS", §"Coloured order", §"Four contacts per lane". A contact's entry is
//! built by `pgs_setup.rs`; the views a visit reads it through are in `pgs_rows.rs`.

use super::pgs_lanes::{LANES, LaneGroup, grouped};
use super::pgs_rows::{BodyRows, CachedRows, LaneRows, Slot, lane_copies, write_back};
use super::pgs_settings::{ContactOrder, Lanes};
use super::pgs_setup::build_entry;
use super::pgs_visit::ContactRows;
use super::prefetch::prefetch_object;
use super::projection::project_feasible;
use super::residual::RowScales;
use super::sweep_entry::{Entry, RowLaw};
use crate::problem::{ContactProblem, RowBounds};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// The most contacts a batch of islands takes by default ([`PgsWorkspace::set_batch_contacts`]):
/// about 1.2 MB of groups in 3D (568 bytes a contact), so that a batch's groups, its bodies' Δu
/// and its λ stay in a 2 MB second-level cache over its sweeps (docs/contact.md §"Island by
/// island").
pub const BATCH_CONTACTS: usize = 2048;

/// Buffers PGS reuses from solve to solve, so that a solve does not allocate once they have
/// grown to the problem's size; also the random generator, so a run's orders are reproducible.
#[derive(Clone, Debug)]
pub struct PgsWorkspace<const D: usize, const R: usize> {
    /// Δu per body: the velocity change the current λ causes.
    pub(super) delta_velocity: Vec<SVector<f64, D>>,
    /// What a sweep reads of the contacts it visits one at a time, in visiting order (every
    /// contact where the sweeps go one at a time; else the rest of each segment, a batch's
    /// colour, after its groups); `entry_contact[i]` is entry i's contact.
    pub(super) entries: Vec<Entry<D, R>>,
    pub(super) entry_contact: Vec<usize>,
    /// Row scales per contact (the full block, for the exact local solve and the residuals).
    pub(super) scales: Vec<RowScales<R>>,
    /// The visiting order.
    pub(super) order: Vec<usize>,
    /// Where each contact's entry is: in `entries` or in a lane of `groups`.
    pub(super) slot: Vec<Slot>,
    /// With the coloured order: where each segment starts in `order` (the end appended),
    /// segment `b · colours + c` holding batch b's contacts of colour c (one batch where the
    /// islands are not batched, so that the segments are the colours), and the colouring's
    /// scratch.
    pub(super) colour_starts: Vec<usize>,
    pub(super) colour_masks: Vec<u64>,
    pub(super) colour_of: Vec<usize>,
    /// The batches of whole islands the last solve swept one after another (1: all the
    /// contacts at once; docs/contact.md §"Island by island").
    pub(super) batches: usize,
    /// The most contacts a batch of islands takes ([`PgsWorkspace::set_batch_contacts`]);
    /// `None`: the islands are not batched.
    pub(super) batch_contacts: Option<usize>,
    /// The batching's scratch: per body its island's parent, its island's contacts and its
    /// island's batch; per contact its batch.
    pub(super) island_parent: Vec<usize>,
    pub(super) island_size: Vec<usize>,
    pub(super) island_batch: Vec<usize>,
    pub(super) batch_of: Vec<usize>,
    /// Per body: whether its inverse mass is not zero (a pinned body's Δu never changes).
    pub(super) moving: Vec<bool>,
    /// Threads a coloured sweep runs on ([`PgsWorkspace::set_threads`]; 1 by default).
    pub(super) threads: usize,
    /// Threads the last solve's sweeps ran on.
    pub(super) last_threads: usize,
    /// Whether a coloured sweep, row by row, takes its colours' contacts four at a time
    /// ([`PgsWorkspace::set_lanes`]; natively by default).
    pub(super) lanes: Lanes,
    /// With four contacts at a time: the groups, segment by segment (a batch's colour; see
    /// `colour_starts`), segment s's being `groups[group_starts[s]..group_starts[s + 1]]`,
    /// each holding the entries of its four contacts (built there, not copied from `entries`);
    /// empty when the last solve went one contact at a time.
    pub(super) groups: Vec<LaneGroup<D, R>>,
    pub(super) group_starts: Vec<usize>,
    pub(super) rng: ChaCha8Rng,
    /// With the random coloured order: the random permutation of the contacts the solve's
    /// colouring takes them in, and each sweep's order of the colours (sweep s's being
    /// `sweep_colours[s * colours..(s + 1) * colours]`); empty otherwise.
    pub(super) shuffled: Vec<usize>,
    pub(super) sweep_colours: Vec<usize>,
    /// Per contact: whether both sides' M_s⁻¹ J_sᵀ, as the set-up built them, are finite (then
    /// a zero warm start moves no Δu and is skipped: [`moves_nothing`]).
    pub(super) finite_columns: Vec<bool>,
    /// Whether the warm start skips the contacts whose start moves nothing (on by default;
    /// [`PgsWorkspace::set_zero_starts_skipped`]).
    pub(super) skip_zero_starts: bool,
    /// With a coloured order: each contact's two bodies gathered in problem order once per
    /// solve, so that the colouring (which, in the random coloured order, takes the contacts in
    /// a random order) and the batching of islands read them from a small array instead of
    /// from all over the problem.
    pub(super) contact_bodies: Vec<[Option<usize>; 2]>,
    /// Exact visits of the current solve that took the local solve's best candidate because no
    /// case was exact to round-off ([`super::local::solve_local`]).
    pub(super) local_fallbacks: u32,
}

/// A contact's rows wherever its entry is, with the bodies' Δu (the exact local solve's and the
/// warm start's visits): one-at-a-time entries as [`BodyRows`], lanes as [`LaneRows`] with their
/// copies written back after each update.
pub(super) struct SlotRows<'a, const D: usize, const R: usize> {
    workspace: &'a mut PgsWorkspace<D, R>,
    k: usize,
}

impl<const D: usize, const R: usize> ContactRows<R> for SlotRows<'_, D, R> {
    fn velocity(&self, r: usize) -> f64 {
        self.workspace.row_velocity(self.k, r)
    }
    fn apply(&mut self, r: usize, delta: f64) {
        let ws = &mut *self.workspace;
        match ws.slot[self.k] {
            Slot::One(i) => ws.entries[i].apply(&mut ws.delta_velocity, r, delta),
            Slot::Lane(i) => {
                let (group, lane) = (&ws.groups[i / LANES], i % LANES);
                let mut rows = LaneRows {
                    group,
                    lane,
                    delta_velocity: lane_copies(group, lane, &ws.delta_velocity),
                };
                rows.apply(r, delta);
                write_back(group, lane, &rows.delta_velocity, &mut ws.delta_velocity);
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
            entry_contact: Vec::new(),
            scales: Vec::new(),
            order: Vec::new(),
            slot: Vec::new(),
            colour_starts: Vec::new(),
            colour_masks: Vec::new(),
            colour_of: Vec::new(),
            batches: 1,
            batch_contacts: Some(BATCH_CONTACTS),
            island_parent: Vec::new(),
            island_size: Vec::new(),
            island_batch: Vec::new(),
            batch_of: Vec::new(),
            moving: Vec::new(),
            threads: 1,
            last_threads: 1,
            lanes: Lanes::Native,
            groups: Vec::new(),
            group_starts: Vec::new(),
            rng: ChaCha8Rng::seed_from_u64(seed),
            shuffled: Vec::new(),
            sweep_colours: Vec::new(),
            finite_columns: Vec::new(),
            skip_zero_starts: true,
            contact_bodies: Vec::new(),
            local_fallbacks: 0,
        }
    }

    /// Continues the seeded random orders of `other` (a workspace of the same bodies with
    /// another row count): the next solve draws what `other`'s next solve would have drawn.
    /// Post-stabilisation hands the generator over when it changes between its full and its
    /// normal-rows workspace (docs/blocks2d.md §"Post-stabilisation", "Normal rows only").
    pub fn continue_orders_of<const R2: usize>(&mut self, other: &PgsWorkspace<D, R2>) {
        self.rng.clone_from(&other.rng);
    }

    /// Δu of body `i` after the last solve: add it to the body's velocity.
    pub fn delta_velocity(&self, i: usize) -> &SVector<f64, D> {
        &self.delta_velocity[i]
    }

    /// Builds the entries for `problem`, once, where the sweeps read them, and applies the warm
    /// start. With a coloured order the contacts are coloured first and the entries laid out in
    /// visiting order: with `lanes`, each segment's (a colour, or a batch's colour) first
    /// ⌊n / 4⌋ × 4 contacts in its groups of four, lane by lane, and the rest of the segment in
    /// `entries`; else all in `entries`.
    /// Otherwise in problem order. `slot[k]` is contact k's place.
    ///
    /// The entries are then built in problem order, each written to its place (the problem is
    /// read front to back), and each contact's start applied as its entry is built: λ₀
    /// projected onto its feasible set into `lambda`, then Δu_s += (M_s⁻¹ J_sᵀ)_r λ₀,r row by row
    /// with the entry's own M⁻¹Jᵀ (docs/contact.md §"Warm starting": problem order, so the same
    /// sums as a warm start applied after the set-up), except a start that moves nothing
    /// ([`moves_nothing`]).
    ///
    /// With `batched` (a coloured order, every sweep run, `threads` 1), batching on
    /// ([`Self::set_batch_contacts`]) and more contacts than a batch takes, each colour is
    /// split by batch of islands ([`Self::batch_islands`]), for sweeps that go batch by batch.
    ///
    /// Returns whether the sweeps take four contacts at a time: `lanes`, unless a body's M⁻¹ is
    /// not a rigid body's, so that the groups cannot hold its contacts' M⁻¹Jᵀ
    /// ([`LaneGroup::set_lane`]); then every contact is laid out one at a time and the entries
    /// are built again.
    pub(super) fn prepare(
        &mut self,
        problem: &ContactProblem<D, R>,
        order: ContactOrder,
        lanes: bool,
        batched: bool,
        lambda: &mut Vec<SVector<f64, R>>,
    ) -> bool {
        self.entry_contact.clear();
        self.order.clear();
        self.colour_starts.clear();
        self.sweep_colours.clear();
        self.group_starts.clear();
        self.local_fallbacks = 0;
        self.batches = 1;
        let count = problem.contacts.len();
        if order.is_coloured() {
            self.colour(problem, order);
            // More contacts than a batch takes, or the islands make one batch anyway.
            if let (true, Some(budget)) = (batched, self.batch_contacts)
                && count > budget
            {
                self.batch_islands(budget);
            }
        } else {
            self.order.extend(0..count);
        }
        // Every contact's scales, slot and finite_columns are written below (each contact is
        // in the order once), so the last solve's are left in place rather than cleared: only
        // the length changes.
        self.scales
            .resize(count, RowScales::of_block(SMatrix::zeros()));
        self.slot.resize(count, Slot::One(0));
        self.finite_columns.resize(count, false);
        self.lay_out(lanes);
        if self.build(problem, lambda) || !lanes {
            return lanes;
        }
        self.entry_contact.clear();
        self.group_starts.clear();
        self.lay_out(false);
        self.build(problem, lambda);
        false
    }

    /// The entries built where [`Self::lay_out`] placed them, in problem order, and the warm
    /// start applied as they are (see [`Self::prepare`]), Δu and `lambda` from the start.
    /// Returns whether every lane holds its contact's entry whole ([`LaneGroup::set_lane`]).
    fn build(&mut self, problem: &ContactProblem<D, R>, lambda: &mut Vec<SVector<f64, R>>) -> bool {
        let skip_zero_starts = self.skip_zero_starts;
        let PgsWorkspace {
            entries,
            scales,
            slot,
            moving,
            groups,
            finite_columns,
            delta_velocity,
            ..
        } = self;
        delta_velocity.clear();
        delta_velocity.resize(problem.bodies.len(), SVector::zeros());
        lambda.clear();
        let mut whole = true;
        for (k, c) in problem.contacts.iter().enumerate() {
            let entry = build_entry(problem, k, &mut scales[k]);
            finite_columns[k] = columns_finite(&entry);
            let start = match c.bounds {
                RowBounds::Contact => project_feasible(&c.lambda0, c.mu, problem.friction),
                RowBounds::Free => c.lambda0,
            };
            lambda.push(start);
            if !moves_nothing(skip_zero_starts, finite_columns[k], &start) {
                for r in 0..R {
                    entry.apply(delta_velocity, r, start[r]);
                }
            }
            match slot[k] {
                Slot::One(i) => entries[i] = entry,
                Slot::Lane(i) => {
                    let inverse_mass = |s: usize| {
                        c.bodies[s].map_or(0.0, |b| problem.bodies[b].inverse_mass[(0, 0)])
                    };
                    whole &= groups[i / LANES].set_lane(
                        i % LANES,
                        k,
                        &entry,
                        moving,
                        [inverse_mass(0), inverse_mass(1)],
                    );
                }
            }
        }
        whole
    }

    /// Each contact's place in visiting order (`slot`, `entry_contact`, the groups' extent;
    /// see [`Self::prepare`]), the entries not yet built. `entries` and `groups` keep the last
    /// solve's where there are as many (each is written whole by `prepare`), so that a solve
    /// neither clears nor zeroes them again: about 2.3 kB per group of four in 3D.
    fn lay_out(&mut self, lanes: bool) {
        let PgsWorkspace {
            entries,
            entry_contact,
            order,
            slot,
            colour_starts,
            groups,
            group_starts,
            ..
        } = self;
        if !lanes {
            groups.clear();
            for (position, &k) in order.iter().enumerate() {
                slot[k] = Slot::One(position);
                entry_contact.push(k);
            }
        } else {
            let mut used = 0;
            group_starts.push(0);
            for colour in colour_starts.windows(2) {
                let (a, b) = (colour[0], colour[1]);
                let in_groups = a + grouped(b - a);
                for position in a..b {
                    let k = order[position];
                    if position < in_groups {
                        let lane = (position - a) % LANES;
                        if lane == 0 {
                            if used == groups.len() {
                                groups.push(LaneGroup::empty());
                            }
                            used += 1;
                        }
                        slot[k] = Slot::Lane((used - 1) * LANES + lane);
                    } else {
                        slot[k] = Slot::One(entry_contact.len());
                        entry_contact.push(k);
                    }
                }
                group_starts.push(used);
            }
            groups.truncate(used);
        }
        // Places for the one-at-a-time entries; new ones hold a placeholder until `prepare`
        // writes them.
        let ones = entry_contact.len();
        entries.truncate(ones);
        if entries.len() < ones {
            entries.resize(ones, Entry::placeholder());
        }
    }

    /// Contact `k`'s constants as a visit reads them.
    #[inline(always)]
    pub(super) fn law(&self, k: usize) -> RowLaw<R> {
        match self.slot[k] {
            Slot::One(i) => self.entries[i].law,
            Slot::Lane(i) => self.groups[i / LANES].law(i % LANES),
        }
    }

    /// M_s⁻¹ J_sᵀ of contact `k`.
    pub(super) fn inverse_mass_jacobian_t(&self, k: usize, s: usize) -> SMatrix<f64, D, R> {
        match self.slot[k] {
            Slot::One(i) => self.entries[i].inverse_mass_jacobian_t[s],
            Slot::Lane(i) => self.groups[i / LANES].inverse_mass_jacobian_t(i % LANES, s),
        }
    }

    /// Holds side `s` of contact `k` fixed (shock propagation): its M_s⁻¹ J_sᵀ set to zero, so
    /// that a visit does not move it.
    pub(super) fn hold_side_fixed(&mut self, k: usize, s: usize) {
        match self.slot[k] {
            Slot::One(i) => self.entries[i].inverse_mass_jacobian_t[s] = SMatrix::zeros(),
            Slot::Lane(i) => self.groups[i / LANES].hold_side_fixed(i % LANES, s),
        }
    }

    /// Sets contact `k`'s row scales (shock propagation: those of its free sides).
    pub(super) fn set_scales(&mut self, k: usize, scales: RowScales<R>) {
        match self.slot[k] {
            Slot::One(i) => {
                self.entries[i].law.diagonal = scales.diagonal;
                self.entries[i].law.tangent_rho = scales.tangent_rho;
            }
            Slot::Lane(i) => {
                self.groups[i / LANES].set_scales(i % LANES, &scales.diagonal, scales.tangent_rho)
            }
        }
        self.scales[k] = scales;
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
            contact_bodies,
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
        contact_bodies.clear();
        contact_bodies.extend(problem.contacts.iter().map(|c| c.bodies));
        let contact_bodies = &*contact_bodies;
        super::colour::colour_contacts_in(
            count,
            |i| shuffled[i],
            |k| contact_bodies[k],
            moving,
            colour_masks,
            colour_of,
            order,
            colour_starts,
        );
    }

    /// Splits each colour of the coloured order into batches of whole islands of at most
    /// `budget` contacts each (an island larger is a batch of its own; src/solve/islands.rs):
    /// `order` batch by batch, colour by colour within a batch, problem order within a colour.
    /// Where the islands make one batch, the order is left as the colouring wrote it.
    fn batch_islands(&mut self, budget: usize) {
        let PgsWorkspace {
            order,
            colour_starts,
            colour_of,
            moving,
            contact_bodies,
            island_parent,
            island_size,
            island_batch,
            batch_of,
            batches,
            ..
        } = self;
        *batches = super::islands::batch_islands(
            colour_of.len(),
            |k| contact_bodies[k],
            moving,
            budget,
            island_parent,
            island_size,
            island_batch,
            batch_of,
        );
        if *batches == 1 {
            return;
        }
        let colours = colour_starts.len() - 1;
        for (c, &b) in colour_of.iter_mut().zip(batch_of.iter()) {
            *c += b * colours;
        }
        super::colour::sort_by_key(colour_of, *batches * colours, order, colour_starts);
    }

    /// The contacts of batch `batch`'s colour `colour`: a range of `order`.
    #[inline(always)]
    pub(super) fn segment(&self, batch: usize, colour: usize) -> std::ops::Range<usize> {
        let s = batch * self.colours() + colour;
        self.colour_starts[s]..self.colour_starts[s + 1]
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
    /// drawn afresh each sweep). Where the sweeps went batch by batch of islands, a colour
    /// lists its contacts of every batch, in problem order (each batch visits its own in that
    /// order, and two batches share nothing a visit reads: docs/contact.md §"Island by
    /// island"). For checking an order, not for a hot loop: it allocates.
    pub fn sweep_colours(&self, sweep: usize) -> Vec<Vec<usize>> {
        if self.colour_starts.is_empty() {
            return vec![self.order.clone()];
        }
        (0..self.colours())
            .map(|i| {
                let c = self.colour_at(sweep, i);
                let mut colour: Vec<usize> = (0..self.batches)
                    .flat_map(|b| self.order[self.segment(b, c)].iter().copied())
                    .collect();
                if self.batches > 1 {
                    colour.sort_unstable();
                }
                colour
            })
            .collect()
    }

    /// Whether and how a coloured solve that runs every sweep (no tolerance) on one thread
    /// goes island by island: in batches of whole islands of at most `contacts` contacts each,
    /// every sweep of a batch before the next batch (an island larger is a batch of its own);
    /// `None`: all the contacts every sweep. The same bits either way (docs/contact.md
    /// §"Island by island"); [`BATCH_CONTACTS`] by default.
    pub fn set_batch_contacts(&mut self, contacts: Option<usize>) {
        self.batch_contacts = contacts.map(|n| n.max(1));
    }

    /// The batches of islands the last solve swept one after another (1 unless it went island
    /// by island).
    pub fn last_batches(&self) -> usize {
        self.batches
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

    /// Whether the warm start skips the contacts whose start λ is zero (±0 in every row) and
    /// whose M_s⁻¹ J_sᵀ are finite: Δu_s += (M_s⁻¹ J_sᵀ)_r · (±0) adds ±0 to a Δu that is never
    /// −0 (it starts at +0, and a sum is −0 only when both terms are), which changes no bit, so
    /// skipping them gives the same bits (docs/contact.md §"Warm start", "Zero starts
    /// skipped"). On by default; off to compare.
    pub fn set_zero_starts_skipped(&mut self, skip: bool) {
        self.skip_zero_starts = skip;
    }

    /// The groups of four the last solve's sweeps visited (0 when they went one at a time).
    pub fn last_groups(&self) -> usize {
        self.groups.len()
    }

    /// The number of colours of the last coloured solve.
    pub fn colours(&self) -> usize {
        self.colour_starts.len().saturating_sub(1) / self.batches
    }

    /// Asks the processor to start loading the entry of contact `k` (a visit two ahead, in a
    /// random order that its own prefetcher cannot guess). Only a hint: it changes no value.
    #[inline(always)]
    pub(super) fn prefetch(&self, k: usize) {
        if let Slot::One(i) = self.slot[k] {
            prefetch_object(&self.entries[i]);
        }
    }

    /// The rows of contact `k` with the bodies' Δu, wherever its entry is.
    #[inline(always)]
    pub(super) fn rows(&mut self, k: usize) -> SlotRows<'_, D, R> {
        SlotRows { workspace: self, k }
    }

    /// The rows of the one-at-a-time entry `i` with the bodies' Δu, borrowed apart.
    #[inline(always)]
    pub(super) fn entry_rows(&mut self, i: usize) -> BodyRows<'_, D, R> {
        BodyRows {
            entry: &self.entries[i],
            delta_velocity: &mut self.delta_velocity,
        }
    }

    /// Entry `i`'s rows with copies of its bodies' Δu (zeros for the static world), or `None`
    /// when both sides are the same body (then the copies would not see each other's writes).
    #[inline(always)]
    pub(super) fn cached_rows(&self, i: usize) -> Option<CachedRows<'_, D, R>> {
        let entry = &self.entries[i];
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
        match self.slot[k] {
            Slot::One(i) => self.entries[i].velocity(&self.delta_velocity, r),
            Slot::Lane(i) => {
                let (group, lane) = (&self.groups[i / LANES], i % LANES);
                group.lane_velocity(lane, &lane_copies(group, lane, &self.delta_velocity), r)
            }
        }
    }
}

/// Whether a contact's warm start `start` moves no Δu bit and is skipped: skipping on, its
/// M⁻¹Jᵀ finite, every row of the start ±0 (docs/contact.md §"Warm starting", "Zero starts
/// skipped").
#[inline(always)]
fn moves_nothing<const R: usize>(
    skip: bool,
    finite_columns: bool,
    start: &SVector<f64, R>,
) -> bool {
    skip && finite_columns && start.iter().all(|&x| x == 0.0)
}

/// Whether both sides' M_s⁻¹ J_sᵀ of `entry` are finite (the static world's side is zero).
#[inline(always)]
fn columns_finite<const D: usize, const R: usize>(entry: &Entry<D, R>) -> bool {
    entry
        .inverse_mass_jacobian_t
        .iter()
        .all(|m| m.iter().all(|x| x.is_finite()))
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
