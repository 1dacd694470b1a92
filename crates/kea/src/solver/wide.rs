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
    fn gather8(records: &[[Real; 8]], idx: &Self::Index) -> [Self; 8] {
        let mut a: [Self::Array; 8] = Default::default();
        for (l, &i) in idx.as_ref().iter().enumerate() {
            let r = &records[i as usize];
            for k in 0..8 {
                a[k].as_mut()[l] = r[k];
            }
        }
        std::array::from_fn(|k| Self::load(&a[k]))
    }
    /// The inverse of [`FloatW::gather8`] for the lanes whose `write` is not 0.
    #[inline(always)]
    fn scatter8(records: &mut [[Real; 8]], idx: &Self::Index, write: &Self::Index, v: [Self; 8]) {
        let mut a: [Self::Array; 8] = Default::default();
        for k in 0..8 {
            v[k].store(&mut a[k]);
        }
        for (l, (&i, &ok)) in idx.as_ref().iter().zip(write.as_ref()).enumerate() {
            if ok != 0 {
                let r = &mut records[i as usize];
                for k in 0..8 {
                    r[k] = a[k].as_ref()[l];
                }
            }
        }
    }
}

/// Which lane width the contact solver uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
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

#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
mod x86 {
    use super::{Add, Div, FloatW, Mul, Neg, Sub};
    use std::arch::x86_64::*;

    /// Four `f32` lanes in an SSE register (every x86-64 has SSE2).
    #[derive(Clone, Copy)]
    pub(crate) struct Narrow(__m128);

    pack_ops!(
        Narrow,
        _mm_add_ps,
        _mm_sub_ps,
        _mm_mul_ps,
        _mm_div_ps,
        _mm_xor_ps,
        _mm_set1_ps,
        -0.0
    );

    impl FloatW for Narrow {
        const LANES: usize = 4;
        type Array = [f32; 4];
        type Index = [u32; 4];
        type Mask = __m128;
        #[inline(always)]
        fn splat(x: f32) -> Self {
            // SAFETY: SSE2 is part of x86-64.
            Self(unsafe { _mm_set1_ps(x) })
        }
        #[inline(always)]
        fn load(a: &[f32; 4]) -> Self {
            // SAFETY: `a` holds four floats.
            Self(unsafe { _mm_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, a: &mut [f32; 4]) {
            // SAFETY: `a` holds four floats.
            unsafe { _mm_storeu_ps(a.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn gt(self, o: Self) -> __m128 {
            // SAFETY: SSE2.
            unsafe { _mm_cmpgt_ps(self.0, o.0) }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> __m128 {
            // SAFETY: SSE2.
            unsafe { _mm_cmplt_ps(self.0, o.0) }
        }
        #[inline(always)]
        fn le(self, o: Self) -> __m128 {
            // SAFETY: SSE2.
            unsafe { _mm_cmple_ps(self.0, o.0) }
        }
        #[inline(always)]
        fn and(a: __m128, b: __m128) -> __m128 {
            // SAFETY: SSE2.
            unsafe { _mm_and_ps(a, b) }
        }
        #[inline(always)]
        fn select(m: __m128, a: Self, b: Self) -> Self {
            // SAFETY: SSE2 (blendv would need SSE4.1).
            Self(unsafe { _mm_or_ps(_mm_and_ps(m, a.0), _mm_andnot_ps(m, b.0)) })
        }
        #[inline(always)]
        fn any(m: __m128) -> bool {
            // SAFETY: SSE2.
            unsafe { _mm_movemask_ps(m) != 0 }
        }
    }

    /// Eight `f32` lanes in an AVX register; only used after run-time detection of AVX2.
    #[derive(Clone, Copy)]
    pub(crate) struct Wide(__m256);

    pack_ops!(
        Wide,
        _mm256_add_ps,
        _mm256_sub_ps,
        _mm256_mul_ps,
        _mm256_div_ps,
        _mm256_xor_ps,
        _mm256_set1_ps,
        -0.0
    );

    impl FloatW for Wide {
        const LANES: usize = 8;
        type Array = [f32; 8];
        type Index = [u32; 8];
        type Mask = __m256;
        #[inline(always)]
        fn splat(x: f32) -> Self {
            // SAFETY: callers run only where AVX2 was detected.
            Self(unsafe { _mm256_set1_ps(x) })
        }
        #[inline(always)]
        fn load(a: &[f32; 8]) -> Self {
            // SAFETY: `a` holds eight floats; AVX detected.
            Self(unsafe { _mm256_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, a: &mut [f32; 8]) {
            // SAFETY: `a` holds eight floats; AVX detected.
            unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn gt(self, o: Self) -> __m256 {
            // SAFETY: AVX detected.
            unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> __m256 {
            // SAFETY: AVX detected.
            unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn le(self, o: Self) -> __m256 {
            // SAFETY: AVX detected.
            unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn and(a: __m256, b: __m256) -> __m256 {
            // SAFETY: AVX detected.
            unsafe { _mm256_and_ps(a, b) }
        }
        #[inline(always)]
        fn select(m: __m256, a: Self, b: Self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_blendv_ps(b.0, a.0, m) })
        }
        #[inline(always)]
        fn any(m: __m256) -> bool {
            // SAFETY: AVX detected.
            unsafe { _mm256_movemask_ps(m) != 0 }
        }
        #[inline(always)]
        fn gather8(records: &[[f32; 8]], idx: &[u32; 8]) -> [Self; 8] {
            // SAFETY: AVX detected; every record holds 8 floats.
            unsafe {
                let r: [__m256; 8] =
                    std::array::from_fn(|l| _mm256_loadu_ps(records[idx[l] as usize].as_ptr()));
                transpose8(r).map(Self)
            }
        }
        #[inline(always)]
        fn scatter8(records: &mut [[f32; 8]], idx: &[u32; 8], write: &[u32; 8], v: [Self; 8]) {
            // SAFETY: AVX detected; every record holds 8 floats.
            unsafe {
                let rows = transpose8(v.map(|x| x.0));
                for l in 0..8 {
                    if write[l] != 0 {
                        _mm256_storeu_ps(records[idx[l] as usize].as_mut_ptr(), rows[l]);
                    }
                }
            }
        }
    }

    /// Transposes an 8×8 matrix of floats held as 8 rows (its own inverse).
    #[inline(always)]
    unsafe fn transpose8(r: [__m256; 8]) -> [__m256; 8] {
        // SAFETY (for the intrinsics): callers run only where AVX was detected.
        unsafe {
            let t0 = _mm256_unpacklo_ps(r[0], r[1]);
            let t1 = _mm256_unpackhi_ps(r[0], r[1]);
            let t2 = _mm256_unpacklo_ps(r[2], r[3]);
            let t3 = _mm256_unpackhi_ps(r[2], r[3]);
            let t4 = _mm256_unpacklo_ps(r[4], r[5]);
            let t5 = _mm256_unpackhi_ps(r[4], r[5]);
            let t6 = _mm256_unpacklo_ps(r[6], r[7]);
            let t7 = _mm256_unpackhi_ps(r[6], r[7]);
            let s0 = _mm256_shuffle_ps::<0x44>(t0, t2);
            let s1 = _mm256_shuffle_ps::<0xEE>(t0, t2);
            let s2 = _mm256_shuffle_ps::<0x44>(t1, t3);
            let s3 = _mm256_shuffle_ps::<0xEE>(t1, t3);
            let s4 = _mm256_shuffle_ps::<0x44>(t4, t6);
            let s5 = _mm256_shuffle_ps::<0xEE>(t4, t6);
            let s6 = _mm256_shuffle_ps::<0x44>(t5, t7);
            let s7 = _mm256_shuffle_ps::<0xEE>(t5, t7);
            [
                _mm256_permute2f128_ps::<0x20>(s0, s4),
                _mm256_permute2f128_ps::<0x20>(s1, s5),
                _mm256_permute2f128_ps::<0x20>(s2, s6),
                _mm256_permute2f128_ps::<0x20>(s3, s7),
                _mm256_permute2f128_ps::<0x31>(s0, s4),
                _mm256_permute2f128_ps::<0x31>(s1, s5),
                _mm256_permute2f128_ps::<0x31>(s2, s6),
                _mm256_permute2f128_ps::<0x31>(s3, s7),
            ]
        }
    }
}

#[cfg(all(target_arch = "x86_64", feature = "f64"))]
mod x86 {
    use super::{Add, Div, FloatW, Mul, Neg, Sub};
    use std::arch::x86_64::*;

    /// Two `f64` lanes in an SSE2 register.
    #[derive(Clone, Copy)]
    pub(crate) struct Narrow(__m128d);

    pack_ops!(
        Narrow,
        _mm_add_pd,
        _mm_sub_pd,
        _mm_mul_pd,
        _mm_div_pd,
        _mm_xor_pd,
        _mm_set1_pd,
        -0.0
    );

    impl FloatW for Narrow {
        const LANES: usize = 2;
        type Array = [f64; 2];
        type Index = [u32; 2];
        type Mask = __m128d;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            // SAFETY: SSE2 is part of x86-64.
            Self(unsafe { _mm_set1_pd(x) })
        }
        #[inline(always)]
        fn load(a: &[f64; 2]) -> Self {
            // SAFETY: `a` holds two doubles.
            Self(unsafe { _mm_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, a: &mut [f64; 2]) {
            // SAFETY: `a` holds two doubles.
            unsafe { _mm_storeu_pd(a.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_min_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_max_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn gt(self, o: Self) -> __m128d {
            // SAFETY: SSE2.
            unsafe { _mm_cmpgt_pd(self.0, o.0) }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> __m128d {
            // SAFETY: SSE2.
            unsafe { _mm_cmplt_pd(self.0, o.0) }
        }
        #[inline(always)]
        fn le(self, o: Self) -> __m128d {
            // SAFETY: SSE2.
            unsafe { _mm_cmple_pd(self.0, o.0) }
        }
        #[inline(always)]
        fn and(a: __m128d, b: __m128d) -> __m128d {
            // SAFETY: SSE2.
            unsafe { _mm_and_pd(a, b) }
        }
        #[inline(always)]
        fn select(m: __m128d, a: Self, b: Self) -> Self {
            // SAFETY: SSE2.
            Self(unsafe { _mm_or_pd(_mm_and_pd(m, a.0), _mm_andnot_pd(m, b.0)) })
        }
        #[inline(always)]
        fn any(m: __m128d) -> bool {
            // SAFETY: SSE2.
            unsafe { _mm_movemask_pd(m) != 0 }
        }
    }

    /// Four `f64` lanes in an AVX register; only used after run-time detection of AVX2.
    #[derive(Clone, Copy)]
    pub(crate) struct Wide(__m256d);

    pack_ops!(
        Wide,
        _mm256_add_pd,
        _mm256_sub_pd,
        _mm256_mul_pd,
        _mm256_div_pd,
        _mm256_xor_pd,
        _mm256_set1_pd,
        -0.0
    );

    impl FloatW for Wide {
        const LANES: usize = 4;
        type Array = [f64; 4];
        type Index = [u32; 4];
        type Mask = __m256d;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            // SAFETY: callers run only where AVX2 was detected.
            Self(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        fn load(a: &[f64; 4]) -> Self {
            // SAFETY: `a` holds four doubles; AVX detected.
            Self(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, a: &mut [f64; 4]) {
            // SAFETY: `a` holds four doubles; AVX detected.
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_min_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_max_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn gt(self, o: Self) -> __m256d {
            // SAFETY: AVX detected.
            unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> __m256d {
            // SAFETY: AVX detected.
            unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn le(self, o: Self) -> __m256d {
            // SAFETY: AVX detected.
            unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn and(a: __m256d, b: __m256d) -> __m256d {
            // SAFETY: AVX detected.
            unsafe { _mm256_and_pd(a, b) }
        }
        #[inline(always)]
        fn select(m: __m256d, a: Self, b: Self) -> Self {
            // SAFETY: AVX detected.
            Self(unsafe { _mm256_blendv_pd(b.0, a.0, m) })
        }
        #[inline(always)]
        fn any(m: __m256d) -> bool {
            // SAFETY: AVX detected.
            unsafe { _mm256_movemask_pd(m) != 0 }
        }
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use x86::{Narrow, Wide};

/// A 3-vector of packs: one vector per lane.
#[derive(Clone, Copy)]
pub(crate) struct V3<F> {
    pub(crate) x: F,
    pub(crate) y: F,
    pub(crate) z: F,
}

impl<F: FloatW> V3<F> {
    #[inline(always)]
    pub(crate) fn new(x: F, y: F, z: F) -> Self {
        Self { x, y, z }
    }
    #[inline(always)]
    pub(crate) fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub(crate) fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    #[inline(always)]
    pub(crate) fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
    #[inline(always)]
    pub(crate) fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
    #[inline(always)]
    pub(crate) fn scale(self, s: F) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

/// A 3-vector of packs as stored in memory.
#[derive(Clone, Copy, Default, Debug)]
pub(crate) struct V3A<F: FloatW> {
    pub(crate) x: F::Array,
    pub(crate) y: F::Array,
    pub(crate) z: F::Array,
}

impl<F: FloatW> V3A<F> {
    #[inline(always)]
    pub(crate) fn load(&self) -> V3<F> {
        V3::new(F::load(&self.x), F::load(&self.y), F::load(&self.z))
    }
    /// Writes one lane.
    #[inline]
    pub(crate) fn set_lane(&mut self, lane: usize, v: crate::math::Vec3) {
        self.x.as_mut()[lane] = v.x;
        self.y.as_mut()[lane] = v.y;
        self.z.as_mut()[lane] = v.z;
    }
    /// Reads one lane.
    #[inline]
    pub(crate) fn lane(&self, lane: usize) -> crate::math::Vec3 {
        crate::math::Vec3::new(
            self.x.as_ref()[lane],
            self.y.as_ref()[lane],
            self.z.as_ref()[lane],
        )
    }
}

/// A symmetric 3×3 matrix of packs as stored (world inverse inertia of one body per lane).
#[derive(Clone, Copy, Default, Debug)]
pub(crate) struct Sym3A<F: FloatW> {
    pub(crate) xx: F::Array,
    pub(crate) yy: F::Array,
    pub(crate) zz: F::Array,
    pub(crate) xy: F::Array,
    pub(crate) xz: F::Array,
    pub(crate) yz: F::Array,
}

/// A symmetric 3×3 matrix of packs, loaded.
#[derive(Clone, Copy, Default)]
pub(crate) struct Sym3<F> {
    xx: F,
    yy: F,
    zz: F,
    xy: F,
    xz: F,
    yz: F,
}

impl<F: FloatW> Sym3A<F> {
    #[inline(always)]
    pub(crate) fn load(&self) -> Sym3<F> {
        Sym3 {
            xx: F::load(&self.xx),
            yy: F::load(&self.yy),
            zz: F::load(&self.zz),
            xy: F::load(&self.xy),
            xz: F::load(&self.xz),
            yz: F::load(&self.yz),
        }
    }
    /// Writes one lane from a (symmetric) matrix.
    #[inline]
    pub(crate) fn set_lane(&mut self, lane: usize, m: &crate::math::Mat3) {
        self.xx.as_mut()[lane] = m.x_axis.x;
        self.yy.as_mut()[lane] = m.y_axis.y;
        self.zz.as_mut()[lane] = m.z_axis.z;
        self.xy.as_mut()[lane] = m.y_axis.x;
        self.xz.as_mut()[lane] = m.z_axis.x;
        self.yz.as_mut()[lane] = m.z_axis.y;
    }
}

impl<F: FloatW> Sym3<F> {
    #[inline(always)]
    pub(crate) fn mul(&self, v: V3<F>) -> V3<F> {
        V3::new(
            self.xx * v.x + self.xy * v.y + self.xz * v.z,
            self.xy * v.x + self.yy * v.y + self.yz * v.z,
            self.xz * v.x + self.yz * v.y + self.zz * v.z,
        )
    }
}

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
        let records: Vec<[Real; 8]> = (0..20)
            .map(|i| std::array::from_fn(|k| (i * 8 + k) as Real))
            .collect();
        let mut idx = F::Index::default();
        let mut write = F::Index::default();
        for (l, (i, w)) in idx.as_mut().iter_mut().zip(write.as_mut()).enumerate() {
            *i = (3 * l as u32 + 1) % 20;
            *w = (l % 2) as u32;
        }
        let g = F::gather8(&records, &idx);
        let mut out = records.clone();
        let doubled = g.map(|x| x + x);
        F::scatter8(&mut out, &idx, &write, doubled);
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
