//! Wide floats: the SIMD lanes the contact solver runs in.
//!
//! [`FloatW`] is a pack of `LANES` [`Real`]s with the few operations the contact kernels need
//! (add, subtract, multiply, divide, min, max, square root, compare and select). The kernels
//! are written once, generic over it, and instantiated for:
//!
//! | type | lanes (`f32` / `f64`) | instructions | used when |
//! |---|---|---|---|
//! | [`Real`] itself | 1 | scalar | overflow constraints; targets other than x86-64 |
//! | `Narrow` | 4 / 2 | SSE2 (part of every x86-64) | x86-64 without AVX2 |
//! | `Wide` | 8 / 4 | AVX2 (with FMA present) | chosen at run time when the CPU has both |
//!
//! The choice is made at run time ([`SimdLevel::detect`]), so the default build target serves
//! every x86-64 machine and no `target-cpu=native` is needed.
//!
//! **No fused multiply-add, on purpose.** Every lane performs the same IEEE operations in the
//! same order as the scalar code (`a * b + c` rounds twice everywhere), and `min`/`max` follow
//! the SSE rule (`a < b ? a : b`) in the scalar code too. So a constraint gets bit-identical
//! results whatever the lane width: a replay recorded on an AVX2 machine reproduces on one
//! without, and the scalar, 4- and 8-lane solvers can be checked against each other (Box2D v3
//! avoids FMA for the same cross-platform determinism). FMA would save one rounding per
//! multiply-add; the kernels are bound by gathering bodies, not by arithmetic.

use crate::math::Real;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A pack of `LANES` reals with lane-wise arithmetic (see the module docs).
pub(crate) trait FloatW:
    Copy
    + Default
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Number of lanes.
    const LANES: usize;
    /// The lanes in memory.
    type Array: Copy + Default + std::fmt::Debug + AsRef<[Real]> + AsMut<[Real]> + Send + Sync;
    /// One `u32` per lane (body indices).
    type Index: Copy + Default + std::fmt::Debug + AsRef<[u32]> + AsMut<[u32]> + Send + Sync;
    /// The result of a lane-wise comparison.
    type Mask: Copy;
    /// Every lane `x`.
    fn splat(x: Real) -> Self;
    /// Loads the lanes.
    fn load(a: &Self::Array) -> Self;
    /// Stores the lanes.
    fn store(self, a: &mut Self::Array);
    /// Lane-wise `if self < o { self } else { o }`.
    fn min(self, o: Self) -> Self;
    /// Lane-wise `if self > o { self } else { o }`.
    fn max(self, o: Self) -> Self;
    /// Lane-wise correctly rounded square root.
    fn sqrt(self) -> Self;
    /// Lane-wise `self > o`.
    fn gt(self, o: Self) -> Self::Mask;
    /// Lane-wise `self < o`.
    fn lt(self, o: Self) -> Self::Mask;
    /// Lane-wise `self <= o`.
    fn le(self, o: Self) -> Self::Mask;
    /// Lanes where both masks are set.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Lane-wise `if m { a } else { b }`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Whether any lane of the mask is set.
    fn any(m: Self::Mask) -> bool;
    /// Zero in every lane.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
    /// Loads one record of 8 reals per lane, transposed: field `k` of `records[idx[l]]` in lane
    /// `l` of `out[k]` (the body states the contact kernels gather).
    #[inline(always)]
    fn gather8(records: Records<'_>, idx: &Self::Index) -> [Self; 8] {
        let mut a: [Self::Array; 8] = Default::default();
        for (l, &i) in idx.as_ref().iter().enumerate() {
            let r = records.get(i);
            for k in 0..8 {
                a[k].as_mut()[l] = r[k];
            }
        }
        // Each load written out: a closure would not inherit the caller's target features.
        [
            Self::load(&a[0]),
            Self::load(&a[1]),
            Self::load(&a[2]),
            Self::load(&a[3]),
            Self::load(&a[4]),
            Self::load(&a[5]),
            Self::load(&a[6]),
            Self::load(&a[7]),
        ]
    }
    /// The inverse of [`FloatW::gather8`] for the lanes whose `write` is not 0.
    #[inline(always)]
    fn scatter8(records: Records<'_>, idx: &Self::Index, write: &Self::Index, v: [Self; 8]) {
        let mut a: [Self::Array; 8] = Default::default();
        for k in 0..8 {
            v[k].store(&mut a[k]);
        }
        for (l, (&i, &ok)) in idx.as_ref().iter().zip(write.as_ref()).enumerate() {
            if ok != 0 {
                let mut r: [Real; 8] = [0.0; 8];
                for (k, x) in r.iter_mut().enumerate() {
                    *x = a[k].as_ref()[l];
                }
                records.set(i, r);
            }
        }
    }
}

/// Which lane width the contact solver uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SimdLevel {
    /// The widest the processor supports, found at run time (the default).
    #[default]
    Auto,
    /// One lane: plain scalar code.
    Scalar,
    /// 128-bit lanes (SSE2): 4 `f32` or 2 `f64`. Scalar on targets other than x86-64.
    Narrow,
    /// 256-bit lanes (AVX2, requiring FMA too): 8 `f32` or 4 `f64`. Falls back to `Narrow` on a
    /// processor without them.
    Wide,
}

impl SimdLevel {
    /// The level this processor runs for a requested level: `Auto` becomes the widest
    /// available, and a level the processor lacks becomes the next narrower one.
    #[must_use]
    pub fn detect(self) -> SimdLevel {
        let wide = has_avx2_fma();
        let narrow = cfg!(target_arch = "x86_64");
        match self {
            SimdLevel::Auto | SimdLevel::Wide if wide => SimdLevel::Wide,
            SimdLevel::Auto | SimdLevel::Wide | SimdLevel::Narrow if narrow => SimdLevel::Narrow,
            _ => SimdLevel::Scalar,
        }
    }

    /// Lanes per pack at this level for [`Real`] (after [`SimdLevel::detect`]).
    #[must_use]
    pub fn lanes(self) -> usize {
        let bytes = match self.detect() {
            SimdLevel::Wide => 32,
            SimdLevel::Narrow => 16,
            _ => return 1,
        };
        bytes / std::mem::size_of::<Real>()
    }
}

#[cfg(target_arch = "x86_64")]
fn has_avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

#[cfg(not(target_arch = "x86_64"))]
fn has_avx2_fma() -> bool {
    false
}

impl FloatW for Real {
    const LANES: usize = 1;
    type Array = [Real; 1];
    type Index = [u32; 1];
    type Mask = bool;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        x
    }
    #[inline(always)]
    fn load(a: &[Real; 1]) -> Self {
        a[0]
    }
    #[inline(always)]
    fn store(self, a: &mut [Real; 1]) {
        a[0] = self;
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        if self < o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        if self > o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Real::sqrt(self)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn le(self, o: Self) -> bool {
        self <= o
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a && b
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn any(m: bool) -> bool {
        m
    }
}

/// Implements the arithmetic operators of an x86 pack through its intrinsics.
#[cfg(target_arch = "x86_64")]
macro_rules! pack_ops {
    ($t:ident, $add:ident, $sub:ident, $mul:ident, $div:ident, $xor:ident, $set1:ident, $neg0:expr) => {
        impl Default for $t {
            #[inline(always)]
            fn default() -> Self {
                // SAFETY: the pack type exists only where its instruction set is present.
                Self(unsafe { $set1(0.0) })
            }
        }
        impl std::fmt::Debug for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                let mut a = <Self as FloatW>::Array::default();
                self.store(&mut a);
                write!(f, "{:?}", a)
            }
        }
        impl Add for $t {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                // SAFETY: the pack type exists only where its instruction set is present.
                Self(unsafe { $add(self.0, o.0) })
            }
        }
        impl Sub for $t {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                // SAFETY: as for `add`.
                Self(unsafe { $sub(self.0, o.0) })
            }
        }
        impl Mul for $t {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                // SAFETY: as for `add`.
                Self(unsafe { $mul(self.0, o.0) })
            }
        }
        impl Div for $t {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                // SAFETY: as for `add`.
                Self(unsafe { $div(self.0, o.0) })
            }
        }
        impl Neg for $t {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                // Flip the sign bit: exact, like scalar negation.
                // SAFETY: as for `add`.
                Self(unsafe { $xor(self.0, $set1($neg0)) })
            }
        }
    };
}

// The packs of x86-64, for the build's precision.
#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
#[path = "x86_f32.rs"]
mod x86;
#[cfg(all(target_arch = "x86_64", feature = "f64"))]
#[path = "x86_f64.rs"]
mod x86;

#[cfg(target_arch = "x86_64")]
pub(crate) use x86::{Narrow, Wide};

mod records;
pub(crate) use records::Records;
mod vectors;
pub(crate) use vectors::{Sym3, Sym3A, V3, V3A};

#[cfg(test)]
mod tests {
    use super::*;

    /// The same sequence of operations through a pack of any width.
    fn kernel<F: FloatW>(a: &[Real], b: &[Real], out: &mut [Real]) {
        let mut xa = F::Array::default();
        let mut xb = F::Array::default();
        xa.as_mut().copy_from_slice(a);
        xb.as_mut().copy_from_slice(b);
        let (x, y) = (F::load(&xa), F::load(&xb));
        let r = (x * y + x / y - y).max(F::zero()).sqrt();
        let m = F::gt(x, y);
        let r = F::select(m, r, -r).min(F::splat(1.5));
        let mut o = F::Array::default();
        r.store(&mut o);
        out.copy_from_slice(o.as_ref());
    }

    fn check_width<F: FloatW>() {
        let a: Vec<Real> = (0..F::LANES).map(|i| 0.37 + i as Real * 1.13).collect();
        let b: Vec<Real> = (0..F::LANES).map(|i| 2.9 - i as Real * 0.71).collect();
        let mut wide = vec![0.0; F::LANES];
        kernel::<F>(&a, &b, &mut wide);
        for l in 0..F::LANES {
            let mut one = [0.0];
            kernel::<Real>(&a[l..=l], &b[l..=l], &mut one);
            assert_eq!(
                one[0].to_bits(),
                wide[l].to_bits(),
                "lane {l} of {}",
                F::LANES
            );
        }
    }

    #[test]
    fn every_width_gives_the_scalar_bits() {
        check_width::<Real>();
        #[cfg(target_arch = "x86_64")]
        {
            check_width::<Narrow>();
            if SimdLevel::Wide.detect() == SimdLevel::Wide {
                check_width::<Wide>();
            }
        }
    }

    fn check_gather<F: FloatW>() {
        let mut records: Vec<[Real; 8]> = (0..20)
            .map(|i| std::array::from_fn(|k| (i * 8 + k) as Real))
            .collect();
        let mut idx = F::Index::default();
        let mut write = F::Index::default();
        for (l, (i, w)) in idx.as_mut().iter_mut().zip(write.as_mut()).enumerate() {
            *i = (3 * l as u32 + 1) % 20;
            *w = (l % 2) as u32;
        }
        let g = F::gather8(Records::new(&mut records), &idx);
        let mut out = records.clone();
        let doubled = g.map(|x| x + x);
        F::scatter8(Records::new(&mut out), &idx, &write, doubled);
        for (l, &i) in idx.as_ref().iter().enumerate() {
            for k in 0..8 {
                let mut a = F::Array::default();
                g[k].store(&mut a);
                assert_eq!(a.as_ref()[l], records[i as usize][k]);
                let expect = if write.as_ref()[l] != 0 { 2.0 } else { 1.0 };
                assert_eq!(out[i as usize][k], expect * records[i as usize][k]);
            }
        }
    }

    #[test]
    fn gathers_and_scatters_transpose_the_records() {
        check_gather::<Real>();
        #[cfg(target_arch = "x86_64")]
        {
            check_gather::<Narrow>();
            if SimdLevel::Wide.detect() == SimdLevel::Wide {
                check_gather::<Wide>();
            }
        }
    }

    #[test]
    fn detection_never_claims_more_than_asked() {
        assert_eq!(SimdLevel::Scalar.detect(), SimdLevel::Scalar);
        assert_ne!(SimdLevel::Narrow.detect(), SimdLevel::Wide);
        assert_eq!(SimdLevel::Scalar.lanes(), 1);
    }
}
