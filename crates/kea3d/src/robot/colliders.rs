//! A robot's collision geometry as Kea colliders: each file shape made a Kea shape (placed,
//! grown by its contact skin, a flat mesh's hull falling back to the mesh), and the collision
//! groups and masks that give MuJoCo's contype/conaffinity rule and a robot's self-collision
//! setting.

use super::spec::{GeomShape, GeomSpec, RobotSpec};
use crate::Collider;
use kea::{Quat, Real, Vec3};
use kea_collision::Shape;

/// Collision bit of robot links whose own links must not collide with each other.
pub(crate) const NO_SELF_COLLISION_BIT: u32 = 1 << 31;

/// Each body's geometries' Kea collision groups and mask.
///
/// URDF geometry keeps the default (group 1, every mask bit). MJCF's rule — a pair collides if
/// either one's `contype` meets the other's `conaffinity` — is an OR that Kea's filter (both
/// ways must meet) cannot say bit for bit, so each distinct (contype, conaffinity) pair of the
/// file becomes a class with its own bit (1 to 30) as its group, whose mask holds the classes
/// it collides with and bit 0 (the world's default group) when it collides with anything at
/// all. Without self-collision a robot's geometry (a URDF's welded base included) has bit 31
/// alone as its group and not in its mask, so it meets everything but itself; an MJCF
/// worldbody's geometry (the floor) adds bit 31 to its mask to keep meeting the robot.
pub(crate) fn collision_filters(
    spec: &RobotSpec,
    geoms: &[Vec<(usize, GeomSpec)>],
    self_collision: bool,
) -> Vec<Vec<(u32, u32)>> {
    let mut classes: Vec<(u32, u32)> = Vec::new();
    if spec.mujoco_filter {
        for (_, g) in geoms.iter().flatten() {
            if !classes.contains(&(g.groups, g.mask)) {
                classes.push((g.groups, g.mask));
            }
        }
    }
    let by_class = spec.mujoco_filter && classes.len() <= 30;
    let meets = |a: (u32, u32), b: (u32, u32)| a.0 & b.1 != 0 || b.0 & a.1 != 0;
    geoms
        .iter()
        .enumerate()
        .map(|(link, list)| {
            list.iter()
                .map(|(_, g)| {
                    let (mut groups, mut mask) = if by_class {
                        let me = (g.groups, g.mask);
                        let bit = |i: usize| 1u32 << (i + 1);
                        let own = classes.iter().position(|c| *c == me).map_or(0, bit);
                        let mut mask = classes
                            .iter()
                            .enumerate()
                            .filter(|(_, c)| meets(me, **c))
                            .fold(0, |m, (i, _)| m | bit(i));
                        if me.0 != 0 || me.1 != 0 {
                            mask |= 1;
                        }
                        (own, mask)
                    } else {
                        (g.groups, g.mask)
                    };
                    // A URDF's world link holds only the robot's own welded base; an MJCF
                    // worldbody's geometry (the floor) meets the robot whatever the setting.
                    let robot_part = link != 0 || !spec.mujoco_filter;
                    if !self_collision && mask != 0 {
                        if robot_part {
                            // Its group is the robot's bit alone, which its own mask lacks.
                            groups = NO_SELF_COLLISION_BIT;
                            mask &= !NO_SELF_COLLISION_BIT;
                        } else {
                            mask |= NO_SELF_COLLISION_BIT;
                        }
                    }
                    (groups, mask)
                })
                .collect()
        })
        .collect()
}

/// The shape grown by `skin` on every side (a plane moves out by it; a mesh stays as it is).
fn grown(shape: &GeomShape, skin: Real) -> GeomShape {
    if skin <= 0.0 {
        return shape.clone();
    }
    match shape {
        GeomShape::Cuboid(h) => GeomShape::Cuboid(*h + Vec3::splat(skin)),
        GeomShape::Sphere(r) => GeomShape::Sphere(r + skin),
        GeomShape::Cylinder {
            radius,
            half_length,
        } => GeomShape::Cylinder {
            radius: radius + skin,
            half_length: half_length + skin,
        },
        GeomShape::Capsule {
            radius,
            half_length,
        } => GeomShape::Capsule {
            radius: radius + skin,
            half_length: *half_length,
        },
        GeomShape::Hull(points, triangles) => {
            let centre = points.iter().copied().sum::<Vec3>() / points.len().max(1) as Real;
            GeomShape::Hull(
                points
                    .iter()
                    .map(|&p| p + (p - centre).normalize_or_zero() * skin)
                    .collect(),
                triangles.clone(),
            )
        }
        GeomShape::Mesh(..) | GeomShape::Plane => shape.clone(),
    }
}

/// A geometry's collider, and a note when a flat mesh's hull (no volume) had to collide as the
/// mesh itself.
pub(crate) fn collider(
    g: &GeomSpec,
    (groups, mask): (u32, u32),
) -> (Collider, Option<&'static str>) {
    let (mut offset, rotation) = placement(g);
    if g.shape == GeomShape::Plane {
        offset += g.pose.rotation * Vec3::Z * g.skin.max(0.0);
    }
    let mut note = None;
    let shape = match (shape_of(&grown(&g.shape, g.skin)), &g.shape) {
        (Err(_), GeomShape::Hull(points, triangles)) if !triangles.is_empty() => {
            note =
                Some("its mesh is flat (its convex hull has no volume): it collides as the mesh");
            Shape::trimesh(points.clone(), triangles.clone())
        }
        (shape, _) => shape,
    };
    let mut c = Collider::from_result(shape)
        .translation(offset)
        .rotation(rotation)
        .collision_groups(groups, mask);
    if let Some(mu) = g.friction {
        c = c.friction(mu);
    }
    (c, note)
}

/// The shape's own placement in the geometry's frame (cylinders and capsules: z to y).
pub(crate) fn placement(g: &GeomSpec) -> (Vec3, Quat) {
    let turn = match g.shape {
        GeomShape::Cylinder { .. } | GeomShape::Capsule { .. } => {
            Quat::from_rotation_x(kea::PI_REAL / 2.0)
        }
        GeomShape::Plane => Quat::from_rotation_arc(Vec3::Y, Vec3::Z),
        _ => Quat::IDENTITY,
    };
    (g.pose.translation, (g.pose.rotation * turn).normalize())
}

pub(crate) fn shape_of(shape: &GeomShape) -> crate::Result<Shape> {
    match shape {
        GeomShape::Cuboid(h) => Shape::cuboid(*h),
        GeomShape::Sphere(r) => Shape::sphere(*r),
        GeomShape::Cylinder {
            radius,
            half_length,
        } => Shape::cylinder(*half_length, *radius),
        GeomShape::Capsule {
            radius,
            half_length,
        } => Shape::capsule(*half_length, *radius),
        GeomShape::Hull(points, _) => Shape::convex_hull(points),
        GeomShape::Mesh(v, i) => Shape::trimesh(v.clone(), i.clone()),
        GeomShape::Plane => Shape::plane(Vec3::Y),
    }
}
