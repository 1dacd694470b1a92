//! Issue 12: the collision entry points refuse a non-positive or non-finite `dt` and negative
//! or non-finite public settings (`margin`, `touch_distance`) with an error naming the
//! argument, before anything changes: no parry assertion is reached, and the world's contacts,
//! bodies and time are those of before the call.

use kea::{BodyDef, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
mod common;

/// A box resting on a plane, after one step (so it has contacts).
fn resting_box() -> (World, CollisionWorld) {
    let mut world = World::with_capacity(4, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let shape = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let mp = shape.mass_properties(1000.0).unwrap();
    let body = world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: Vec3::new(0.0, 0.49, 0.0),
            ..Default::default()
        })
        .unwrap();
    collision
        .add_collider(&world, ColliderDef::new(Some(body), shape))
        .unwrap();
    collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
    (world, collision)
}

/// What a refused call must leave alone: contact count, the body's pose and the world's time.
fn fingerprint(world: &World) -> (usize, Vec3, f64) {
    let (_, body) = world.bodies().next().unwrap();
    (world.constraint_count(), body.position(), world.time())
}

fn assert_refused(result: Result<impl std::fmt::Debug, kea_collision::CollisionError>, arg: &str) {
    let err = result.expect_err("a bad value was accepted");
    let text = err.to_string();
    assert!(text.contains(arg), "the error does not name {arg}: {text}");
}

#[test]
fn a_bad_dt_is_refused_before_anything_changes() {
    for dt in [0.0, -1.0e-6, -1.0, Real::NAN, Real::INFINITY] {
        let (mut world, mut collision) = resting_box();
        let before = fingerprint(&world);
        assert!(before.0 > 0, "the box should rest on contacts");
        assert_refused(common::step(&mut collision, &mut world, dt), "dt");
        assert_eq!(fingerprint(&world), before, "step({dt}) changed the world");
        assert_refused(collision.update_contacts(&mut world, dt), "dt");
        assert_eq!(
            fingerprint(&world),
            before,
            "update_contacts({dt}) changed the world"
        );
        // And the world steps on normally afterwards.
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
    }
}

#[test]
fn bad_public_settings_are_refused_before_anything_changes() {
    for value in [
        -1.0e-3,
        -1.0,
        1.0e30,
        Real::NAN,
        Real::NEG_INFINITY,
        Real::INFINITY,
    ] {
        for setting in ["margin", "touch_distance"] {
            let (mut world, mut collision) = resting_box();
            let before = fingerprint(&world);
            let good = match setting {
                "margin" => std::mem::replace(&mut collision.margin, value),
                _ => std::mem::replace(&mut collision.touch_distance, value),
            };
            assert_refused(
                common::step(&mut collision, &mut world, 1.0 / 60.0),
                setting,
            );
            assert_eq!(
                fingerprint(&world),
                before,
                "{setting} = {value} changed the world"
            );
            match setting {
                "margin" => collision.margin = good,
                _ => collision.touch_distance = good,
            }
            common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        }
    }
}
