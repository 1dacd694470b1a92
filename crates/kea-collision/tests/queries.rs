//! Scene queries: rays (closest, any, all, through a mesh without holes), shape casts,
//! overlaps and point projection, with filters.

use kea::BodyHandle;
use kea::{BodyDef, Quat, Real, Vec3, World};
use kea_collision::{ColliderDef, ColliderHandle, CollisionWorld, QueryFilter, Shape, ShapeCast};

fn sweep(shape: &Shape, position: Vec3, velocity: Vec3) -> ShapeCast {
    ShapeCast {
        shape: shape.clone(),
        position,
        rotation: Quat::IDENTITY,
        velocity,
        max_time: 10.0,
    }
}

/// A world with a ground plane and a unit box resting on it at `x`: (world, collision, the box's
/// body, the ground's collider, the box's collider).
fn ground_and_unit_box(
    x: Real,
) -> (
    World,
    CollisionWorld,
    BodyHandle,
    ColliderHandle,
    ColliderHandle,
) {
    let mut world = World::with_capacity(8, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let plane = ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap());
    let ground = collision.add_collider(&world, plane).unwrap();
    let position = Vec3::new(x, 0.5, 0.0);
    let b = world
        .create_body(&BodyDef {
            position,
            ..Default::default()
        })
        .unwrap();
    let cube = ColliderDef::new(Some(b), Shape::cuboid(Vec3::splat(0.5)).unwrap());
    let cube = collision.add_collider(&world, cube).unwrap();
    (world, collision, b, ground, cube)
}

#[test]
fn rays_hit_what_they_should_in_order() {
    let (world, collision, b, ground, cube) = ground_and_unit_box(0.0);
    let all = QueryFilter::default();
    let down = -Vec3::Y;
    let origin = Vec3::new(0.1, 10.0, 0.2);
    let hits = collision
        .cast_ray_all(
            &world,
            &kea_collision::RayCast::new(origin, down, 100.0),
            all,
        )
        .unwrap();
    assert_eq!(hits.len(), 2);
    assert_eq!((hits[0].collider, hits[1].collider), (cube, ground));
    assert!((hits[0].distance - 9.0).abs() < 1e-4 && hits[0].normal.abs_diff_eq(Vec3::Y, 1e-5));
    assert!((hits[1].distance - 10.0).abs() < 1e-4);
    assert!(hits[0].point.abs_diff_eq(Vec3::new(0.1, 1.0, 0.2), 1e-4));
    let closest = collision
        .cast_ray(
            &world,
            &kea_collision::RayCast::new(origin, down, 100.0),
            all,
        )
        .unwrap()
        .unwrap();
    assert_eq!(closest.collider, cube);
    // Excluding the box's body, the ray sees the ground; too short a ray sees nothing.
    let skip = QueryFilter {
        exclude: Some(b),
        ..Default::default()
    };
    assert_eq!(
        collision
            .cast_ray(
                &world,
                &kea_collision::RayCast::new(origin, down, 100.0),
                skip
            )
            .unwrap()
            .unwrap()
            .collider,
        ground
    );
    assert!(!collision
        .cast_ray_any(&world, &kea_collision::RayCast::new(origin, down, 8.9), all)
        .unwrap());
    assert!(collision
        .cast_ray_any(&world, &kea_collision::RayCast::new(origin, down, 9.1), all)
        .unwrap());
    // Upwards from below the box's top misses it when it starts outside... and hits at 0 inside.
    let inside = collision
        .cast_ray(
            &world,
            &kea_collision::RayCast::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Y, 5.0),
            skip,
        )
        .unwrap();
    assert!(inside.is_none(), "the ground is behind an upward ray");
    let inside = collision
        .cast_ray(
            &world,
            &kea_collision::RayCast::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Y, 5.0),
            all,
        )
        .unwrap();
    assert_eq!(
        inside.unwrap().distance,
        0.0,
        "solid: a ray from inside hits at once"
    );
    // Bad input is named.
    let e = collision
        .cast_ray(
            &world,
            &kea_collision::RayCast::new(origin, Vec3::ZERO, 1.0),
            all,
        )
        .unwrap_err();
    assert!(e.to_string().contains("direction"), "{e}");
}

#[test]
fn a_ray_at_one_collider_sees_only_that_collider() {
    let (world, collision, _, ground, cube) = ground_and_unit_box(0.0);
    let origin = Vec3::new(0.1, 10.0, 0.2);
    let on_ground = collision
        .cast_ray_at(
            &world,
            ground,
            &kea_collision::RayCast::new(origin, -Vec3::Y, 100.0),
        )
        .unwrap()
        .unwrap();
    // The box stands in the way, but this ray looks at the ground only.
    assert_eq!(on_ground.collider, ground);
    assert!((on_ground.distance - 10.0).abs() < 1e-4);
    assert!(on_ground.point.abs_diff_eq(Vec3::new(0.1, 0.0, 0.2), 1e-4));
    let on_box = collision
        .cast_ray_at(
            &world,
            cube,
            &kea_collision::RayCast::new(origin, -Vec3::Y, 100.0),
        )
        .unwrap()
        .unwrap();
    assert!((on_box.distance - 9.0).abs() < 1e-4);
    assert!(collision
        .cast_ray_at(
            &world,
            cube,
            &kea_collision::RayCast::new(Vec3::new(3.0, 10.0, 0.0), -Vec3::Y, 100.0)
        )
        .unwrap()
        .is_none());
    let e = collision
        .cast_ray_at(
            &world,
            cube,
            &kea_collision::RayCast::new(origin, Vec3::new(Real::NAN, 0.0, 0.0), 1.0),
        )
        .unwrap_err();
    assert!(e.to_string().contains("direction"), "{e}");
}

#[test]
fn rays_pass_no_holes_in_a_mesh() {
    // A 4×4 m floor made of 2×2 quads (8 triangles, shared edges and a shared centre vertex).
    let world = World::with_capacity(4, 16).unwrap();
    let mut collision = CollisionWorld::new();
    let mut vertices = Vec::new();
    for z in 0..3 {
        for x in 0..3 {
            vertices.push(Vec3::new(x as Real * 2.0 - 2.0, 0.0, z as Real * 2.0 - 2.0));
        }
    }
    let mut indices = Vec::new();
    for z in 0..2u32 {
        for x in 0..2u32 {
            let i = z * 3 + x;
            indices.push([i, i + 3, i + 4]);
            indices.push([i, i + 4, i + 1]);
        }
    }
    let mesh = collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::trimesh(vertices, indices).unwrap()),
        )
        .unwrap();
    // Rays straight down on a fine grid, including exactly on edges, diagonals and vertices.
    let mut missed = Vec::new();
    for iz in 0..=40 {
        for ix in 0..=40 {
            let (x, z) = (-1.99 + ix as Real * 0.0995, -1.99 + iz as Real * 0.0995);
            for (x, z) in [(x, z), (x.round(), z.round()), (x, x.clamp(-1.99, 1.99))] {
                let hit = collision
                    .cast_ray(
                        &world,
                        &kea_collision::RayCast::new(Vec3::new(x, 3.0, z), -Vec3::Y, 10.0),
                        QueryFilter::default(),
                    )
                    .unwrap();
                match hit {
                    Some(h) if h.collider == mesh && (h.distance - 3.0).abs() < 1e-4 => {}
                    other => missed.push((x, z, other)),
                }
            }
        }
    }
    assert!(
        missed.is_empty(),
        "{} rays missed, first {:?}",
        missed.len(),
        missed.first()
    );
}

#[test]
fn shape_casts_overlaps_and_point_projection() {
    let (world, collision, _, ground, cube) = ground_and_unit_box(3.0);
    let ball = Shape::sphere(0.25).unwrap();
    let all = QueryFilter::default();
    // A ball dropped from y = 5 at 1 m/s reaches the ground at t = 4.75 ...
    let hit = collision
        .cast_shape(
            &world,
            &sweep(&ball, Vec3::new(0.0, 5.0, 0.0), -Vec3::Y),
            all,
        )
        .unwrap()
        .unwrap();
    assert_eq!(hit.collider, ground);
    assert!((hit.time - 4.75).abs() < 1e-3, "time {}", hit.time);
    assert!(hit.normal.abs_diff_eq(Vec3::Y, 1e-4) && hit.point.y.abs() < 1e-3);
    // ... and, thrown sideways at the box, meets its face at x = 2.5 − 0.25.
    let hit = collision
        .cast_shape(
            &world,
            &sweep(&ball, Vec3::new(0.0, 0.5, 0.0), Vec3::X),
            all,
        )
        .unwrap()
        .unwrap();
    assert_eq!(hit.collider, cube);
    assert!((hit.time - 2.25).abs() < 1e-3, "time {}", hit.time);
    assert!(
        hit.normal.abs_diff_eq(-Vec3::X, 1e-4),
        "normal {}",
        hit.normal
    );
    // Overlaps: a ball at the box's corner touches the box and the ground; above, nothing.
    let near = collision
        .overlaps(&world, &ball, Vec3::new(2.6, 0.1, 0.0), Quat::IDENTITY, all)
        .unwrap();
    assert_eq!(near, vec![ground, cube]);
    let above = collision
        .overlaps(&world, &ball, Vec3::new(0.0, 2.0, 0.0), Quat::IDENTITY, all)
        .unwrap();
    assert!(above.is_empty());
    // Point projection: the nearest surface to a point above the box's top is the top.
    let p = collision
        .project_point(&world, Vec3::new(3.1, 1.3, 0.0), 10.0, all)
        .unwrap()
        .unwrap();
    assert_eq!(p.collider, cube);
    assert!((p.distance - 0.3).abs() < 1e-4 && !p.inside);
    let inside = collision
        .project_point(&world, Vec3::new(3.0, 0.5, 0.0), 10.0, all)
        .unwrap()
        .unwrap();
    assert!(inside.inside);
    assert!(collision
        .project_point(&world, Vec3::new(0.0, 5.0, 0.0), 1.0, all)
        .unwrap()
        .is_none());
}
