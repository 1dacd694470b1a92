//! A slice whose elements several threads write, each its own.

use std::cell::UnsafeCell;

/// A view of a slice through which each element is written by one thread only (the caller's
/// promise, checked where it is made): the contact solver's write-back, where every contact
/// belongs to one lane of one batch.
pub(crate) struct Disjoint<'a, T> {
    items: &'a [UnsafeCell<T>],
}

// SAFETY: elements are only reached through `Disjoint::with`, whose callers never reach one
// element from two threads (type docs); `T: Send` lets an element be written from any thread.
unsafe impl<T: Send> Sync for Disjoint<'_, T> {}

impl<'a, T> Disjoint<'a, T> {
    /// A view of `items` for as long as they are borrowed.
    pub(crate) fn new(items: &'a mut [T]) -> Self {
        // SAFETY: `UnsafeCell<T>` has the layout of `T`, and the exclusive borrow makes this
        // view the only way to reach the items while it lives (as `Cell::from_mut`).
        let items = unsafe { &*(items as *mut [T] as *const [UnsafeCell<T>]) };
        Self { items }
    }

    /// Runs `f` on element `i`, if there is one.
    ///
    /// # Safety
    /// No other call may reach element `i` while this one runs.
    #[inline(always)]
    pub(crate) unsafe fn with<R>(&self, i: usize, f: impl FnOnce(&mut T) -> R) -> Option<R> {
        // SAFETY: the caller promises that element `i` is reached by this call alone.
        self.items.get(i).map(|c| f(unsafe { &mut *c.get() }))
    }
}
