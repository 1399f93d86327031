//! The stopwatch: wall and thread CPU time of a piece of work (the 2D step times its contact
//! solves with it; the scaling report re-times with it).

/// Runs `f` and returns its result with the wall time and the thread CPU time it took, s (the
/// CPU time `None` where the platform has no thread clock). Thread CPU time does not count the
/// time the thread was preempted by other processes on a shared machine.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, f64, Option<f64>) {
    let cpu_start = cpu_time::ThreadTime::try_now().ok();
    let wall_start = std::time::Instant::now();
    let value = f();
    let wall = wall_start.elapsed().as_secs_f64();
    let cpu = cpu_start
        .and_then(|t| t.try_elapsed().ok())
        .map(|d| d.as_secs_f64());
    (value, wall, cpu)
}
