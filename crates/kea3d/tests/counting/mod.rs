//! An allocator that counts allocations while asked to, for the tests that prove a warm step
//! allocates nothing. A test binary installs it (`#[global_allocator]`) and holds one test, so
//! nothing else steps beside it. Only the stepping thread (and, with threads, the pool's
//! workers) is counted: the test harness's own thread may allocate meanwhile (it waits on a
//! channel with a timer), and that is no step's.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The system allocator, counting allocations and reallocations while [`COUNTING`] is set.
pub struct CountingAllocator;

/// Whether allocations are being counted.
pub static COUNTING: AtomicBool = AtomicBool::new(false);
/// Allocations counted so far.
pub static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator; only counts on the side.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

thread_local! {
    /// Whether this thread steps the world under test.
    static STEPS_HERE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

fn count() {
    if COUNTING.load(Ordering::Relaxed) && (STEPS_HERE.with(std::cell::Cell::get) || on_pool()) {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

/// Whether this thread is one of rayon's workers (reading a thread-local, no allocation).
fn on_pool() -> bool {
    #[cfg(feature = "parallel")]
    return rayon::current_thread_index().is_some();
    #[cfg(not(feature = "parallel"))]
    false
}

/// The allocations `f` makes on this thread (and the pool's), counted from zero.
pub fn allocations_in(f: impl FnOnce()) -> usize {
    STEPS_HERE.with(|c| c.set(true));
    ALLOCATIONS.store(0, Ordering::SeqCst);
    COUNTING.store(true, Ordering::SeqCst);
    f();
    COUNTING.store(false, Ordering::SeqCst);
    ALLOCATIONS.load(Ordering::SeqCst)
}
