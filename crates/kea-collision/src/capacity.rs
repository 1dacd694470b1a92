//! Growing buffers ahead of time, so that a warm step allocates nothing.

/// Grows `v`'s capacity to hold at least `n` items in all (not `n` more).
pub(crate) fn reserve_total<T>(v: &mut Vec<T>, n: usize) {
    if v.capacity() < n {
        v.reserve(n - v.len());
    }
}
