//! Filtering (groups and masks, jointed bodies) and contact events.

use kea::{BodyDef, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, ContactEventKind, Shape};
mod common;

const DT: Real = 1.0 / 60.0;

fn ball(world: &mut World, position: Vec3) -> kea::BodyHandle {
    let s = Shape::sphere(0.5).unwrap().mass_properties(1000.0).unwrap();
    world
        .create_body(&BodyDef {
            mass: s.mass,
            inertia: s.inertia,
            position,
            ..Default::default()
        })
        .unwrap()
}

/// An empty world without gravity, and its collision layer.
fn weightless() -> (World, CollisionWorld) {
    let mut world = World::with_capacity(8, 64).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    (world, CollisionWorld::new())
}

/// A ball at `position` with its collider (every group, colliding with every group).
fn ball_with_collider(
    world: &mut World,
    collision: &mut CollisionWorld,
    position: Vec3,
) -> (kea::BodyHandle, kea_collision::ColliderHandle) {
    let b = ball(world, position);
    let def = ColliderDef::new(Some(b), Shape::sphere(0.5).unwrap());
    (b, collision.add_collider(world, def).unwrap())
}

/// Sets a body's velocity.
fn launch(world: &mut World, body: kea::BodyHandle, velocity: Vec3) {
    world
        .body_mut(body)
        .unwrap()
        .set_linear_velocity(velocity)
        .unwrap();
}

#[test]
fn groups_masks_and_joints_filter_pairs() {
    let mut world = World::with_capacity(8, 64).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let mut collision = CollisionWorld::new();
    let s = Shape::sphere(0.5).unwrap();
    let a = ball(&mut world, Vec3::ZERO);
    let b = ball(&mut world, Vec3::new(0.9, 0.0, 0.0));
    let mut da = ColliderDef::new(Some(a), s.clone());
    da.groups = 0b01;
    da.mask = 0b01;
    let mut db = ColliderDef::new(Some(b), s.clone());
    db.groups = 0b10;
    let ca = collision.add_collider(&world, da).unwrap();
    let cb = collision.add_collider(&world, db).unwrap();
    collision.update_contacts(&mut world, DT).unwrap();
    assert!(
        collision.contacts_between(ca, cb).unwrap().is_empty(),
        "a's mask excludes b"
    );
    assert_eq!(world.constraint_count(), 0);

    // Same groups, but joined by a ball joint: still no contacts, until allowed.
    let (mut world, mut collision) = weightless();
    let (a, ca) = ball_with_collider(&mut world, &mut collision, Vec3::ZERO);
    let (b, cb) = ball_with_collider(&mut world, &mut collision, Vec3::new(0.9, 0.0, 0.0));
    collision.update_contacts(&mut world, DT).unwrap();
    assert_eq!(
        collision.contacts_between(ca, cb).unwrap().len(),
        1,
        "unjoined: they collide"
    );
    let joint = world
        .create_joint(a, Some(b), kea::JointSpec::ball(Vec3::new(0.45, 0.0, 0.0)))
        .unwrap();
    collision.update_contacts(&mut world, DT).unwrap();
    assert!(
        collision.contacts_between(ca, cb).unwrap().is_empty(),
        "joined: no contacts"
    );
    assert_eq!(world.constraint_count(), 1, "only the joint is left");
    collision
        .set_joint_collisions(&world, joint.into(), true)
        .unwrap();
    collision.update_contacts(&mut world, DT).unwrap();
    assert_eq!(
        collision.contacts_between(ca, cb).unwrap().len(),
        1,
        "allowed to collide"
    );
    collision
        .set_joint_collisions(&world, joint.into(), false)
        .unwrap();
    world.set_constraint_enabled(joint, false).unwrap();
    collision.update_contacts(&mut world, DT).unwrap();
    assert_eq!(
        collision.contacts_between(ca, cb).unwrap().len(),
        1,
        "a disabled joint lets go"
    );
}

/// A joint made between two bodies of a sleeping pile, which the narrow phase passes by while
/// they rest, still parts their contacts at the next update; contacts come and go without
/// touching the world's joint revision, joints move it on.
#[test]
fn a_joint_made_in_a_sleeping_pile_parts_its_bodies_contacts() {
    let mut world = World::with_capacity(8, 64).unwrap();
    world
        .update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))
        .unwrap();
    world
        .update_settings(|s| {
            s.dem = kea::DemSettings {
                mode: kea::DemMode::PartitionAutoDisable,
                ..Default::default()
            }
        })
        .unwrap();
    let mut collision = CollisionWorld::new();
    collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let mp = cube.mass_properties(100.0).unwrap();
    let mut boxes = Vec::new();
    for i in 0..2 {
        let b = world
            .create_body(&BodyDef {
                mass: mp.mass,
                inertia: mp.inertia,
                position: Vec3::new(0.0, 0.5 + i as Real, 0.0),
                ..Default::default()
            })
            .unwrap();
        let c = collision
            .add_collider(&world, ColliderDef::new(Some(b), cube.clone()))
            .unwrap();
        boxes.push((b, c));
    }
    let revision = world.joint_revision();
    for _ in 0..600 {
        common::step(&mut collision, &mut world, DT).unwrap();
    }
    let [(a, ca), (b, cb)] = [boxes[0], boxes[1]];
    assert!(world.body(b).unwrap().is_sleeping(), "the pile sleeps");
    assert_eq!(world.joint_revision(), revision, "contacts are not joints");
    assert!(!collision.contacts_between(ca, cb).unwrap().is_empty());
    let joint = world
        .create_joint(a, Some(b), kea::JointSpec::ball(Vec3::new(0.0, 1.0, 0.0)))
        .unwrap();
    assert_ne!(world.joint_revision(), revision, "a new joint");
    collision.update_contacts(&mut world, DT).unwrap();
    assert!(world.body(b).unwrap().is_sleeping(), "still asleep");
    assert!(
        collision.contacts_between(ca, cb).unwrap().is_empty(),
        "joined: no contacts"
    );
    let revision = world.joint_revision();
    world.set_constraint_enabled(joint, false).unwrap();
    assert_ne!(world.joint_revision(), revision, "a disabled joint");
}

#[test]
fn events_begin_and_end_exactly_once_and_impulse_carries_the_weight() {
    let mut world = World::with_capacity(8, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let ground = collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let b = ball(&mut world, Vec3::new(0.0, 1.0, 0.0));
    let cb = collision
        .add_collider(
            &world,
            ColliderDef::new(Some(b), Shape::sphere(0.5).unwrap()),
        )
        .unwrap();
    let (mut began, mut ended, mut persisted) = (0, 0, 0);
    let mut count = |collision: &CollisionWorld| {
        for e in collision.events() {
            assert_eq!(e.colliders, [ground, cb]);
            match e.kind {
                ContactEventKind::Began => began += 1,
                ContactEventKind::Persisted => persisted += 1,
                ContactEventKind::Ended => ended += 1,
            }
        }
    };
    // Fall 0.5 m onto the ground and rest there for 2 s.
    for _ in 0..150 {
        common::step(&mut collision, &mut world, DT).unwrap();
        count(&collision);
    }
    let weight = world.body(b).unwrap().mass() * 9.81;
    let impulse = collision.pair_impulse(&world, cb, ground).unwrap();
    eprintln!(
        "resting ball: impulse {impulse} N·s per step, weight·dt {}",
        weight * DT
    );
    assert!(
        (impulse.y - weight * DT).abs() < 1e-3 * weight * DT,
        "impulse {impulse}"
    );
    assert!(
        (collision.pair_impulse(&world, ground, cb).unwrap() + impulse).length() < 1e-6 * weight
    );
    // Lift it away: the pair ends once.
    world
        .body_mut(b)
        .unwrap()
        .set_position(Vec3::new(0.0, 5.0, 0.0))
        .unwrap();
    for _ in 0..10 {
        common::step(&mut collision, &mut world, DT).unwrap();
        count(&collision);
    }
    assert_eq!((began, ended), (1, 1), "persisted {persisted}");
    assert!(persisted > 100);
    // Removing a touching collider ends its pair too.
    world
        .body_mut(b)
        .unwrap()
        .set_position(Vec3::new(0.0, 0.5, 0.0))
        .unwrap();
    common::step(&mut collision, &mut world, DT).unwrap();
    assert_eq!(collision.events()[0].kind, ContactEventKind::Began);
    collision.remove_collider(&mut world, cb).unwrap();
    assert_eq!(world.constraint_count(), 0, "its contacts went with it");
    collision.update_contacts(&mut world, DT).unwrap();
    assert_eq!(collision.events().len(), 1);
    assert_eq!(collision.events()[0].kind, ContactEventKind::Ended);
}

/// Two jointed balls are the only colliders: no pair is possible, so the updates pass the
/// broad and narrow phases by while the balls fly far from where their boxes were last set.
/// Queries still see them where they are; a ground added later, and the joint removed, find
/// their pairs at once.
#[test]
fn colliders_that_cannot_pair_are_found_again_once_they_can() {
    let (mut world, mut collision) = weightless();
    let (a, ca) = ball_with_collider(&mut world, &mut collision, Vec3::ZERO);
    let (b, cb) = ball_with_collider(&mut world, &mut collision, Vec3::new(0.9, 0.0, 0.0));
    let joint = world
        .create_joint(a, Some(b), kea::JointSpec::ball(Vec3::new(0.45, 0.0, 0.0)))
        .unwrap();
    for h in [a, b] {
        launch(&mut world, h, Vec3::new(0.0, -3.0, 0.0));
    }
    // 2 s at 3 m/s: 6 m down, far outside any box set before.
    for _ in 0..120 {
        let stats = common::step(&mut collision, &mut world, DT).unwrap();
        assert_eq!(stats.collision.pairs, 0);
        assert!(collision.events().is_empty());
    }
    let y = world.body(a).unwrap().position().y;
    assert!((y + 6.0).abs() < 1.0e-3, "fell 6 m: y = {y}");
    let ray = kea_collision::RayCast::new(Vec3::new(0.0, 10.0, 0.0), Vec3::NEG_Y, 100.0);
    let hit = collision
        .cast_ray(&world, &ray, Default::default())
        .unwrap()
        .expect("the ball is where it is");
    assert_eq!(hit.collider, ca);
    assert!((hit.distance - (10.0 - y - 0.5)).abs() < 1.0e-3);

    // A floor just below: the balls reach it within the step and touch.
    let floor = collision
        .add_collider(
            &world,
            ColliderDef {
                offset: Vec3::new(0.0, y - 1.02, 0.0),
                ..ColliderDef::new(None, Shape::cuboid(Vec3::new(5.0, 0.5, 5.0)).unwrap())
            },
        )
        .unwrap();
    for _ in 0..3 {
        common::step(&mut collision, &mut world, DT).unwrap();
    }
    assert!(!collision.contacts_between(ca, floor).unwrap().is_empty());
    assert!(!collision.contacts_between(cb, floor).unwrap().is_empty());
    assert!(collision.contacts_between(ca, cb).unwrap().is_empty());

    // The joint gone, the overlapping balls are a pair too.
    world.destroy_constraint(joint).unwrap();
    common::step(&mut collision, &mut world, DT).unwrap();
    assert!(!collision.contacts_between(ca, cb).unwrap().is_empty());
}

/// A lone ball flies 3 m while it is the only collider (its updates pass the broad phase by),
/// then is disabled where it is, fixed in place. A second ball thrown at it there must meet
/// it there: the first ball's box and pose follow it once pairs are possible again, although
/// an update leaves a disabled body's box alone.
#[test]
fn a_body_disabled_after_passed_updates_is_met_where_it_is() {
    let (mut world, mut collision) = weightless();
    let (a, ca) = ball_with_collider(&mut world, &mut collision, Vec3::ZERO);
    launch(&mut world, a, Vec3::new(3.0, 0.0, 0.0));
    for _ in 0..60 {
        common::step(&mut collision, &mut world, DT).unwrap();
    }
    let at = world.body(a).unwrap().position();
    assert!((at.x - 3.0).abs() < 1.0e-3, "flew 3 m: {at}");
    world.body_mut(a).unwrap().set_enabled(false);
    let (b, cb) = ball_with_collider(&mut world, &mut collision, at + Vec3::new(0.0, 1.2, 0.0));
    launch(&mut world, b, Vec3::new(0.0, -1.0, 0.0));
    for _ in 0..30 {
        common::step(&mut collision, &mut world, DT).unwrap();
    }
    assert!(
        !collision.contacts_between(ca, cb).unwrap().is_empty(),
        "the thrown ball rests on the disabled one"
    );
    let y = world.body(b).unwrap().position().y;
    assert!(
        (y - (at.y + 1.0)).abs() < 0.02,
        "stopped on it, not through it: y = {y}"
    );
}
