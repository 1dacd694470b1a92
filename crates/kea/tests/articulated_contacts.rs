//! A tree's contacts with its base in joint space (`kea::articulation`, MuJoCo's soft contact
//! model): a block on a vertical slider comes to rest at the model's own equilibrium depth and
//! reads its weight; a block sliding on the ground slows at μ·g; a frictionless one keeps its
//! speed; a hinged rod falling onto the ground stops on it. Every integrator that takes
//! contacts (Euler, Runge–Kutta 4).

use glam::{DMat3, DQuat, DVec3};
use kea::articulation::{ArticulatedTree, Integrator, TreeContact, TreeJointKind, TreeLink};
use kea::math::wide;
use kea::SoftLimit;

const G: f64 = 9.81;
const H: f64 = 0.002;
const INTEGRATORS: [Integrator; 2] = [Integrator::Euler, Integrator::RungeKutta4];

fn slider(parent: Option<usize>, axis: DVec3, mass: f64) -> TreeLink {
    TreeLink {
        parent,
        kind: TreeJointKind::Slider,
        axis,
        mass,
        inertia: DMat3::IDENTITY * (mass / 6.0),
        ..TreeLink::default()
    }
}

/// MuJoCo's impedance at `x` past the margin (its default `solimp`).
fn impedance(s: &SoftLimit, x: f64) -> f64 {
    let [dmin, dmax, width, mid, power] = s.solimp.map(wide);
    let x = (x.abs() / width).min(1.0);
    let y = if x <= mid {
        x.powf(power) / mid.powf(power - 1.0)
    } else {
        1.0 - (1.0 - x).powf(power) / (1.0 - mid).powf(power - 1.0)
    };
    dmin + y * (dmax - dmin)
}

/// The depth at which the model holds a weight at rest: with the free acceleration `−g`, the
/// row's force solves `(A + R) f = a_ref + g`, `R = (1 − d)/d · A`, `a_ref = −k d x`, and the
/// body rests when `A f = g`: `g (1 − d) = −k d² x`. Found by bisection on `x < 0`.
fn rest_depth(s: &SoftLimit, h: f64) -> f64 {
    let tau = wide(s.solref[0]).max(2.0 * h);
    let (zeta, dmax) = (wide(s.solref[1]), wide(s.solimp[1]));
    let k = 1.0 / (dmax * dmax * tau * tau * zeta * zeta);
    let f = |x: f64| {
        let d = impedance(s, x);
        G * (1.0 - d) + k * d * d * x
    };
    let (mut lo, mut hi) = (-0.1, 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A 2 kg block whose bottom is at the slider's coordinate `q`, on the ground at 0: its
/// contact for the step starting at `q`.
fn ground(link: usize, q: f64, mu: f64, point: DVec3) -> TreeContact {
    TreeContact {
        link,
        point,
        normal: DVec3::Z,
        distance: q,
        friction: mu,
        other: None,
        warm: DVec3::ZERO,
    }
}

#[test]
fn a_block_comes_to_rest_at_the_models_depth_and_reads_its_weight() {
    let model = SoftLimit::default();
    let expected = rest_depth(&model, H);
    for integrator in INTEGRATORS {
        let links = vec![slider(None, DVec3::Z, 2.0)];
        let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
        tree.set_integrator(integrator);
        // Dropped from 5 cm.
        let (mut q, mut qd) = (vec![0.05], vec![0.0]);
        for _ in 0..2000 {
            let c = ground(0, q[0], 0.0, DVec3::ZERO);
            tree.set_contacts(&[c], model).unwrap();
            tree.step(&mut q, &mut qd, &[0.0], H).unwrap();
            assert!(q[0] > -0.01, "{integrator:?}: sank to {}", q[0]);
        }
        let force = tree.contact_forces()[0];
        eprintln!(
            "{integrator:?}: rests at {:.4e} m (model {:.4e}), rate {:.1e}, force {force}",
            q[0], expected, qd[0]
        );
        assert!(
            (q[0] - expected).abs() < 1e-7,
            "{integrator:?}: depth {}",
            q[0]
        );
        assert!(qd[0].abs() < 1e-7);
        assert!((force.z - 2.0 * G).abs() < 1e-6 * 2.0 * G, "{force}");
        assert!(force.x.abs() < 1e-9 && force.y.abs() < 1e-9);
    }
}

#[test]
fn a_sliding_block_is_slowed_by_mu_times_its_normal_impulse() {
    // While it slides, only the pyramid's rear edge pushes: the friction impulse is μ times
    // the normal impulse, whatever the normal force does (a pyramid's edge rows also push the
    // block up in proportion to its sliding speed, and it hops a millimetre as it slides:
    // MuJoCo's pyramidal cone does the same, 4.117 m/s² over this window for its box against
    // 4.114 here). So `m₁ Δv_x = −μ (M g t + M Δv_z)`. Frictionless, the speed is kept.
    let (m0, m1, mu) = (1e-3, 1.0, 0.4);
    let mass = m0 + m1;
    for integrator in INTEGRATORS {
        for friction in [mu, 0.0] {
            // A light carriage on a vertical slider carrying the block on a horizontal one.
            let links = vec![slider(None, DVec3::Z, m0), slider(Some(0), DVec3::X, m1)];
            let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
            tree.set_integrator(integrator);
            let depth = rest_depth(&SoftLimit::default(), H);
            let (mut q, mut qd) = (vec![depth, 0.0], vec![0.0, 2.0]);
            let start = qd.clone();
            let steps = 200;
            for _ in 0..steps {
                let c = ground(1, q[0], friction, DVec3::ZERO);
                tree.set_contacts(&[c], SoftLimit::default()).unwrap();
                tree.step(&mut q, &mut qd, &[0.0, 0.0], H).unwrap();
                let f = tree.contact_forces()[0];
                assert!(
                    f.x <= 0.0 && (f.x + friction * f.z).abs() <= 1e-9 * f.z.max(1.0),
                    "{f}"
                );
            }
            assert!(qd[1] > 0.1, "still sliding");
            let t = steps as f64 * H;
            let lost = m1 * (start[1] - qd[1]);
            let normal = mass * G * t + mass * (qd[0] - start[0]);
            eprintln!(
                "{integrator:?} μ = {friction}: speed {:.4} m/s after {t} s, x-impulse lost {lost:.6} N·s, μ·normal impulse {:.6} N·s",
                qd[1],
                friction * normal
            );
            if friction > 0.0 {
                assert!((lost - friction * normal).abs() < 1e-9 * lost, "{lost}");
            } else {
                assert!(lost.abs() < 1e-12, "{lost}");
            }
        }
    }
}

#[test]
fn a_hinged_rod_falls_onto_the_ground_and_stops_on_it() {
    // A 1 m rod on a hinge about y at the origin, released horizontal along +x, over ground
    // 0.5 m below the pivot: its far half lands and stays.
    for integrator in INTEGRATORS {
        let links = vec![TreeLink {
            parent: None,
            kind: TreeJointKind::Hinge,
            origin: (DVec3::new(0.5, 0.0, 0.0), DQuat::IDENTITY),
            axis: DVec3::Y,
            anchor: DVec3::new(-0.5, 0.0, 0.0),
            mass: 1.0,
            inertia: DMat3::from_diagonal(DVec3::new(1e-4, 1.0 / 12.0, 1.0 / 12.0)),
            ..TreeLink::default()
        }];
        let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
        tree.set_integrator(integrator);
        let (mut q, mut qd): (Vec<f64>, Vec<f64>) = (vec![0.0], vec![0.0]);
        let tip = DVec3::new(0.5, 0.0, 0.0);
        for _ in 0..3000 {
            // The tip's height (the rod turns about +y: positive angles lower +x).
            let height = -(q[0].sin()) + 0.5;
            tree.set_contacts(&[ground(0, height, 0.0, tip)], SoftLimit::default())
                .unwrap();
            tree.step(&mut q, &mut qd, &[0.0], H).unwrap();
        }
        let height = 0.5 - q[0].sin();
        let force = tree.contact_forces()[0];
        eprintln!(
            "{integrator:?}: tip at {height:.3e} m, rate {:.1e}, force {force}",
            qd[0]
        );
        // At rest on its tip: the ground carries half the weight (moments about the pivot).
        assert!(height.abs() < 1e-3 && height < 0.0, "{height}");
        assert!(qd[0].abs() < 1e-6);
        assert!((force.length() - 0.5 * G).abs() < 1e-3 * G, "{force}");
    }
}

#[test]
fn bad_contacts_are_refused_by_name() {
    let links = vec![slider(None, DVec3::Z, 1.0)];
    let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
    let good = ground(0, 0.0, 0.5, DVec3::ZERO);
    let cases = [
        ("link", TreeContact { link: 1, ..good }),
        (
            "normal",
            TreeContact {
                normal: DVec3::new(0.0, 0.0, 2.0),
                ..good
            },
        ),
        (
            "point",
            TreeContact {
                distance: f64::NAN,
                ..good
            },
        ),
        (
            "friction",
            TreeContact {
                friction: -1.0,
                ..good
            },
        ),
    ];
    for (arg, c) in cases {
        let e = tree.set_contacts(&[c], SoftLimit::default()).unwrap_err();
        assert!(e.to_string().contains(arg), "{arg}: {e}");
    }
    assert!(
        tree.contact_forces().is_empty(),
        "a refused call changes nothing"
    );
}
