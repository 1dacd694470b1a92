//! Body records shared by the lanes (and, with the `parallel` feature, the threads) of one
//! colour.
//!
//! The contact kernels read and write bodies as records of 8 reals. Within a colour no
//! writable body appears in two constraints, so the batches of a colour can run on several
//! threads at once: each writable record is touched by one lane of one batch only, and the
//! records several batches share (static and kinematic bodies) are only read. Handing each
//! thread a `&mut` slice of all the records would alias; [`Records`] instead hands out the
//! records behind a shared view with interior mutability, the way `Cell::from_mut` does.

use crate::math::Real;
use std::cell::UnsafeCell;

/// One record: 8 reals, mutable through a shared view.
type Record = UnsafeCell<[Real; 8]>;

/// A view of body records that the lanes of one colour read and write (module docs).
#[derive(Clone, Copy)]
pub(crate) struct Records<'a> {
    rows: &'a [Record],
}

// SAFETY: `Records` is only shared between the batches of one colour, which never write a
// record that another batch reads or writes (module docs); the records are plain reals.
unsafe impl Send for Records<'_> {}
// SAFETY: as above.
unsafe impl Sync for Records<'_> {}

impl<'a> Records<'a> {
    /// A view of `rows` for as long as they are borrowed.
    pub(crate) fn new(rows: &'a mut [[Real; 8]]) -> Self {
        // SAFETY: `UnsafeCell<T>` has the layout of `T`, and the exclusive borrow of `rows`
        // makes this view the only way to reach them while it lives (as `Cell::from_mut`).
        let rows = unsafe { &*(rows as *mut [[Real; 8]] as *const [Record]) };
        Self { rows }
    }

    /// Record `i` (bounds checked).
    #[inline(always)]
    pub(crate) fn get(&self, i: u32) -> [Real; 8] {
        // SAFETY: no other lane writes a record this lane reads (module docs).
        unsafe { *self.rows[i as usize].get() }
    }

    /// A pointer to record `i` for a 256-bit load (bounds checked).
    #[cfg_attr(any(feature = "f64", not(target_arch = "x86_64")), allow(dead_code))]
    #[inline(always)]
    pub(crate) fn ptr(&self, i: u32) -> *const Real {
        self.rows[i as usize].get().cast()
    }

    /// A pointer to record `i` for a 256-bit store (bounds checked).
    #[cfg_attr(any(feature = "f64", not(target_arch = "x86_64")), allow(dead_code))]
    #[inline(always)]
    pub(crate) fn ptr_mut(&self, i: u32) -> *mut Real {
        self.rows[i as usize].get().cast()
    }

    /// Overwrites record `i` (bounds checked).
    #[inline(always)]
    pub(crate) fn set(&self, i: u32, r: [Real; 8]) {
        // SAFETY: only the lane that owns a writable record writes it (module docs).
        unsafe { *self.rows[i as usize].get() = r }
    }
}
