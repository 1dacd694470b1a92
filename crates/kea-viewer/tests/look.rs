//! What the Viewer draws besides bodies, checked without a window: shadows land on the static
//! surface below, gizmos show joints' limits and contacts' forces, and scenes reload.

use kea::{Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
use kea_scene::Scene;
use kea_viewer::gizmos::{force_length, typical_weight, Gizmos, CONTACT, NOW, RANGE};
use kea_viewer::shadows::{Receivers, LIFT};
use kea_viewer::App;

fn scene(name: &str) -> Scene {
    let path = format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_shadow_falls_on_a_step_where_there_is_one_and_on_the_ground_elsewhere() {
    let world = World::with_capacity(4, 16).unwrap();
    let mut collision = CollisionWorld::new();
    let ground = ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap());
    collision.add_collider(&world, ground).unwrap();
    // A step 0.5 m high, 2 m square, about the origin.
    let mut step = ColliderDef::new(None, Shape::cuboid(Vec3::new(1.0, 0.25, 1.0)).unwrap());
    step.offset = Vec3::new(0.0, 0.25, 0.0);
    collision.add_collider(&world, step).unwrap();
    let receivers = Receivers::new(&world, &collision);
    let shadow = |p: Vec3, light: Vec3| receivers.shadow_of(&world, &collision, p, light).unwrap();
    let on_step = shadow(Vec3::new(0.2, 2.0, -0.3), Vec3::Y);
    assert!(
        (on_step - Vec3::new(0.2, 0.5 + LIFT, -0.3)).length() < 1e-4,
        "{on_step}"
    );
    let on_ground = shadow(Vec3::new(3.0, 2.0, 0.0), Vec3::Y);
    assert!(
        (on_ground - Vec3::new(3.0, LIFT, 0.0)).length() < 1e-4,
        "{on_ground}"
    );
    // Slanted light: the point's shadow moves along the light to the step's top.
    let light = kea_render::light_direction();
    let p = Vec3::new(0.0, 1.5, 0.0);
    let expected = p - light * (1.0 / light.y) + Vec3::Y * LIFT;
    assert!((shadow(p, light) - expected).length() < 1e-4);
    // Past the step's edge the same light reaches the ground.
    let q = Vec3::new(-1.2, 1.5, 0.0);
    assert!(
        shadow(q, light).y.abs() < 2.0 * LIFT,
        "{}",
        shadow(q, light)
    );
    // A point below the ground casts nowhere.
    assert!(receivers
        .shadow_of(&world, &collision, Vec3::new(5.0, -1.0, 0.0), Vec3::Y)
        .is_none());
}

#[test]
fn a_limited_hinge_shows_its_range_and_where_it_is() {
    let mut app = App::new(scene("hinge.json"), 1.0 / 60.0).unwrap();
    for _ in 0..30 {
        app.step_once();
    }
    let mut g = Gizmos::new(Vec3::new(0.0, 3.0, 8.0));
    g.joints(&app);
    let count = |colour: [u8; 3]| g.pieces.iter().filter(|(_, c)| *c == colour).count();
    assert!(count(RANGE) > 16, "an arc: {} pieces", count(RANGE));
    assert!(count(NOW) > 0, "a pointer at the angle now");
    assert!(g
        .pieces
        .iter()
        .all(|(t, _)| t.iter().all(|p| p.is_finite())));
}

#[test]
fn contact_normals_grow_with_the_force_they_carry() {
    assert_eq!(force_length(0.0, 10.0, 0.5), 0.0);
    assert!((force_length(10.0, 10.0, 0.5) - 0.5).abs() < 1e-6);
    assert!((force_length(5.0, 10.0, 0.5) - 0.25).abs() < 1e-6);
    assert!((force_length(1e6, 10.0, 0.5) - 1.5).abs() < 1e-6, "capped");
    assert_eq!(force_length(-3.0, 10.0, 0.5), 0.0, "a pull draws nothing");
    // A box resting on the ground: its contact forces carry its weight, and they are drawn.
    let mut app = App::new(scene("drop.json"), 1.0 / 60.0).unwrap();
    for _ in 0..180 {
        app.step_once();
    }
    let world = app.physics.dynamics();
    let weight = typical_weight(world);
    let box_body = app.physics.body_by_name("box").unwrap();
    let mass = world.body(box_body).unwrap().mass();
    assert!((weight - mass * 9.81).abs() < 1e-3 * weight, "{weight}");
    let carried: Real = world
        .contacts()
        .flat_map(|(_, c, _)| c.forces().iter().map(|f| f.normal))
        .sum();
    assert!(
        (carried - weight).abs() < 0.02 * weight,
        "{carried} vs {weight}"
    );
    let mut g = Gizmos::new(Vec3::new(0.0, 3.0, 8.0));
    g.contacts(&app, weight, 0.5);
    assert!(g.pieces.iter().filter(|(_, c)| *c == CONTACT).count() >= 4 * 8);
}

#[test]
fn a_reloaded_scene_replaces_the_running_one_and_a_bad_one_changes_nothing() {
    let mut app = App::new(scene("drop.json"), 1.0 / 60.0).unwrap();
    for _ in 0..10 {
        app.step_once();
    }
    assert_eq!(
        app.subject(),
        app.physics.body_by_name("box"),
        "the only body"
    );
    app.replace(scene("car.json")).unwrap();
    assert_eq!(app.step_count(), 0);
    assert_eq!(app.wheels().len(), 4);
    assert_eq!(
        app.subject(),
        app.physics.body_by_name("chassis"),
        "a car is followed by its chassis"
    );
    let mut broken = scene("drop.json");
    broken.world.epsilon = -1.0;
    let bodies = app.physics.dynamics().body_count();
    assert!(app.replace(broken).is_err());
    assert_eq!(
        app.physics.dynamics().body_count(),
        bodies,
        "the car is kept"
    );
    assert_eq!(app.wheels().len(), 4);
}
