//! What sets a resting contact's softness, as `ContactParams::softness` and docs/api-map.md say:
//! not the world's ε (the guide's knob for joints), but the world's mass-independent contact
//! spring. A box resting on the ground sinks `g / (n ω²)` (ω = 2π·frequency, n the iterative
//! path's substeps, each of which pushes the spring's stretch back): four times deeper at half
//! the frequency, the same for any ε.

use kea3d::prelude::*;

/// How deep a 1 m box rests in the ground after 2 s, with the world's settings changed by
/// `settings`.
fn sink(settings: impl FnOnce(&mut kea3d::dynamics::WorldSettings)) -> f64 {
    let mut world = PhysicsWorld::new();
    world.dynamics_mut().update_settings(settings).unwrap();
    let ground = world.insert_body(Body::fixed()).unwrap();
    world
        .insert_collider(Collider::cuboid([5.0, 0.5, 5.0]), Some(ground))
        .unwrap();
    let b = world
        .insert_body(Body::dynamic().position([0.0, 1.0, 0.0]))
        .unwrap();
    world
        .insert_collider(Collider::cuboid([0.5, 0.5, 0.5]).density(1000.0), Some(b))
        .unwrap();
    for _ in 0..120 {
        world.step(1.0 / 60.0).unwrap();
    }
    // The ground's top is at y = 0.5, the box's centre 0.5 above it when just touching.
    1.0 - kea3d::dynamics::math::wide(world.position(b).unwrap().y)
}

#[test]
fn the_contact_spring_not_the_worlds_epsilon_sets_how_deep_a_box_rests() {
    let spring = |hz: Real| {
        move |s: &mut kea3d::dynamics::WorldSettings| {
            s.contact_spring = kea3d::dynamics::Spring::new(hz, s.contact_spring.damping_ratio);
        }
    };
    let at_20 = sink(spring(20.0));
    let at_10 = sink(spring(10.0));
    let stiff_eps = sink(|s| {
        s.contact_spring = kea3d::dynamics::Spring::new(20.0, s.contact_spring.damping_ratio);
        s.epsilon = 1e-6;
    });
    let soft_eps = sink(|s| {
        s.contact_spring = kea3d::dynamics::Spring::new(20.0, s.contact_spring.damping_ratio);
        s.epsilon = 0.5;
    });
    let omega = |hz: f64| 2.0 * std::f64::consts::PI * hz;
    eprintln!(
        "sink: 20 Hz {at_20:.3e} m (g/ω² {:.3e}), 10 Hz {at_10:.3e} m (g/ω² {:.3e}); ε 1e-6 {stiff_eps:.3e}, ε 0.5 {soft_eps:.3e}",
        9.81 / omega(20.0).powi(2),
        9.81 / omega(10.0).powi(2)
    );
    assert_eq!(at_20, stiff_eps, "the world's ε does not change a contact");
    assert_eq!(at_20, soft_eps, "the world's ε does not change a contact");
    let n = f64::from(kea3d::dynamics::IterativeParams::default().substeps);
    for (depth, hz) in [(at_20, 20.0), (at_10, 10.0)] {
        let expected = 9.81 / (n * omega(hz).powi(2));
        assert!(
            (depth / expected - 1.0).abs() < 0.05,
            "{hz} Hz: rests {depth} m deep, g/(n ω²) = {expected}"
        );
    }
}
