//! Static and kinetic friction (`FrictionModel::StaticKinetic`): a box pulled sideways holds
//! until the pull passes μs·N, then slides against μk·N, and once let go decelerates at μk·g
//! until it stops — on every solver path.

mod common;

use kea::{
    BodyDef, BodyHandle, ConstraintHandle, Contact, ContactParams, ContactPoint, FrictionModel,
    Mat3, Real, SolverMode, Vec3, World,
};

const G: Real = 9.81;
const HALF: Real = 0.5;
const DT: Real = 1.0 / 120.0;

/// A box of mass `m` on a four-point contact with the ground, the contact following it.
fn box_on_ground(
    mode: SolverMode,
    m: Real,
    mu: (Real, Real),
) -> (World, BodyHandle, ConstraintHandle) {
    // Default gravity: (0, −G, 0).
    let mut w = common::world_on(mode, 4, 8);
    let b = w
        .create_body(&BodyDef {
            mass: m,
            inertia: Mat3::from_diagonal(Vec3::splat(m * HALF * HALF / 1.5)),
            position: Vec3::new(0.0, HALF, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    let mut c = Contact::with_points(Vec3::Y, &corners(Vec3::ZERO)).unwrap();
    c.set_params(ContactParams {
        friction: [FrictionModel::StaticKinetic {
            static_mu: mu.0,
            kinetic_mu: mu.1,
        }; 2],
        ..ContactParams::default()
    })
    .unwrap();
    let h = w.create_contact(b, None, c).unwrap();
    (w, b, h)
}

fn corners(at: Vec3) -> Vec<ContactPoint> {
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .enumerate()
        .map(|(i, &(x, z))| {
            ContactPoint::new(
                Vec3::new(at.x + x * HALF, 0.0, at.z + z * HALF),
                0.0,
                i as u32,
            )
        })
        .collect()
}

/// Steps `n` times pulling with `pull` (N, along x); returns the speeds along x.
fn run(w: &mut World, b: BodyHandle, h: ConstraintHandle, pull: Real, n: usize) -> Vec<Real> {
    (0..n)
        .map(|_| {
            let at = w.body(b).unwrap().position();
            w.contact_mut(h)
                .unwrap()
                .update(Vec3::Y, &corners(at))
                .unwrap();
            w.body_mut(b)
                .unwrap()
                .add_force(Vec3::new(pull, 0.0, 0.0))
                .unwrap();
            w.step(DT).unwrap();
            w.body(b).unwrap().linear_velocity().x
        })
        .collect()
}

#[test]
fn a_box_holds_below_the_static_bound_then_slides_against_the_kinetic_one() {
    let (m, mu_s, mu_k) = (2.0, 0.6, 0.3);
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        let (mut w, b, h) = box_on_ground(mode, m, (mu_s, mu_k));
        let weight = m * G;
        // Pulled with 0.55 m g, under μs m g but over μk m g: it holds.
        let speeds = run(&mut w, b, h, 0.55 * weight, 120);
        let x = w.body(b).unwrap().position().x;
        assert!(
            x.abs() < 2e-3 && speeds.iter().all(|v| v.abs() < 1e-2),
            "{mode:?}: crept {x} m at 0.55 m g"
        );
        assert!(!w.contact(h).unwrap().is_sliding(), "{mode:?}");
        // Pulled with 0.7 m g, past μs m g: it gives way and slides against μk m g,
        // a = (0.7 − 0.3) g.
        let speeds = run(&mut w, b, h, 0.7 * weight, 120);
        assert!(w.contact(h).unwrap().is_sliding(), "{mode:?}");
        let a = (speeds[119] - speeds[60]) / (59.0 * DT);
        assert!(
            (a - 0.4 * G).abs() < 0.02 * G,
            "{mode:?}: accelerates at {a}, expected {}",
            0.4 * G
        );
        // Let go: it decelerates at μk g and stops, and stays stopped.
        let v0 = speeds[119];
        let speeds = run(&mut w, b, h, 0.0, 240);
        let a = (speeds[40] - speeds[10]) / (30.0 * DT);
        assert!(
            (a + mu_k * G).abs() < 0.02 * G,
            "{mode:?}: decelerates at {a}, expected {}",
            -mu_k * G
        );
        let stop = v0 / (mu_k * G);
        let at_rest = ((stop / DT) as usize + 10).min(239);
        assert!(
            speeds[at_rest..].iter().all(|v| v.abs() < 1e-2),
            "{mode:?}: still moving {} s after it should have stopped",
            (240 - at_rest) as Real * DT
        );
        assert!(!w.contact(h).unwrap().is_sliding(), "{mode:?}: held again");
    }
}

#[test]
fn a_static_coefficient_below_the_kinetic_one_is_refused_by_name() {
    let mut c = Contact::default();
    let bad = ContactParams {
        friction: [FrictionModel::StaticKinetic {
            static_mu: 0.2,
            kinetic_mu: 0.5,
        }; 2],
        ..ContactParams::default()
    };
    let before = c;
    let e = c.set_params(bad).unwrap_err();
    assert!(e.to_string().contains("static_mu"), "{e}");
    assert_eq!(c, before);
}
