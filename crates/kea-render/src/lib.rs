//! Headless frames: a small CPU rasterizer (z-buffer, Lambert shading from one directional
//! light, shadows of the bodies from a shadow map, two-sided faces) that draws every collider of
//! a scene into an RGB image and writes PNG.
//! It needs no GPU and no display, and the same input always gives the same pixels, so tests
//! can check pixels at known places. [`car`] drives a scene's car for pictures of it moving
//! (the Viewer's arrow keys drive through it too).

#![warn(missing_docs)]

pub mod car;
mod framing;
mod look;
mod raster;
mod shadow;

pub use framing::{subject_bounds, subject_points, Bounds, Camera};
pub use look::{
    checker_contrast, joint_links, rod, tile_size, toned, Fog, Tiling, BODY_COLOURS, CHECKER_SHADE,
    GROUND_COLOUR, LINK_COLOUR, SKY, STATIC_COLOUR,
};
use raster::{draw_triangle, Paint, Projector};
pub use raster::{shade, Surface};
use shadow::ShadowMap;

use kea::{Real, Vec3, World};
use kea_collision::CollisionWorld;

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

impl Image {
    /// The pixel at column `x`, row `y` (row 0 at the top); panics outside the image.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Checks that the pixel count matches the size (the fields are public).
    fn check(&self) -> Result<(), String> {
        if self.pixels.len() as u64 != u64::from(self.width) * u64::from(self.height) {
            return Err(format!(
                "an image of {}×{} needs {} pixels, it has {}",
                self.width,
                self.height,
                u64::from(self.width) * u64::from(self.height),
                self.pixels.len()
            ));
        }
        Ok(())
    }

    /// The image as an 8-bit RGB PNG file's bytes.
    pub fn png_bytes(&self) -> Result<Vec<u8>, String> {
        self.check()?;
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
        let bytes: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        writer.write_image_data(&bytes).map_err(|e| e.to_string())?;
        writer.finish().map_err(|e| e.to_string())?;
        Ok(out)
    }

    /// Writes the image as an 8-bit RGB PNG (whole or not at all: see [`write_file`]).
    pub fn write_png(&self, path: &std::path::Path) -> Result<(), String> {
        write_file(path, &self.png_bytes()?)
    }
}

/// Writes `bytes` to `path` whole or not at all (see [`write_files`]).
pub fn write_file(path: &std::path::Path, bytes: &[u8]) -> Result<(), String> {
    write_files(&[(path, bytes)])
}

/// The temporary file beside `path` that an output is written into before it is renamed into
/// place (`name.kea-partial`); `None` if `path` names no file.
#[must_use]
pub fn partial_path(path: &std::path::Path) -> Option<std::path::PathBuf> {
    let mut name = path.file_name()?.to_os_string();
    name.push(".kea-partial");
    Some(path.with_file_name(name))
}

/// Writes several files all or none: each into a temporary file beside it, and only once every
/// one is complete are they renamed over their paths, so a failure (a full disk, a missing
/// folder) leaves no partial or half-set output. Errors name the path.
pub fn write_files(files: &[(&std::path::Path, &[u8])]) -> Result<(), String> {
    let mut written: Vec<std::path::PathBuf> = Vec::with_capacity(files.len());
    let clean = |written: &[std::path::PathBuf]| {
        for t in written {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, bytes) in files {
        let Some(temporary) = partial_path(path) else {
            clean(&written);
            return Err(format!("{}: not a file name", path.display()));
        };
        if let Err(e) = std::fs::write(&temporary, bytes) {
            let _ = std::fs::remove_file(&temporary);
            clean(&written);
            return Err(format!("{}: {e}", path.display()));
        }
        written.push(temporary);
    }
    for ((path, _), temporary) in files.iter().zip(&written) {
        if let Err(e) = std::fs::rename(temporary, path) {
            clean(&written);
            return Err(format!("{}: {e}", path.display()));
        }
    }
    Ok(())
}

/// An animated GIF built frame by frame in memory (compressed, so one frame's pixels at a
/// time), each frame quantised to 256 colours, looping forever.
pub struct GifWriter {
    encoder: gif::Encoder<Vec<u8>>,
    size: (u32, u32),
    delay_cs: u16,
}

impl GifWriter {
    /// A GIF of `width` × `height` frames shown `delay_cs` hundredths of a second each.
    pub fn new(width: u32, height: u32, delay_cs: u16) -> Result<Self, String> {
        let gw = u16::try_from(width).map_err(|_| format!("GIF width {width} is over 65535"))?;
        let gh = u16::try_from(height).map_err(|_| format!("GIF height {height} is over 65535"))?;
        let mut encoder = gif::Encoder::new(Vec::new(), gw, gh, &[]).map_err(|e| e.to_string())?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        Ok(Self {
            encoder,
            size: (width, height),
            delay_cs,
        })
    }

    /// Adds a frame, which must have the GIF's size.
    pub fn push(&mut self, image: &Image) -> Result<(), String> {
        image.check()?;
        if (image.width, image.height) != self.size {
            return Err(format!(
                "a {}×{} frame in a {}×{} GIF",
                image.width, image.height, self.size.0, self.size.1
            ));
        }
        let rgb: Vec<u8> = image.pixels.iter().flatten().copied().collect();
        // The size fits u16: `new` checked it.
        let (w, h) = (self.size.0 as u16, self.size.1 as u16);
        let mut frame = gif::Frame::from_rgb_speed(w, h, &rgb, 10);
        frame.delay = self.delay_cs;
        self.encoder.write_frame(&frame).map_err(|e| e.to_string())
    }

    /// The finished file's bytes.
    pub fn finish(self) -> Result<Vec<u8>, String> {
        self.encoder.into_inner().map_err(|e| e.to_string())
    }
}

/// Writes frames as an animated GIF (each frame quantised to 256 colours), `delay_cs`
/// hundredths of a second apart, looping forever. All frames must have the size of the first.
pub fn write_gif(frames: &[Image], delay_cs: u16, path: &std::path::Path) -> Result<(), String> {
    let first = frames.first().ok_or("no frames to write")?;
    let mut gif = GifWriter::new(first.width, first.height, delay_cs)?;
    for image in frames {
        gif.push(image)?;
    }
    write_file(path, &gif.finish()?)
}

/// The direction towards the light (unit): high, from the right and the front.
#[must_use]
pub fn light_direction() -> Vec3 {
    Vec3::new(0.4, 1.0, 0.3).normalize()
}

/// Draws every collider of `collision` as `world` places it, seen from `camera`: bodies in
/// their colours, static geometry in [`STATIC_COLOUR`], ground planes checkered, the links of
/// joints, shadows of everything that moves and distance fog.
#[must_use]
pub fn render(
    world: &World,
    collision: &CollisionWorld,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Image {
    let (w, h) = (width.max(1), height.max(1));
    let count = w as usize * h as usize;
    let mut image = Image {
        width: w,
        height: h,
        pixels: vec![SKY; count],
    };
    let mut depth = vec![Real::INFINITY; count];
    let projector = Projector::new(camera, w, h);
    let light = light_direction();
    let view = View::new(camera, h, scene_tile(world, collision));
    let triangles = world_triangles(world, collision, &view);
    let occluders = triangles.iter().filter(|t| t.casts).map(|t| t.corners);
    let shadow = ShadowMap::build(light, occluders);
    for t in &triangles {
        let [a, b, c] = t.corners;
        let mut normal = (b - a).cross(c - a).normalize_or_zero();
        if normal.dot(camera.eye - a) < 0.0 {
            normal = -normal; // two-sided: light the face the camera sees
        }
        let paint = Paint {
            surface: Surface {
                colour: t.colour,
                lambert: normal.dot(light).max(0.0),
            },
            tiling: t.tiling.as_ref(),
            fog: &view.fog,
        };
        draw_triangle(
            &mut image, &mut depth, &projector, t.corners, &paint, &shadow,
        );
    }
    image
}

/// The side of the ground's tiles for a scene: [`tile_size`] of its [`subject_bounds`].
#[must_use]
pub fn scene_tile(world: &World, collision: &CollisionWorld) -> Real {
    tile_size(subject_bounds(world, collision).radius())
}

/// What a picture needs to know of its camera besides the projection.
struct View {
    target: Vec3,
    /// How far the ground reaches from the target: past where the fog hides it.
    ground_reach: Real,
    fog: Fog,
    /// Half the width of joint links, m: about a pixel at the target's distance.
    link_radius: Real,
    tile: Real,
}

impl View {
    fn new(camera: &Camera, height: u32, tile: Real) -> Self {
        let distance = (camera.eye - camera.target).length();
        let fog = Fog::for_distance(distance);
        let pixel = 2.0 * distance * (camera.fov_y * 0.5).tan() / height.max(1) as Real;
        Self {
            target: camera.target,
            ground_reach: fog.far + distance,
            fog,
            link_radius: pixel,
            tile,
        }
    }
}

/// One triangle in world coordinates with its base colour.
struct WorldTriangle {
    corners: [Vec3; 3],
    colour: [u8; 3],
    /// How static geometry is checkered.
    tiling: Option<Tiling>,
    /// Whether it casts a shadow (bodies and joint links do).
    casts: bool,
}

/// Every collider's triangles placed in the world, bodies coloured by collider order, ground
/// planes as a checkered patch around the view's target, and the joints' links.
fn world_triangles(world: &World, collision: &CollisionWorld, view: &View) -> Vec<WorldTriangle> {
    let mut out = Vec::new();
    let mut dynamic_index = 0;
    for (handle, def) in collision.colliders() {
        let Ok((position, rotation)) = collision.collider_pose(world, handle) else {
            continue;
        };
        if let Some(tiling) = ground_tiling(def, view.tile) {
            let patch = tiling.patch(view.target, view.ground_reach, 16);
            out.extend(patch.into_iter().map(|corners| WorldTriangle {
                corners,
                colour: GROUND_COLOUR,
                tiling: Some(tiling),
                casts: false,
            }));
            continue;
        }
        let colour = if def.body.is_some() {
            dynamic_index += 1;
            BODY_COLOURS[(dynamic_index - 1) % BODY_COLOURS.len()]
        } else {
            STATIC_COLOUR
        };
        let (vertices, triangles) = def.shape.triangles();
        let placed: Vec<Vec3> = vertices.iter().map(|v| position + rotation * *v).collect();
        out.extend(triangles.iter().map(|t| {
            let corners = t.map(|k| placed[k as usize]);
            let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
            WorldTriangle {
                corners,
                colour,
                tiling: def.body.is_none().then(|| Tiling::face(normal, view.tile)),
                casts: def.body.is_some(),
            }
        }));
    }
    for [a, b] in joint_links(world) {
        out.extend(
            rod(a, b, view.link_radius)
                .into_iter()
                .map(|corners| WorldTriangle {
                    corners,
                    colour: LINK_COLOUR,
                    tiling: None,
                    casts: true,
                }),
        );
    }
    out
}

/// The tiling of a static plane collider (a ground), with tiles of side `tile`; `None` for
/// any other collider.
#[must_use]
pub fn ground_tiling(def: &kea_collision::ColliderDef, tile: Real) -> Option<Tiling> {
    if def.body.is_some() {
        return None;
    }
    let half_space = def.shape.parry_shape().as_halfspace()?;
    let normal = (def.rotation * Vec3::from(half_space.normal)).normalize_or_zero();
    Some(Tiling::plane(def.offset, normal, tile))
}
