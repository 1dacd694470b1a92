//! The x86-64 packs in `f64`: 2 lanes in SSE2, 4 in AVX2.

use super::FloatW;
use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Neg, Sub};

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
