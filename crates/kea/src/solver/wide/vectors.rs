//! Vectors and symmetric matrices of packs: one per lane.

use super::FloatW;

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
