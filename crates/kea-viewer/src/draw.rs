//! Drawing a scene with macroquad, in the look `kea render` uses (see `kea_render::look`): a
//! checkered ground that fades into the sky, checkered static geometry in its own colour,
//! bodies flat-shaded by one directional light, their shadows on every static surface, the
//! links of joints, and on top the optional gizmos (joints, contacts, the held point).

use crate::app::App;
use crate::convert::{to_f64, to_mq};
use crate::gizmos::{Gizmos, Piece};
use crate::islands::Islands;
use crate::shadows::Receivers;
use kea::{BodyHandle, Real, Vec3};
use kea_collision::ColliderHandle;
use kea_render::{
    joint_links, rod, shade, Fog, Surface, Tiling, BODY_COLOURS, GROUND_COLOUR, LINK_COLOUR, SKY,
    STATIC_COLOUR,
};
use macroquad::math as mq;
use macroquad::models::{draw_mesh, Mesh, Vertex};
use macroquad::texture::Texture2D;
use std::collections::HashMap;

/// Vertices per draw call (macroquad indexes with u16 and batches up to its capacity).
pub const BATCH_VERTICES: usize = 9000;
/// How dark a shadow is: the share of the surface's light it takes away.
pub const SHADOW_ALPHA: u8 = 100;
/// Squares per side of the ground patch (the fog is interpolated between their corners).
pub const GROUND_CELLS: u32 = 32;

/// What to draw besides the bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Toggles {
    /// Contact points and normals scaled by force.
    pub contacts: bool,
    /// Joint gizmos: anchors, axes and limit ranges.
    pub joints: bool,
    /// Colour bodies by island.
    pub islands: bool,
    /// Grey out sleeping bodies.
    pub sleeping: bool,
    /// Bodies' shadows on the static geometry.
    pub shadows: bool,
}

/// A collider's triangles in its own frame, kept between frames.
struct LocalMesh {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

/// A batch of triangles drawn in one call, with or without the checker texture.
struct Batch {
    mesh: Mesh,
}

impl Batch {
    fn new(texture: Option<Texture2D>) -> Self {
        Self {
            mesh: Mesh {
                vertices: Vec::with_capacity(BATCH_VERTICES),
                indices: Vec::with_capacity(BATCH_VERTICES),
                texture,
            },
        }
    }

    /// Adds a triangle: corners, colours with alpha, and texture coordinates.
    fn push(&mut self, tri: [Vec3; 3], colours: [[u8; 4]; 3], uv: [(Real, Real); 3]) {
        if self.mesh.vertices.len() + 3 > BATCH_VERTICES {
            self.flush();
        }
        let base = self.mesh.vertices.len() as u16;
        for ((p, colour), (u, v)) in tri.into_iter().zip(colours).zip(uv) {
            self.mesh.vertices.push(Vertex {
                position: to_mq(p),
                uv: mq::Vec2::new(to_f64(u) as f32, to_f64(v) as f32),
                color: colour,
                normal: mq::Vec4::ZERO,
            });
        }
        self.mesh.indices.extend([base, base + 1, base + 2]);
    }

    fn push_flat(&mut self, tri: [Vec3; 3], colour: [u8; 3]) {
        let c = [colour[0], colour[1], colour[2], 255];
        self.push(tri, [c; 3], [(0.0, 0.0); 3]);
    }

    fn flush(&mut self) {
        if !self.mesh.vertices.is_empty() {
            draw_mesh(&self.mesh);
            self.mesh.vertices.clear();
            self.mesh.indices.clear();
        }
    }
}

/// The drawing state: cached meshes, the checker texture and the batches.
pub struct Painter {
    meshes: HashMap<ColliderHandle, LocalMesh>,
    statics: Batch,
    shadows: Batch,
    bodies: Batch,
    islands: Islands,
    receivers: Option<Receivers>,
    tile: Real,
    corners: Vec<Vec3>,
}

/// Where the scene is seen from, this frame.
#[derive(Debug, Clone, Copy)]
pub struct Eye {
    /// The eye.
    pub position: Vec3,
    /// The point looked at.
    pub target: Vec3,
}

impl Painter {
    /// An empty painter drawing static geometry with `checker` (see [`checker_texture`]).
    #[must_use]
    pub fn new(checker: Option<Texture2D>) -> Self {
        Self {
            meshes: HashMap::new(),
            statics: Batch::new(checker),
            shadows: Batch::new(None),
            bodies: Batch::new(None),
            islands: Islands::default(),
            receivers: None,
            tile: 1.0,
            corners: Vec::new(),
        }
    }

    /// Forgets cached meshes and static geometry (after a reset or a reload, handles may be
    /// reused by other shapes).
    pub fn clear(&mut self) {
        self.meshes.clear();
        self.receivers = None;
    }

    /// Draws the scene from `eye` at the interpolated poses; returns the number of triangles
    /// drawn.
    pub fn draw_scene(&mut self, app: &App, eye: Eye, toggles: Toggles) -> usize {
        let world = app.physics.dynamics();
        let collision = app.physics.collision();
        if self.receivers.is_none() {
            self.receivers = Some(Receivers::new(world, collision));
            self.tile = kea_render::scene_tile(world, collision);
        }
        if toggles.islands {
            self.islands.rebuild(world);
        }
        let fog = Fog::for_distance((eye.position - eye.target).length());
        let light = kea_render::light_direction();
        let mut count = self.draw_statics(app, eye, &fog, light);
        // Fewer segments on curved shapes when there are many bodies: a thousand balls at 16
        // segments is half a million triangles a frame.
        let bodies = collision.collider_count().max(1) as Real;
        let segments = (16.0 * (150.0 / bodies).sqrt()).clamp(6.0, 16.0) as u32;
        for (handle, def) in collision.colliders() {
            let Some(body) = def.body else { continue };
            let Some((x, q)) = app.body_pose(body) else {
                continue;
            };
            let (position, rotation) = (x + q * def.offset, q * def.rotation);
            let colour = self.colour_of(app, body, toggles);
            let mesh = self.meshes.entry(handle).or_insert_with(|| {
                let (vertices, triangles) = def.shape.triangles_with_segments(segments);
                LocalMesh {
                    vertices,
                    triangles,
                }
            });
            count += mesh.triangles.len();
            self.corners.clear();
            self.corners
                .extend(mesh.vertices.iter().map(|v| position + rotation * *v));
            for t in &mesh.triangles {
                let tri = t.map(|k| self.corners[k as usize]);
                let surface = lit_surface(tri, eye.position, light, colour);
                let lit = fog.apply(shade(surface, true), (tri[0] - eye.position).length());
                self.bodies.push_flat(tri, lit);
            }
            if toggles.shadows {
                if let Some(receivers) = &self.receivers {
                    let caster = (&self.corners[..], &mesh.triangles[..]);
                    cast_shadow(app, receivers, caster, light, &mut self.shadows);
                }
            }
        }
        let link_radius = 0.0012 * (eye.position - eye.target).length();
        for [a, b] in joint_links(world) {
            for tri in rod(a, b, link_radius) {
                let surface = lit_surface(tri, eye.position, light, LINK_COLOUR);
                self.bodies.push_flat(tri, shade(surface, true));
            }
        }
        self.shadows.flush();
        self.bodies.flush();
        count
    }

    /// Ground planes as a checkered patch around the target out to where the fog ends, and
    /// every other static collider checkered in [`STATIC_COLOUR`]; fog fades them into the
    /// sky.
    fn draw_statics(&mut self, app: &App, eye: Eye, fog: &Fog, light: Vec3) -> usize {
        let collision = app.physics.collision();
        let reach = fog.far + (eye.position - eye.target).length();
        let mut count = 0;
        for (handle, def) in collision.colliders() {
            if def.body.is_some() {
                continue;
            }
            let Ok((position, rotation)) = collision.collider_pose(app.physics.dynamics(), handle)
            else {
                continue;
            };
            let triangles: Vec<([Vec3; 3], Tiling, [u8; 3])> =
                match kea_render::ground_tiling(def, self.tile) {
                    Some(tiling) => tiling
                        .patch(eye.target, reach, GROUND_CELLS)
                        .into_iter()
                        .map(|t| (t, tiling, GROUND_COLOUR))
                        .collect(),
                    None => {
                        let (vertices, triangles) = def.shape.triangles();
                        triangles
                            .iter()
                            .map(|t| {
                                let tri = t.map(|k| position + rotation * vertices[k as usize]);
                                let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                                (tri, Tiling::face(normal, self.tile), STATIC_COLOUR)
                            })
                            .collect()
                    }
                };
            count += triangles.len();
            for (tri, tiling, colour) in triangles {
                let surface = lit_surface(tri, eye.position, light, colour);
                let [r, g, b] = shade(surface, true);
                let colours = tri.map(|p| {
                    let clear = 1.0 - fog.amount((p - eye.position).length());
                    [r, g, b, (clear * 255.0).round() as u8]
                });
                // The texture holds 2 × 2 tiles.
                let uv = tri.map(|p| {
                    let (a, b) = tiling.coordinates(p);
                    (a * 0.5, b * 0.5)
                });
                self.statics.push(tri, colours, uv);
            }
        }
        self.statics.flush();
        count
    }

    fn colour_of(&self, app: &App, b: BodyHandle, toggles: Toggles) -> [u8; 3] {
        if toggles.sleeping
            && app
                .physics
                .dynamics()
                .body(b)
                .is_ok_and(|b| b.is_sleeping())
        {
            return [90, 90, 110];
        }
        let index = if toggles.islands {
            self.islands.island_of(b).unwrap_or(0)
        } else {
            b.index() as usize
        };
        BODY_COLOURS[index % BODY_COLOURS.len()]
    }

    /// Draws gizmo triangles with no depth test, so that they show through bodies.
    pub fn draw_on_top(&mut self, pieces: &[Piece]) {
        self.bodies.flush();
        // SAFETY: macroquad's context is live on this (its only) thread while a frame is drawn.
        let gl = unsafe { macroquad::window::get_internal_gl() };
        gl.quad_gl.depth_test(false);
        for (tri, colour) in pieces {
            self.bodies.push_flat(*tri, *colour);
        }
        self.bodies.flush();
        gl.quad_gl.depth_test(true);
    }
}

/// The light-facing triangles of one collider (its placed `corners` and `triangles`), carried
/// along the light onto the static surfaces below them as translucent dark triangles.
fn cast_shadow(
    app: &App,
    receivers: &Receivers,
    (corners, triangles): (&[Vec3], &[[u32; 3]]),
    light: Vec3,
    out: &mut Batch,
) {
    if receivers.is_empty() {
        return;
    }
    let (world, collision) = (app.physics.dynamics(), app.physics.collision());
    let dropped: Vec<Option<Vec3>> = corners
        .iter()
        .map(|p| receivers.shadow_of(world, collision, *p, light))
        .collect();
    let dark = [0, 0, 0, SHADOW_ALPHA];
    for t in triangles {
        let tri = t.map(|k| corners[k as usize]);
        // A convex shape's light-facing faces cover its shadow exactly once.
        if (tri[1] - tri[0]).cross(tri[2] - tri[0]).dot(light) <= 0.0 {
            continue;
        }
        if let [Some(a), Some(b), Some(c)] = t.map(|k| dropped[k as usize]) {
            out.push([a, b, c], [dark; 3], [(0.0, 0.0); 3]);
        }
    }
}

/// How a triangle of `colour` is lit, seen from `eye` (two-sided: the face the camera sees).
fn lit_surface(tri: [Vec3; 3], eye: Vec3, light: Vec3, colour: [u8; 3]) -> Surface {
    let mut normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
    if normal.dot(eye - tri[0]) < 0.0 {
        normal = -normal;
    }
    Surface {
        colour,
        lambert: normal.dot(light).max(0.0),
    }
}

/// The checker texture static geometry is drawn with: 2 × 2 tiles, light and
/// [`kea_render::CHECKER_SHADE`] dark, repeating, mipmapped so far tiles fade to their mean
/// instead of shimmering. Vertex colours tint it.
#[must_use]
pub fn checker_texture() -> Texture2D {
    use macroquad::miniquad::{
        FilterMode, MipmapFilterMode, TextureAccess, TextureFormat, TextureParams, TextureSource,
        TextureWrap,
    };
    const SIDE: usize = 64;
    let dark = (255.0 * kea_render::CHECKER_SHADE).round() as u8;
    let mut bytes = Vec::with_capacity(SIDE * SIDE * 4);
    for y in 0..SIDE {
        for x in 0..SIDE {
            let tone = if (x < SIDE / 2) == (y < SIDE / 2) {
                255
            } else {
                dark
            };
            bytes.extend([tone, tone, tone, 255]);
        }
    }
    let params = TextureParams {
        format: TextureFormat::RGBA8,
        wrap: TextureWrap::Repeat,
        min_filter: FilterMode::Linear,
        mag_filter: FilterMode::Nearest,
        mipmap_filter: MipmapFilterMode::Linear,
        width: SIDE as u32,
        height: SIDE as u32,
        allocate_mipmaps: true,
        ..TextureParams::default()
    };
    // SAFETY: called on macroquad's thread once its window is up.
    let gl = unsafe { macroquad::window::get_internal_gl() };
    let id =
        gl.quad_context
            .new_texture(TextureAccess::Static, TextureSource::Bytes(&bytes), params);
    gl.quad_context.texture_generate_mipmaps(id);
    Texture2D::from_miniquad_texture(id)
}

/// The sky's colour for `clear_background`.
#[must_use]
pub fn sky() -> macroquad::color::Color {
    let [r, g, b] = SKY.map(|c| f32::from(c) / 255.0);
    macroquad::color::Color::new(r, g, b, 1.0)
}

/// Gizmos for this frame: joints and contacts as the toggles ask, and the held point.
#[must_use]
pub fn gizmos(app: &App, eye: Vec3, toggles: Toggles, weight: Real, length: Real) -> Gizmos {
    let mut g = Gizmos::new(eye);
    if toggles.joints {
        g.joints(app);
    }
    if toggles.contacts {
        g.contacts(app, weight, length);
    }
    if let Some(p) = app.drag_point() {
        g.point(p, [255, 230, 0]);
    }
    g
}
