//! Contact parameters beyond friction: reaction forces, adhesion, softness, 1D friction, and the
//! grouping of a body pair's contacts (the guide's MdtContactGetNext).

mod common;
use common::{world_on, BoxPlaneContacts, F64, PATHS};
use kea::{
    inertia, BodyDef, Contact, ContactParams, ContactType, FrictionModel, Real, SolverMode, Vec3,
    World,
};

const HALF: Vec3 = Vec3::new(0.5, 0.25, 0.5);
const H: Real = 1.0 / 60.0;

fn box_world(mode: SolverMode, mass: Real) -> (World, kea::BodyHandle) {
    let mut world = world_on(mode, 4, 32);
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

/// Steps a box on the ground `steps` times with persistent corner contacts.
fn run_on_ground(
    world: &mut World,
    b: kea::BodyHandle,
    params: ContactParams,
    direction: Option<Vec3>,
    margin: Real,
    steps: usize,
    push: Vec3,
) -> BoxPlaneContacts {
    let mut contacts = BoxPlaneContacts::default();
    for _ in 0..steps {
        contacts.update(world, b, HALF, Vec3::Y, 0.0, margin, params, direction);
        world.body_mut(b).unwrap().add_force(push).unwrap();
        world.step(H).unwrap();
    }
    contacts
}

#[test]
fn resting_contact_forces_sum_to_the_weight() {
    for mode in PATHS {
        let (mut world, b) = box_world(mode, 3.0);
        let contacts = run_on_ground(
            &mut world,
            b,
            ContactParams::default(),
            None,
            0.01,
            120,
            Vec3::ZERO,
        );
        let handles: Vec<_> = contacts.handles().collect();
        let total: Vec3 = handles
            .iter()
            .map(|&c| world.contact_force(c).unwrap())
            .sum();
        let weight = 3.0 * 9.81;
        assert_eq!(handles.len(), 4);
        let tol = if mode == SolverMode::Exact {
            1e-4
        } else {
            2e-2
        };
        eprintln!("{mode:?}: contact forces sum to {total} (weight {weight})");
        assert!(
            (total.y - weight).abs() < tol * weight,
            "{mode:?}: normal force {total}"
        );
        assert!(
            total.x.abs() < tol && total.z.abs() < tol,
            "{mode:?}: {total}"
        );
        if mode == SolverMode::Exact {
            // Symmetric box: each contact carries a quarter (the exact, regularised solution).
            for &c in &handles {
                let l = world.constraint_lambdas(c).unwrap();
                assert_eq!(l.len(), 3);
                assert!((l[0] - weight / 4.0).abs() < 1e-3 * weight, "λn = {}", l[0]);
            }
        }
    }
}

#[test]
fn adhesion_holds_up_to_its_maximum_force() {
    for mode in PATHS {
        for (pull, held) in [(0.9 as Real, true), (1.1, false)] {
            let (mut world, b) = box_world(mode, 1.0);
            world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
            let params = ContactParams {
                max_adhesive_force: 2.0,
                ..Default::default()
            };
            // 4 contacts × 2 N of adhesion = 8 N.
            run_on_ground(
                &mut world,
                b,
                params,
                None,
                0.01,
                60,
                Vec3::new(0.0, pull * 8.0, 0.0),
            );
            let y = world.body(b).unwrap().position().y - HALF.y;
            if held {
                assert!(y.abs() < 1e-3, "{mode:?}: pulled off below the limit: {y}");
            } else {
                assert!(y > 1e-3, "{mode:?}: held above the limit: {y}");
            }
        }
    }
}

#[test]
fn soft_contact_settles_at_the_spring_deflection() {
    // A soft row is a spring k = γ/(ε h²): the box sinks by m g / (4k) on four contacts.
    let softness: Real = 0.05;
    for mode in PATHS {
        let (mut world, b) = box_world(mode, 2.0);
        let params = ContactParams {
            softness: Some(softness),
            ..Default::default()
        };
        run_on_ground(&mut world, b, params, None, 0.05, 600, Vec3::ZERO);
        let k = world.settings().gamma / (softness * H * H);
        let expected = 2.0 * 9.81 / (4.0 * k);
        let sink = HALF.y - world.body(b).unwrap().position().y;
        eprintln!("{mode:?}: soft contact sink {sink:e}, expected {expected:e}");
        assert!(
            (sink - expected).abs() < 1e-3 * expected + if F64 { 0.0 } else { 1e-6 },
            "{mode:?}: sink {sink} vs {expected}"
        );
    }
}

#[test]
fn one_dimensional_friction_holds_only_along_its_direction() {
    for mode in PATHS {
        for (push, should_move) in [
            (Vec3::new(2.0, 0.0, 0.0), false),
            (Vec3::new(0.0, 0.0, 2.0), true),
        ] {
            let (mut world, b) = box_world(mode, 1.0);
            let params = ContactParams {
                contact_type: ContactType::Friction1D,
                friction: [FrictionModel::Infinite; 2],
                ..Default::default()
            };
            run_on_ground(&mut world, b, params, Some(Vec3::X), 0.01, 60, push);
            let v = world.body(b).unwrap().linear_velocity();
            if should_move {
                assert!(
                    (v.z - 2.0).abs() < 1e-3,
                    "{mode:?}: frictionless direction: {v}"
                );
            } else {
                assert!(v.length() < 1e-4, "{mode:?}: held direction moved: {v}");
            }
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
