//! Issue 36: limits hold on impact. The demo's three ragdolls, raised 3 m and dropped onto the
//! steps: at every step every hinge (elbows, knees) and every ball joint's cone and twist stays
//! within 0.1 rad of its stops, on every path a user can force.

use kea::{BallJoint, Hinge, JointHandle, Real, Routing, SolverMode};
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene};

/// How far past its stops a limit reads now, rad (0 inside).
fn past(l: &kea::Limit) -> Real {
    if !l.is_limited() {
        return 0.0;
    }
    let p = l.position();
    (l.lower().stop - p).max(p - l.upper().stop).max(0.0)
}

#[test]
fn a_ragdoll_dropped_3_m_onto_steps_keeps_every_limit_within_a_tenth_of_a_radian() {
    let path = format!("{}/../../scenes/ragdoll.json", env!("CARGO_MANIFEST_DIR"));
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for g in json["groups"].as_array_mut().unwrap() {
        let y = &mut g["ragdoll"]["origin"][1];
        *y = serde_json::json!(y.as_f64().unwrap() + 3.0);
    }
    let scene = Scene::from_json(&json.to_string()).unwrap();
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        let mut world = PhysicsWorld::from_scene(build(&scene).unwrap());
        world
            .dynamics_mut()
            .update_settings(|s| s.routing = Routing { mode, ..s.routing })
            .unwrap();
        let joints: Vec<_> = world.dynamics().enabled_joints().map(|(h, _)| h).collect();
        let (mut worst, mut hinges, mut balls): (Real, usize, usize) = (0.0, 0, 0);
        let mut by_kind: [Real; 3] = [0.0; 3];
        for _ in 0..300 {
            world.step(1.0 / 60.0).unwrap();
            for &h in &joints {
                let w = world.dynamics();
                if let Ok(j) = JointHandle::<Hinge>::try_from_raw(w, h) {
                    worst = worst.max(past(j.get(w).unwrap().limit()));
                    by_kind[0] = by_kind[0].max(past(j.get(w).unwrap().limit()));
                    hinges += 1;
                } else if let Ok(j) = JointHandle::<BallJoint>::try_from_raw(w, h) {
                    if let Some(l) = j.get(w).unwrap().limits {
                        worst = worst.max(past(&l.cone)).max(past(&l.twist));
                        by_kind[1] = by_kind[1].max(past(&l.cone));
                        by_kind[2] = by_kind[2].max(past(&l.twist));
                        balls += 1;
                    }
                }
            }
        }
        eprintln!(
            "{mode:?}: worst limit overrun {worst:.3} rad (hinges, cones, twists: {by_kind:?})"
        );
        assert!(hinges > 0 && balls > 0, "the ragdolls have limited joints");
        assert!(worst <= 0.1, "{mode:?}: a limit overran by {worst} rad");
    }
}
