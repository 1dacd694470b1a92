//! Static and kinetic friction through colliders' surfaces (`Collider::static_friction`): a
//! box on the ground holds under a pull below μs·m·g and slides against μk·m·g above it.

use kea3d::prelude::*;

const G: Real = 9.81;

/// A 2 kg, 0.5 m box resting on a ground plane; both surfaces μk = 0.3, μs = 0.6.
fn box_on_ground() -> (PhysicsWorld, BodyHandle) {
    let mut world = PhysicsWorld::new();
    world.set_gravity([0.0, -G, 0.0]).unwrap();
    world
        .insert_collider(
            Collider::halfspace([0.0, 1.0, 0.0])
                .friction(0.3)
                .static_friction(0.6),
            None,
        )
        .unwrap();
    let b = world
        .insert_body(Body::dynamic().position([0.0, 0.25, 0.0]))
        .unwrap();
    world
        .insert_collider(
            Collider::cuboid([0.25, 0.25, 0.25])
                .mass(2.0)
                .friction(0.3)
                .static_friction(0.6),
            Some(b),
        )
        .unwrap();
    for _ in 0..60 {
        world.step(1.0 / 120.0).unwrap(); // settle
    }
    (world, b)
}

fn pull(world: &mut PhysicsWorld, b: BodyHandle, f: Real, steps: usize) -> Vec<Real> {
    (0..steps)
        .map(|_| {
            world.add_force(b, [f, 0.0, 0.0]).unwrap();
            world.step(1.0 / 120.0).unwrap();
            world.linear_velocity(b).unwrap().x
        })
        .collect()
}

#[test]
fn a_box_holds_below_its_static_friction_and_slides_against_its_kinetic_friction() {
    let (mut world, b) = box_on_ground();
    let weight = 2.0 * G;
    let x0 = world.position(b).unwrap().x;
    let speeds = pull(&mut world, b, 0.5 * weight, 120);
    let crept = world.position(b).unwrap().x - x0;
    assert!(
        crept.abs() < 2e-3 && speeds.iter().all(|v| v.abs() < 2e-2),
        "crept {crept}"
    );
    let speeds = pull(&mut world, b, 0.7 * weight, 120);
    let a = (speeds[119] - speeds[60]) / (59.0 / 120.0);
    assert!(
        (a - 0.4 * G).abs() < 0.03 * G,
        "accelerates at {a}, expected {}",
        0.4 * G
    );
}

#[test]
fn a_static_coefficient_below_the_kinetic_one_is_refused_by_name() {
    let mut world = PhysicsWorld::new();
    let e = world
        .insert_collider(
            Collider::halfspace([0.0, 1.0, 0.0])
                .friction(0.5)
                .static_friction(0.2),
            None,
        )
        .unwrap_err();
    assert!(e.to_string().contains("static_friction"), "{e}");
}
