//! VALIDATION #9 and #10: bounces rebound at e·v_in, apex heights fall by e² per bounce, and an
//! impact below the velocity threshold does not bounce and comes to rest.

mod common;
use common::{clear_contacts, sphere_ground_contact, world_on, F64, PATHS};
use kea::{inertia, BodyDef, ContactParams, Real, SolverMode, Vec3, World};

const R: Real = 0.1;

fn ball_world(mode: SolverMode, height: Real) -> (World, kea::BodyHandle) {
    let mut world = world_on(mode, 4, 16);
    let ball = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, height + R, 0.0),
            inertia: inertia::solid_sphere(1.0, R).unwrap(),
            ..Default::default()
        })
        .unwrap();
    (world, ball)
}

#[test]
fn rebound_speed_is_e_times_impact_speed_and_apexes_fall_by_e_squared() {
    for mode in PATHS {
        bounce_run(mode);
    }
}

fn bounce_run(mode: SolverMode) {
    let e: Real = 0.6;
    let h: Real = 1.0e-3;
    let g: Real = 9.81;
    // Start so that the ball lands exactly on the plane at step N (impact aligned to a step):
    // the discrete fall is ½ g h² N(N+1).
    let n_steps = 450.0;
    let (mut world, ball) = ball_world(mode, 0.5 * g * h * h * n_steps * (n_steps + 1.0));
    let params = ContactParams {
        restitution: e,
        restitution_threshold: 0.05,
        ..Default::default()
    };
    let mut contacts = Vec::new();
    let mut apexes = Vec::new();
    let mut ratios = Vec::new();
    let mut prev_vy: Real = 0.0;
    for _ in 0..4000 {
        clear_contacts(&mut world, &mut contacts);
        // bounce.c: a contact only while penetrating.
        sphere_ground_contact(&mut world, ball, R, 0.0, params, &mut contacts);
        let v_in = world.body(ball).unwrap().linear_velocity().y;
        world.step(h).unwrap();
        let b = world.body(ball).unwrap();
        let vy = b.linear_velocity().y;
        if v_in < -0.05 && vy > 0.0 && !contacts.is_empty() {
            ratios.push(vy / -v_in);
        }
        if prev_vy > 0.0 && vy <= 0.0 {
            apexes.push(b.position().y - R);
        }
        prev_vy = vy;
    }
    assert!(ratios.len() >= 3, "{mode:?}: bounces: {ratios:?}");
    for r in &ratios[..3] {
        assert!(
            (r - e).abs() < if F64 { 1e-9 } else { 1e-5 },
            "{mode:?}: rebound ratio {r}"
        );
    }
    assert!(apexes.len() >= 3, "apexes {apexes:?}");
    let h0 = 0.5 * g * h * h * n_steps * (n_steps + 1.0);
    let first = apexes[0] / h0;
    eprintln!(
        "{mode:?}: rebound ratios {:?}, apexes {:?}",
        &ratios[..3],
        &apexes[..3]
    );
    assert!(
        (first - e * e).abs() / (e * e) < 1e-2,
        "{mode:?}: first apex ratio {first}"
    );
    for k in 0..2 {
        let ratio = apexes[k + 1] / apexes[k];
        assert!(
            (ratio - e * e).abs() / (e * e) < 0.02,
            "apex ratio {k}: {ratio}"
        );
    }
}

#[test]
fn impact_below_threshold_does_not_bounce_and_settles_quickly() {
    for mode in PATHS {
        settle_run(mode);
    }
}

fn settle_run(mode: SolverMode) {
    let h: Real = 1.0 / 60.0;
    let (mut world, ball) = ball_world(mode, 0.02); // lands at ~0.6 m/s
    let params = ContactParams {
        restitution: 0.9,
        restitution_threshold: 1.0,
        ..Default::default()
    };
    let mut contacts = Vec::new();
    let mut landed_at = None;
    let mut max_height_after: Real = 0.0;
    for step in 0..120 {
        clear_contacts(&mut world, &mut contacts);
        // Speculative contacts, as the collision layer makes them: within one step of travel.
        let v = world.body(ball).unwrap().linear_velocity().length();
        sphere_ground_contact(&mut world, ball, R, v * h + 1e-3, params, &mut contacts);
        world.step(h).unwrap();
        let b = world.body(ball).unwrap();
        if landed_at.is_none() && b.position().y - R < 1e-3 {
            landed_at = Some(step);
        }
        if let Some(l) = landed_at {
            max_height_after = max_height_after.max(b.position().y - R);
            if step > l + 6 {
                // within 0.1 s of landing
                assert!(
                    b.linear_velocity().length() < 1e-3,
                    "{mode:?} step {step}: v = {}",
                    b.linear_velocity()
                );
            }
        }
    }
    assert!(landed_at.is_some());
    assert!(
        max_height_after < 1e-3,
        "{mode:?}: bounced to {max_height_after}"
    );
}
