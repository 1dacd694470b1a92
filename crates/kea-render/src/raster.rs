//! Rasterizing world-space triangles into the image: projection, z-buffer, and per-pixel
//! shading with the shadow test.

use crate::shadow::ShadowMap;
use crate::{checker_contrast, toned, Camera, Fog, Image, Tiling, CHECKER_SHADE};
use kea::{Real, Vec3};

/// Light a shadowed surface still gets, as a share of its direct light (sky and bounce light).
const SHADOW_LIGHT: Real = 0.3;
/// Light every surface gets whatever its direction.
const AMBIENT: Real = 0.3;

/// How a triangle is lit: its base colour and the cosine of its normal with the light.
#[derive(Debug, Clone, Copy)]
pub struct Surface {
    /// Base colour.
    pub colour: [u8; 3],
    /// max(0, n·l).
    pub lambert: Real,
}

/// World to screen: pixel x and y (row 0 at the top) and the distance along the view direction.
pub struct Projector {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    focal: Real,
    half: (Real, Real),
}

impl Projector {
    /// The projection of `camera` onto a `width` × `height` image.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let forward = (camera.target - camera.eye).normalize_or_zero();
        let right = forward.cross(camera.up).normalize_or_zero();
        let up = right.cross(forward);
        let half = (width as Real * 0.5, height as Real * 0.5);
        // Pixels per unit of (lateral offset / distance), from the vertical field of view.
        let focal = half.1 / (camera.fov_y * 0.5).tan();
        Self {
            eye: camera.eye,
            right,
            up,
            forward,
            focal,
            half,
        }
    }

    /// `None` behind (or almost at) the eye.
    fn project(&self, p: Vec3) -> Option<Vec3> {
        let d = p - self.eye;
        let distance = d.dot(self.forward);
        if distance <= 0.05 {
            return None;
        }
        let x = self.half.0 + self.focal * d.dot(self.right) / distance;
        let y = self.half.1 - self.focal * d.dot(self.up) / distance;
        Some(Vec3::new(x, y, distance))
    }
}

/// The colour of a surface: ambient light plus direct light by Lambert's cosine, the direct
/// part cut to a share when the surface is in shadow (`lit` false). The Viewer shades with it
/// too, so both draw the same colours.
#[must_use]
pub fn shade(surface: Surface, lit: bool) -> [u8; 3] {
    let direct = if lit { 1.0 } else { SHADOW_LIGHT };
    let s = AMBIENT + (1.0 - AMBIENT) * surface.lambert * direct;
    surface
        .colour
        .map(|ch| (Real::from(ch) * s).min(255.0) as u8)
}

/// How a triangle's pixels get their colour: its surface, toned by a checker under each pixel
/// for static geometry, then fog by the pixel's distance from the eye.
pub struct Paint<'a> {
    /// Base colour and light.
    pub surface: Surface,
    /// A static surface's checker, which darkens every other tile pixel by pixel.
    pub tiling: Option<&'a Tiling>,
    /// Distance fog.
    pub fog: &'a Fog,
}

/// Rasterizes one world-space triangle with a depth test; triangles reaching behind the eye are
/// skipped (scenes are framed so that nothing sits on the camera). Each pixel's world point is
/// interpolated perspective-correctly, coloured by the paint and tested against the shadow map.
pub fn draw_triangle(
    image: &mut Image,
    depth: &mut [Real],
    projector: &Projector,
    tri: [Vec3; 3],
    paint: &Paint<'_>,
    shadow: &Option<ShadowMap>,
) {
    let (w, h) = (image.width as Real, image.height as Real);
    let mut screen = [Vec3::ZERO; 3];
    for (s, p) in screen.iter_mut().zip(tri) {
        match projector.project(p) {
            Some(q) => *s = q,
            None => return,
        }
    }
    let [p0, p1, p2] = screen;
    let area = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
    if area.abs() < 1e-12 {
        return;
    }
    let surface = paint.surface;
    // A tile's size in pixels at unit depth, shrunk by how obliquely the face is seen.
    let tile_pixels = paint.tiling.map_or(0.0, |t| {
        let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
        let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
        let slant = normal
            .dot((projector.eye - centre).normalize_or_zero())
            .abs();
        t.tile() * projector.focal * slant
    });
    // Shadows only matter on faces the light reaches.
    let shadow = shadow.as_ref().filter(|_| surface.lambert > 0.0);
    let min_x = p0.x.min(p1.x).min(p2.x).floor().max(0.0) as u32;
    let max_x = p0.x.max(p1.x).max(p2.x).ceil().min(w - 1.0).max(0.0) as u32;
    let min_y = p0.y.min(p1.y).min(p2.y).floor().max(0.0) as u32;
    let max_y = p0.y.max(p1.y).max(p2.y).ceil().min(h - 1.0).max(0.0) as u32;
    for y in min_y..=max_y {
        for x in min_x..=max_x {
            let (px, py) = (x as Real + 0.5, y as Real + 0.5);
            let w0 = ((p1.x - px) * (p2.y - py) - (p1.y - py) * (p2.x - px)) / area;
            let w1 = ((p2.x - px) * (p0.y - py) - (p2.y - py) * (p0.x - px)) / area;
            let w2 = 1.0 - w0 - w1;
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            // Distance is affine in 1/z across the screen (perspective-correct depth).
            let (q0, q1, q2) = (w0 / p0.z, w1 / p1.z, w2 / p2.z);
            let z = 1.0 / (q0 + q1 + q2);
            let i = y as usize * image.width as usize + x as usize;
            if z < depth[i] {
                depth[i] = z;
                let point = (tri[0] * q0 + tri[1] * q1 + tri[2] * q2) * z;
                let lit = shadow.is_none_or(|map| map.is_lit(point));
                let colour = paint.tiling.map_or(surface.colour, |t| {
                    let keep = checker_contrast(tile_pixels / z);
                    let mean = 0.5 * (1.0 + CHECKER_SHADE);
                    toned(surface.colour, mean + (t.tone(point) - mean) * keep)
                });
                let shaded = shade(Surface { colour, ..surface }, lit);
                image.pixels[i] = paint.fog.apply(shaded, (point - projector.eye).length());
            }
        }
    }
}
