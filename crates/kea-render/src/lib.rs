//! Headless frames: a small CPU rasterizer (z-buffer, Lambert shading from one directional
//! light, two-sided faces) that draws every collider of a scene into an RGB image and writes PNG.
//! It needs no GPU and no display, and the same input always gives the same pixels, so tests
//! can check pixels at known places.

#![warn(missing_docs)]

use kea::{Real, Vec3, World};
use kea_collision::CollisionWorld;

/// A pinhole camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Where the eye is.
    pub eye: Vec3,
    /// The point it looks at.
    pub target: Vec3,
    /// Which way is up.
    pub up: Vec3,
    /// Vertical field of view, rad.
    pub fov_y: Real,
}

impl Camera {
    /// A camera that frames every body of `world`: it looks at the middle of their positions
    /// from above and to the side, far enough to see them all.
    #[must_use]
    pub fn framing(world: &World) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY));
        for (_, b) in world.bodies() {
            lo = lo.min(b.position());
            hi = hi.max(b.position());
        }
        if lo.x > hi.x {
            (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
        }
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(2.0);
        let direction = Vec3::new(0.45, 0.8, 1.0).normalize();
        Self {
            eye: centre + direction * radius * 2.6,
            target: centre,
            up: Vec3::Y,
            fov_y: 0.8,
        }
    }
}

/// An RGB image, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels.
    pub pixels: Vec<[u8; 3]>,
}

/// The colour of the background (sky).
pub const SKY: [u8; 3] = [200, 220, 245];
/// The base colour of static geometry.
pub const STATIC_COLOUR: [u8; 3] = [150, 150, 145];
/// Base colours of bodies, by collider order.
pub const BODY_COLOURS: [[u8; 3]; 6] = [
    [220, 90, 60],
    [70, 140, 220],
    [240, 190, 60],
    [90, 190, 110],
    [170, 100, 200],
    [60, 190, 190],
];

impl Image {
    /// The pixel at column `x`, row `y` (row 0 at the top).
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Writes the image as an 8-bit RGB PNG.
    pub fn write_png(&self, path: &std::path::Path) -> Result<(), String> {
        let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
        let bytes: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        writer.write_image_data(&bytes).map_err(|e| e.to_string())
    }
}

/// Writes frames as an animated GIF (each frame quantised to 256 colours), `delay_cs`
/// hundredths of a second apart, looping forever. All frames must have the size of the first.
pub fn write_gif(frames: &[Image], delay_cs: u16, path: &std::path::Path) -> Result<(), String> {
    let first = frames.first().ok_or("no frames to write")?;
    let (w, h) = (first.width, first.height);
    let (gw, gh) = (
        u16::try_from(w).map_err(|_| "GIF width over 65535")?,
        u16::try_from(h).map_err(|_| "GIF height over 65535")?,
    );
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut encoder =
        gif::Encoder::new(std::io::BufWriter::new(file), gw, gh, &[]).map_err(|e| e.to_string())?;
    encoder
        .set_repeat(gif::Repeat::Infinite)
        .map_err(|e| e.to_string())?;
    for image in frames {
        if (image.width, image.height) != (w, h) {
            return Err("every GIF frame must have the same size".into());
        }
        let rgb: Vec<u8> = image.pixels.iter().flatten().copied().collect();
        let mut frame = gif::Frame::from_rgb_speed(gw, gh, &rgb, 10);
        frame.delay = delay_cs;
        encoder.write_frame(&frame).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Draws every collider of `collision` as `world` places it, seen from `camera`.
#[must_use]
pub fn render(
    world: &World,
    collision: &CollisionWorld,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Image {
    let (w, h) = (width.max(1), height.max(1));
    let mut image = Image {
        width: w,
        height: h,
        pixels: vec![SKY; (w * h) as usize],
    };
    let mut depth = vec![Real::INFINITY; (w * h) as usize];
    let projector = Projector::new(camera, w, h);
    let light = Vec3::new(0.4, 1.0, 0.3).normalize();
    let mut dynamic_index = 0;
    for (handle, def) in collision.colliders() {
        let Ok((position, rotation)) = collision.collider_pose(world, handle) else {
            continue;
        };
        let colour = if def.body.is_some() {
            dynamic_index += 1;
            BODY_COLOURS[(dynamic_index - 1) % BODY_COLOURS.len()]
        } else {
            STATIC_COLOUR
        };
        let (vertices, triangles) = def.shape.triangles();
        let world_vertices: Vec<Vec3> = vertices.iter().map(|v| position + rotation * *v).collect();
        for t in &triangles {
            let [a, b, c] = t.map(|k| world_vertices[k as usize]);
            let mut normal = (b - a).cross(c - a).normalize_or_zero();
            if normal.dot(camera.eye - a) < 0.0 {
                normal = -normal; // two-sided: light the face the camera sees
            }
            let shade = 0.3 + 0.7 * normal.dot(light).max(0.0);
            let lit = colour.map(|ch| (Real::from(ch) * shade).min(255.0) as u8);
            draw_triangle(&mut image, &mut depth, &projector, [a, b, c], lit);
        }
    }
    image
}

/// World to screen: pixel x and y (row 0 at the top) and the distance along the view direction.
struct Projector {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    focal: Real,
    half: (Real, Real),
}

impl Projector {
    fn new(camera: &Camera, width: u32, height: u32) -> Self {
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

/// Rasterizes one world-space triangle with a depth test; triangles reaching behind the eye are
/// skipped (scenes are framed so that nothing sits on the camera).
fn draw_triangle(
    image: &mut Image,
    depth: &mut [Real],
    projector: &Projector,
    tri: [Vec3; 3],
    colour: [u8; 3],
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
            let z = 1.0 / (w0 / p0.z + w1 / p1.z + w2 / p2.z);
            let i = (y * image.width + x) as usize;
            if z < depth[i] {
                depth[i] = z;
                image.pixels[i] = colour;
            }
        }
    }
}
