//! The schedule of PGS sweeps in the coloured order on several threads (`threads: N`):
//! which thread visits which contacts, and the barriers between colours. docs/contact.md
//! §"Coloured order". The visits themselves are [`super::pgs_sweep`]'s (one contact) and
//! [`super::pgs_lanes`]'s (four, §"Four contacts per lane").
//!
//! The contacts of one colour share no moving body, so their visits are independent: each reads
//! and writes only its own bodies' Δu and its own λ. The threads split each colour into
//! contiguous parts, visit their part, and meet at a barrier before the next colour. Every
//! visit does the arithmetic the one-thread coloured sweep does on the same values, so the
//! result is bit for bit the same for any number of threads. A pinned body's Δu (shared by
//! contacts of one colour) is read but never written: it stays +0, as it does on one thread,
//! where adding M⁻¹Jᵀ δ = 0 leaves it +0.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

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

/// Runs up to `sweeps` sweeps on `threads` threads: in sweep s, for each i of `colours`
/// colours, thread t visits its share of the sweep's i-th colour with `visit(s, i, t)`
/// ([`share`] splits a range), and all
/// meet at a barrier before the next colour. After each sweep thread 0 calls `after_sweep`
/// while the others wait; it returns true to stop. Returns the sweeps done.
pub(super) fn sweep_in_threads(
    sweeps: u32,
    colours: usize,
    threads: usize,
    visit: &(dyn Fn(usize, usize, usize) + Sync),
    after_sweep: &(dyn Fn() -> bool + Sync),
) -> u32 {
    let barrier = SpinBarrier::new(threads);
    let stop = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let work = |t: usize| {
        for sweep in 0..sweeps {
            for i in 0..colours {
                visit(sweep as usize, i, t);
                barrier.wait();
            }
            if t == 0 {
                done.store(sweep as usize + 1, Ordering::Relaxed);
                if after_sweep() {
                    stop.store(true, Ordering::Relaxed);
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
    done.load(Ordering::Relaxed) as u32
}

/// Thread t's contiguous part of `range` when `threads` threads split it.
pub(super) fn share(
    range: std::ops::Range<usize>,
    t: usize,
    threads: usize,
) -> std::ops::Range<usize> {
    let (a, n) = (range.start, range.len());
    (a + n * t / threads)..(a + n * (t + 1) / threads)
}
