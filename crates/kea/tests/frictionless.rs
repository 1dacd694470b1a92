//! Frictionless contacts (`ContactType::Frictionless`): a box slides on one without losing
//! speed, a sideways push accelerates it at F/m, and it still carries its weight — on every
//! solver path.

mod common;

use kea::{
    BodyDef, Contact, ContactParams, ContactPoint, ContactType, Mat3, Real, SolverMode, Vec3,
};

const G: Real = 9.81;

#[test]
fn a_box_on_a_frictionless_contact_slides_freely_and_is_held_up() {
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        // Default gravity: (0, −G, 0).
        let mut w = common::world_on(mode, 4, 8);
        let (m, half) = (2.0, 0.5);
        let b = w
            .create_body(&BodyDef {
                mass: m,
                inertia: Mat3::from_diagonal(Vec3::splat(m * half * half / 1.5)),
                position: Vec3::new(0.0, half, 0.0),
                linear_velocity: Vec3::new(1.5, 0.0, -0.5),
                ..BodyDef::default()
            })
            .unwrap();
        let corners = |x0: Real| -> Vec<ContactPoint> {
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .iter()
                .enumerate()
                .map(|(i, &(x, z))| {
                    ContactPoint::new(Vec3::new(x0 + x * half, 0.0, z * half), 0.0, i as u32)
                })
                .collect()
        };
        let mut contact = Contact::with_points(Vec3::Y, &corners(0.0)).unwrap();
        contact
            .set_params(ContactParams {
                contact_type: ContactType::Frictionless,
                ..ContactParams::default()
            })
            .unwrap();
        let h = w.create_contact(b, None, contact).unwrap();
        let push = Vec3::new(1.0, 0.0, 0.0);
        let dt = 1.0 / 60.0;
        for _ in 0..60 {
            // The contact follows the box, as a collision layer would move it.
            let p = w.body(b).unwrap().position();
            let mut pts = corners(p.x);
            for q in &mut pts {
                q.position.z += p.z;
            }
            w.contact_mut(h).unwrap().update(Vec3::Y, &pts).unwrap();
            w.body_mut(b).unwrap().add_force(push).unwrap();
            w.step(dt).unwrap();
        }
        let body = w.body(b).unwrap();
        // No friction: the push alone changes the sliding velocity, a = F/m for 1 s.
        let v = body.linear_velocity();
        let expected = Vec3::new(1.5 + push.x / m, 0.0, -0.5);
        assert!((v - expected).length() < 1e-3, "{mode:?}: v = {v}");
        assert!(
            (body.position().y - half).abs() < 1e-2,
            "{mode:?}: sank to {}",
            body.position().y
        );
        assert!(body.angular_velocity().length() < 1e-3, "{mode:?}: spun");
        // The contact carries the weight and pushes nothing sideways.
        let f = w.contact_force(h).unwrap();
        assert!(
            (f - Vec3::new(0.0, m * G, 0.0)).length() < 1e-2 * m * G,
            "{mode:?}: {f}"
        );
    }
}
