//! The x86-64 packs in `f32`: 4 lanes in SSE2, 8 in AVX2.

use super::{FloatW, Records};
use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Neg, Sub};

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
    // Written out load by load, with no closure: a closure (or `array::from_fn`) is a function
    // of its own without this caller's AVX, so the loads would be called out of line.
    #[inline(always)]
    fn gather8(records: Records<'_>, idx: &[u32; 8]) -> [Self; 8] {
        // SAFETY: AVX detected; every record holds 8 floats; no other lane writes them.
        unsafe {
            let load = |l: usize| records.ptr(idx[l]);
            let r = [
                _mm256_loadu_ps(load(0)),
                _mm256_loadu_ps(load(1)),
                _mm256_loadu_ps(load(2)),
                _mm256_loadu_ps(load(3)),
                _mm256_loadu_ps(load(4)),
                _mm256_loadu_ps(load(5)),
                _mm256_loadu_ps(load(6)),
                _mm256_loadu_ps(load(7)),
            ];
            let t = transpose8(r);
            [
                Self(t[0]),
                Self(t[1]),
                Self(t[2]),
                Self(t[3]),
                Self(t[4]),
                Self(t[5]),
                Self(t[6]),
                Self(t[7]),
            ]
        }
    }
    #[inline(always)]
    fn scatter8(records: Records<'_>, idx: &[u32; 8], write: &[u32; 8], v: [Self; 8]) {
        // SAFETY: AVX detected; every record holds 8 floats; only this lane writes it.
        unsafe {
            let rows = transpose8([
                v[0].0, v[1].0, v[2].0, v[3].0, v[4].0, v[5].0, v[6].0, v[7].0,
            ]);
            for l in 0..8 {
                if write[l] != 0 {
                    _mm256_storeu_ps(records.ptr_mut(idx[l]), rows[l]);
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
