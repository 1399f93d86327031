//! A PGS sweep: every contact visited once in the workspace's order, one at a time, four at a
//! time (a coloured sweep's groups), or on several threads colour by colour.
//! docs/contact.md §"PGS", §"Coloured order", §"Four contacts per lane".

use super::local::LocalSolve;
use super::pgs_lanes::LANES;
use super::pgs_residual::row_residual;
use super::pgs_rows::{CachedRows, LaneRows, Slot, lane_copies, write_back};
use super::pgs_settings::{ContactOrder, Lanes, PgsSettings};
use super::pgs_threads::share;
use super::pgs_visit::{solve_contact, solve_free_rows, visit_exactly};
use super::pgs_workspace::{PgsWorkspace, colour_at};
use super::sweep_entry::{Entry, Shared};
use crate::problem::{ContactProblem, RowBounds};
use nalgebra::SVector;
use rand::seq::SliceRandom;

impl<const D: usize, const R: usize> PgsWorkspace<D, R> {
    /// Coloured sweep number `sweep` of batch `batch` with the contacts four at a time: per
    /// colour (in the sweep's order of the colours) the batch's groups, then the rest of the
    /// batch's colour one at a time (docs/contact.md §"Four contacts per lane").
    pub(super) fn sweep_in_lanes(
        &mut self,
        problem: &ContactProblem<D, R>,
        batch: usize,
        sweep: usize,
        lambda: &mut [SVector<f64, R>],
    ) {
        let colours = self.colours();
        for i in 0..colours {
            let segment = batch * colours + self.colour_at(sweep, i);
            let (a, b) = (self.colour_starts[segment], self.colour_starts[segment + 1]);
            let grouped = super::pgs_lanes::grouped(b - a);
            let groups = &self.groups[self.group_starts[segment]..self.group_starts[segment + 1]];
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

    /// Runs the sweeps of a coloured solve on [`PgsWorkspace::set_threads`] threads, colour by
    /// colour with a barrier between colours (src/solve/pgs_threads.rs), four at a time where
    /// `lanes` (the groups laid out): at most `settings.max_iterations` sweeps, stopping at the
    /// tolerance. Returns the sweeps run and whether the tolerance was reached. Bit for bit the
    /// one-thread sweeps (docs/contact.md §"Coloured order"). The islands are not batched
    /// here: the threads meet after every colour of the whole problem.
    pub(super) fn sweep_in_threads(
        &mut self,
        problem: &ContactProblem<D, R>,
        settings: &PgsSettings,
        lanes: bool,
        lambda: &mut [SVector<f64, R>],
    ) -> (u32, bool) {
        debug_assert_eq!(self.batches, 1, "threads sweep the islands in one batch");
        let lanes_setting = self.lanes;
        let PgsWorkspace {
            entries,
            entry_contact,
            slot,
            order,
            colour_starts,
            moving,
            delta_velocity,
            threads,
            groups,
            group_starts,
            sweep_colours,
            ..
        } = self;
        let threads = *threads;
        let (bodies, contacts) = (delta_velocity.len(), lambda.len());
        let shared = Shared {
            delta_velocity: delta_velocity.as_mut_ptr(),
            lambda: lambda.as_mut_ptr(),
        };
        let (entries, order, moving, starts) = (&*entries, &*order, &*moving, &*colour_starts);
        let (slot, entry_contact) = (&*slot, &*entry_contact);
        let (groups, group_starts) = (&*groups, &*group_starts);
        let (sweep_colours, colours) = (&*sweep_colours, colour_starts.len().saturating_sub(1));
        let native = lanes_setting == Lanes::Native;
        // The closures take `shared` whole (a reference), not its pointer fields, which are
        // not Sync on their own.
        let shared = &shared;
        let visit = |position: usize| {
            // Contacts visited one at a time have their entry in `entries`.
            let k = order[position];
            let Slot::One(i) = slot[k] else {
                unreachable!("a contact in a group is visited with its group")
            };
            // SAFETY: see `Shared`: within a colour no other visit touches contact k's λ or
            // its moving bodies' Δu, and the threads meet at a barrier between colours.
            unsafe { visit_shared(problem, &entries[i], k, moving, shared, bodies, contacts) };
        };
        // Thread t's share of the sweep's i-th colour: a contiguous part of its groups and of
        // the rest (with four at a time), or of its contacts.
        let visit_share = |sweep: usize, i: usize, t: usize| {
            let colour = colour_at(sweep_colours, colours, sweep, i);
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
            let done =
                row_residual(problem.friction, groups, entries, entry_contact, dv, l) <= tolerance;
            reached.store(done, std::sync::atomic::Ordering::Relaxed);
            done
        };
        let iterations = super::pgs_threads::sweep_in_threads(
            settings.max_iterations,
            colours,
            threads,
            &visit_share,
            &after_sweep,
        );
        (
            iterations,
            reached.load(std::sync::atomic::Ordering::Relaxed),
        )
    }

    /// Sweep number `sweep` of batch `batch` on one thread: every contact of the batch
    /// visited once in the workspace's order (a fresh permutation first for the random order;
    /// colour by colour in the sweep's order of the colours for the random coloured order), a
    /// coloured order's groups four at a time where `lanes` (the groups laid out). Batch 0 is
    /// every contact where the islands are not batched (docs/contact.md §"Island by island").
    pub(super) fn sweep(
        &mut self,
        problem: &ContactProblem<D, R>,
        settings: &PgsSettings,
        batch: usize,
        sweep: usize,
        lanes: bool,
        lambda: &mut [SVector<f64, R>],
    ) {
        if settings.order == ContactOrder::Random {
            let PgsWorkspace { order, rng, .. } = &mut *self;
            order.shuffle(rng);
        }
        if lanes {
            self.sweep_in_lanes(problem, batch, sweep, lambda);
        } else if settings.order == ContactOrder::RandomColoured {
            for i in 0..self.colours() {
                let colour = self.colour_at(sweep, i);
                for position in self.segment(batch, colour) {
                    let k = self.order[position];
                    visit(problem, settings.local, self, k, &mut lambda[k]);
                }
            }
        } else {
            // The batch's colours in turn (problem order: every contact).
            let colours = self.colours();
            let positions = if settings.order.is_coloured() && colours > 0 {
                self.colour_starts[batch * colours]..self.colour_starts[(batch + 1) * colours]
            } else {
                0..problem.contacts.len()
            };
            for i in positions.clone() {
                let k = self.order[i];
                if i + 2 < positions.end {
                    self.prefetch(self.order[i + 2]);
                }
                visit(problem, settings.local, self, k, &mut lambda[k]);
            }
        }
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
    let law = workspace.law(k);
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
    let i = match workspace.slot[k] {
        Slot::One(i) => i,
        Slot::Lane(i) => {
            // A contact of a group visited on its own (shock propagation): a contact, not a
            // joint, between two different bodies, as every grouped contact is.
            let (group, lane) = (&workspace.groups[i / LANES], i % LANES);
            let mut rows = LaneRows {
                group,
                lane,
                delta_velocity: lane_copies(group, lane, &workspace.delta_velocity),
            };
            solve_contact(problem.friction, &law, &contact.lambda0, &mut rows, lambda);
            let copies = rows.delta_velocity;
            write_back(group, lane, &copies, &mut workspace.delta_velocity);
            return;
        }
    };
    if let Some(mut rows) = workspace.cached_rows(i) {
        let (bounds, lambda0) = (rows.entry.bounds, rows.entry.lambda0);
        match bounds {
            RowBounds::Free => solve_free_rows(&law, &mut rows, lambda),
            RowBounds::Contact => {
                solve_contact(problem.friction, &law, &lambda0, &mut rows, lambda)
            }
        }
        let copies = rows.delta_velocity;
        let bodies = workspace.entries[i].bodies;
        for s in 0..2 {
            if let Some(b) = bodies[s] {
                workspace.delta_velocity[b] = copies[s];
            }
        }
        return;
    }
    let mut rows = workspace.entry_rows(i);
    match contact.bounds {
        RowBounds::Free => solve_free_rows(&law, &mut rows, lambda),
        RowBounds::Contact => {
            solve_contact(problem.friction, &law, &contact.lambda0, &mut rows, lambda)
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
