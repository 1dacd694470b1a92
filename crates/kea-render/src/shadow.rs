//! A shadow map for the directional light: the bodies' triangles seen from the light in an
//! orthographic view, keeping for every texel how far towards the light the nearest occluder
//! reaches. A point is in shadow when something reaches further towards the light above it.

use kea::{Real, Vec3};

/// Texels along the longer side of the occluders' extent.
const RESOLUTION: usize = 1024;

/// The occluders' depth seen from the light.
pub struct ShadowMap {
    light: Vec3,
    u: Vec3,
    v: Vec3,
    origin: (Real, Real),
    texel: Real,
    size: (usize, usize),
    /// Per texel, the largest `p·light` of any occluder (−∞: nothing there).
    height: Vec<Real>,
}

impl ShadowMap {
    /// The map of `occluders` lit along unit `light` (pointing towards the light); `None`
    /// when there is nothing to cast a shadow.
    pub fn build(light: Vec3, occluders: impl Iterator<Item = [Vec3; 3]> + Clone) -> Option<Self> {
        let u = light.any_orthonormal_vector();
        let v = light.cross(u);
        let (mut lo, mut hi) = (
            (Real::INFINITY, Real::INFINITY),
            (Real::NEG_INFINITY, Real::NEG_INFINITY),
        );
        for p in occluders.clone().flatten() {
            let (a, b) = (p.dot(u), p.dot(v));
            lo = (lo.0.min(a), lo.1.min(b));
            hi = (hi.0.max(a), hi.1.max(b));
        }
        if !lo.0.is_finite() {
            return None;
        }
        let extent = (hi.0 - lo.0).max(hi.1 - lo.1).max(1e-3);
        let texel = extent / (RESOLUTION - 2) as Real;
        let size = (
            ((hi.0 - lo.0) / texel) as usize + 2,
            ((hi.1 - lo.1) / texel) as usize + 2,
        );
        let mut map = Self {
            light,
            u,
            v,
            origin: (lo.0 - texel * 0.5, lo.1 - texel * 0.5),
            texel,
            size,
            height: vec![Real::NEG_INFINITY; size.0 * size.1],
        };
        for tri in occluders {
            map.rasterize(tri);
        }
        Some(map)
    }

    /// Texel coordinates (continuous) of a point.
    fn texel_of(&self, p: Vec3) -> (Real, Real) {
        (
            (p.dot(self.u) - self.origin.0) / self.texel,
            (p.dot(self.v) - self.origin.1) / self.texel,
        )
    }

    fn rasterize(&mut self, tri: [Vec3; 3]) {
        let s = tri.map(|p| {
            let (x, y) = self.texel_of(p);
            Vec3::new(x, y, p.dot(self.light))
        });
        let area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[1].y - s[0].y) * (s[2].x - s[0].x);
        // Edge-on triangles still block light along their edge: widen by keeping the vertex
        // texels.
        for p in &s {
            self.raise(p.x, p.y, p.z);
        }
        if area.abs() < 1e-12 {
            return;
        }
        let clamp = |a: Real, n: usize| a.max(0.0).min((n - 1) as Real) as usize;
        let x0 = clamp(s[0].x.min(s[1].x).min(s[2].x).floor(), self.size.0);
        let x1 = clamp(s[0].x.max(s[1].x).max(s[2].x).ceil(), self.size.0);
        let y0 = clamp(s[0].y.min(s[1].y).min(s[2].y).floor(), self.size.1);
        let y1 = clamp(s[0].y.max(s[1].y).max(s[2].y).ceil(), self.size.1);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (x as Real + 0.5, y as Real + 0.5);
                let w0 = ((s[1].x - px) * (s[2].y - py) - (s[1].y - py) * (s[2].x - px)) / area;
                let w1 = ((s[2].x - px) * (s[0].y - py) - (s[2].y - py) * (s[0].x - px)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let h = w0 * s[0].z + w1 * s[1].z + w2 * s[2].z;
                let cell = &mut self.height[y * self.size.0 + x];
                *cell = cell.max(h);
            }
        }
    }

    fn raise(&mut self, x: Real, y: Real, h: Real) {
        if x >= 0.0 && y >= 0.0 {
            let (x, y) = (x as usize, y as usize);
            if x < self.size.0 && y < self.size.1 {
                let cell = &mut self.height[y * self.size.0 + x];
                *cell = cell.max(h);
            }
        }
    }

    /// Whether the light reaches `p`: nothing reaches further towards the light above it
    /// (with a bias of two texels, so a lit face does not shadow itself).
    #[must_use]
    pub fn is_lit(&self, p: Vec3) -> bool {
        let (x, y) = self.texel_of(p);
        if x < 0.0 || y < 0.0 {
            return true;
        }
        let (x, y) = (x as usize, y as usize);
        if x >= self.size.0 || y >= self.size.1 {
            return true;
        }
        self.height[y * self.size.0 + x] <= p.dot(self.light) + 2.0 * self.texel + 1e-4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_shades_the_ground_below_it_along_the_light_and_nothing_else() {
        // A 1 m square at height 2, light straight down.
        let (a, b, c, d) = (
            Vec3::new(-0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, 0.5),
            Vec3::new(-0.5, 2.0, 0.5),
        );
        let tris = [[a, b, c], [a, c, d]];
        let map = ShadowMap::build(Vec3::Y, tris.iter().copied()).unwrap();
        assert!(!map.is_lit(Vec3::new(0.0, 0.0, 0.0)), "under the square");
        assert!(!map.is_lit(Vec3::new(0.4, 0.0, -0.4)), "under a corner");
        assert!(map.is_lit(Vec3::new(0.7, 0.0, 0.0)), "beside it");
        assert!(
            map.is_lit(Vec3::new(0.0, 2.0, 0.0)),
            "the square itself is lit"
        );
        assert!(map.is_lit(Vec3::new(0.0, 3.0, 0.0)), "above it");
        // Slanted light moves the shadow: along (1, 1, 0)/√2 it falls 2 m towards −x.
        let slant = Vec3::new(1.0, 1.0, 0.0).normalize();
        let map = ShadowMap::build(slant, tris.iter().copied()).unwrap();
        assert!(!map.is_lit(Vec3::new(-2.0, 0.0, 0.0)));
        assert!(map.is_lit(Vec3::new(0.0, 0.0, 0.0)));
    }
}
