//! Headless frames show the scene: objects where the camera sees them, sky and ground elsewhere.

use kea::{BodyDef, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
use kea_render::{render, Camera, BODY_COLOURS, SKY};

#[test]
fn a_box_above_the_ground_appears_where_the_camera_sees_it() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let mut collision = CollisionWorld::new();
    collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 2.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    collision
        .add_collider(
            &world,
            ColliderDef::new(Some(b), Shape::cuboid(Vec3::splat(0.5)).unwrap()),
        )
        .unwrap();
    // Level with the box, 8 m away: the box fills the middle, the sky is above, the ground below.
    let camera = Camera {
        eye: Vec3::new(0.0, 2.0, 8.0),
        target: Vec3::new(0.0, 2.0, 0.0),
        up: Vec3::Y,
        fov_y: 0.8,
    };
    let image = render(&world, &collision, &camera, 160, 120);
    let centre = image.pixel(80, 60);
    // The face towards the camera is the box's colour, shaded (same hue: red the largest channel).
    let base = BODY_COLOURS[0];
    assert!(
        centre != SKY && centre[0] > centre[1] && centre[0] > centre[2],
        "centre {centre:?}, base {base:?}"
    );
    assert_eq!(image.pixel(80, 2), SKY, "sky above the box");
    let ground = image.pixel(80, 118);
    assert!(
        ground != SKY && ground[0].abs_diff(ground[1]) < 20,
        "grey ground below: {ground:?}"
    );
    // The box spans about ±0.5 m at 7.5 m: ±(0.5/7.5)·focal pixels around the centre.
    let focal = 60.0 / (0.4f64).tan();
    let half_width = (0.5 / 7.5 * focal) as u32;
    assert_ne!(
        image.pixel(80 + half_width - 2, 60),
        SKY,
        "inside the box's edge"
    );
    assert_eq!(
        image.pixel(80 + half_width + 3, 60),
        SKY,
        "outside the box's edge"
    );
    // Same input, same pixels.
    assert_eq!(render(&world, &collision, &camera, 160, 120), image);
}

#[test]
fn framed_points_fill_the_frame_less_the_margin() {
    // A long low box, seen as the camera frames it in a 4:3 picture with a 15% margin.
    let points: Vec<Vec3> = kea_render::Bounds {
        lo: Vec3::new(-3.0, 0.0, -0.5),
        hi: Vec3::new(4.0, 1.0, 0.5),
    }
    .corners()
    .into();
    let aspect = 4.0 / 3.0;
    let camera = Camera::framing_points(&points, aspect, 0.15);
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let half_y = (camera.fov_y * 0.5).tan();
    let half_x = half_y * aspect;
    // Each point's place in the frame, -1..1 from edge to edge.
    let (mut lo, mut hi): ([Real; 2], [Real; 2]) = ([1.0; 2], [-1.0; 2]);
    for p in &points {
        let q = *p - camera.eye;
        let depth = q.dot(forward);
        let (x, y) = (q.dot(right) / depth / half_x, q.dot(up) / depth / half_y);
        for (k, v) in [x, y].into_iter().enumerate() {
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    let fits = |v: Real| v.abs() <= 0.85 + 1e-3;
    assert!(
        lo.iter().chain(&hi).all(|&v| fits(v)),
        "inside the margin: {lo:?} {hi:?}"
    );
    // Filling it: touching the margin on both sides one way, centred both ways.
    let touches = (0..2).any(|k| lo[k] < -0.84 && hi[k] > 0.84);
    assert!(touches, "filling the frame: {lo:?} {hi:?}");
    for k in 0..2 {
        assert!((lo[k] + hi[k]).abs() < 0.02, "centred: {lo:?} {hi:?}");
    }
}
