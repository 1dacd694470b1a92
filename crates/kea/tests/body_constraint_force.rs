//! The per-body constraint force (`World::body_constraint_force`): the sum of what every joint
//! and contact on a body did to it in the last step, equal to m·a − (m·g + applied force), on
//! every solver path.

mod common;

use kea::{BodyDef, BodyHandle, Contact, ContactPoint, Mat3, Real, SolverMode, Vec3, World};

const G: Real = 9.81;

/// A world of default gravity, (0, −G, 0), whose islands all take `mode`'s path.
fn world(mode: SolverMode) -> World {
    common::world_on(mode, 8, 16)
}

const MODES: [SolverMode; 4] = [
    SolverMode::Hybrid,
    SolverMode::Exact,
    SolverMode::Iterative,
    SolverMode::Split,
];

/// m·a − m·g − f for a body after a step that applied `applied`.
fn newton(w: &World, b: BodyHandle, applied: Vec3) -> Vec3 {
    let body = w.body(b).unwrap();
    body.mass() * body.linear_acceleration() - body.mass() * Vec3::new(0.0, -G, 0.0) - applied
}

#[test]
fn a_swinging_bob_is_pulled_by_its_joint_with_m_a_minus_its_weight() {
    for mode in MODES {
        let mut w = world(mode);
        let bob = w
            .create_body(&BodyDef {
                mass: 1.5,
                position: Vec3::new(0.8, -0.6, 0.0),
                linear_velocity: Vec3::new(0.0, 0.0, 0.7),
                ..BodyDef::default()
            })
            .unwrap();
        w.create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
            .unwrap();
        let push = Vec3::new(0.0, 0.0, 2.0);
        for step in 0..60 {
            w.body_mut(bob).unwrap().add_force(push).unwrap();
            w.step(1.0 / 120.0).unwrap();
            let measured = w.body_constraint_force(bob).unwrap().force;
            let expected = newton(&w, bob, push);
            assert!(
                (measured - expected).length() < 2e-3 * expected.length().max(1.0),
                "{mode:?} step {step}: {measured} vs m a − m g − f = {expected}"
            );
        }
        // The rod pulls towards the pivot, and holds more than the weight's share as it swings.
        let f = w.body_constraint_force(bob).unwrap().force;
        let towards_pivot = -w.body(bob).unwrap().position().normalize();
        assert!(f.dot(towards_pivot) > 0.9 * f.length(), "{mode:?}: {f}");
    }
}

#[test]
fn a_box_at_rest_on_four_contacts_carries_its_weight_and_no_torque() {
    for mode in MODES {
        let mut w = world(mode);
        let (m, half) = (3.0, 0.25);
        let b = w
            .create_body(&BodyDef {
                mass: m,
                inertia: Mat3::from_diagonal(Vec3::splat(0.1)),
                position: Vec3::new(0.4, half, -0.2),
                ..BodyDef::default()
            })
            .unwrap();
        let corners: Vec<ContactPoint> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .enumerate()
            .map(|(i, &(x, z))| {
                ContactPoint::new(
                    Vec3::new(0.4 + x * half, 0.0, -0.2 + z * half),
                    0.0,
                    i as u32,
                )
            })
            .collect();
        let c = Contact::with_points(Vec3::Y, &corners).unwrap();
        w.create_contact(b, None, c).unwrap();
        for _ in 0..120 {
            w.step(1.0 / 60.0).unwrap();
        }
        let r = w.body_constraint_force(b).unwrap();
        let weight = m * G;
        assert!(
            (r.force - Vec3::new(0.0, weight, 0.0)).length() < 1e-2 * weight,
            "{mode:?}: {}",
            r.force
        );
        assert!(
            r.torque.length() < 1e-2 * weight * half,
            "{mode:?}: {}",
            r.torque
        );
        let expected = newton(&w, b, Vec3::ZERO);
        assert!((r.force - expected).length() < 1e-2 * weight, "{mode:?}");
    }
}

#[test]
fn a_body_between_two_joints_sums_both_and_a_free_body_has_none() {
    let mut w = world(SolverMode::Exact);
    let mid = w
        .create_body(&BodyDef {
            mass: 2.0,
            position: Vec3::new(1.0, 0.0, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    let free = w
        .create_body(&BodyDef {
            position: Vec3::new(5.0, 0.0, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    let left = w
        .create_joint(mid, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let right = w
        .create_joint(mid, None, kea::JointSpec::ball(Vec3::new(2.0, 0.0, 0.0)))
        .unwrap();
    for _ in 0..10 {
        w.step(1.0 / 60.0).unwrap();
    }
    let total = w.body_constraint_force(mid).unwrap().force;
    let sum = w.constraint_reaction(left).unwrap()[0].force
        + w.constraint_reaction(right).unwrap()[0].force;
    assert!((total - sum).length() < 1e-5);
    assert!(
        (total - Vec3::new(0.0, 2.0 * G, 0.0)).length() < 1e-2,
        "{total}"
    );
    assert_eq!(w.body_constraint_force(free).unwrap().force, Vec3::ZERO);
    // A destroyed body's handle is refused by name.
    w.destroy_body(free).unwrap();
    assert!(w.body_constraint_force(free).is_err());
}

#[test]
fn a_hinged_rod_in_reduced_coordinates_reports_its_hinge_force_the_same_way() {
    let mut w = world(SolverMode::Hybrid);
    let rod = w
        .create_body(&BodyDef {
            mass: 1.2,
            inertia: Mat3::from_diagonal(Vec3::splat(0.04)),
            position: Vec3::new(0.3, -0.4, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    w.create_joint(rod, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
        .unwrap();
    for step in 0..120 {
        let stats = w.step(1.0 / 240.0).unwrap();
        assert_eq!(stats.reduced_trees, 1);
        let measured = w.body_constraint_force(rod).unwrap().force;
        let expected = newton(&w, rod, Vec3::ZERO);
        // The reaction is Newton–Euler's at the step's start; the body's acceleration spans
        // the step: they agree to first order in h.
        assert!(
            (measured - expected).length() < 0.02 * expected.length().max(1.0),
            "step {step}: {measured} vs {expected}"
        );
    }
}
