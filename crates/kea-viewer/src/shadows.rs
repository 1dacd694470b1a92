//! Shadows on every static surface: each corner of a body's light-facing triangles is carried
//! along the light onto the first static collider below it (a ground plane exactly, any other
//! shape by a ray cast against it), so a shadow lies on steps, ramps and height fields alike.

use kea::{Real, Vec3, World};
use kea_collision::{ColliderHandle, CollisionWorld};
use kea_render::Bounds;

/// How far a shadow floats above the surface it falls on, m, so it draws over it.
pub const LIFT: Real = 0.004;
/// How far below a point a shadow is looked for, m.
pub const REACH: Real = 1.0e3;

/// A static collider shadows can fall on.
enum Receiver {
    /// A ground plane, met in closed form.
    Plane { point: Vec3, normal: Vec3 },
    /// Any other static shape, met by a ray cast where the ray passes its box.
    Solid {
        collider: ColliderHandle,
        bounds: Bounds,
    },
}

/// The static geometry of a scene, as shadows see it (static colliders never move).
pub struct Receivers {
    list: Vec<Receiver>,
}

impl Receivers {
    /// The static colliders of `collision`.
    #[must_use]
    pub fn new(world: &World, collision: &CollisionWorld) -> Self {
        let mut list = Vec::new();
        for (handle, def) in collision.colliders() {
            if def.body.is_some() {
                continue;
            }
            if let Some(h) = def.shape.parry_shape().as_halfspace() {
                let normal = (def.rotation * Vec3::from(h.normal)).normalize_or_zero();
                list.push(Receiver::Plane {
                    point: def.offset,
                    normal,
                });
                continue;
            }
            let Ok((position, rotation)) = collision.collider_pose(world, handle) else {
                continue;
            };
            let mut bounds = Bounds::EMPTY;
            for v in def.shape.triangles().0 {
                bounds.add(position + rotation * v);
            }
            list.push(Receiver::Solid {
                collider: handle,
                bounds,
            });
        }
        Self { list }
    }

    /// Whether there is anything to cast shadows on.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Where the shadow of `p` falls, lit along unit `light` (pointing towards the light):
    /// the nearest static surface below `p` along −light, lifted by [`LIFT`] off it.
    #[must_use]
    pub fn shadow_of(
        &self,
        world: &World,
        collision: &CollisionWorld,
        p: Vec3,
        light: Vec3,
    ) -> Option<Vec3> {
        let down = -light;
        let mut best: Option<(Real, Vec3)> = None;
        for r in &self.list {
            let hit = match r {
                Receiver::Plane { point, normal } => {
                    let height = (p - *point).dot(*normal);
                    let facing = light.dot(*normal);
                    (height >= 0.0 && facing > 0.05).then(|| (height / facing, *normal))
                }
                Receiver::Solid { collider, bounds } => {
                    if !ray_meets_box(p, down, bounds) {
                        continue;
                    }
                    match collision.cast_ray_at(
                        world,
                        *collider,
                        &kea_collision::RayCast::new(p, down, REACH),
                    ) {
                        Ok(Some(hit)) => Some((hit.distance, hit.normal)),
                        _ => None,
                    }
                }
            };
            if let Some((t, normal)) = hit {
                if best.is_none_or(|(b, _)| t < b) {
                    best = Some((t, normal));
                }
            }
        }
        best.map(|(t, normal)| p + down * t + normal * LIFT)
    }
}

/// Whether the ray from `origin` along `direction` passes through `bounds` (slab test).
fn ray_meets_box(origin: Vec3, direction: Vec3, bounds: &Bounds) -> bool {
    let (mut near, mut far) = (0.0 as Real, REACH);
    for k in 0..3 {
        let (o, d, lo, hi) = (origin[k], direction[k], bounds.lo[k], bounds.hi[k]);
        if d.abs() < 1e-12 {
            if o < lo || o > hi {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo - o) / d, (hi - o) / d);
        near = near.max(a.min(b));
        far = far.min(a.max(b));
        if near > far {
            return false;
        }
    }
    true
}
