//! Drawing a scene with macroquad: every collider as flat-shaded triangles lit by one
//! directional light, and the optional overlays (contacts, joint frames, islands, sleeping
//! bodies, the held point).

use crate::app::App;
use crate::convert::to_mq;
use crate::islands::Islands;
use kea::{BodyHandle, Quat, Real, Vec3};
use kea_collision::ColliderHandle;
use kea_render::{shade, Surface, BODY_COLOURS, STATIC_COLOUR};
use macroquad::color::Color;
use macroquad::math as mq;
use macroquad::models::{draw_line_3d, draw_mesh, Mesh, Vertex};
use std::collections::HashMap;

/// Vertices per draw call (macroquad indexes with u16 and batches up to its capacity).
pub const BATCH_VERTICES: usize = 9000;

/// What to draw besides the bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Toggles {
    /// Contact points and normals.
    pub contacts: bool,
    /// Joint frames: the bodies' axes and a line between jointed bodies.
    pub joints: bool,
    /// Colour bodies by island.
    pub islands: bool,
    /// Grey out sleeping bodies.
    pub sleeping: bool,
    /// Bodies' shadows on the ground plane.
    pub shadows: bool,
}

/// A collider's triangles in its own frame, kept between frames.
struct LocalMesh {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

/// The drawing state: cached meshes and the vertex batch.
pub struct Painter {
    meshes: HashMap<ColliderHandle, LocalMesh>,
    batch: Option<Mesh>,
    islands: Islands,
}

impl Default for Painter {
    fn default() -> Self {
        Self::new()
    }
}

impl Painter {
    /// An empty painter.
    #[must_use]
    pub fn new() -> Self {
        Self {
            meshes: HashMap::new(),
            batch: Some(Mesh {
                vertices: Vec::with_capacity(BATCH_VERTICES),
                indices: Vec::with_capacity(BATCH_VERTICES),
                texture: None,
            }),
            islands: Islands::default(),
        }
    }

    /// Forgets cached meshes (after a reset, handles may be reused by other shapes).
    pub fn clear(&mut self) {
        self.meshes.clear();
    }

    /// Draws every collider of the scene, from `eye`, at the interpolated poses; returns the
    /// number of triangles drawn.
    pub fn draw_scene(&mut self, app: &App, eye: Vec3, toggles: Toggles) -> usize {
        let mut count = 0;
        if toggles.islands {
            self.islands.rebuild(&app.scene.world);
        }
        let light = kea_render::light_direction();
        let collision = &app.scene.collision;
        let ground = toggles.shadows.then(|| ground_plane(app)).flatten();
        // Fewer segments on curved shapes when there are many bodies: a thousand balls at 16
        // segments is half a million triangles a frame.
        let bodies = collision.collider_count().max(1) as Real;
        let segments = (16.0 * (150.0 / bodies).sqrt()).clamp(6.0, 16.0) as u32;
        for (handle, def) in collision.colliders() {
            let (position, rotation) = match def.body {
                Some(b) => match app.body_pose(b) {
                    Some((x, q)) => (x + q * def.offset, q * def.rotation),
                    None => continue,
                },
                None => (def.offset, def.rotation),
            };
            let colour = self.colour_of(app, def.body, toggles);
            let mesh = self.meshes.entry(handle).or_insert_with(|| {
                let (vertices, triangles) = def.shape.triangles_with_segments(segments);
                LocalMesh {
                    vertices,
                    triangles,
                }
            });
            count += mesh.triangles.len();
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|k| position + rotation * mesh.vertices[k as usize]);
                if let (Some(plane), Some(_)) = (&ground, def.body) {
                    if let Some(shadow) = plane.shadow([a, b, c], light) {
                        push_triangle(&mut self.batch, shadow, plane.shadow_colour);
                    }
                }
                let mut normal = (b - a).cross(c - a).normalize_or_zero();
                if normal.dot(eye - a) < 0.0 {
                    normal = -normal; // two-sided: light the face the camera sees
                }
                let surface = Surface {
                    colour,
                    lambert: normal.dot(light).max(0.0),
                };
                let lit = shade(surface, true);
                push_triangle(&mut self.batch, [a, b, c], lit);
            }
        }
        flush(&mut self.batch);
        count
    }

    fn colour_of(&self, app: &App, body: Option<BodyHandle>, toggles: Toggles) -> [u8; 3] {
        let Some(b) = body else { return STATIC_COLOUR };
        if toggles.sleeping && app.scene.world.body(b).is_ok_and(|b| b.is_sleeping()) {
            return [90, 90, 110];
        }
        let index = if toggles.islands {
            self.islands.island_of(b).unwrap_or(0)
        } else {
            b.index() as usize
        };
        BODY_COLOURS[index % BODY_COLOURS.len()]
    }
}

/// The scene's ground: its first static plane, onto which bodies cast shadows.
struct Ground {
    point: Vec3,
    normal: Vec3,
    shadow_colour: [u8; 3],
}

impl Ground {
    /// A triangle's shadow on the plane along the light, lifted 3 mm so that it draws over
    /// the ground; none if a corner is below the plane or the light grazes it.
    fn shadow(&self, tri: [Vec3; 3], light: Vec3) -> Option<[Vec3; 3]> {
        let facing = light.dot(self.normal);
        if facing <= 0.05 {
            return None;
        }
        let mut out = [Vec3::ZERO; 3];
        for (o, p) in out.iter_mut().zip(tri) {
            let height = (p - self.point).dot(self.normal);
            if height < 0.0 {
                return None;
            }
            *o = p - light * (height / facing) + self.normal * 0.003;
        }
        Some(out)
    }
}

fn ground_plane(app: &App) -> Option<Ground> {
    let (_, def) = app
        .scene
        .collision
        .colliders()
        .find(|(_, d)| d.body.is_none() && d.shape.kind_name() == "plane")?;
    let half_space = def.shape.parry_shape().as_halfspace()?;
    let normal = (def.rotation * Vec3::from(half_space.normal)).normalize_or_zero();
    // Ground in shadow gets the ambient light and a share of the direct light, as in
    // `kea render`.
    let surface = Surface {
        colour: STATIC_COLOUR,
        lambert: normal.dot(kea_render::light_direction()).max(0.0),
    };
    Some(Ground {
        point: def.offset,
        normal,
        shadow_colour: shade(surface, false),
    })
}

fn push_triangle(batch: &mut Option<Mesh>, tri: [Vec3; 3], colour: [u8; 3]) {
    if batch
        .as_ref()
        .is_some_and(|m| m.vertices.len() + 3 > BATCH_VERTICES)
    {
        flush(batch);
    }
    let Some(mesh) = batch else { return };
    let base = mesh.vertices.len() as u16;
    for p in tri {
        mesh.vertices.push(Vertex {
            position: to_mq(p),
            uv: mq::Vec2::ZERO,
            color: [colour[0], colour[1], colour[2], 255],
            normal: mq::Vec4::ZERO,
        });
    }
    mesh.indices.extend([base, base + 1, base + 2]);
}

fn flush(batch: &mut Option<Mesh>) {
    if let Some(mesh) = batch {
        if !mesh.vertices.is_empty() {
            draw_mesh(mesh);
            mesh.vertices.clear();
            mesh.indices.clear();
        }
    }
}

/// Contact points (a dot) and normals (a line 0.25 m long).
pub fn draw_contacts(app: &App) {
    let red = Color::new(0.9, 0.1, 0.1, 1.0);
    for (_, contact, _) in app.scene.world.contacts() {
        let p = contact.position();
        let n = contact.normal();
        draw_line_3d(to_mq(p), to_mq(p + n * 0.25), red);
        draw_cross(p, 0.04, red);
    }
}

/// Each jointed body's axes (red x, green y, blue z) and a line between the joint's bodies.
pub fn draw_joints(app: &App) {
    let world = &app.scene.world;
    for (_, bodies) in world.enabled_joints() {
        let poses: Vec<(Vec3, Quat)> = bodies
            .iter()
            .flatten()
            .filter_map(|b| app.body_pose(*b))
            .collect();
        for (x, q) in &poses {
            draw_axes(*x, *q, 0.3);
        }
        if let [(a, _), (b, _)] = poses[..] {
            draw_line_3d(to_mq(a), to_mq(b), Color::new(1.0, 0.85, 0.1, 1.0));
        }
    }
}

/// The held point and a line to it from the held body.
pub fn draw_drag(app: &App) {
    if let Some(p) = app.drag_point() {
        draw_cross(p, 0.08, Color::new(1.0, 0.9, 0.0, 1.0));
    }
}

fn draw_axes(x: Vec3, q: Quat, length: Real) {
    let colours = [
        Color::new(0.9, 0.1, 0.1, 1.0),
        Color::new(0.1, 0.8, 0.1, 1.0),
        Color::new(0.1, 0.2, 0.9, 1.0),
    ];
    for (axis, colour) in [Vec3::X, Vec3::Y, Vec3::Z].into_iter().zip(colours) {
        draw_line_3d(to_mq(x), to_mq(x + q * axis * length), colour);
    }
}

fn draw_cross(p: Vec3, size: Real, colour: Color) {
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        draw_line_3d(to_mq(p - axis * size), to_mq(p + axis * size), colour);
    }
}
