//! The demo scenes do what they show: the conveyor carries its crates at the belt's speed, the
//! car drives forward, the animated hand's grip breaks when it jerks, the ragdolls' joints stay
//! within their limits, and the cradle's last ball swings out.

use kea::{BallJoint, BodyHandle, Hinge, JointHandle, Real};
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene};

const DT: Real = 1.0 / 60.0;

fn load(name: &str) -> PhysicsWorld {
    let path = format!("{}/../../scenes/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    PhysicsWorld::from_scene(build(&Scene::from_json(&text).unwrap()).unwrap())
}

fn body(built: &PhysicsWorld, name: &str) -> BodyHandle {
    built
        .body_by_name(name)
        .unwrap_or_else(|| panic!("no body {name}"))
}

#[test]
fn the_conveyor_carries_crates_at_the_belt_speed_and_drops_them_off_the_end() {
    let mut built = load("conveyor");
    let crate0 = body(&built, "crate0");
    let last = body(&built, "crate3");
    for _ in 0..60 {
        built.step(DT).unwrap();
    }
    let v = built.dynamics().body(crate0).unwrap().linear_velocity();
    eprintln!("crate0 after 1 s: {v}");
    assert!((v.x - 1.5).abs() < 0.03 * 1.5, "v = {v}");
    assert!(v.z.abs() < 0.05, "v = {v}");
    for _ in 0..180 {
        built.step(DT).unwrap();
    }
    let p = built.dynamics().body(last).unwrap().position();
    eprintln!("crate3 after 4 s: {p}");
    assert!(p.x > 4.0 && p.y < 0.6, "crate3 fell off the end: {p}");
}

#[test]
fn the_car_drives_forward_on_its_rear_wheels() {
    let mut built = load("car");
    let chassis = body(&built, "chassis");
    let x0 = built.dynamics().body(chassis).unwrap().position().x;
    for _ in 0..180 {
        built.step(DT).unwrap();
    }
    let c = built.dynamics().body(chassis).unwrap();
    let (p, v) = (c.position(), c.linear_velocity());
    eprintln!("chassis after 3 s: position {p}, velocity {v}");
    assert!(p.x - x0 > 5.0, "moved {}", p.x - x0);
    assert!(v.x > 2.0, "v = {v}");
    assert!(p.z.abs() < 0.5, "kept straight: {p}");
    let up = c.orientation() * kea::Vec3::Y;
    assert!(up.y > 0.9, "stayed upright: {up}");
    for name in ["wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"] {
        let j = built.joint_by_name(name).unwrap();
        assert_eq!(
            built.dynamics().constraint_kind(j).unwrap(),
            "car wheel joint"
        );
    }
}

#[test]
fn the_animated_hand_drops_its_object_when_it_jerks() {
    let mut built = load("animated_hand");
    let grip = built.joint_by_name("grip").unwrap();
    let hand = body(&built, "hand");
    let mut broke_at = None;
    for i in 0..300 {
        let stats = built.step(DT).unwrap();
        if stats.broken_joints > 0 || built.dynamics().broken_last_step().contains(&grip) {
            broke_at.get_or_insert((i + 1) as Real * DT);
        }
        if i == 100 {
            // Still held while the hand moves smoothly; the hand is on its path.
            assert!(built.dynamics().is_constraint_enabled(grip).unwrap());
            let p = built.dynamics().body(hand).unwrap().position();
            assert!((p.y - 1.3).abs() < 0.01, "hand at {p}");
        }
    }
    let t = broke_at.expect("the grip broke");
    eprintln!("the grip broke at t = {t:.3} s");
    assert!((2.4..2.7).contains(&t), "broke at {t}");
    assert!(!built.dynamics().is_constraint_enabled(grip).unwrap());
}

/// How far each of the ragdolls' joints is beyond its limits: hinge angle, ball cone, ball twist.
fn ragdoll_overshoot(built: &PhysicsWorld) -> [(Real, String); 3] {
    let mut worst = [
        (0.0, String::new()),
        (0.0, String::new()),
        (0.0, String::new()),
    ];
    let mut note = |k: usize, v: Real, name: &str| {
        if v > worst[k].0 {
            worst[k] = (v, name.to_string());
        }
    };
    for (name, h) in built.named_joints() {
        let w = built.dynamics();
        if let Ok(hinge) = JointHandle::<Hinge>::from_raw(*h).get(w) {
            let l = hinge.limit();
            note(
                0,
                (l.lower().stop - hinge.angle()).max(hinge.angle() - l.upper().stop),
                name,
            );
        } else {
            let ball = JointHandle::<BallJoint>::from_raw(*h);
            let limits = ball.get(w).unwrap().limits.unwrap();
            note(1, limits.cone.position() - limits.cone.upper().stop, name);
            note(2, limits.twist.overshoot().abs(), name);
        }
    }
    worst
}

/// Runs the ragdoll scene for 5 s at step `dt`; returns the worst overshoots (hinge, cone,
/// twist) over the whole run and over the last second.
fn run_ragdolls(dt: Real) -> ([Real; 3], [Real; 3]) {
    let mut built = load("ragdoll");
    assert_eq!(built.named_joints().len(), 30);
    let steps = (5.0 / dt).round() as usize;
    let (mut during, mut settled) = ([0.0 as Real; 3], [0.0 as Real; 3]);
    for i in 0..steps {
        built.step(dt).unwrap();
        let worst = ragdoll_overshoot(&built);
        for k in 0..3 {
            during[k] = during[k].max(worst[k].0);
            if i >= steps * 4 / 5 {
                settled[k] = settled[k].max(worst[k].0);
            }
        }
    }
    (during, settled)
}

#[test]
fn the_ragdolls_joints_stay_within_their_limits() {
    for (hz, landing) in [(60.0, 0.6), (240.0, 0.2)] {
        let (during, settled) = run_ragdolls(1.0 / hz);
        eprintln!(
            "ragdolls at {hz} Hz: worst overshoot (hinge, cone, twist) while landing {during:.3?} rad, in the last second {settled:.3?} rad"
        );
        // Settled, every limit holds to within 0.05 rad.
        assert!(settled.iter().all(|w| *w < 0.05), "{settled:?}");
        // Landing, a stop row is written only once the joint is within a step's travel of it at
        // the speed before the step, so an impact can carry a joint past a stop for a few steps;
        // by how much shrinks with the step.
        assert!(during.iter().all(|w| *w < landing), "{during:?}");
    }
}

#[test]
fn the_cradle_passes_the_swing_to_the_last_ball() {
    let mut built = load("newtons_cradle");
    let balls: Vec<_> = (0..5).map(|i| body(&built, &format!("ball{i}"))).collect();
    let rest_y = built.dynamics().body(balls[4]).unwrap().position().y;
    let start_rise = built.dynamics().body(balls[0]).unwrap().position().y - rest_y;
    let mut rise = [0.0 as Real; 5];
    for _ in 0..90 {
        built.step(DT).unwrap();
        for (k, b) in balls.iter().enumerate() {
            let y = built.dynamics().body(*b).unwrap().position().y - rest_y;
            rise[k] = rise[k].max(y);
        }
    }
    eprintln!("cradle: first ball starts {start_rise:.4} m up; highest rise in the first 1.5 s {rise:.4?}");
    assert!(
        rise[4] > 0.8 * start_rise,
        "the last ball swings out: {rise:?}"
    );
    assert!(
        rise[1..4].iter().all(|r| *r < 0.2 * start_rise),
        "the middle stays: {rise:?}"
    );
}
