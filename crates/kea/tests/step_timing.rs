//! Step timing off: the statistics' stage times read zero, and the world steps to the same
//! bits as one that reads the clock (timing only observes), on both solver paths.

mod common;
use common::{world_on, PATHS};
use kea::{BodyDef, BodyHandle, Real, StepStats, Vec3, World};
use std::time::Duration;

/// A three-link chain hanging from the world, let go at an angle.
fn chain(world: &mut World) -> Vec<BodyHandle> {
    let mut links = Vec::new();
    let mut parent = None;
    for i in 0..3 {
        let x = 0.5 + i as Real;
        let b = world
            .create_body(&BodyDef {
                position: Vec3::new(x, 0.0, 0.0),
                ..Default::default()
            })
            .unwrap();
        let anchor = Vec3::new(x - 0.5, 0.0, 0.0);
        world
            .create_joint(
                b,
                parent,
                kea::JointSpec::hinge(anchor, Vec3::new(0.0, 0.0, 1.0)),
            )
            .unwrap();
        parent = Some(b);
        links.push(b);
    }
    links
}

fn stage_times(s: &StepStats) -> [Duration; 10] {
    [
        s.time_collect,
        s.time_gather,
        s.time_write_back,
        s.time_projection,
        s.time_total,
        s.solver.time_islands,
        s.solver.time_solve_exact,
        s.solver.time_solve_iterative,
        s.solver.time_solve,
        s.solver.time_integrate,
    ]
}

#[test]
fn untimed_steps_read_zero_and_keep_the_bits() {
    for mode in PATHS {
        let mut timed = world_on(mode, 4, 4);
        let links = chain(&mut timed);
        let mut untimed = timed.clone();
        assert!(
            timed.settings().step_timing,
            "worlds time their steps by default"
        );
        untimed.update_settings(|s| s.step_timing = false).unwrap();
        assert!(!untimed.settings().step_timing);
        let mut clocked = Duration::ZERO;
        let mut lowest: Real = 0.0;
        for _ in 0..120 {
            let t = timed.step(1.0 / 60.0).unwrap();
            let u = untimed.step(1.0 / 60.0).unwrap();
            clocked += t.time_total;
            lowest = lowest.min(timed.body(links[2]).unwrap().position().y);
            assert!(
                stage_times(&u).iter().all(|d| d.is_zero()),
                "{mode:?}: untimed step reported {:?}",
                stage_times(&u)
            );
        }
        assert!(!clocked.is_zero(), "{mode:?}: timed steps read the clock");
        for &h in &links {
            let (a, b) = (timed.body(h).unwrap(), untimed.body(h).unwrap());
            assert_eq!(
                a.position().to_array().map(Real::to_bits),
                b.position().to_array().map(Real::to_bits),
                "{mode:?}: positions differ"
            );
            assert_eq!(
                a.angular_velocity().to_array().map(Real::to_bits),
                b.angular_velocity().to_array().map(Real::to_bits),
                "{mode:?}: angular velocities differ"
            );
        }
        // It did swing: the last link fell well below its starting height.
        assert!(
            lowest < -1.0,
            "{mode:?}: chain end fell only to y = {lowest}"
        );
    }
}
