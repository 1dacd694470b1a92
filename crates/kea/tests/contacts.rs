//! Contact parameters beyond friction: reaction forces, adhesion, softness, 1D friction, and the
//! grouping of a body pair's contacts (the guide's MdtContactGetNext).

mod common;
use common::{box_plane_contacts, clear_contacts, ground_box_contacts, F64};
use kea::{
    inertia, BodyDef, Contact, ContactParams, ContactType, FrictionModel, Real, Vec3, World,
};

const HALF: Vec3 = Vec3::new(0.5, 0.25, 0.5);
const H: Real = 1.0 / 60.0;

fn box_world(mass: Real) -> (World, kea::BodyHandle) {
    let mut world = World::with_capacity(4, 32).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass,
            position: Vec3::new(0.0, HALF.y, 0.0),
            inertia: inertia::solid_box(mass, HALF).unwrap(),
            ..Default::default()
        })
        .unwrap();
    (world, b)
}

#[test]
fn resting_contact_forces_sum_to_the_weight() {
    let (mut world, b) = box_world(3.0);
    let mut contacts = Vec::new();
    for _ in 0..120 {
        clear_contacts(&mut world, &mut contacts);
        ground_box_contacts(
            &mut world,
            b,
            HALF,
            ContactParams::default(),
            None,
            &mut contacts,
        );
        world.step(H).unwrap();
    }
    let total: Vec3 = contacts
        .iter()
        .map(|&c| world.contact_force(c).unwrap())
        .sum();
    let weight = 3.0 * 9.81;
    assert_eq!(contacts.len(), 4);
    assert!(
        (total.y - weight).abs() < 1e-4 * weight,
        "normal force {total}"
    );
    assert!(total.x.abs() < 1e-4 && total.z.abs() < 1e-4);
    // Symmetric box: each contact carries a quarter.
    for &c in &contacts {
        let l = world.constraint_lambdas(c).unwrap();
        assert_eq!(l.len(), 3);
        assert!((l[0] - weight / 4.0).abs() < 1e-3 * weight, "λn = {}", l[0]);
    }
}

#[test]
fn adhesion_holds_up_to_its_maximum_force() {
    for (pull, held) in [(0.9 as Real, true), (1.1, false)] {
        let (mut world, b) = box_world(1.0);
        world.set_gravity(Vec3::ZERO).unwrap();
        let params = ContactParams {
            max_adhesive_force: 2.0,
            ..Default::default()
        };
        let mut contacts = Vec::new();
        for _ in 0..60 {
            clear_contacts(&mut world, &mut contacts);
            ground_box_contacts(&mut world, b, HALF, params, None, &mut contacts);
            // 4 contacts × 2 N of adhesion = 8 N.
            world
                .body_mut(b)
                .unwrap()
                .add_force(Vec3::new(0.0, pull * 8.0, 0.0))
                .unwrap();
            world.step(H).unwrap();
        }
        let y = world.body(b).unwrap().position().y - HALF.y;
        if held {
            assert!(y.abs() < 1e-3, "pulled off below the limit: {y}");
        } else {
            assert!(y > 1e-3, "held above the limit: {y}");
        }
    }
}

#[test]
fn soft_contact_settles_at_the_spring_deflection() {
    // A soft row is a spring k = γ/(ε h²): the box sinks by m g / (4k) on four contacts.
    let softness: Real = 0.05;
    let (mut world, b) = box_world(2.0);
    let params = ContactParams {
        softness: Some(softness),
        ..Default::default()
    };
    let mut contacts = Vec::new();
    for _ in 0..600 {
        clear_contacts(&mut world, &mut contacts);
        box_plane_contacts(
            &mut world,
            b,
            HALF,
            Vec3::Y,
            0.0,
            0.05,
            params,
            None,
            &mut contacts,
        );
        world.step(H).unwrap();
    }
    let k = world.gamma() / (softness * H * H);
    let expected = 2.0 * 9.81 / (4.0 * k);
    let sink = HALF.y - world.body(b).unwrap().position().y;
    assert!(
        (sink - expected).abs() < 1e-3 * expected + if F64 { 0.0 } else { 1e-6 },
        "sink {sink} vs {expected}"
    );
}

#[test]
fn one_dimensional_friction_holds_only_along_its_direction() {
    for (push, should_move) in [
        (Vec3::new(2.0, 0.0, 0.0), false),
        (Vec3::new(0.0, 0.0, 2.0), true),
    ] {
        let (mut world, b) = box_world(1.0);
        let params = ContactParams {
            contact_type: ContactType::Friction1D,
            friction: [FrictionModel::Infinite; 2],
            ..Default::default()
        };
        let mut contacts = Vec::new();
        for _ in 0..60 {
            clear_contacts(&mut world, &mut contacts);
            ground_box_contacts(&mut world, b, HALF, params, Some(Vec3::X), &mut contacts);
            world.body_mut(b).unwrap().add_force(push).unwrap();
            world.step(H).unwrap();
        }
        let v = world.body(b).unwrap().linear_velocity();
        if should_move {
            assert!((v.z - 2.0).abs() < 1e-3, "frictionless direction: {v}");
        } else {
            assert!(v.length() < 1e-4, "held direction moved: {v}");
        }
    }
}

#[test]
fn contacts_of_a_pair_form_a_group() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let a = world.create_body(&BodyDef::default()).unwrap();
    let b = world.create_body(&BodyDef::default()).unwrap();
    let c = Contact::default();
    let g1 = world.create_contact(a, None, c).unwrap();
    let ab = world.create_contact(a, Some(b), c).unwrap();
    let g2 = world.create_contact(a, None, c).unwrap();
    let ba = world.create_contact(b, Some(a), c).unwrap();
    let ground: Vec<_> = world.contacts_between(a, None).collect();
    assert_eq!(ground, vec![g1, g2]);
    let pair: Vec<_> = world.contacts_between(a, Some(b)).collect();
    assert_eq!(pair, vec![ab, ba]);
    assert_eq!(world.contact_next(g1).unwrap(), Some(g2));
    assert_eq!(world.contact_next(g2).unwrap(), None);
    assert_eq!(world.contact_next(ab).unwrap(), Some(ba));
}
