//! Subnormal numbers flushed to zero while a step runs, as Jolt does in its jobs.
//!
//! glam's SIMD types compute on four lanes. A `Vec3` read from a struct for a SIMD turn or
//! product is loaded as sixteen bytes: its fourth lane is whatever follows it, an id or a
//! count, whose bits read as a float are subnormal. That lane's result is thrown away, but
//! on x86 every multiply or divide that meets a subnormal operand takes a microcode assist
//! of a hundred cycles or more. Measured on a 2-core Intel Xeon (kea-bench, 32 ragdolls on
//! steps): 10.2 ms a step, 6.3 ms with subnormals flushed; the same holds wherever such
//! loads sit in a hot loop, and they cannot all be found by hand.
//!
//! [`FlushSubnormals`] sets the x86 control bits FTZ (results that would be subnormal are
//! zero) and DAZ (subnormal operands read as zero) for its lifetime and puts the caller's
//! bits back when dropped. The thrown-away lanes change nothing; a number that really falls
//! below `f32::MIN_POSITIVE` (1.2e-38) or `f64::MIN_POSITIVE` becomes zero, far below any
//! tolerance a step works to. Every thread that works on a step sets it, so the results do
//! not depend on the thread count. On other targets (Arm flushes subnormals at full speed
//! or its compilers keep the lanes clean) it does nothing.

/// The x86 MXCSR bits: flush to zero (15) and denormals are zero (6).
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
const FLUSH_BITS: u32 = 0x8040;

/// While alive, subnormal floats are read and written as zero on this thread (module docs);
/// dropping it restores the thread's mode. Cheap to make where the mode is already set.
#[must_use = "the mode lasts only while the guard lives"]
pub struct FlushSubnormals {
    /// The control word to put back, if this guard changed it.
    #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
    restore: Option<u32>,
}

impl FlushSubnormals {
    /// Flushes subnormals on this thread until the guard is dropped.
    #[inline]
    pub fn new() -> Self {
        #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
        {
            let now = csr::read();
            if now & FLUSH_BITS == FLUSH_BITS {
                return Self { restore: None };
            }
            csr::write(now | FLUSH_BITS);
            Self { restore: Some(now) }
        }
        #[cfg(not(any(target_arch = "x86_64", target_arch = "x86")))]
        Self {}
    }
}

impl Default for FlushSubnormals {
    fn default() -> Self {
        Self::new()
    }
}

impl Drop for FlushSubnormals {
    #[inline]
    fn drop(&mut self) {
        #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
        if let Some(old) = self.restore {
            csr::write(old);
        }
    }
}

/// Reading and writing the SSE control and status register.
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
mod csr {
    use core::arch::asm;

    #[inline]
    pub(super) fn read() -> u32 {
        let mut word: u32 = 0;
        // SAFETY: `stmxcsr` stores the 32-bit control word to the given, writable address.
        unsafe {
            asm!("stmxcsr [{}]", in(reg) &mut word, options(nostack, preserves_flags));
        }
        word
    }

    #[inline]
    pub(super) fn write(word: u32) {
        // SAFETY: `ldmxcsr` loads the control word from the given, readable address; the
        // word is one `read` returned with only the FTZ and DAZ bits changed, which no
        // reserved bit is.
        unsafe {
            asm!("ldmxcsr [{}]", in(reg) &word, options(nostack, readonly, preserves_flags));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subnormals_are_zero_while_the_guard_lives_and_not_after() {
        let tiny = std::hint::black_box(f32::MIN_POSITIVE);
        let half = std::hint::black_box(0.5_f32);
        let before = tiny * half;
        assert!(before > 0.0, "a subnormal result before the guard");
        {
            let _outer = FlushSubnormals::new();
            let _nested = FlushSubnormals::new();
            let during = std::hint::black_box(tiny) * std::hint::black_box(half);
            if cfg!(any(target_arch = "x86_64", target_arch = "x86")) {
                assert_eq!(during, 0.0, "flushed while the guard lives");
            }
        }
        let after = std::hint::black_box(tiny) * std::hint::black_box(half);
        assert_eq!(after.to_bits(), before.to_bits(), "the mode is put back");
    }
}
