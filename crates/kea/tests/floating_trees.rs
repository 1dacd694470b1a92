//! Floating trees in reduced coordinates (`WorldSettings::reduced_free_trees`): bodies joined
//! by a tree's joints and held to nothing step in joint coordinates, the root's six first. A
//! hinged pair and a three-link chain with a ball joint, tumbling in zero gravity, keep their
//! linear and angular momentum and their energy; under gravity their centre of mass falls on
//! the parabola (to the integrator's truncation). In f32 and f64.

use kea::{inertia, BodyDef, JointSpec, Real, Vec3, World, WorldDef, WorldSettings};

fn world(gravity: Vec3) -> World {
    World::new(WorldDef {
        settings: WorldSettings {
            gravity,
            reduced_free_trees: true,
            ..WorldSettings::default()
        },
        ..WorldDef::default()
    })
    .unwrap()
}

/// A 2 kg box and a 1 kg rod on a hinge, and (with `ball`) a half-kilogram ball on a ball
/// joint at the rod's end, spinning and drifting with velocities the joints allow.
fn tumbler(w: &mut World, ball: bool) {
    let (xa, va, wa) = (
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.3, 0.5, -0.2),
        Vec3::new(0.4, 2.0, 0.7),
    );
    let (xb, hinge) = (Vec3::new(0.6, 1.0, 0.0), Vec3::new(0.3, 1.0, 0.0));
    let wb = wa + Vec3::Z * 3.0;
    let vb = va + wa.cross(hinge - xa) + wb.cross(xb - hinge);
    let a = w
        .create_body(&BodyDef {
            position: xa,
            linear_velocity: va,
            angular_velocity: wa,
            inertia: inertia::solid_box(2.0, Vec3::new(0.2, 0.1, 0.15)).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let b = w
        .create_body(&BodyDef {
            position: xb,
            linear_velocity: vb,
            angular_velocity: wb,
            inertia: inertia::solid_box(1.0, Vec3::new(0.3, 0.05, 0.05)).unwrap(),
            ..Default::default()
        })
        .unwrap();
    w.create_joint(b, Some(a), JointSpec::hinge(hinge, Vec3::Z))
        .unwrap();
    if ball {
        let (xc, pivot) = (Vec3::new(1.2, 1.0, 0.0), Vec3::new(0.9, 1.0, 0.0));
        let wc = Vec3::new(-1.0, 0.5, 1.5);
        let vc = vb + wb.cross(pivot - xb) + wc.cross(xc - pivot);
        let c = w
            .create_body(&BodyDef {
                position: xc,
                linear_velocity: vc,
                angular_velocity: wc,
                inertia: inertia::solid_sphere(0.5, 0.1).unwrap(),
                ..Default::default()
            })
            .unwrap();
        w.create_joint(c, Some(b), JointSpec::ball(pivot)).unwrap();
    }
}

fn momenta(w: &World) -> (Vec3, Vec3, Real, Vec3) {
    let (mut p, mut l, mut m, mut c) = (Vec3::ZERO, Vec3::ZERO, 0.0, Vec3::ZERO);
    for (_, b) in w.bodies() {
        let v = b.linear_velocity();
        p += v * b.mass();
        m += b.mass();
        c += b.position() * b.mass();
        let r = b.position();
        let rot = kea::Mat3::from_quat(b.orientation());
        let i_world = rot * b.inertia() * rot.transpose();
        l += r.cross(v * b.mass()) + i_world * b.angular_velocity();
    }
    (p, l, m, c / m)
}

#[test]
fn a_floating_tree_keeps_its_momentum_and_energy() {
    for ball in [false, true] {
        let mut w = world(Vec3::ZERO);
        tumbler(&mut w, ball);
        let (p0, l0, _, _) = momenta(&w);
        let e0 = w.kinetic_energy();
        let h = 1.0 / 240.0;
        for k in 0..480 {
            let stats = w.step(h).unwrap();
            assert_eq!(stats.reduced_trees, 1, "step {k}: one floating tree");
        }
        let (p, l, _, _) = momenta(&w);
        let e = w.kinetic_energy();
        // Round-off in f32; Runge-Kutta 4's truncation (it keeps momenta only to its order)
        // in f64: 2e-9 measured.
        let tol: Real = if cfg!(feature = "f64") { 1e-8 } else { 1e-5 };
        eprintln!(
            "ball {ball}: momentum drift {:.2e}, angular {:.2e}, energy {:.2e} (relative) over 2 s",
            (p - p0).length() / p0.length(),
            (l - l0).length() / l0.length(),
            (e - e0).abs() / e0
        );
        assert!((p - p0).length() < tol * p0.length(), "{p} vs {p0}");
        assert!((l - l0).length() < 10.0 * tol * l0.length(), "{l} vs {l0}");
        assert!((e - e0).abs() < 10.0 * tol * e0, "energy {e} vs {e0}");
        assert!(w.joint_error() < 1e-4, "joints closed: {}", w.joint_error());
    }
}

#[test]
fn a_floating_tree_falls_on_the_parabola() {
    let g = Vec3::new(0.0, -9.81, 0.0);
    let mut w = world(g);
    tumbler(&mut w, true);
    let (p0, _, m, c0) = momenta(&w);
    let v0 = p0 / m;
    let h = 1.0 / 60.0;
    let steps = 60;
    for _ in 0..steps {
        assert_eq!(w.step(h).unwrap().reduced_trees, 1);
    }
    let t = steps as Real * h;
    let (_, _, _, c) = momenta(&w);
    let expected = c0 + v0 * t + g * (0.5 * t * t);
    // Gravity moves the centre on the parabola exactly; the joint coordinates it is read
    // through carry Runge-Kutta 4's truncation at 60 Hz (6e-7 m measured, f32 and f64 alike).
    let tol: Real = 1e-5;
    eprintln!("centre of mass {c}, parabola {expected}");
    assert!((c - expected).length() < tol, "{c} vs {expected}");
}
