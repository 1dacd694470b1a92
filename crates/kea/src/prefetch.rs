//! Cache prefetch hints for memory a coming step will read: a batch steps many small worlds
//! in turn, each cold in memory, and asks for the next world's buffers while it steps this
//! one ([`crate::World::prefetch`]). Hints only: nothing is read, no result changes, and on
//! targets without the instruction they do nothing.

/// Bytes of one slice asked for at most (the start of a long buffer is what a step of a
/// small world reads first).
const MAX_BYTES: usize = 16384;

/// Asks for the cache lines of `s` (its first 16 KB).
#[inline]
pub fn slice<T>(s: &[T]) {
    let bytes = std::mem::size_of_val(s).min(MAX_BYTES);
    let start = s.as_ptr().cast::<u8>();
    let mut offset = 0;
    while offset < bytes {
        // SAFETY: the address is inside `s` (offset < its size), and a prefetch reads nothing.
        line(unsafe { start.add(offset) });
        offset += 64;
    }
}

/// Asks for the cache lines of the first `len` bytes of `value` (at most its size): the
/// head of a struct that lays out first what a coming step reads.
#[inline]
pub fn head<T>(value: &T, len: usize) {
    let bytes = len.min(std::mem::size_of::<T>());
    let start = std::ptr::from_ref(value).cast::<u8>();
    let mut offset = 0;
    while offset < bytes {
        // SAFETY: the address is inside `value` (offset < its size); a prefetch reads nothing.
        line(unsafe { start.add(offset) });
        offset += 64;
    }
}

#[inline]
fn line(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: `_mm_prefetch` is a hint; it never faults or reads into the program.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
