//! Materials: combine rules and pair entries give the physics they promise, and the sleeping
//! pairs are left alone.

use kea::{
    BodyDef, ContactParams, DemMode, DemSettings, FrictionModel, Real, Vec3, World, WorldDef,
};
use kea_collision::{ColliderDef, CollisionWorld, Shape, Surface};
mod common;

const G: Real = 9.81;
const DT: Real = 1.0 / 60.0;

/// A box sliding at 5 m/s over a ground of material `ground`, itself of material `block`;
/// returns its deceleration over the first half second.
fn deceleration(collision: &mut CollisionWorld, block: u32, ground: u32) -> Real {
    let mut world = World::with_capacity(4, 64).unwrap();
    let mut g = ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap());
    g.material = ground;
    collision.add_collider(&world, g).unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.25)).unwrap();
    let mp = cube.mass_properties(1000.0).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: Vec3::new(0.0, 0.25, 0.0),
            ..Default::default()
        })
        .unwrap();
    let mut d = ColliderDef::new(Some(b), cube);
    d.material = block;
    collision.add_collider(&world, d).unwrap();
    for _ in 0..10 {
        common::step(collision, &mut world, DT).unwrap(); // settle
    }
    world
        .body_mut(b)
        .unwrap()
        .set_linear_velocity(Vec3::new(5.0, 0.0, 0.0))
        .unwrap();
    for _ in 0..30 {
        common::step(collision, &mut world, DT).unwrap();
    }
    let v = world.body(b).unwrap().linear_velocity().x;
    let impulse = collision.body_pair_impulse(&world, b, None);
    assert!(
        impulse.x < 0.0 && impulse.y > 0.0,
        "friction opposes, the ground holds: {impulse}"
    );
    (5.0 - v) / (30.0 * DT)
}

#[test]
fn friction_combines_by_geometric_mean_and_pair_entries_override() {
    let mut collision = CollisionWorld::new();
    let ice = collision
        .materials
        .add(Surface {
            friction: 0.2,
            ..Default::default()
        })
        .unwrap();
    let rubber = collision
        .materials
        .add(Surface {
            friction: 0.8,
            ..Default::default()
        })
        .unwrap();
    let a = deceleration(&mut collision, ice, rubber);
    let mu = (0.2 * 0.8 as Real).sqrt();
    eprintln!("ice on rubber: deceleration {a}, μg = {}", mu * G);
    assert!((a - mu * G).abs() < 0.02 * mu * G, "a = {a}");
    // A pair entry overrides the rule: box friction of 50 N on this pair only. The box rests on
    // four contact points and each carries up to 50 N (the guide's box model is per contact).
    let params = ContactParams {
        friction: [FrictionModel::Box { max_force: 50.0 }; 2],
        ..Default::default()
    };
    collision.materials.set_pair(rubber, ice, params).unwrap();
    let mass = 0.5 * 0.5 * 0.5 * 1000.0;
    let a = deceleration(&mut clone_materials(&collision), ice, rubber);
    let expected = 4.0 * 50.0 / mass;
    eprintln!("box friction 4 × 50 N on {mass} kg: deceleration {a}, expected {expected}");
    assert!((a - expected).abs() < 0.02 * expected, "a = {a}");
    // A negative μ is refused by name (it must not hide behind √(μ·μ)).
    let bad = Surface {
        friction: -1.0,
        ..Default::default()
    };
    let e = collision.materials.add(bad).unwrap_err();
    assert!(e.to_string().contains("friction"), "{e}");
    // Unknown ids are refused by name.
    let e = collision.materials.params(ice, 99).unwrap_err();
    assert!(e.to_string().contains("99"), "{e}");
}

fn clone_materials(c: &CollisionWorld) -> CollisionWorld {
    let mut fresh = CollisionWorld::new();
    fresh.materials = c.materials.clone();
    fresh
}

#[test]
fn restitution_is_the_larger_of_the_pair_and_sleeping_pairs_are_left_alone() {
    let mut world = World::new(WorldDef {
        max_bodies: 4,
        max_constraints: 64,
        settings: kea::WorldSettings {
            dem: DemSettings {
                mode: DemMode::PartitionAutoDisable,
                ..Default::default()
            },
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    let mut collision = CollisionWorld::new();
    let dull = collision
        .materials
        .add(Surface {
            restitution: 0.0,
            ..Default::default()
        })
        .unwrap();
    let bouncy = collision
        .materials
        .add(Surface {
            restitution: 0.5,
            restitution_threshold: 0.3,
            ..Default::default()
        })
        .unwrap();
    let mut g = ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap());
    g.material = dull;
    collision.add_collider(&world, g).unwrap();
    let ball = Shape::sphere(0.25).unwrap();
    let mp = ball.mass_properties(1000.0).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: Vec3::new(0.0, 2.25, 0.0),
            ..Default::default()
        })
        .unwrap();
    let mut d = ColliderDef::new(Some(b), ball);
    d.material = bouncy;
    collision.add_collider(&world, d).unwrap();
    let mut ratio = None;
    for _ in 0..600 {
        let v_in = world.body(b).unwrap().linear_velocity().y;
        common::step(&mut collision, &mut world, DT).unwrap();
        let v = world.body(b).unwrap().linear_velocity().y;
        if ratio.is_none() && v_in < -1.0 && v > 0.0 {
            ratio = Some(v / -v_in);
        }
    }
    let ratio = ratio.expect("no bounce");
    eprintln!("bouncy on dull: rebound ratio {ratio}");
    assert!((ratio - 0.5).abs() < 0.01, "ratio {ratio}");
    // After 10 s the ball sleeps; its contact is kept as it was, untouched, step after step.
    assert!(
        world.body(b).unwrap().is_sleeping(),
        "the ball should be asleep"
    );
    let before: Vec<_> = world.contacts_between(b, None).collect();
    let kept = *world.contact(before[0]).unwrap();
    common::step(&mut collision, &mut world, DT).unwrap();
    let after: Vec<_> = world.contacts_between(b, None).collect();
    assert_eq!(before, after);
    assert_eq!(*world.contact(after[0]).unwrap(), kept);
}

/// A 0.5 m box dropped at rest on a static belt whose pair entry slides at 1 m/s along the
/// world direction `direction` (given for the pair in the order `box_first`); returns the box's
/// velocity after `seconds` and the time at which its speed first reached 0.99 m/s.
fn ride_belt(direction: Vec3, box_first: bool, slide: Real, seconds: Real) -> (Vec3, Real) {
    let mut world = World::with_capacity(4, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let belt = collision.materials.add(Surface::default()).unwrap();
    let params = ContactParams {
        slide: [slide, 0.0],
        ..Default::default()
    };
    let (a, b) = if box_first { (0, belt) } else { (belt, 0) };
    collision
        .materials
        .set_pair_with_direction(a, b, params, Some(direction))
        .unwrap();
    let mut g = ColliderDef::new(None, Shape::cuboid(Vec3::new(5.0, 0.1, 1.0)).unwrap());
    g.offset = Vec3::new(0.0, -0.1, 0.0);
    g.material = belt;
    collision.add_collider(&world, g).unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.25)).unwrap();
    let mp = cube.mass_properties(1000.0).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: Vec3::new(-3.0, 0.25, 0.0),
            ..Default::default()
        })
        .unwrap();
    collision
        .add_collider(&world, ColliderDef::new(Some(b), cube))
        .unwrap();
    let mut reached = Real::INFINITY;
    let steps = (seconds / DT).round() as usize;
    for i in 0..steps {
        common::step(&mut collision, &mut world, DT).unwrap();
        let v = world.body(b).unwrap().linear_velocity();
        if reached.is_infinite() && v.length() > 0.99 {
            reached = (i + 1) as Real * DT;
        }
    }
    (world.body(b).unwrap().linear_velocity(), reached)
}

#[test]
fn a_conveyor_pair_carries_a_box_along_its_world_direction() {
    // μ = 0.5 drags the box at μg until it moves with the belt: 1 m/s after 1/(μg) ≈ 0.20 s.
    let expected_time = 1.0 / (0.5 * G);
    for (direction, box_first, slide) in [
        (Vec3::X, true, 1.0),
        (Vec3::X, false, -1.0), // the belt's surface moves at −1 m/s under the box
        (Vec3::new(0.6, 0.0, 0.8), true, 1.0),
    ] {
        let (v, t) = ride_belt(direction, box_first, slide, 1.0);
        eprintln!("belt along {direction} (box first: {box_first}): v = {v}, reached at {t:.3} s");
        assert!((v - direction).length() < 0.03, "v = {v}");
        assert!((t - expected_time).abs() < 0.05, "reached at {t}");
    }
}
