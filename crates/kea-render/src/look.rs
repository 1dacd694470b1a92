//! The look both `kea render` and the Viewer share: colours, a checkered ground, distance fog
//! and the links that show where joints hold bodies. One place, so the two never disagree.

use kea::{BodyHandle, Real, Vec3, World};

/// The colour of the background (sky); fog fades towards it.
pub const SKY: [u8; 3] = [200, 220, 245];
/// The colour of a ground plane (its light tiles).
pub const GROUND_COLOUR: [u8; 3] = [206, 204, 194];
/// The colour of static geometry that is not a ground plane (steps, ramps, height fields):
/// a slate blue, so it never reads as ground or as a body.
pub const STATIC_COLOUR: [u8; 3] = [120, 136, 160];
/// How much darker a checker's dark tiles are than its light ones: static geometry is
/// checkered so that slopes, bumps and motion over it can be read.
pub const CHECKER_SHADE: Real = 0.84;
/// The colour of joint links (strings, axles, mounts).
pub const LINK_COLOUR: [u8; 3] = [70, 70, 78];
/// Base colours of bodies, by collider order.
pub const BODY_COLOURS: [[u8; 3]; 6] = [
    [220, 90, 60],
    [70, 140, 220],
    [240, 190, 60],
    [90, 190, 110],
    [170, 100, 200],
    [60, 190, 190],
];

/// Distance fog: clear up to `near`, the sky's colour from `far` on, smooth between.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fog {
    /// Where the fog starts, m from the eye.
    pub near: Real,
    /// Where only sky is left, m from the eye.
    pub far: Real,
}

impl Fog {
    /// The fog for a camera `distance` m from what it looks at: clear to twice that, so the
    /// subject and its surroundings stay sharp, and gone into the sky at six times.
    #[must_use]
    pub fn for_distance(distance: Real) -> Self {
        let d = if distance.is_finite() {
            distance.max(0.1)
        } else {
            10.0
        };
        Self {
            near: 2.0 * d,
            far: 6.0 * d,
        }
    }

    /// How much of the sky a point `distance` away shows through, 0..1.
    #[must_use]
    pub fn amount(&self, distance: Real) -> Real {
        let t = ((distance - self.near) / (self.far - self.near).max(1e-6)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    /// `colour` seen from `distance` away.
    #[must_use]
    pub fn apply(&self, colour: [u8; 3], distance: Real) -> [u8; 3] {
        let f = self.amount(distance);
        let mut out = colour;
        for (o, s) in out.iter_mut().zip(SKY) {
            *o = (Real::from(*o) * (1.0 - f) + Real::from(s) * f).round() as u8;
        }
        out
    }
}

/// The side of a ground tile for a scene whose subject has `radius`: the largest of 1, 2 or 5
/// times a power of ten that fits the subject's width five times (20 cm for a 1 m box, 2 m
/// for a pyramid of boxes), so tiles read as a scale.
#[must_use]
pub fn tile_size(radius: Real) -> Real {
    if !(radius.is_finite() && radius > 0.0) {
        return 1.0;
    }
    let fit = 2.0 * radius / 5.0;
    let decade = (10.0 as Real).powf(fit.log10().floor());
    let step = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|m| m * decade <= fit * 1.0001)
        .unwrap_or(1.0);
    (step * decade).clamp(0.01, 100.0)
}

/// How much of a checker's contrast to keep where one tile covers `tile_pixels` pixels: all
/// of it from six pixels up, none below two, so far tiles fade to their mean instead of
/// shimmering (what mipmaps do for the Viewer's texture).
#[must_use]
pub fn checker_contrast(tile_pixels: Real) -> Real {
    ((tile_pixels - 2.0) / 4.0).clamp(0.0, 1.0)
}

/// How a static surface is tiled: two coordinates in tiles for every point, whose integer
/// parts pick the light or dark tone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tiling {
    origin: Vec3,
    /// Unit directions of the two coordinates, divided by the tile side.
    u: Vec3,
    v: Vec3,
}

impl Tiling {
    /// Square tiles of side `tile` on the plane through `point` with `normal`, lined up with
    /// the world's x and z on a level ground.
    #[must_use]
    pub fn plane(point: Vec3, normal: Vec3, tile: Real) -> Self {
        let normal = normal.normalize_or(Vec3::Y);
        let tile = if tile > 0.0 { tile } else { 1.0 };
        let u = (Vec3::X - normal * normal.x).normalize_or(normal.any_orthonormal_vector());
        Self {
            origin: point,
            u: u / tile,
            v: normal.cross(u) / tile,
        }
    }

    /// Tiles of side `tile` for a face with `normal`, projected along the world axis nearest
    /// the normal. The grid is shifted off round coordinates, where faces often lie (a face on
    /// a tile boundary would speckle).
    #[must_use]
    pub fn face(normal: Vec3, tile: Real) -> Self {
        let tile = if tile > 0.0 { tile } else { 1.0 };
        let n = normal.abs();
        let (u, v) = if n.y >= n.x && n.y >= n.z {
            (Vec3::X, Vec3::Z)
        } else if n.x >= n.z {
            (Vec3::Z, Vec3::Y)
        } else {
            (Vec3::X, Vec3::Y)
        };
        Self {
            origin: Vec3::splat(-0.237 * tile),
            u: u / tile,
            v: v / tile,
        }
    }

    /// Where `p` lies, in tiles.
    #[must_use]
    pub fn coordinates(&self, p: Vec3) -> (Real, Real) {
        let d = p - self.origin;
        (d.dot(self.u), d.dot(self.v))
    }

    /// The light (1) or dark ([`CHECKER_SHADE`]) tone of the tile under `p`.
    #[must_use]
    pub fn tone(&self, p: Vec3) -> Real {
        let (a, b) = self.coordinates(p);
        if (a.floor() as i64 + b.floor() as i64).rem_euclid(2) == 0 {
            1.0
        } else {
            CHECKER_SHADE
        }
    }

    /// The side of a tile, m.
    #[must_use]
    pub fn tile(&self) -> Real {
        1.0 / self.u.length()
    }

    /// A square of a [`Tiling::plane`] around `centre`'s foot, `half` m to each side, cut into
    /// `cells` × `cells` squares (two triangles each, counter-clockwise seen from the normal's
    /// side): the ground a camera sees, out to where the fog hides its edge.
    #[must_use]
    pub fn patch(&self, centre: Vec3, half: Real, cells: u32) -> Vec<[Vec3; 3]> {
        let (ca, cb) = self.coordinates(centre);
        let tile = self.tile();
        let (h, n) = (half / tile, cells.max(1));
        let step = 2.0 * h / n as Real;
        let (u, v) = (self.u * tile * tile, self.v * tile * tile);
        let at = |i: u32, j: u32| {
            let (a, b) = (ca - h + i as Real * step, cb - h + j as Real * step);
            self.origin + u * a + v * b
        };
        let mut out = Vec::with_capacity((n * n * 2) as usize);
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                out.push([a, b, c]);
                out.push([a, c, d]);
            }
        }
        out
    }
}

/// `colour` darkened by a checker `tone`.
#[must_use]
pub fn toned(colour: [u8; 3], tone: Real) -> [u8; 3] {
    colour.map(|c| (Real::from(c) * tone).round() as u8)
}

/// The segments that show how joints hold bodies: from each jointed body's centre to its
/// anchor (a pendulum's string, a car's axle), and a beam along world anchors that sit close
/// together (a Newton's cradle's frame). Drawn thin, in [`LINK_COLOUR`].
#[must_use]
pub fn joint_links(world: &World) -> Vec<[Vec3; 2]> {
    let centre = |b: BodyHandle| world.body(b).ok().map(|b| b.position());
    let mut links = Vec::new();
    let mut mounts: Vec<(Vec3, Real)> = Vec::new();
    for (h, bodies) in world.enabled_joints() {
        let Ok(Some(sketch)) = world.joint_sketch(h) else {
            continue;
        };
        for (body, anchor) in bodies.iter().zip(sketch.anchors) {
            match body.and_then(centre) {
                Some(c) => {
                    if (c - anchor).length() > 1e-6 {
                        links.push([c, anchor]);
                    }
                }
                None => {
                    let reach = bodies[0]
                        .and_then(centre)
                        .map_or(0.0, |c| (c - anchor).length());
                    mounts.push((anchor, reach));
                }
            }
        }
    }
    // A beam joins world anchors closer to each other than the strings hanging from them.
    for pair in mounts.windows(2) {
        let ((a, ra), (b, rb)) = (pair[0], pair[1]);
        if (a - b).length() < ra.min(rb) {
            links.push([a, b]);
        }
    }
    links
}

/// A thin square rod from `a` to `b` of half-width `radius`, as 8 triangles (none if the ends
/// meet).
#[must_use]
pub fn rod(a: Vec3, b: Vec3, radius: Real) -> Vec<[Vec3; 3]> {
    let axis = b - a;
    if axis.length_squared() < 1e-12 || !radius.is_finite() {
        return Vec::new();
    }
    let (s, t) = axis.normalize().any_orthonormal_pair();
    let corners = [s + t, t - s, -s - t, s - t].map(|c| c * radius);
    let mut out = Vec::with_capacity(8);
    for k in 0..4 {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        out.push([a + p, a + q, b + q]);
        out.push([a + p, b + q, b + p]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fog_is_clear_near_and_sky_far_and_smooth_between() {
        let fog = Fog::for_distance(5.0);
        assert_eq!(fog.apply([10, 20, 30], 9.0), [10, 20, 30]);
        assert_eq!(fog.apply([10, 20, 30], 31.0), SKY);
        let half = fog.amount(20.0);
        assert!((half - 0.5).abs() < 1e-6, "{half}");
        assert!(fog.amount(15.0) < fog.amount(16.0));
    }

    #[test]
    fn tiles_are_powers_of_ten_and_neighbours_differ() {
        assert!(
            (tile_size(0.87) - 0.2).abs() < 1e-6,
            "a 1 m box: {}",
            tile_size(0.87)
        );
        assert!((tile_size(5.0) - 2.0).abs() < 1e-6);
        assert!((tile_size(12.5) - 5.0).abs() < 1e-5);
        assert!((tile_size(2.5) - 1.0).abs() < 1e-6);
        assert_eq!(tile_size(Real::NAN), 1.0);
        let c = Tiling::plane(Vec3::ZERO, Vec3::Y, 1.0);
        let here = c.tone(Vec3::new(0.5, 0.0, 0.5));
        assert_ne!(here, c.tone(Vec3::new(1.5, 0.0, 0.5)));
        assert_ne!(here, c.tone(Vec3::new(0.5, 0.0, -0.5)));
        assert_eq!(here, c.tone(Vec3::new(1.5, 0.0, 1.5)));
        // A wall facing x is tiled in z and y, half a metre tiles.
        let wall = Tiling::face(Vec3::X, 0.5);
        assert_ne!(
            wall.tone(Vec3::new(3.0, 0.1, 0.1)),
            wall.tone(Vec3::new(3.0, 0.6, 0.1))
        );
        assert_eq!(
            wall.tone(Vec3::new(3.0, 0.1, 0.1)),
            wall.tone(Vec3::new(9.0, 0.1, 0.1))
        );
        // The patch lies on the plane and faces up.
        for [a, b, cc] in
            Tiling::plane(Vec3::ZERO, Vec3::Y, 0.5).patch(Vec3::new(3.0, 2.0, -1.0), 10.0, 4)
        {
            assert!(a.y.abs() < 1e-5 && b.y.abs() < 1e-5 && cc.y.abs() < 1e-5);
            assert!((b - a).cross(cc - a).y > 0.0);
        }
    }
}
