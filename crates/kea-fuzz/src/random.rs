//! The driver's random numbers: SplitMix64 (a seed gives the same run everywhere), and values
//! drawn the way a fuzzer should: mostly ordinary, sometimes at or past the edges.

use kea::{Quat, Real, Vec3};

/// A SplitMix64 generator.
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9e37_79b9_7f4a_7c15)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n` ≥ 1).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> Real {
        (lo + (hi - lo) * self.unit()) as Real
    }

    /// A value at or past an edge: zero, negatives, NaN, infinities, the extremes of f32.
    pub fn odd(&mut self) -> Real {
        const ODD: [f64; 14] = [
            0.0,
            -0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f32::MAX as f64,
            f32::MIN_POSITIVE as f64,
            1.0e-40,
            1.0e30,
            -1.0e30,
            1.0e-9,
            1.0e9,
            3.0e38,
        ];
        ODD[self.below(ODD.len())] as Real
    }

    /// A number: 85% in [lo, hi), the rest odd.
    pub fn real(&mut self, lo: f64, hi: f64) -> Real {
        if self.chance(0.85) {
            self.range(lo, hi)
        } else {
            self.odd()
        }
    }

    /// A size, m: mostly in [0.05, 2).
    pub fn size(&mut self) -> Real {
        self.real(0.05, 2.0)
    }

    /// A vector with components from [`Rng::real`].
    pub fn vec3(&mut self, lo: f64, hi: f64) -> Vec3 {
        Vec3::new(self.real(lo, hi), self.real(lo, hi), self.real(lo, hi))
    }

    /// A unit vector, or (sometimes) not one.
    pub fn direction(&mut self) -> Vec3 {
        if self.chance(0.9) {
            let v = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            v.try_normalize().unwrap_or(Vec3::Y)
        } else {
            self.vec3(-2.0, 2.0)
        }
    }

    /// A unit quaternion, or (sometimes) not one.
    pub fn rotation(&mut self) -> Quat {
        if self.chance(0.9) {
            let axis = self.direction();
            Quat::from_axis_angle(
                axis.try_normalize().unwrap_or(Vec3::Y),
                self.range(-3.2, 3.2),
            )
        } else {
            Quat::from_xyzw(
                self.odd(),
                self.range(-1.0, 1.0),
                0.0,
                self.range(-1.0, 1.0),
            )
        }
    }
}
