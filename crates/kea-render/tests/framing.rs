//! Golden framing: every demo scene, drawn with the camera `kea render` uses, shows its subject
//! (the bodies) whole and large: not clipped at the edges, not a speck in the middle.
//!
//! Subject pixels are told by colour: bodies are drawn in saturated colours, the sky and the
//! static geometry in near-greys, so a pixel whose channels spread by more than 60 is a body;
//! joint links (a pendulum's string) are a dark neutral grey, darker than any shadowed ground.

use kea::Real;
use kea_render::{render, Camera, Image};

const SCENES: &[&str] = &[
    "drop",
    "bounce",
    "hinge",
    "pendulum",
    "pyramid",
    "ball_pit",
    "chain",
    "newtons_cradle",
    "ragdoll",
    "car",
    "conveyor",
    "animated_hand",
];

/// The box of the body- and link-coloured pixels, `(x0, y0, x1, y1)` inclusive, and their
/// count.
fn subject_box(image: &Image) -> Option<((u32, u32, u32, u32), usize)> {
    let mut b = (u32::MAX, u32::MAX, 0, 0);
    let mut count = 0;
    for y in 0..image.height {
        for x in 0..image.width {
            let p = image.pixel(x, y);
            let (max, min) = (*p.iter().max().unwrap(), *p.iter().min().unwrap());
            let link = max < 80 && max - min <= 10;
            if max - min > 60 || link {
                count += 1;
                b = (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y));
            }
        }
    }
    (count > 0).then_some((b, count))
}

#[test]
fn every_demo_scene_is_framed_whole_and_large() {
    let (w, h) = (240u32, 180u32);
    for name in SCENES {
        let path = format!("{}/../../scenes/{name}.json", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = kea_scene::Scene::from_json(&text).unwrap();
        let mut world = kea3d::PhysicsWorld::from_scene(kea_scene::build(&scene).unwrap());
        for _ in 0..60 {
            world.step(1.0 / 60.0).unwrap();
        }
        let aspect = w as Real / h as Real;
        let (dynamics, collision) = (world.dynamics(), world.collision());
        let camera = Camera::framing_scene(dynamics, collision, aspect);
        let image = render(dynamics, collision, &camera, w, h);
        let ((x0, y0, x1, y1), count) =
            subject_box(&image).unwrap_or_else(|| panic!("{name}: no body in the picture"));
        eprintln!("{name}: subject box x {x0}..{x1}, y {y0}..{y1}, {count} pixels");
        // Whole: the subject keeps clear of every edge.
        assert!(
            x0 > 0 && y0 > 0 && x1 < w - 1 && y1 < h - 1,
            "{name}: the subject touches the frame's edge: x {x0}..{x1}, y {y0}..{y1}"
        );
        // Large: it spans at least 40% of the frame one way or the other.
        let (span_x, span_y) = (
            f64::from(x1 - x0 + 1) / f64::from(w),
            f64::from(y1 - y0 + 1) / f64::from(h),
        );
        assert!(
            span_x.max(span_y) >= 0.4,
            "{name}: the subject spans only {span_x:.2} × {span_y:.2} of the frame"
        );
    }
}
