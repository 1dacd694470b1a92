//! Joints from issue 4 that exist so far: each removes exactly its degrees of freedom; hinge
//! motors, brakes, hard and soft stops; continuous hinge angles beyond ±π.

mod common;
use common::{world_on, F64, PATHS};
use kea::{inertia, BodyDef, BodyHandle, Real, SingleLimit, SolverMode, Vec3, World, PI_REAL};

/// Deterministic pseudo-random vectors in [-1, 1]³.
struct Rng(u64);
impl Rng {
    fn vec(&mut self) -> Vec3 {
        let mut f = || {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 40) as Real / (1u64 << 24) as Real) * 2.0 - 1.0
        };
        Vec3::new(f(), f(), f())
    }
}

fn body(world: &mut World, p: Vec3) -> BodyHandle {
    world
        .create_body(&BodyDef {
            position: p,
            inertia: inertia::solid_box(1.0, Vec3::new(0.3, 0.2, 0.1)).unwrap(),
            ..Default::default()
        })
        .unwrap()
}

/// Pushes `b` with random forces (up to 2 N) and torques (up to 0.3 N·m) for 2 s and returns
/// the largest value of `err`. (Much harder shaking spins the body fast enough for the
/// velocity-level rows' curvature drift, (v h)²/(2r)/γ per step, to pass 1 mm at 60 Hz.)
fn shake(world: &mut World, b: BodyHandle, mut err: impl FnMut(&World) -> Real) -> Real {
    let mut rng = Rng(7);
    let mut worst: Real = 0.0;
    for _ in 0..120 {
        let (f, t) = (rng.vec() * 2.0, rng.vec() * 0.3);
        let bm = world.body_mut(b).unwrap();
        bm.add_force(f).unwrap();
        bm.add_torque(t).unwrap();
        world.step(1.0 / 60.0).unwrap();
        worst = worst.max(err(world));
    }
    worst
}

#[test]
fn hinge_removes_five_dof_and_turns_freely() {
    for mode in PATHS {
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::new(0.5, 0.0, 0.0));
        let h = world
            .create_joint(b, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
            .unwrap();
        let worst = shake(&mut world, b, |w| {
            let body = w.body(b).unwrap();
            let anchor_gap = body
                .point_to_world(h.get(&w).unwrap().local_anchor1)
                .length();
            let tilt = (body.orientation() * Vec3::Z).cross(Vec3::Z).length();
            anchor_gap.max(tilt)
        });
        let angle = h.get(&world).unwrap().angle();
        eprintln!("{mode:?}: hinge worst constrained drift {worst:e}, angle {angle}");
        assert!(worst < 1e-3, "{mode:?}: constrained motion {worst}");
        assert!(
            angle.abs() > 0.05,
            "{mode:?}: the free rotation did not happen ({angle})"
        );
    }
}

#[test]
fn prismatic_fixed_universal_and_linear_joints_remove_their_dof() {
    for mode in PATHS {
        // Prismatic along x: no rotation, no motion off the axis.
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::ZERO);
        let s = world
            .create_joint(b, None, kea::JointSpec::prismatic(Vec3::ZERO, Vec3::X))
            .unwrap();
        let worst = shake(&mut world, b, |w| {
            let body = w.body(b).unwrap();
            let p = body.position();
            (p.y.abs())
                .max(p.z.abs())
                .max(2.0 * body.orientation().xyz().length())
        });
        let d = s.get(&world).unwrap().distance();
        assert!(
            worst < 1e-3 && d.abs() > 0.01,
            "{mode:?}: prismatic {worst} {d}"
        );
        // Fixed: nothing moves.
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::new(0.2, 0.0, 0.0));
        world
            .create_joint(b, None, kea::JointSpec::fixed(Vec3::ZERO))
            .unwrap();
        let worst = shake(&mut world, b, |w| {
            let body = w.body(b).unwrap();
            (body.position() - Vec3::new(0.2, 0.0, 0.0))
                .length()
                .max(2.0 * body.orientation().xyz().length())
        });
        assert!(worst < 1e-3, "{mode:?}: fixed {worst}");
        // Linear1: the anchor stays on the plane y = 0, everything else is free.
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::new(0.0, 0.3, 0.0));
        let j = world
            .create_joint(b, None, kea::JointSpec::linear1(Vec3::ZERO, Vec3::Y))
            .unwrap();
        let local = Vec3::new(0.0, -0.3, 0.0);
        let stored = *j.get(&world).unwrap();
        assert!(stored.local_anchor1.abs_diff_eq(local, 1e-6));
        assert!(stored.local_normal2.abs_diff_eq(Vec3::Y, 1e-6));
        let as_linear2 = kea::JointHandle::<kea::Linear2>::from_raw(j.raw());
        assert!(
            as_linear2.get(&world).is_err(),
            "a linear1 joint is not a linear2"
        );
        let mut moved: Real = 0.0;
        let worst = shake(&mut world, b, |w| {
            let p = w.body(b).unwrap().point_to_world(local);
            moved = moved.max(p.x.abs() + p.z.abs());
            p.y.abs()
        });
        assert!(
            worst < 1e-3 && moved > 0.01,
            "{mode:?}: linear1 {worst} {moved}"
        );
        // Linear2: the anchor stays on the line along x.
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::new(0.0, 0.3, 0.0));
        let j = world
            .create_joint(b, None, kea::JointSpec::linear2(Vec3::ZERO, Vec3::X))
            .unwrap();
        let direction = j.get(&world).unwrap().local_direction2;
        assert!(direction.abs_diff_eq(Vec3::X, 1e-6));
        let mut slid: Real = 0.0;
        let worst = shake(&mut world, b, |w| {
            let p = w.body(b).unwrap().point_to_world(local);
            slid = slid.max(p.x.abs());
            p.y.abs().max(p.z.abs())
        });
        assert!(
            worst < 1e-3 && slid > 0.01,
            "{mode:?}: linear2 {worst} {slid}"
        );
        // Universal: anchor held, the two axes stay perpendicular.
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::new(0.0, -0.4, 0.0));
        world
            .create_joint(
                b,
                None,
                kea::JointSpec::universal(Vec3::ZERO, Vec3::X, Vec3::Z),
            )
            .unwrap();
        let worst = shake(&mut world, b, |w| {
            let body = w.body(b).unwrap();
            let gap = body.point_to_world(Vec3::new(0.0, 0.4, 0.0)).length();
            gap.max((body.orientation() * Vec3::X).dot(Vec3::Z).abs())
        });
        assert!(worst < 1e-3, "{mode:?}: universal {worst}");
    }
}

fn flywheel(mode: SolverMode) -> (World, BodyHandle, kea::JointHandle<kea::Hinge>, Real) {
    let mut world = world_on(mode, 4, 4);
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let i = inertia::solid_cylinder(2.0, 0.5, 0.1).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: 2.0,
            inertia: i,
            ..Default::default()
        })
        .unwrap();
    let h = world
        .create_joint(b, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Y))
        .unwrap();
    (world, b, h, i.y_axis.y)
}

#[test]
fn hinge_motor_spins_up_at_the_torque_limited_rate_and_stalls_or_brakes() {
    let h_step: Real = 1.0 / 60.0;
    for mode in PATHS {
        let (mut world, b, h, i) = flywheel(mode);
        let (target, tau) = (5.0 as Real, 2.0 as Real);
        h.limit_mut(&mut world)
            .unwrap()
            .set_motor(target, tau)
            .unwrap();
        let mut max_err: Real = 0.0;
        for n in 1..=60 {
            world.step(h_step).unwrap();
            let w = world.body(b).unwrap().angular_velocity().y;
            let expected = target.min(n as Real * h_step * tau / i);
            max_err = max_err.max((w - expected).abs() / target);
        }
        let tol = match mode {
            SolverMode::Exact => {
                if F64 {
                    1e-9
                } else {
                    1e-5
                }
            }
            _ => 1e-4,
        };
        eprintln!("{mode:?}: motor spin-up max relative error {max_err:e}");
        assert!(max_err < tol, "{mode:?}: motor ω off by {max_err}");
        // A load above the limit stalls it (and drives it backwards at (load − τ)/I).
        let (mut world, b, h, i) = flywheel(mode);
        h.limit_mut(&mut world)
            .unwrap()
            .set_motor(target, tau)
            .unwrap();
        for _ in 0..60 {
            world
                .body_mut(b)
                .unwrap()
                .add_torque(Vec3::new(0.0, -3.0, 0.0))
                .unwrap();
            world.step(h_step).unwrap();
        }
        let w = world.body(b).unwrap().angular_velocity().y;
        assert!(
            (w + 1.0 * 1.0 / i).abs() < 1e-3 * (1.0 / i),
            "{mode:?}: stalled motor ω {w}"
        );
        // A brake holds a load below its limit.
        let (mut world, b, h, _) = flywheel(mode);
        h.limit_mut(&mut world)
            .unwrap()
            .set_motor(0.0, tau)
            .unwrap();
        for _ in 0..60 {
            world
                .body_mut(b)
                .unwrap()
                .add_torque(Vec3::new(0.0, 1.5, 0.0))
                .unwrap();
            world.step(h_step).unwrap();
        }
        let w = world.body(b).unwrap().angular_velocity().y;
        assert!(w.abs() < 1e-6, "{mode:?}: the brake slipped: {w}");
    }
}

#[test]
fn hard_stop_rebounds_with_its_restitution() {
    for mode in PATHS {
        let (mut world, b, h, _) = flywheel(mode);
        h.limit_mut(&mut world)
            .unwrap()
            .set_limits(SingleLimit::hard(-0.5, 0.5), SingleLimit::hard(0.5, 0.5))
            .unwrap();
        world
            .body_mut(b)
            .unwrap()
            .set_angular_velocity(Vec3::new(0.0, 3.0, 0.0))
            .unwrap();
        let mut after = None;
        for _ in 0..80 {
            world.step(1.0 / 240.0).unwrap();
            let w = world.body(b).unwrap().angular_velocity().y;
            if w < 0.0 && after.is_none() {
                after = Some(w);
            }
            assert!(
                h.get(&world).unwrap().angle() < 0.5 + 1e-3,
                "{mode:?}: went through the stop"
            );
        }
        let w = after.expect("no rebound");
        eprintln!("{mode:?}: rebound {w} rad/s from 3 rad/s, e = 0.5");
        assert!((w + 1.5).abs() < 0.02 * 1.5, "{mode:?}: rebound {w}");
    }
}

#[test]
fn soft_stop_settles_at_f_over_k_and_rings_at_sqrt_k_over_i() {
    let (k, load): (Real, Real) = (40.0, 2.0);
    for mode in PATHS {
        let (mut world, b, h, i) = flywheel(mode);
        h.limit_mut(&mut world)
            .unwrap()
            .set_limits(
                SingleLimit::soft(-1.0, k, 0.0),
                SingleLimit::soft(0.0, k, 0.0),
            )
            .unwrap();
        let h_step: Real = 1.0 / 240.0;
        let mut crossings = Vec::new();
        let mut prev: Real = 0.0;
        let target = load / k;
        for n in 0..2400 {
            world
                .body_mut(b)
                .unwrap()
                .add_torque(Vec3::new(0.0, load, 0.0))
                .unwrap();
            world.step(h_step).unwrap();
            let a = h.get(&world).unwrap().angle();
            if prev < target && a >= target && n > 0 {
                crossings.push(n as Real * h_step);
            }
            prev = a;
        }
        // Undamped: it oscillates about F/k at ω = √(k/I); the mean of the angle is F/k.
        let periods: Vec<Real> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
        let period = periods.iter().sum::<Real>() / periods.len() as Real;
        let expected = 2.0 * PI_REAL * (i / k).sqrt();
        eprintln!("{mode:?}: soft stop period {period} s, expected {expected} s");
        assert!(
            (period - expected).abs() < 0.02 * expected,
            "{mode:?}: period {period}"
        );
        // With damping it settles at F/k.
        let (mut world, b, h, _) = flywheel(mode);
        h.limit_mut(&mut world)
            .unwrap()
            .set_limits(
                SingleLimit::soft(-1.0, k, 2.0),
                SingleLimit::soft(0.0, k, 2.0),
            )
            .unwrap();
        for _ in 0..1200 {
            world
                .body_mut(b)
                .unwrap()
                .add_torque(Vec3::new(0.0, load, 0.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        let a = h.get(&world).unwrap().angle();
        eprintln!("{mode:?}: soft stop rests at {a} rad, F/k = {target}");
        assert!((a - target).abs() < 0.02 * target, "{mode:?}: rests at {a}");
    }
}

#[test]
fn hinge_limits_near_and_beyond_pi_hold_while_spinning_fast() {
    let deg = PI_REAL / 180.0;
    for mode in PATHS {
        for (lo, hi) in [(-170.0 * deg, 170.0 * deg), (-200.0 * deg, 200.0 * deg)] {
            let (mut world, _b, h, _) = flywheel(mode);
            let limit = h.limit_mut(&mut world).unwrap();
            limit
                .set_limits(SingleLimit::hard(lo, 0.0), SingleLimit::hard(hi, 0.0))
                .unwrap();
            limit.set_motor(30.0, 50.0).unwrap();
            let mut max_angle: Real = -10.0;
            for _ in 0..120 {
                world.step(1.0 / 60.0).unwrap();
                max_angle = max_angle.max(h.get(&world).unwrap().angle());
            }
            let over = max_angle - hi;
            eprintln!(
                "{mode:?}: limit {:.0}°, driven at 30 rad/s: max angle {:.3}°",
                hi / deg,
                max_angle / deg
            );
            assert!(
                over < 2e-3,
                "{mode:?}: passed the {}° stop by {over} rad",
                hi / deg
            );
            assert!(max_angle > hi - 0.01, "{mode:?}: never reached the stop");
        }
    }
}

#[test]
fn ball_joint_twist_cone_and_segment_limits_hold() {
    for mode in PATHS {
        // A bob hanging 1 m below a ball joint; primary axis down, orthogonal axis along x.
        let setup = |mut world: &mut World| {
            let b = body(world, Vec3::new(0.0, -1.0, 0.0));
            let j = world
                .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
                .unwrap();
            j.set_limit_axes(&mut world, -Vec3::Y, Vec3::X).unwrap();
            (b, j)
        };
        // Cone: pushed sideways hard, it stops at 0.3 rad.
        let mut world = world_on(mode, 4, 4);
        let (b, j) = setup(&mut world);
        j.limits_mut(&mut world)
            .unwrap()
            .cone
            .set_limits(SingleLimit::hard(-1.0, 0.0), SingleLimit::hard(0.3, 0.0))
            .unwrap();
        let mut max_cone: Real = 0.0;
        for _ in 0..120 {
            world
                .body_mut(b)
                .unwrap()
                .add_force(Vec3::new(8.0, 0.0, 3.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
            max_cone = max_cone.max(j.limits_mut(&mut world).unwrap().cone.position());
        }
        let p = world.body(b).unwrap().position();
        let com_angle = p.normalize().dot(-Vec3::Y).clamp(-1.0, 1.0).acos();
        eprintln!("{mode:?}: cone limit 0.3 rad, largest cone angle {max_cone} (centre of mass at {com_angle})");
        assert!(
            max_cone < 0.3 + 5e-3 && max_cone > 0.29,
            "{mode:?}: cone {max_cone}"
        );
        // Twist: a torque about the hanging axis stops at 0.5 rad.
        let mut world = world_on(mode, 4, 4);
        let (b, j) = setup(&mut world);
        j.limits_mut(&mut world)
            .unwrap()
            .twist
            .set_limits(SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(0.5, 0.0))
            .unwrap();
        for _ in 0..120 {
            world
                .body_mut(b)
                .unwrap()
                .add_torque(Vec3::new(0.0, 2.0, 0.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        let twist = j.limits_mut(&mut world).unwrap().twist.position();
        eprintln!("{mode:?}: twist limit 0.5 rad, twist {twist}");
        assert!((twist.abs() - 0.5).abs() < 5e-3, "{mode:?}: twist {twist}");
        // Segment: swung towards +z (longitude 90° from x), it stops at longitude 0.4 rad.
        let mut world = world_on(mode, 4, 4);
        let (b, j) = setup(&mut world);
        j.limits_mut(&mut world)
            .unwrap()
            .segment
            .set_limits(SingleLimit::hard(-0.4, 0.0), SingleLimit::hard(0.4, 0.0))
            .unwrap();
        world
            .body_mut(b)
            .unwrap()
            .set_position(Vec3::new(0.3, -0.954, 0.0))
            .unwrap();
        for _ in 0..120 {
            world
                .body_mut(b)
                .unwrap()
                .add_force(Vec3::new(0.0, 0.0, 20.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        let seg = j.limits_mut(&mut world).unwrap().segment.position();
        eprintln!("{mode:?}: segment limit 0.4 rad, segment {seg}");
        assert!(seg.abs() < 0.4 + 1e-2, "{mode:?}: segment {seg}");
    }
}

#[test]
fn prismatic_hard_stop_rebounds_and_a_motor_leaves_it_without_a_jump() {
    // VALIDATION #14.
    for mode in PATHS {
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::ZERO);
        let s = world
            .create_joint(b, None, kea::JointSpec::prismatic(Vec3::ZERO, Vec3::X))
            .unwrap();
        s.limit_mut(&mut world)
            .unwrap()
            .set_limits(SingleLimit::hard(-0.2, 0.6), SingleLimit::hard(0.2, 0.6))
            .unwrap();
        world
            .body_mut(b)
            .unwrap()
            .set_linear_velocity(Vec3::new(2.0, 0.0, 0.0))
            .unwrap();
        let mut rebound = None;
        for _ in 0..60 {
            world.step(1.0 / 240.0).unwrap();
            let v = world.body(b).unwrap().linear_velocity().x;
            if v < 0.0 && rebound.is_none() {
                rebound = Some(v);
            }
        }
        let v = rebound.expect("no rebound");
        assert!((v + 1.2).abs() < 0.02 * 1.2, "{mode:?}: rebound {v}");
        // Resting on the lower stop, a motor drives away: its first step is at most h·F/m.
        let mut world = world_on(mode, 4, 4);
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = body(&mut world, Vec3::ZERO);
        let s = world
            .create_joint(b, None, kea::JointSpec::prismatic(Vec3::ZERO, Vec3::X))
            .unwrap();
        s.limit_mut(&mut world)
            .unwrap()
            .set_limits(SingleLimit::hard(0.0, 0.0), SingleLimit::hard(1.0, 0.0))
            .unwrap();
        for _ in 0..10 {
            world
                .body_mut(b)
                .unwrap()
                .add_force(Vec3::new(-5.0, 0.0, 0.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        s.limit_mut(&mut world)
            .unwrap()
            .set_motor(3.0, 4.0)
            .unwrap();
        world.step(1.0 / 60.0).unwrap();
        let v = world.body(b).unwrap().linear_velocity().x;
        assert!(
            v > 0.0 && v <= 4.0 / 60.0 + 1e-5,
            "{mode:?}: first step away at {v} m/s"
        );
    }
}

#[test]
fn physical_pendulum_on_a_hinge_has_the_rod_period() {
    // VALIDATION #6: a rod of length L hinged at one end, small swing: T = 2π√(2L/(3g)).
    let l: Real = 1.0;
    for mode in PATHS {
        let mut world = world_on(mode, 4, 4);
        let theta: Real = 0.05;
        let rod = world
            .create_body(&BodyDef {
                position: Vec3::new(0.5 * l * theta.sin(), -0.5 * l * theta.cos(), 0.0),
                orientation: kea::Quat::from_rotation_z(theta),
                inertia: inertia::solid_box(1.0, Vec3::new(0.01, 0.5 * l, 0.01)).unwrap(),
                ..Default::default()
            })
            .unwrap();
        let h = world
            .create_joint(rod, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
            .unwrap();
        // The hinge angle is 0 where it was created (θ from the vertical): the rod hangs
        // vertical at angle −θ.
        let mut crossings = Vec::new();
        let mut prev = h.get(&world).unwrap().angle() + theta;
        let mut max_tilt: Real = 0.0;
        for n in 0..1200 {
            world.step(1.0 / 60.0).unwrap();
            let a = h.get(&world).unwrap().angle() + theta;
            if prev > 0.0 && a <= 0.0 {
                crossings.push((n as Real + prev / (prev - a)) / 60.0);
            }
            prev = a;
            let axis = world.body(rod).unwrap().orientation() * Vec3::Z;
            max_tilt = max_tilt.max(axis.cross(Vec3::Z).length());
        }
        let periods: Vec<Real> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
        let period = periods.iter().sum::<Real>() / periods.len() as Real;
        // Exact for this box: I_pivot = m(L²/3 + w²/12) → T = 2π√(I_pivot/(m g L/2)).
        let i_pivot = (l * l / 3.0 + 0.02 * 0.02 / 12.0) as Real;
        let expected = 2.0 * PI_REAL * (i_pivot / (9.81 * 0.5 * l)).sqrt();
        eprintln!(
            "{mode:?}: rod pendulum T = {period} s, expected {expected} s; tilt {max_tilt:e}"
        );
        assert!(
            (period - expected).abs() < 5e-3 * expected,
            "{mode:?}: period {period}"
        );
        assert!(max_tilt < 1e-3, "{mode:?}: off-axis tilt {max_tilt}");
    }
}
