//! A cache hint for the hot loops that visit records out of order (the iterative path's
//! contact loaders, the collision layer's narrow phase): fetch a few records ahead.

/// Asks the processor to bring `x` into cache (a hint: nothing happens elsewhere than x86-64).
#[inline(always)]
pub fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        let p = (x as *const T).cast::<i8>();
        for line in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch never faults, and `p + line` stays inside `x`.
            unsafe {
                std::arch::x86_64::_mm_prefetch(p.add(line), std::arch::x86_64::_MM_HINT_T0);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}
