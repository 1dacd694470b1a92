//! The hop onto the thread pool. With the `parallel` feature, a big step called from outside
//! rayon's pool moves onto one of its threads once, so that its parallel sections do not each
//! wait to be handed over (and rayon's fork-join inside a pool allocates nothing). Without the
//! feature, or for a small world, or already inside the pool, it runs where it is called.

/// With the `parallel` feature, the count of awake bodies from which a step called from outside
/// rayon's pool moves onto one of its threads: handing a step over costs tens of microseconds, which
/// a smaller world does not win back (its work is too small to split anyway).
pub const PARALLEL_MIN_BODIES: usize = 256;

/// Runs `step` (the step of a world of `bodies` awake bodies) on the pool when that pays (module
/// docs), else here. Whoever owns the whole step calls this once; the layers inside see that
/// they are on the pool and stay there.
pub fn on_pool<R: Send>(bodies: usize, step: impl FnOnce() -> R + Send) -> R {
    #[cfg(feature = "parallel")]
    if rayon::current_thread_index().is_none() && bodies >= PARALLEL_MIN_BODIES {
        return rayon::join(step, || ()).0;
    }
    let _ = bodies;
    step()
}
