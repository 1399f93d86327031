//! PGS sweeps in the coloured order on several threads (`threads: N`). docs/contact.md
//! §"Coloured order".
//!
//! The contacts of one colour share no moving body, so their visits are independent: each reads
//! and writes only its own bodies' Δu and its own λ. The threads split each colour into
//! contiguous parts, visit their part, and meet at a barrier before the next colour. Every
//! visit does the arithmetic the one-thread coloured sweep does on the same values, so the
//! result is bit for bit the same for any number of threads. A pinned body's Δu (shared by
//! contacts of one colour) is read but never written: it stays +0, as it does on one thread,
//! where adding M⁻¹Jᵀ δ = 0 leaves it +0.

use super::pgs::{CachedRows, Entry, PgsSettings};
use crate::problem::{ContactProblem, RowBounds};
use nalgebra::SVector;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The residual of (Δu, λ), m/s, for the tolerance's stop.
type Residual<'a, const D: usize, const R: usize> =
    dyn Fn(&[SVector<f64, D>], &[SVector<f64, R>]) -> f64 + Sync + 'a;

/// A barrier the threads spin at (a colour's visits take microseconds; an OS wait would cost
/// more than the work), yielding after a while so that a descheduled partner can run.
struct SpinBarrier {
    threads: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
}

impl SpinBarrier {
    fn new(threads: usize) -> Self {
        SpinBarrier {
            threads,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
        }
    }

    /// Returns once every thread has called it (for this generation). Everything a thread
    /// wrote before its call is visible to every thread after.
    fn wait(&self) {
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::Release);
            return;
        }
        let mut spins = 0u32;
        while self.generation.load(Ordering::Acquire) == generation {
            spins += 1;
            if spins < 4096 {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }
}

/// What the threads share: the bodies' Δu and the contacts' λ, written through raw pointers.
struct Shared<const D: usize, const R: usize> {
    delta_velocity: *mut SVector<f64, D>,
    lambda: *mut SVector<f64, R>,
}

// SAFETY: the pointers are written only at indices that one thread owns for the current colour
// (a contact's λ; its moving bodies' Δu, which no other contact of the colour touches); the
// barrier between colours orders every write before the next colour's reads.
unsafe impl<const D: usize, const R: usize> Sync for Shared<D, R> {}

/// The sweeps of a coloured solve on `threads` threads. `order` and `starts` are the colouring
/// ([`super::colour::colour_contacts`]), `entries` laid out in that order (entry i is contact
/// `order[i]`), `moving` which bodies may be written. Returns the
/// sweeps done and whether the tolerance stopped them.
#[allow(clippy::too_many_arguments)]
pub(super) fn sweep_in_threads<const D: usize, const R: usize>(
    problem: &ContactProblem<D, R>,
    settings: &PgsSettings,
    entries: &[Entry<D, R>],
    order: &[usize],
    starts: &[usize],
    moving: &[bool],
    delta_velocity: &mut [SVector<f64, D>],
    lambda: &mut [SVector<f64, R>],
    threads: usize,
    residual: &Residual<'_, D, R>,
) -> (u32, bool) {
    let shared = Shared {
        delta_velocity: delta_velocity.as_mut_ptr(),
        lambda: lambda.as_mut_ptr(),
    };
    let (bodies, contacts) = (delta_velocity.len(), lambda.len());
    let barrier = SpinBarrier::new(threads);
    let stop = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let converged = AtomicBool::new(false);
    let work = |t: usize| {
        for sweep in 0..settings.max_iterations {
            for colour in 0..starts.len() - 1 {
                let (a, b) = (starts[colour], starts[colour + 1]);
                let part = (a + (b - a) * t / threads)..(a + (b - a) * (t + 1) / threads);
                for i in part {
                    // The entries are laid out in visiting order: entry i is contact order[i].
                    let k = order[i];
                    // SAFETY: see `Shared`; k < contacts, its bodies < bodies.
                    unsafe {
                        visit_shared(problem, &entries[i], k, moving, &shared, bodies, contacts)
                    };
                }
                barrier.wait();
            }
            if t == 0 {
                done.store(sweep as usize + 1, Ordering::Relaxed);
                if let Some(tolerance) = settings.tolerance {
                    // SAFETY: every thread is at the barrier below; nothing writes meanwhile.
                    let (dv, l) = unsafe {
                        (
                            std::slice::from_raw_parts(shared.delta_velocity, bodies),
                            std::slice::from_raw_parts(shared.lambda, contacts),
                        )
                    };
                    if residual(dv, l) <= tolerance {
                        converged.store(true, Ordering::Relaxed);
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
            barrier.wait();
            if stop.load(Ordering::Relaxed) {
                break;
            }
        }
    };
    std::thread::scope(|s| {
        for t in 1..threads {
            let work = &work;
            s.spawn(move || work(t));
        }
        work(0);
    });
    (
        done.load(Ordering::Relaxed) as u32,
        converged.load(Ordering::Relaxed),
    )
}

/// One visit of contact `k` (row by row, as [`super::pgs::visit`] with [`CachedRows`]): copy
/// its bodies' Δu, update, write back the moving ones.
///
/// # Safety
/// No other thread reads or writes contact `k`'s λ or its moving bodies' Δu meanwhile, and
/// nothing writes a pinned body's Δu.
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
        RowBounds::Free => super::pgs::solve_free_rows(&entry.law, &mut rows, lambda),
        RowBounds::Contact => super::pgs::solve_contact(
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
