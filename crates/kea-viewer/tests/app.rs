//! The Viewer's simulation without a window: fixed-dt stepping, interpolation, pause, reset,
//! shooting and dragging, checked against the physics they should produce.

use kea::{Real, Vec3};
use kea_scene::Scene;
use kea_viewer::app::{App, MAX_STEPS_PER_FRAME, SHOT_SPEED};

fn scene(name: &str) -> Scene {
    let path = format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn drop_app() -> App {
    App::new(scene("drop.json"), 1.0 / 60.0).unwrap()
}

#[test]
fn frames_take_whole_fixed_steps_and_keep_the_rest_for_interpolation() {
    let mut app = drop_app();
    let dt = kea::math::wide(app.dt());
    assert_eq!(app.advance(2.5 * dt), 2);
    assert!((app.alpha() - 0.5).abs() < 1e-3, "{}", app.alpha());
    assert_eq!(app.advance(0.75 * dt), 1);
    assert!((app.alpha() - 0.25).abs() < 1e-3, "{}", app.alpha());
    assert_eq!(app.step_count(), 3);
    // A very slow frame is capped rather than running the backlog.
    assert_eq!(app.advance(10.0), MAX_STEPS_PER_FRAME);
}

#[test]
fn the_drawn_pose_lies_between_the_last_two_steps() {
    let mut app = drop_app();
    let body = app.physics.body_by_name("box").unwrap();
    app.physics
        .dynamics_mut()
        .body_mut(body)
        .unwrap()
        .set_linear_velocity(Vec3::new(0.0, -3.0, 0.0))
        .unwrap();
    let before = app.physics.dynamics().body(body).unwrap().position();
    assert_eq!(app.advance(1.5 * kea::math::wide(app.dt())), 1);
    let after = app.physics.dynamics().body(body).unwrap().position();
    let (drawn, _) = app.body_pose(body).unwrap();
    let expected = before.lerp(after, app.alpha());
    assert!((drawn - expected).length() < 1e-5, "{drawn} vs {expected}");
    assert!(drawn.y < before.y && drawn.y > after.y);
}

#[test]
fn paused_scenes_do_not_step_and_reset_restores_the_loaded_scene() {
    let mut app = drop_app();
    let body = app.physics.body_by_name("box").unwrap();
    let start = app.physics.dynamics().body(body).unwrap().position();
    app.advance(0.5);
    app.paused = true;
    let n = app.step_count();
    assert_eq!(app.advance(1.0), 0);
    assert_eq!(app.step_count(), n);
    assert!(app.step_once());
    assert_eq!(app.step_count(), n + 1);
    app.reset();
    assert_eq!(app.step_count(), 0);
    let body = app.physics.body_by_name("box").unwrap();
    assert_eq!(app.physics.dynamics().body(body).unwrap().position(), start);
}

#[test]
fn a_shot_ball_leaves_at_the_shot_speed_and_falls_under_gravity() {
    let mut app = drop_app();
    let bodies = app.physics.dynamics().body_count();
    let origin = Vec3::new(0.0, 20.0, 10.0);
    app.shoot(origin, Vec3::new(0.0, 0.0, -2.0));
    assert_eq!(
        app.physics.dynamics().body_count(),
        bodies + 1,
        "{:?}",
        app.message
    );
    let (ball, _) = app
        .physics
        .dynamics()
        .bodies()
        .find(|(_, b)| b.position() == origin)
        .unwrap();
    let dt: Real = 1.0 / 60.0;
    for _ in 0..6 {
        app.step_once();
    }
    let v = app.physics.dynamics().body(ball).unwrap().linear_velocity();
    assert!((v.z + SHOT_SPEED).abs() < 1e-3, "{v}");
    assert!((v.y - (-9.81 * 6.0 * dt)).abs() < 1e-3, "{v}");
}

#[test]
fn dragging_holds_the_grabbed_point_where_the_mouse_puts_it() {
    let mut app = drop_app();
    let body = app.physics.body_by_name("box").unwrap();
    // The box (half extent 0.5) starts at y = 3: a ray down from above hits its top face.
    let eye = Vec3::new(0.0, 10.0, 0.0);
    assert!(app.begin_drag(eye, -Vec3::Y));
    let grabbed = app.drag_point().unwrap();
    assert!(
        (grabbed - Vec3::new(0.0, 3.5, 0.0)).length() < 1e-3,
        "{grabbed}"
    );
    // Move the mouse ray sideways in the horizontal plane through the held point.
    app.drag_to(eye, (Vec3::new(1.0, 3.5, 0.0) - eye).normalize(), -Vec3::Y);
    assert!((app.drag_point().unwrap() - Vec3::new(1.0, 3.5, 0.0)).length() < 1e-3);
    for _ in 0..120 {
        app.step_once();
    }
    // Held at its top face's centre, the box hangs below the point instead of falling.
    let p = app.physics.dynamics().body(body).unwrap().position();
    assert!((p - Vec3::new(1.0, 3.0, 0.0)).length() < 0.05, "{p}");
    app.end_drag();
    for _ in 0..30 {
        app.step_once();
    }
    assert!(
        app.physics.dynamics().body(body).unwrap().position().y < 2.5,
        "falls once let go"
    );
}

#[test]
fn a_ray_that_misses_every_body_grabs_nothing() {
    let mut app = drop_app();
    assert!(!app.begin_drag(Vec3::new(0.0, 10.0, 0.0), Vec3::Y));
    assert!(app.drag_point().is_none());
}

fn chassis_pose(app: &App) -> (Vec3, Vec3) {
    let chassis = app.physics.body_by_name("chassis").unwrap();
    let b = app.physics.dynamics().body(chassis).unwrap();
    (b.position(), b.orientation() * Vec3::X)
}

#[test]
fn the_throttle_drives_the_car_forwards_and_the_steering_turns_it_left() {
    let mut app = App::new(scene("car.json"), 1.0 / 60.0).unwrap();
    assert_eq!(app.wheels().len(), 4);
    for _ in 0..30 {
        app.step_once(); // settle on the suspension
    }
    let (start, _) = chassis_pose(&app);
    for _ in 0..120 {
        app.drive(1.0, 0.0);
        app.step_once();
    }
    let (moved, heading) = chassis_pose(&app);
    // The front (steerable) wheels sit towards +x: forwards is +x.
    assert!(moved.x - start.x > 2.0, "moved {}", moved - start);
    assert!(
        (moved.z - start.z).abs() < 0.3,
        "drifted sideways {}",
        moved.z - start.z
    );
    assert!(heading.z.abs() < 0.1, "kept its heading: {heading}");
    for _ in 0..120 {
        app.drive(1.0, 1.0);
        app.step_once();
    }
    // Turning left (seen from above, +y up): the heading swings from +x towards −z.
    let (_, turned) = chassis_pose(&app);
    assert!(turned.z < -0.2, "heading after steering left: {turned}");
    // Reverse: the car slows, stops and backs away along its heading.
    let (before, heading) = chassis_pose(&app);
    for _ in 0..240 {
        app.drive(-1.0, 0.0);
        app.step_once();
    }
    let (after, _) = chassis_pose(&app);
    let chassis = app.physics.body_by_name("chassis").unwrap();
    let v = app
        .physics
        .dynamics()
        .body(chassis)
        .unwrap()
        .linear_velocity();
    assert!(
        v.dot(heading) < -1.0,
        "backing up: velocity {v} along heading {heading}"
    );
    assert!(
        (after - before).length() > 0.1,
        "it moved: {}",
        after - before
    );
}

#[test]
fn f1_and_o_show_and_hide_the_help_and_the_statistics() {
    use kea_viewer::keys::BINDINGS;
    use kea_viewer::overlay::{FrameTimes, Panels};
    use macroquad::input::KeyCode;

    let mut app = drop_app();
    app.advance(3.0 * kea::math::wide(app.dt()));
    let frame = FrameTimes {
        fps: 60,
        ..FrameTimes::default()
    };
    let mut panels = Panels::default();
    // At first: the statistics only, reading the world as it is.
    let text = panels.text(&app, &frame);
    assert_eq!(text.len(), 1, "{text:?}");
    assert!(text[0][0].starts_with("60 fps | step 3"), "{:?}", text[0]);
    let bodies = app.physics.dynamics().body_count();
    assert!(
        text[0]
            .iter()
            .any(|l| l.starts_with(&format!("bodies {bodies} awake"))),
        "{:?}",
        text[0]
    );
    assert_eq!(text[0].last().unwrap(), "F1: help");
    // F1: the help joins it, a line for every key the Viewer answers.
    assert!(panels.press(KeyCode::F1));
    let text = panels.text(&app, &frame);
    assert_eq!(text.len(), 2);
    let help = &text[1];
    assert_eq!(help[0], "Kea Viewer keys");
    for b in BINDINGS {
        assert!(
            help.iter()
                .any(|l| l.starts_with(b.label) && l.ends_with(b.help)),
            "no help line for {}: {help:?}",
            b.label
        );
    }
    // O hides the statistics; F1 again hides the help; O brings the statistics back.
    assert!(panels.press(KeyCode::O));
    let text = panels.text(&app, &frame);
    assert_eq!(text, vec![help.clone()]);
    assert!(panels.press(KeyCode::F1));
    assert!(panels.text(&app, &frame).is_empty());
    assert!(panels.press(KeyCode::O));
    assert_eq!(panels.text(&app, &frame).len(), 1);
    // Other keys are not the panels'.
    assert!(!panels.press(KeyCode::B));
    assert_eq!(panels, Panels::default());
}
