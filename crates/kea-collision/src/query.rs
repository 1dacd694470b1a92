//! Scene queries: ray casts (closest, any, all), shape casts, overlap tests and point
//! projection, each with a [`QueryFilter`]. Each query tests the colliders whose bounds it can
//! reach, in slot order, so equal inputs give equal answers.

use crate::cast_window::{height_field_window, Window, MAX_CAST_CELLS};
use crate::collision_world::{
    collider_pose, handle_of, ColliderDef, ColliderHandle, CollisionWorld,
};
use crate::error::{
    check_non_negative, check_unit_quat, check_vec3, CollisionError, CollisionResult,
};
use crate::guard::guarded;
use crate::parry::math::Pose;
use crate::parry::query::{self, Ray, RayCast as _, ShapeCastOptions};
use crate::shape::Shape;
use kea::{BodyHandle, Quat, Real, Vec3, World};

/// Which colliders a query sees: those whose groups meet `mask` and, if set, not on `exclude`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QueryFilter {
    /// Groups (bits) the query sees.
    pub mask: u32,
    /// A body whose colliders are skipped (say, the character casting the ray).
    pub exclude: Option<BodyHandle>,
}

impl Default for QueryFilter {
    /// Sees everything.
    fn default() -> Self {
        Self {
            mask: u32::MAX,
            exclude: None,
        }
    }
}

impl QueryFilter {
    fn accepts(&self, def: &ColliderDef) -> bool {
        def.groups & self.mask != 0 && (self.exclude.is_none() || def.body != self.exclude)
    }
}

/// Where a ray met a collider.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayHit {
    /// The collider hit.
    pub collider: ColliderHandle,
    /// Distance along the ray, in units of the direction's length.
    pub distance: Real,
    /// The hit point, world frame.
    pub point: Vec3,
    /// The surface normal there, world frame.
    pub normal: Vec3,
}

impl RayHit {
    fn new(collider: ColliderHandle, ray: &Ray, hit: query::RayIntersection) -> Self {
        Self {
            collider,
            distance: hit.time_of_impact,
            point: ray.point_at(hit.time_of_impact),
            normal: hit.normal,
        }
    }
}

/// A ray `origin + t·direction` for `0 ≤ t ≤ max_distance` (distances in units of the
/// direction's length), as the ray queries take it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayCast {
    /// Where the ray starts, world frame.
    pub origin: Vec3,
    /// Its direction (any length but zero), world frame.
    pub direction: Vec3,
    /// How far along it to look.
    pub max_distance: Real,
}

impl RayCast {
    /// The ray from `origin` along `direction`, up to `max_distance`.
    #[must_use]
    pub fn new(origin: Vec3, direction: Vec3, max_distance: Real) -> Self {
        Self {
            origin,
            direction,
            max_distance,
        }
    }

    /// Checks the ray before anything reaches parry; parry's ray.
    fn checked(&self) -> CollisionResult<Ray> {
        check_path(RAY_ARGS, self.origin, self.direction, self.max_distance)?;
        Ok(Ray::new(self.origin, self.direction))
    }
}

/// A shape swept from a pose along `velocity` for `0 ≤ t ≤ max_time`.
#[derive(Debug, Clone)]
pub struct ShapeCast {
    /// The moving shape.
    pub shape: Shape,
    /// Its start position, world frame.
    pub position: Vec3,
    /// Its orientation (kept through the sweep).
    pub rotation: Quat,
    /// Its velocity, m per unit time.
    pub velocity: Vec3,
    /// How far in time to sweep.
    pub max_time: Real,
}

/// Where a moving shape first touches a collider.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeHit {
    /// The collider touched.
    pub collider: ColliderHandle,
    /// Time of impact, in units of the cast's velocity (the fraction of `velocity` travelled).
    pub time: Real,
    /// The first touching point on the collider, world frame.
    pub point: Vec3,
    /// The collider's outward normal there, world frame.
    pub normal: Vec3,
}

/// The nearest surface point of a collider to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointHit {
    /// The collider.
    pub collider: ColliderHandle,
    /// The nearest point on its surface (the query point itself when inside and solid).
    pub point: Vec3,
    /// Whether the query point is inside the collider.
    pub inside: bool,
    /// Distance from the query point to `point`.
    pub distance: Real,
}

impl CollisionWorld {
    /// Every collider a filter accepts, with its world pose.
    fn visible<'a>(
        &'a self,
        world: &'a World,
        filter: QueryFilter,
    ) -> impl Iterator<Item = (ColliderHandle, &'a ColliderDef, Pose)> + 'a {
        self.slots.iter().enumerate().filter_map(move |(i, s)| {
            let def = &s.collider.as_ref()?.def;
            if def.body.is_some_and(|b| world.body(b).is_err()) || !filter.accepts(def) {
                return None;
            }
            Some((
                handle_of(&self.slots, i as u32),
                def,
                collider_pose(world, def),
            ))
        })
    }

    /// Every hit of the ray `origin + t·direction`, `0 ≤ t ≤ max_distance`, one per collider,
    /// nearest first. Solid shapes: a ray starting inside one hits it at `t = 0`.
    pub fn cast_ray_all(
        &self,
        world: &World,
        cast: &RayCast,
        filter: QueryFilter,
    ) -> CollisionResult<Vec<RayHit>> {
        let ray = cast.checked()?;
        let (direction, max_distance) = (cast.direction, cast.max_distance);
        if direction.length_squared() == 0.0 {
            return Err(kea::KeaError::NotUnit {
                arg: "direction",
                value: format!("{direction}"),
                length: 0.0,
            }
            .into());
        }
        let mut hits = Vec::new();
        for (collider, def, pose) in self.visible(world, filter) {
            let shape = def.shape.shared.as_ref();
            let hit = guarded(|| {
                let aabb = shape.compute_aabb(&pose);
                aabb.cast_local_ray(&ray, max_distance, true)?;
                shape.cast_ray_and_get_normal(&pose, &ray, max_distance, true)
            })
            .map_err(|message| dependency("cast_ray", collider, message))?;
            if let Some(hit) = hit {
                hits.push(RayHit::new(collider, &ray, hit));
            }
        }
        hits.sort_by(|a, b| {
            a.distance
                .total_cmp(&b.distance)
                .then(a.collider.cmp(&b.collider))
        });
        Ok(hits)
    }

    /// The nearest hit of the ray, if any.
    pub fn cast_ray(
        &self,
        world: &World,
        cast: &RayCast,
        filter: QueryFilter,
    ) -> CollisionResult<Option<RayHit>> {
        Ok(self.cast_ray_all(world, cast, filter)?.into_iter().next())
    }

    /// Whether the ray hits anything (stops at the first collider found).
    pub fn cast_ray_any(
        &self,
        world: &World,
        cast: &RayCast,
        filter: QueryFilter,
    ) -> CollisionResult<bool> {
        let ray = cast.checked()?;
        let max_distance = cast.max_distance;
        for (collider, def, pose) in self.visible(world, filter) {
            let shape = def.shape.shared.as_ref();
            let hit = guarded(|| shape.cast_ray(&pose, &ray, max_distance, true))
                .map_err(|message| dependency("cast_ray_any", collider, message))?;
            if hit.is_some() {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// The ray's hit on one collider, if any: for callers that already know which colliders
    /// they want (a viewer casting shadows onto the static geometry) and must not allocate.
    pub fn cast_ray_at(
        &self,
        world: &World,
        collider: ColliderHandle,
        cast: &RayCast,
    ) -> CollisionResult<Option<RayHit>> {
        let ray = cast.checked()?;
        let max_distance = cast.max_distance;
        let def = self.collider(collider)?;
        let (position, rotation) = self.collider_pose(world, collider)?;
        let pose = Pose::from_parts(position, rotation);
        let shape = def.shape.shared.as_ref();
        let hit = guarded(|| shape.cast_ray_and_get_normal(&pose, &ray, max_distance, true))
            .map_err(|message| dependency("cast_ray_at", collider, message))?;
        Ok(hit.map(|hit| RayHit::new(collider, &ray, hit)))
    }

    /// Sweeps a shape along a straight path and returns the first collider it touches.
    pub fn cast_shape(
        &self,
        world: &World,
        cast: &ShapeCast,
        filter: QueryFilter,
    ) -> CollisionResult<Option<ShapeHit>> {
        let ShapeCast {
            shape,
            position,
            rotation,
            velocity,
            max_time,
        } = cast;
        let (position, velocity, max_time) = (*position, *velocity, *max_time);
        check_path(
            ["position", "velocity", "max_time"],
            position,
            velocity,
            max_time,
        )?;
        if shape.kind_name() == "plane" {
            return Err(kea::KeaError::InvalidState {
                operation: "cast_shape",
                reason: "a plane is unbounded and cannot be swept: cast a bounded shape",
            }
            .into());
        }
        let rotation = check_unit_quat("rotation", *rotation)?;
        let pose = Pose::from_parts(position, rotation);
        let mut best: Option<ShapeHit> = None;
        for (collider, def, other) in self.visible(world, filter) {
            let target = def.shape.shared.as_ref();
            let (start, end) = match cast_times(shape, &pose, velocity, max_time, target, &other) {
                Window::Miss => continue,
                Window::Times(start, end) => (start, end),
                Window::TooLong(cells) => {
                    return Err(CollisionError::QueryTooLong {
                        operation: "cast_shape",
                        reason: format!(
                            "its path crosses {cells:.3e} height-field cells of collider \
                             {collider:?} (at most {MAX_CAST_CELLS:e}): shorten `max_time`"
                        ),
                    })
                }
            };
            let from = Pose::from_parts(position + velocity * start, rotation);
            let options = ShapeCastOptions::with_max_time_of_impact(end - start);
            let cast = guarded(|| {
                query::cast_shapes(
                    &from,
                    velocity,
                    shape.shared.as_ref(),
                    &other,
                    Vec3::ZERO,
                    target,
                    options,
                )
            })
            .map_err(|message| dependency("cast_shape", collider, message))?;
            let Ok(Some(hit)) = cast else {
                continue;
            };
            let time = start + hit.time_of_impact;
            if best.is_none_or(|b| time < b.time) {
                best = Some(ShapeHit {
                    collider,
                    time,
                    point: other.transform_point(hit.witness2),
                    normal: other.rotation * hit.normal2,
                });
            }
        }
        Ok(best)
    }

    /// Every collider that overlaps `shape` placed at `position`/`rotation`, in slot order.
    pub fn overlaps(
        &self,
        world: &World,
        shape: &Shape,
        position: Vec3,
        rotation: Quat,
        filter: QueryFilter,
    ) -> CollisionResult<Vec<ColliderHandle>> {
        kea::error::check_coordinate("position", position)?;
        let rotation = check_unit_quat("rotation", rotation)?;
        let pose = Pose::from_parts(position, rotation);
        let mut found = Vec::new();
        for (collider, def, other) in self.visible(world, filter) {
            let target = def.shape.shared.as_ref();
            let test =
                guarded(|| query::intersection_test(&pose, shape.shared.as_ref(), &other, target))
                    .map_err(|message| dependency("overlaps", collider, message))?;
            if test.is_ok_and(|i| i.intersecting) {
                found.push(collider);
            }
        }
        Ok(found)
    }

    /// The collider surface nearest to `point` (within `max_distance`).
    pub fn project_point(
        &self,
        world: &World,
        point: Vec3,
        max_distance: Real,
        filter: QueryFilter,
    ) -> CollisionResult<Option<PointHit>> {
        kea::error::check_coordinate("point", point)?;
        check_non_negative("max_distance", max_distance)?;
        let mut best: Option<PointHit> = None;
        for (collider, def, pose) in self.visible(world, filter) {
            let shape = def.shape.shared.as_ref();
            let p = guarded(|| shape.project_point(&pose, point, true))
                .map_err(|message| dependency("project_point", collider, message))?;
            let distance = if p.is_inside {
                0.0
            } else {
                (p.point - point).length()
            };
            if distance <= max_distance && best.is_none_or(|b| distance < b.distance) {
                best = Some(PointHit {
                    collider,
                    point: p.point,
                    inside: p.is_inside,
                    distance,
                });
            }
        }
        Ok(best)
    }
}

/// The error of a query that parry panicked in.
fn dependency(
    operation: &'static str,
    collider: ColliderHandle,
    message: String,
) -> CollisionError {
    CollisionError::Dependency {
        operation,
        collider: format!("{collider:?}"),
        message,
    }
}

/// The times of a cast that can touch `target`: all of them, unless one of the two shapes is a
/// height field (see [`height_field_window`]).
fn cast_times(
    shape: &Shape,
    pose: &Pose,
    velocity: Vec3,
    max_time: Real,
    target: &dyn crate::parry::shape::Shape,
    target_pose: &Pose,
) -> Window {
    if let Some(field) = target.as_heightfield() {
        return height_field_window(
            field,
            target_pose,
            shape.shared.as_ref(),
            pose,
            velocity,
            max_time,
        );
    }
    if let Some(field) = shape.shared.as_heightfield() {
        return height_field_window(field, pose, target, target_pose, -velocity, max_time);
    }
    Window::Times(0.0, max_time)
}

/// A ray query's argument names: its origin, direction and length.
const RAY_ARGS: [&str; 3] = ["origin", "direction", "max_distance"];

/// Checks a path query's start point, direction (or velocity) and length (or time), whose
/// argument names are `names`, before anything reaches parry.
fn check_path(
    names: [&'static str; 3],
    start: Vec3,
    direction: Vec3,
    length: Real,
) -> CollisionResult<()> {
    kea::error::check_coordinate(names[0], start)?;
    check_vec3(names[1], direction)?;
    check_non_negative(names[2], length)?;
    check_reach(names[2], direction, length)
}

/// Checks that a query reaches no farther than twice [`kea::error::MAX_COORDINATE`]: parry
/// indexes height-field cells along the path, and a longer one overflows its cell indices.
fn check_reach(arg: &'static str, direction: Vec3, length: Real) -> CollisionResult<()> {
    let reach = direction.length() * length;
    // (A NaN reach, from an infinite direction times zero, is refused too.)
    if reach.is_nan() || reach > 2.0 * kea::error::MAX_COORDINATE {
        return Err(kea::KeaError::OutOfRange {
            arg,
            value: kea::error::format_real(length),
            expected: "the query may reach at most 2e9 m (direction or velocity length times this)",
        }
        .into());
    }
    Ok(())
}
