//! Sleeping piles cost what moves (issue 38's awake set): the world keeps its awake bodies as
//! they change, the collision layer looks only at the colliders of bodies that changed, and
//! a narrow phase with nothing to do is passed by. Each of these must give the bits of the
//! full passes over every body, collider and pair: a world restored from its own snapshot
//! before every step knows nothing of what changed (everything is looked at), and must step
//! on the same bits, with the same contact events, through falling asleep, a push that wakes
//! a pile, a body destroyed while asleep and a ball landing on a sleeping pile.

use kea::{DemMode, Real, Vec3};
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene};

const DT: Real = 1.0 / 60.0;

fn scene(name: &str) -> PhysicsWorld {
    let path = format!("{}/../../scenes/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut world = PhysicsWorld::from_scene(build(&scene).unwrap());
    world
        .dynamics_mut()
        .update_settings(|s| s.dem.mode = DemMode::PartitionAutoDisable)
        .unwrap();
    world
}

/// Every body's pose and velocities, bit for bit, in slot order.
fn state_bits(w: &PhysicsWorld) -> Vec<u64> {
    let mut out = Vec::new();
    for (h, b) in w.dynamics().bodies() {
        out.push(u64::from(h.index()));
        out.push(u64::from(b.is_sleeping()));
        let v = [
            b.position().to_array(),
            b.linear_velocity().to_array(),
            b.angular_velocity().to_array(),
        ];
        #[allow(clippy::unnecessary_cast)] // a no-op in f64
        out.extend(v.iter().flatten().map(|x| x.to_bits() as u64));
        #[allow(clippy::unnecessary_cast)]
        out.extend(b.orientation().to_array().map(|x| x.to_bits() as u64));
    }
    out
}

/// A world that knows nothing of what changed: its own snapshot, restored.
fn forgetful(w: &PhysicsWorld) -> PhysicsWorld {
    PhysicsWorld::restore(w.snapshot().unwrap()).unwrap()
}

/// Steps `w` and its forgetful twin `steps` times; they must agree at every step. Returns
/// the most bodies asleep at once and the steps whose narrow phase kept no manifold up to
/// date (every pair at rest).
fn step_both(w: &mut PhysicsWorld, twin: &mut PhysicsWorld, steps: usize, at: &str) -> (u32, u32) {
    let (mut most_asleep, mut quiet) = (0, 0);
    for k in 0..steps {
        let stats = w.step(DT).unwrap();
        *twin = forgetful(twin);
        twin.step(DT).unwrap();
        assert_eq!(state_bits(w), state_bits(twin), "{at}: step {k}");
        assert_eq!(
            w.collision().events(),
            twin.collision().events(),
            "{at}: step {k}: events"
        );
        most_asleep = most_asleep.max(stats.sleeping_bodies);
        quiet += u32::from(stats.bodies == 0 && stats.collision.manifolds == 0);
    }
    (most_asleep, quiet)
}

#[test]
fn a_sleeping_pyramid_steps_on_the_bits_of_full_passes_through_sleep_and_wake() {
    let mut w = scene("pyramid");
    let mut twin = w.clone();
    let bodies = w.dynamics().body_count() as u32;
    let (asleep, quiet) = step_both(&mut w, &mut twin, 240, "settling");
    assert_eq!(asleep, bodies, "the pyramid falls asleep whole");
    assert!(quiet > 30, "asleep, steps simulate nothing: {quiet}");
    let touching = w.collision().events().len();
    assert!(
        touching > 0,
        "its resting pairs still report persisting contacts"
    );
    // A push on one box wakes the pile (one island), in both.
    let (_, h) = w.named_bodies()[w.named_bodies().len() / 2].clone();
    for world in [&mut w, &mut twin] {
        world
            .dynamics_mut()
            .body_mut(h)
            .unwrap()
            .add_force(Vec3::new(40.0, 0.0, 0.0))
            .unwrap();
    }
    let stats = w.step(DT).unwrap();
    twin = forgetful(&twin);
    twin.step(DT).unwrap();
    assert_eq!(stats.bodies, bodies, "the push wakes the whole pile");
    assert_eq!(state_bits(&w), state_bits(&twin), "after the push");
    step_both(&mut w, &mut twin, 240, "after the push");
    // A box destroyed while the pile sleeps: its pairs end, its neighbours wake.
    let (_, top) = w.named_bodies().last().unwrap().clone();
    for world in [&mut w, &mut twin] {
        assert!(world.dynamics().body(top).unwrap().is_sleeping());
        world.remove_body(top).unwrap();
    }
    let (asleep, _) = step_both(&mut w, &mut twin, 240, "after a box went");
    assert_eq!(asleep, bodies - 1, "asleep again");
}

#[test]
fn balls_landing_on_a_sleeping_pit_wake_it_on_the_bits_of_full_passes() {
    let mut w = scene("ball_pit");
    let mut twin = w.clone();
    let (asleep, quiet) = step_both(&mut w, &mut twin, 600, "settling");
    assert!(
        asleep > 0 && quiet > 0,
        "the pit sleeps: {asleep} asleep, {quiet} quiet"
    );
    // Drop a ball from above onto it: its touch wakes what it lands on.
    let (_, ball) = w.named_bodies()[0].clone();
    for world in [&mut w, &mut twin] {
        let p = world.dynamics().body(ball).unwrap().position();
        world
            .set_position(ball, p + Vec3::new(0.0, 3.0, 0.0))
            .unwrap();
    }
    step_both(&mut w, &mut twin, 240, "a ball dropped");
}

/// Beside a sleeping pyramid, a box slides along the floor (its pair with the floor looked at
/// every step, the pile's passed by: the narrow phase lists the pairs it visits and merges the
/// pile's events with the sled's), a pendulum swings over the floor with a ball bouncing
/// under it (pairs that begin and end touching, and a pair that parts and touches again), a
/// ball lands on the pile and wakes it, and a sleeping box and a sleeping jointed pair lose
/// their body and joint. The forgetful twin, which passes over every pair and rebuilds every
/// event, must agree at every step.
#[test]
fn a_sleeping_pile_beside_moving_bodies_steps_on_the_bits_of_full_passes() {
    use kea3d::prelude::{Body, Collider, Joint};
    let mut w = scene("pyramid");
    let mut twin = w.clone();
    let bodies = w.dynamics().body_count() as u32;
    let (asleep, _) = step_both(&mut w, &mut twin, 240, "settling");
    assert_eq!(asleep, bodies, "the pyramid falls asleep whole");
    // Two boxes joined by a ball joint, resting on the floor away from everything: asleep
    // by the time they are taken apart.
    let mut made = Vec::new();
    for world in [&mut w, &mut twin] {
        let add = |world: &mut PhysicsWorld, at: [Real; 3], c: Collider| {
            let b = world.insert_body(Body::dynamic().position(at)).unwrap();
            world.insert_collider(c, Some(b)).unwrap();
            b
        };
        let sled = add(world, [-6.0, 0.5, 4.0], Collider::cuboid([0.5; 3]));
        world.set_linear_velocity(sled, [4.0, 0.0, 0.0]).unwrap();
        let bob = add(world, [8.0, 1.2, 4.0], Collider::ball(0.2));
        world
            .insert_joint(bob, None, Joint::hinge([10.0, 1.2, 4.0], [0.0, 0.0, 1.0]))
            .unwrap();
        let bouncer = add(world, [9.0, 1.5, 4.0], Collider::ball(0.25));
        let pair = [
            add(world, [-6.0, 0.5, -4.0], Collider::cuboid([0.5; 3])),
            add(world, [-4.9, 0.5, -4.0], Collider::cuboid([0.5; 3])),
        ];
        let joint = world
            .insert_joint(pair[0], Some(pair[1]), Joint::ball([-5.45, 0.5, -4.0]))
            .unwrap();
        made.push((sled, bob, bouncer, pair, joint));
    }
    assert_eq!(made[0].0, made[1].0, "the same handles in both");
    step_both(
        &mut w,
        &mut twin,
        90,
        "the sled slides, the pendulum swings",
    );
    let events = w.collision().events();
    assert!(
        events.len() > 100,
        "the pile's resting pairs are still reported: {}",
        events.len()
    );
    // A sleeping box of the pyramid goes while the others move.
    let (_, top) = w.named_bodies().last().unwrap().clone();
    let (_, _, bouncer, pair, joint) = made[0];
    for world in [&mut w, &mut twin] {
        assert!(world.dynamics().body(top).unwrap().is_sleeping());
        world.remove_body(top).unwrap();
    }
    step_both(&mut w, &mut twin, 120, "a box went");
    // The jointed pair, asleep, loses its joint and then a body.
    for world in [&mut w, &mut twin] {
        assert!(world.dynamics().body(pair[1]).unwrap().is_sleeping());
        world.remove_joint(joint).unwrap();
    }
    step_both(&mut w, &mut twin, 30, "a joint went");
    for world in [&mut w, &mut twin] {
        world.remove_body(pair[0]).unwrap();
    }
    step_both(&mut w, &mut twin, 30, "a jointed body went");
    // A ball thrown onto the pile wakes it.
    for world in [&mut w, &mut twin] {
        world.set_position(bouncer, [0.0, 12.0, 0.0]).unwrap();
        world.set_linear_velocity(bouncer, [0.0, 0.0, 0.0]).unwrap();
    }
    step_both(&mut w, &mut twin, 120, "a ball on the pile");
    assert!(
        w.dynamics().body_count() as u32 > bodies,
        "bodies were added and removed as planned"
    );
}
