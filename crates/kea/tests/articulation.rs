//! The reduced-coordinate tree against closed forms: a pendulum's acceleration, a double
//! pendulum's joint-space inertia, a cart-pole's, energy kept by small steps, damping's decay.

use glam::{DMat3, DQuat, DVec3};
use kea::articulation::{ArticulatedTree, TreeJointKind, TreeLink};

const G: f64 = 9.81;

fn link(
    parent: Option<usize>,
    kind: TreeJointKind,
    origin: DVec3,
    axis: DVec3,
    mass: f64,
    com: DVec3,
    inertia: f64,
) -> TreeLink {
    TreeLink {
        parent,
        kind,
        origin: (origin, DQuat::IDENTITY),
        axis,
        anchor: DVec3::ZERO,
        mass,
        com,
        inertia: DMat3::from_diagonal(DVec3::splat(inertia)),
        armature: 0.0,
        damping: 0.0,
        limits: None,
        motor: None,
        friction: 0.0,
        soft_limit: None,
        servo: None,
        spring: None,
        stop_recovery_speed: f64::INFINITY,
    }
}

#[test]
fn a_pendulum_accelerates_as_its_torque_over_its_pivot_inertia() {
    let (m, l, i) = (2.0, 0.7, 0.05);
    let pendulum = link(
        None,
        TreeJointKind::Hinge,
        DVec3::ZERO,
        DVec3::Y,
        m,
        DVec3::new(0.0, 0.0, -l),
        i,
    );
    let mut tree = ArticulatedTree::new(vec![pendulum], DVec3::new(0.0, 0.0, -G)).unwrap();
    for q in [0.0f64, 0.3, 1.2, -2.0] {
        let qdd = tree.accelerations(&[q], &[1.5], &[0.0]).unwrap()[0];
        let expected = -m * G * l * q.sin() / (i + m * l * l);
        assert!(
            (qdd - expected).abs() < 1e-12,
            "q = {q}: {qdd} vs {expected}"
        );
    }
    // A torque adds τ / I_pivot.
    let qdd = tree.accelerations(&[0.0], &[0.0], &[3.0]).unwrap()[0];
    assert!((qdd - 3.0 / (i + m * l * l)).abs() < 1e-12);
}

#[test]
fn a_double_pendulums_inertia_and_gravity_match_lagranges() {
    let (m1, m2, l1, c1, c2, i1, i2) = (1.5, 0.8, 0.6, 0.3, 0.25, 0.02, 0.01);
    let links = vec![
        link(
            None,
            TreeJointKind::Hinge,
            DVec3::ZERO,
            DVec3::Y,
            m1,
            DVec3::new(0.0, 0.0, -c1),
            i1,
        ),
        link(
            Some(0),
            TreeJointKind::Hinge,
            DVec3::new(0.0, 0.0, -l1),
            DVec3::Y,
            m2,
            DVec3::new(0.0, 0.0, -c2),
            i2,
        ),
    ];
    let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
    let (q1, q2): (f64, f64) = (0.4, -0.9);
    // At rest, q̈ = H⁻¹ (−G) with Lagrange's H and gravity torques.
    let h11 = i1 + i2 + m1 * c1 * c1 + m2 * (l1 * l1 + c2 * c2 + 2.0 * l1 * c2 * q2.cos());
    let h12 = i2 + m2 * (c2 * c2 + l1 * c2 * q2.cos());
    let h22 = i2 + m2 * c2 * c2;
    let g1 = (m1 * c1 + m2 * l1) * G * q1.sin() + m2 * G * c2 * (q1 + q2).sin();
    let g2 = m2 * G * c2 * (q1 + q2).sin();
    let det = h11 * h22 - h12 * h12;
    let expected = [(-g1 * h22 + g2 * h12) / det, (g1 * h12 - g2 * h11) / det];
    let qdd = tree
        .accelerations(&[q1, q2], &[0.0, 0.0], &[0.0, 0.0])
        .unwrap();
    for k in 0..2 {
        assert!(
            (qdd[k] - expected[k]).abs() < 1e-10,
            "{qdd:?} vs {expected:?}"
        );
    }
}

#[test]
fn a_cart_pole_matches_its_equations_of_motion() {
    let (mc, mp, l, ip) = (1.0, 0.1, 0.5, 0.002);
    let links = vec![
        link(
            None,
            TreeJointKind::Slider,
            DVec3::ZERO,
            DVec3::X,
            mc,
            DVec3::ZERO,
            0.01,
        ),
        link(
            Some(0),
            TreeJointKind::Hinge,
            DVec3::ZERO,
            DVec3::Y,
            mp,
            DVec3::new(0.0, 0.0, l),
            ip,
        ),
    ];
    let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
    let (th, thd, f): (f64, f64, f64) = (0.2, 0.7, 4.0);
    let qdd = tree
        .accelerations(&[0.0, th], &[0.0, thd], &[f, 0.0])
        .unwrap();
    // Pole up along +z, turning about +y: its centre at (l sin θ, 0, l cos θ).
    let h = [
        [mc + mp, mp * l * th.cos()],
        [mp * l * th.cos(), ip + mp * l * l],
    ];
    let rhs = [f + mp * l * thd * thd * th.sin(), mp * G * l * th.sin()];
    let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
    let expected = [
        (rhs[0] * h[1][1] - h[0][1] * rhs[1]) / det,
        (h[0][0] * rhs[1] - h[1][0] * rhs[0]) / det,
    ];
    for k in 0..2 {
        assert!(
            (qdd[k] - expected[k]).abs() < 1e-10,
            "{qdd:?} vs {expected:?}"
        );
    }
}

fn energy(tree: &mut ArticulatedTree, links: &[TreeLink], q: &[f64], qd: &[f64]) -> f64 {
    // Kinetic from the bodies' motions by finite differences of forward kinematics, and
    // potential from their centres: both from the tree's own kinematics.
    let eps = 1e-7;
    let poses = tree.link_poses(q).unwrap();
    let ahead: Vec<f64> = q.iter().zip(qd).map(|(a, b)| a + eps * b).collect();
    let next = tree.link_poses(&ahead).unwrap();
    let mut e = 0.0;
    for (k, l) in links.iter().enumerate() {
        let (p0, r0) = poses[k];
        let (p1, r1) = next[k];
        let c0 = p0 + r0 * l.com;
        let c1 = p1 + r1 * l.com;
        let v = (c1 - c0) / eps;
        let d = r1 * r0.inverse();
        let (axis, angle) = d.to_axis_angle();
        let w = axis * angle / eps;
        let iw = DMat3::from_quat(r0) * l.inertia * DMat3::from_quat(r0).transpose();
        e += 0.5 * l.mass * v.length_squared() + 0.5 * w.dot(iw * w) + l.mass * G * c0.z;
    }
    e
}

#[test]
fn small_steps_keep_a_three_link_chains_energy_and_damping_takes_it() {
    let mut links = vec![
        link(
            None,
            TreeJointKind::Hinge,
            DVec3::ZERO,
            DVec3::Y,
            1.0,
            DVec3::new(0.25, 0.0, 0.0),
            0.01,
        ),
        link(
            Some(0),
            TreeJointKind::Hinge,
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(0.0, 0.6, 0.8),
            0.7,
            DVec3::new(0.2, 0.05, 0.0),
            0.008,
        ),
        link(
            Some(1),
            TreeJointKind::Hinge,
            DVec3::new(0.4, 0.0, 0.0),
            DVec3::Y,
            0.5,
            DVec3::new(0.15, 0.0, 0.02),
            0.004,
        ),
    ];
    links[1].inertia = DMat3::from_diagonal(DVec3::new(0.004, 0.009, 0.007));
    let mut tree = ArticulatedTree::new(links.clone(), DVec3::new(0.0, 0.0, -G)).unwrap();
    let (mut q, mut qd) = (vec![0.0, 0.3, -0.2], vec![0.0; 3]);
    let e0 = energy(&mut tree, &links, &q, &qd);
    let mut worst: f64 = 0.0;
    for _ in 0..10_000 {
        tree.step(&mut q, &mut qd, &[0.0; 3], 1e-4).unwrap();
        worst = worst.max((energy(&mut tree, &links, &q, &qd) - e0).abs());
    }
    let scale = 2.2 * G * 1.0; // the chain's weight times its reach, J
    assert!(worst < 2e-3 * scale, "energy drifts by {worst} J");
    // Damping on every joint: the chain comes to rest hanging straight down.
    for l in &mut links {
        l.damping = 0.5;
    }
    let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -G)).unwrap();
    for _ in 0..100_000 {
        tree.step(&mut q, &mut qd, &[0.0; 3], 1e-3).unwrap();
    }
    assert!(qd.iter().all(|v| v.abs() < 1e-3), "{qd:?}");
    let bad = tree.step(&mut q, &mut qd, &[0.0; 2], 1e-3).unwrap_err();
    assert!(bad.to_string().contains("tau"), "{bad}");
}

#[test]
fn stops_hold_motors_drive_and_friction_holds_until_pushed_past_it() {
    // A pendulum released at 1 rad falls onto its stop at 1.5 rad and rests there.
    let mut p = link(
        None,
        TreeJointKind::Hinge,
        DVec3::ZERO,
        DVec3::Y,
        1.0,
        DVec3::new(0.5, 0.0, 0.0),
        0.01,
    );
    // Turning about +y takes +x towards −z: the arm falls towards positive angles.
    let (mut q, mut qd) = (vec![1.0], vec![0.0]);
    p.limits = Some((-0.5, 1.5));
    let mut tree2 = ArticulatedTree::new(vec![p], DVec3::new(0.0, 0.0, -G)).unwrap();
    let mut most: f64 = 0.0;
    for _ in 0..3000 {
        tree2.step(&mut q, &mut qd, &[0.0], 1e-3).unwrap();
        most = most.max(q[0]);
    }
    assert!(most <= 1.5 + 1e-9, "never past the stop: {most}");
    assert!(
        (q[0] - 1.5).abs() < 1e-6 && qd[0].abs() < 1e-6,
        "resting on it: {q:?} {qd:?}"
    );
    // The stop carries the arm's weight: m g l cos(1.5) about the pivot.
    let held = tree2.constraint_forces(1e-3)[0];
    assert!(
        (held.abs() - 1.0 * G * 0.5 * 1.5f64.cos()).abs() < 1e-3,
        "{held}"
    );
    // A motor of at most 2 N·m drives a wheel of 0.5 kg·m² (no gravity about its axis) to
    // 3 rad/s: at 4 rad/s² for 0.75 s, then holds.
    let mut w = link(
        None,
        TreeJointKind::Hinge,
        DVec3::ZERO,
        DVec3::Z,
        1.0,
        DVec3::ZERO,
        0.5,
    );
    w.motor = Some((3.0, 2.0));
    let mut wheel = ArticulatedTree::new(vec![w], DVec3::new(0.0, 0.0, -G)).unwrap();
    let (mut q, mut qd) = (vec![0.0], vec![0.0]);
    for _ in 0..500 {
        wheel.step(&mut q, &mut qd, &[0.0], 1e-3).unwrap();
    }
    assert!((qd[0] - 2.0).abs() < 1e-9, "ramping at 4 rad/s²: {}", qd[0]);
    for _ in 0..500 {
        wheel.step(&mut q, &mut qd, &[0.0], 1e-3).unwrap();
    }
    assert!((qd[0] - 3.0).abs() < 1e-9, "held at 3 rad/s: {}", qd[0]);
    // Dry friction of 1 N·m holds against 0.9 N·m and slips under 1.5 N·m at 0.5 / 0.5 rad/s².
    for (torque, rate) in [(0.9, 0.0), (1.5, 1.0)] {
        let mut f = link(
            None,
            TreeJointKind::Hinge,
            DVec3::ZERO,
            DVec3::Z,
            1.0,
            DVec3::ZERO,
            0.5,
        );
        f.friction = 1.0;
        let mut knob = ArticulatedTree::new(vec![f], DVec3::new(0.0, 0.0, -G)).unwrap();
        let (mut q, mut qd) = (vec![0.0], vec![0.0]);
        for _ in 0..1000 {
            knob.step(&mut q, &mut qd, &[torque], 1e-3).unwrap();
        }
        assert!((qd[0] - rate).abs() < 1e-9, "torque {torque}: {}", qd[0]);
    }
}

#[test]
fn a_servo_brings_its_coordinate_to_the_target_as_a_damped_spring() {
    // kp = 50, kv = 10 on a 0.5 kg·m² wheel: ω = 10 rad/s, ζ = 1 (critical): no overshoot,
    // within 1e-3 of the target after 1.2 s, at any step.
    for h in [1e-3, 1e-2] {
        let mut w = link(
            None,
            TreeJointKind::Hinge,
            DVec3::ZERO,
            DVec3::Z,
            1.0,
            DVec3::ZERO,
            0.5,
        );
        w.servo = Some((1.0, 0.0, 50.0, 10.0));
        let mut wheel = ArticulatedTree::new(vec![w], DVec3::new(0.0, 0.0, -G)).unwrap();
        let (mut q, mut qd) = (vec![0.0], vec![0.0]);
        let mut most: f64 = 0.0;
        for _ in 0..(1.2 / h) as usize {
            wheel.step(&mut q, &mut qd, &[0.0], h).unwrap();
            most = most.max(q[0]);
        }
        assert!(most <= 1.0 + 1e-9, "h {h}: overshoots to {most}");
        assert!((q[0] - 1.0).abs() < 2e-3, "h {h}: {}", q[0]);
    }
}
