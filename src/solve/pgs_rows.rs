//! A contact's rows as a PGS visit reads and updates them, wherever its entry is kept: where that
//! is ([`Slot`]), and the views over the bodies' Δu the visits go through — borrowed
//! ([`BodyRows`]), copied into registers ([`CachedRows`]) or a lane of a group of four
//! ([`LaneRows`]); the workspace's `SlotRows` goes to either. Each view does the same arithmetic on the same
//! numbers, so every path gives the same bits. docs/contact.md §"PGS", §"Four contacts per lane".

use super::pgs_lanes::LaneGroup;
use super::pgs_visit::ContactRows;
use super::sweep_entry::Entry;
use nalgebra::SVector;

/// A contact of the body form with the bodies' Δu, borrowed apart.
pub(super) struct BodyRows<'a, const D: usize, const R: usize> {
    pub(super) entry: &'a Entry<D, R>,
    pub(super) delta_velocity: &'a mut [SVector<f64, D>],
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

/// Where a contact's entry is kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Slot {
    /// `entries[i]`, visited one at a time.
    One(usize),
    /// Lane `i % LANES` of `groups[i / LANES]`.
    Lane(usize),
}

/// A contact kept in a lane of a group, visited on its own (shock propagation, the warm start,
/// the residuals), with copies of its two sides' Δu (zeros for the static world): the
/// arithmetic of [`CachedRows`] on the same numbers, so the same bits.
pub(super) struct LaneRows<'a, const D: usize, const R: usize> {
    pub(super) group: &'a LaneGroup<D, R>,
    pub(super) lane: usize,
    pub(super) delta_velocity: [SVector<f64, D>; 2],
}

impl<const D: usize, const R: usize> ContactRows<R> for LaneRows<'_, D, R> {
    #[inline(always)]
    fn velocity(&self, r: usize) -> f64 {
        self.group.lane_velocity(self.lane, &self.delta_velocity, r)
    }
    #[inline(always)]
    fn apply(&mut self, r: usize, delta: f64) {
        self.group
            .lane_apply(self.lane, &mut self.delta_velocity, r, delta);
    }
}

/// Copies of the Δu of lane `lane`'s two sides (zeros for the static world).
#[inline(always)]
pub(super) fn lane_copies<const D: usize, const R: usize>(
    group: &LaneGroup<D, R>,
    lane: usize,
    delta_velocity: &[SVector<f64, D>],
) -> [SVector<f64, D>; 2] {
    let copy = |s: usize| {
        group
            .body(lane, s)
            .map_or(SVector::zeros(), |b| delta_velocity[b])
    };
    [copy(0), copy(1)]
}

/// Writes lane `lane`'s copies of its sides' Δu back (every side that is a body, as the
/// one-at-a-time visit with [`CachedRows`] does).
#[inline(always)]
pub(super) fn write_back<const D: usize, const R: usize>(
    group: &LaneGroup<D, R>,
    lane: usize,
    copies: &[SVector<f64, D>; 2],
    delta_velocity: &mut [SVector<f64, D>],
) {
    for s in 0..2 {
        if let Some(b) = group.body(lane, s) {
            delta_velocity[b] = copies[s];
        }
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
