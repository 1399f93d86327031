//! Asking the processor to start loading data a loop will read shortly: the set-up's entries in
//! a random order (`pgs_workspace`) and the groups a sweep visits next (`pgs_lanes`). Only
//! hints: they read nothing into the program and change no value. docs/contact.md §"Four
//! contacts per lane", "Loaded ahead".

/// Asks the processor to start loading `value`'s bytes into the first-level cache, a cache line
/// at a time (x86-64; elsewhere nothing). Only a hint: it reads nothing into the program and
/// changes no value.
#[inline(always)]
pub(super) fn prefetch_object<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        let p = value as *const T as *const i8;
        for offset in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch never faults and reads nothing into the program; the
            // addresses are inside `value`.
            unsafe {
                std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                    p.wrapping_add(offset),
                )
            };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
