//! The hop onto the thread pool. With the `parallel` feature, a big step called from outside
//! rayon's pool moves onto one of its threads once, so that its parallel sections do not each
//! wait to be handed over (and rayon's fork-join inside a pool allocates nothing). Without the
//! feature, or for a small world, or already inside the pool, it runs where it is called.
//! Work handed to the pool's threads flushes subnormals there as the step does
//! ([`crate::float_mode`]), so the bits do not depend on which thread did it.

#[cfg(feature = "parallel")]
use crate::float_mode::FlushSubnormals;

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

/// `out[i] = f(i, &mut items[i])` for every item: side by side on the pool when the caller is
/// already on it (a step that hopped, see [`on_pool`]) and there is more than one item, else
/// one after another. The items must share nothing `f` writes; either way each result is the
/// one `f` gives, so the bits do not depend on the thread count.
pub(crate) fn each_side_by_side<T: Send, R: Send>(
    items: &mut [T],
    out: &mut [R],
    f: impl Fn(usize, &mut T) -> R + Sync,
) {
    #[cfg(feature = "parallel")]
    if items.len() > 1 && rayon::current_thread_index().is_some() {
        use rayon::prelude::*;
        items
            .par_iter_mut()
            .zip(out.par_iter_mut())
            .enumerate()
            .for_each_init(FlushSubnormals::new, |_, (i, (item, o))| *o = f(i, item));
        return;
    }
    for (i, (item, o)) in items.iter_mut().zip(out.iter_mut()).enumerate() {
        *o = f(i, item);
    }
}
