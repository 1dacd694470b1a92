//! VALIDATION #15 and #16: a slide (conveyor) contact carries a resting box at the surface
//! speed; a slip factor gives a sliding speed proportional to the tangential force.

mod common;
use common::{world_on, BoxPlaneContacts, PATHS};
use kea::{inertia, BodyDef, ContactParams, ContactType, FrictionModel, Real, SolverMode, Vec3};

const HALF: Vec3 = Vec3::new(0.5, 0.25, 0.5);

fn run(mode: SolverMode, params: ContactParams, push: Vec3, seconds: Real) -> Vec3 {
    let h: Real = 1.0 / 60.0;
    let mut world = world_on(mode, 4, 32);
    let body = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, HALF.y, 0.0),
            inertia: inertia::solid_box(2.0, HALF).unwrap(),
            mass: 2.0,
            ..Default::default()
        })
        .unwrap();
    let mut contacts = BoxPlaneContacts::default();
    for _ in 0..(seconds / h).round() as usize {
        contacts.update(
            &mut world,
            body,
            HALF,
            Vec3::Y,
            0.0,
            0.01,
            params,
            Some(Vec3::X),
        );
        world.body_mut(body).unwrap().add_force(push).unwrap();
        world.step(h).unwrap();
    }
    world.body(body).unwrap().linear_velocity()
}

#[test]
fn slide_carries_a_resting_box_at_the_surface_speed() {
    let u: Real = 1.5;
    let params = ContactParams {
        friction: [FrictionModel::Coulomb { mu: 0.5 }; 2],
        slide: [u, 0.0],
        ..Default::default()
    };
    for mode in PATHS {
        let v = run(mode, params, Vec3::ZERO, 3.0);
        eprintln!("{mode:?}: slide: box speed {v} for surface speed {u}");
        assert!((v.x - u).abs() < 0.01 * u, "{mode:?}: speed {}", v.x);
        assert!(v.z.abs() < 1e-4 && v.y.abs() < 1e-3, "{mode:?}: {v}");
    }
}

#[test]
fn slip_gives_velocity_proportional_to_force() {
    let s: Real = 0.05; // m/s per N
    for push in [2.0 as Real, 8.0] {
        let params = ContactParams {
            contact_type: ContactType::Friction2D,
            friction: [FrictionModel::Infinite; 2],
            slip: [s, 0.0],
            ..Default::default()
        };
        for mode in PATHS {
            let v = run(mode, params, Vec3::new(push, 0.0, 0.0), 2.0);
            // Four contacts share the push: each carries push/4 of tangential force.
            let expected = s * push / 4.0;
            eprintln!(
                "{mode:?}: slip: push {push} N → speed {} (expected {expected})",
                v.x
            );
            assert!(
                (v.x - expected).abs() < 0.02 * expected,
                "{mode:?}: speed {}",
                v.x
            );
            assert!(v.z.abs() < 1e-5, "{mode:?}: no slip sideways: {}", v.z);
        }
    }
}

#[test]
fn slide_without_a_direction_still_carries_the_box() {
    // With no primary direction the slide follows a fixed direction of the contact, not the
    // sliding velocity it causes: the box reaches the surface speed along it.
    let u: Real = 1.0;
    let params = ContactParams {
        friction: [FrictionModel::Coulomb { mu: 0.5 }; 2],
        slide: [u, 0.0],
        ..Default::default()
    };
    for mode in PATHS {
        let h: Real = 1.0 / 60.0;
        let mut world = world_on(mode, 4, 32);
        let body = world
            .create_body(&BodyDef {
                position: Vec3::new(0.0, HALF.y, 0.0),
                inertia: inertia::solid_box(1.0, HALF).unwrap(),
                ..Default::default()
            })
            .unwrap();
        let mut contacts = BoxPlaneContacts::default();
        for _ in 0..180 {
            contacts.update(&mut world, body, HALF, Vec3::Y, 0.0, 0.01, params, None);
            world.step(h).unwrap();
        }
        let speed = world.body(body).unwrap().linear_velocity().length();
        assert!((speed - u).abs() < 0.01 * u, "{mode:?}: speed {speed}");
    }
}
