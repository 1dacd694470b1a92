//! Golden framing: every gallery picture (`docs/gallery.md`), drawn with the camera `kea render`
//! uses, shows its subject (the bodies) whole and large: not clipped at the edges, not a speck
//! in the middle. Every gallery GIF, drawn the way `kea render` draws a GIF, shows its subject
//! move between its first and its last frame.
//!
//! Subject pixels are told by colour: bodies are drawn in saturated colours, the sky and the
//! static geometry in near-greys, so a pixel whose channels spread by more than 60 is a body;
//! joint links (a pendulum's string) are a dark neutral grey, darker than any shadowed ground.

use kea::{Real, Vec3};
use kea3d::PhysicsWorld;
use kea_render::{render, subject_points, Camera, Image};

/// How `kea render` is told to draw a gallery picture: the scene file under `scenes/` (no
/// `.json`), `--steps`, `--focus` and `--throttle`.
struct Shot {
    scene: &'static str,
    steps: u32,
    focus: &'static [&'static str],
    throttle: Option<Real>,
}

impl Shot {
    const fn new(scene: &'static str) -> Self {
        Self {
            scene,
            steps: STEPS,
            focus: &[],
            throttle: None,
        }
    }
}

/// Steps before a PNG: `kea render`'s default, as the gallery's pictures take.
const STEPS: u32 = 600;

/// The gallery's pictures (PNG), with the options `docs/gallery.md` gives them.
const PICTURES: &[Shot] = &[
    Shot::new("drop"),
    Shot::new("bounce"),
    Shot::new("hinge"),
    Shot::new("pendulum"),
    Shot::new("pyramid"),
    Shot {
        steps: 20,
        ..Shot::new("pyramid_struck")
    },
    Shot::new("ball_pit"),
    Shot::new("chain"),
    Shot::new("newtons_cradle"),
    Shot {
        focus: &["ragdoll1"],
        ..Shot::new("ragdoll")
    },
    Shot {
        steps: 360,
        throttle: Some(0.25),
        ..Shot::new("car")
    },
    Shot::new("conveyor"),
    Shot::new("animated_hand"),
];

/// A gallery GIF: the shot, `--frames`, `--every`, and the size.
struct Gif {
    shot: Shot,
    frames: u32,
    every: u32,
    size: (u32, u32),
}

/// The gallery's GIFs, with the options `docs/gallery.md` gives them.
const GIFS: &[Gif] = &[
    Gif {
        shot: Shot {
            steps: 0,
            ..Shot::new("pyramid_struck")
        },
        frames: 30,
        every: 4,
        size: (256, 192),
    },
    Gif {
        shot: Shot {
            steps: 300,
            throttle: Some(0.25),
            ..Shot::new("car")
        },
        frames: 30,
        every: 2,
        size: (256, 192),
    },
    Gif {
        shot: Shot {
            steps: 0,
            ..Shot::new("ball_pit")
        },
        frames: 30,
        every: 2,
        size: (256, 192),
    },
];

fn load(scene: &str) -> PhysicsWorld {
    let path = format!("{}/../../scenes/{scene}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let scene = kea_scene::Scene::from_json(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    // The demo scenes' own test checks this for `scenes/*.json`; the gallery's scenes too.
    assert_eq!(scene.to_json(), text, "{path} does not save back to itself");
    PhysicsWorld::from_scene(kea_scene::build(&scene).unwrap())
}

/// A scene being drawn as `kea render` draws it: stepped with `--throttle` driving its car.
struct Run {
    world: PhysicsWorld,
    drive: Option<(Real, kea_render::car::Wheels)>,
    focus: Vec<kea::BodyHandle>,
}

impl Run {
    fn new(shot: &Shot) -> Self {
        let world = load(shot.scene);
        let drive = shot.throttle.map(|t| {
            let wheels = kea_render::car::car_wheels(world.dynamics());
            assert!(!wheels.is_empty(), "{}: no car to drive", shot.scene);
            (t, wheels)
        });
        let focus = world
            .named_bodies()
            .iter()
            .filter(|(n, _)| {
                shot.focus
                    .iter()
                    .any(|f| n == f || n.starts_with(&format!("{f}.")))
            })
            .map(|(_, h)| *h)
            .collect();
        let mut run = Self {
            world,
            drive,
            focus,
        };
        run.step(shot.steps);
        run
    }

    fn step(&mut self, n: u32) {
        for _ in 0..n {
            if let Some((throttle, wheels)) = &self.drive {
                kea_render::car::drive(self.world.dynamics_mut(), wheels, *throttle, 0.0).unwrap();
            }
            self.world.step(1.0 / 60.0).unwrap();
        }
    }

    /// What the camera frames: every body, or those `--focus` names.
    fn subject(&self) -> Vec<Vec3> {
        let (dynamics, collision) = (self.world.dynamics(), self.world.collision());
        subject_points(dynamics, collision, |b| {
            self.focus.is_empty() || self.focus.contains(&b)
        })
    }
}

fn draw(world: &PhysicsWorld, camera: &Camera, (w, h): (u32, u32)) -> Image {
    render(world.dynamics(), world.collision(), camera, w, h)
}

/// Whether a pixel is drawn in a body's colour or a link's.
fn is_subject(p: [u8; 3]) -> bool {
    let (max, min) = (*p.iter().max().unwrap(), *p.iter().min().unwrap());
    let link = max < 80 && max - min <= 10;
    max - min > 60 || link
}

/// The box of the body- and link-coloured pixels, `(x0, y0, x1, y1)` inclusive, and their
/// count.
fn subject_box(image: &Image) -> Option<((u32, u32, u32, u32), usize)> {
    let mut b = (u32::MAX, u32::MAX, 0, 0);
    let mut count = 0;
    for y in 0..image.height {
        for x in 0..image.width {
            if is_subject(image.pixel(x, y)) {
                count += 1;
                b = (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y));
            }
        }
    }
    (count > 0).then_some((b, count))
}

/// Checks that `image`'s subject is whole (clear of every edge) and large (at least 40% of the
/// frame one way or the other); returns its box.
fn check_whole_and_large(name: &str, image: &Image) -> (u32, u32, u32, u32) {
    let (w, h) = (image.width, image.height);
    let ((x0, y0, x1, y1), count) =
        subject_box(image).unwrap_or_else(|| panic!("{name}: no body in the picture"));
    let (span_x, span_y) = (
        f64::from(x1 - x0 + 1) / f64::from(w),
        f64::from(y1 - y0 + 1) / f64::from(h),
    );
    eprintln!(
        "{name}: subject box x {x0}..{x1}, y {y0}..{y1} ({span_x:.2} × {span_y:.2}), {count} pixels"
    );
    assert!(
        x0 > 0 && y0 > 0 && x1 < w - 1 && y1 < h - 1,
        "{name}: the subject touches the frame's edge: x {x0}..{x1}, y {y0}..{y1}"
    );
    assert!(
        span_x.max(span_y) >= 0.4,
        "{name}: the subject spans only {span_x:.2} × {span_y:.2} of the frame"
    );
    (x0, y0, x1, y1)
}

/// Writes `image` to `$KEA_FRAMING_OUT/<name>.png` when that is set (to look at what the test
/// checks).
fn keep(name: &str, image: &Image) {
    if let Some(dir) = std::env::var_os("KEA_FRAMING_OUT") {
        let file = format!("{}.png", name.replace(['/', ' '], "_"));
        image
            .write_png(&std::path::Path::new(&dir).join(file))
            .unwrap();
    }
}

#[test]
fn every_gallery_picture_is_framed_whole_and_large() {
    let (w, h) = (240u32, 180u32);
    for shot in PICTURES {
        let run = Run::new(shot);
        let camera = Camera::framing_points(&run.subject(), w as Real / h as Real, 0.15);
        let image = draw(&run.world, &camera, (w, h));
        keep(shot.scene, &image);
        check_whole_and_large(shot.scene, &image);
    }
}

/// How much of the subject changed between two frames: the share of the pixels that show it
/// in either frame whose colour changed (by more than 40 in a channel), and the share of them
/// that show it in one frame only (its silhouette moved). Both are 0 for a still subject and
/// 1 when it left every pixel it covered.
fn change(first: &Image, last: &Image) -> (f64, f64) {
    let (mut subject, mut changed, mut silhouette) = (0usize, 0usize, 0usize);
    for (a, b) in first.pixels.iter().zip(&last.pixels) {
        let (in_a, in_b) = (is_subject(*a), is_subject(*b));
        if in_a || in_b {
            subject += 1;
            changed += usize::from(a.iter().zip(b).any(|(x, y)| x.abs_diff(*y) > 40));
            silhouette += usize::from(in_a != in_b);
        }
    }
    let n = subject.max(1) as f64;
    (changed as f64 / n, silhouette as f64 / n)
}

/// A GIF's first and last frames as `kea render` makes them: the worlds, and the camera
/// framed on the subject in every frame.
fn gif_ends(gif: &Gif) -> (PhysicsWorld, PhysicsWorld, Camera) {
    let (w, h) = gif.size;
    let mut run = Run::new(&gif.shot);
    let first = run.world.clone();
    let mut points = run.subject();
    for _ in 1..gif.frames {
        run.step(gif.every);
        points.extend(run.subject());
    }
    let camera = Camera::framing_points(&points, w as Real / h as Real, 0.15);
    (first, run.world, camera)
}

/// `world` drawn without its body `name`.
fn draw_without(world: &PhysicsWorld, name: &str, camera: &Camera, size: (u32, u32)) -> Image {
    let mut world = world.clone();
    let body = world.body_by_name(name).expect("the body to leave out");
    world.remove_body(body).unwrap();
    draw(&world, camera, size)
}

/// Colour change and silhouette change (see [`change`]) a GIF must show at least: most of
/// what the subject covered looks different at the end (a car that drove on, a pyramid
/// knocked down, a pit filled), while a still subject gives nothing (checked below).
const MOVED: (f64, f64) = (0.5, 0.3);

/// The most a still subject may change by either measure (a pyramid settles by a hair).
const STILL: f64 = 0.05;

#[test]
fn every_gallery_gif_shows_its_subject_whole_large_and_moving() {
    for gif in GIFS {
        let name = gif.shot.scene;
        let (first, last, camera) = gif_ends(gif);
        let (a, b) = (
            draw(&first, &camera, gif.size),
            draw(&last, &camera, gif.size),
        );
        keep(&format!("{name} first"), &a);
        keep(&format!("{name} last"), &b);
        check_whole_and_large(&format!("{name}, first frame"), &a);
        check_whole_and_large(&format!("{name}, last frame"), &b);
        // What moved must be what the GIF is about, not only a projectile: a ball thrown at
        // the subject is left out of the comparison.
        let thrown = first.body_by_name("ball").is_some();
        let (a, b) = if thrown {
            (
                draw_without(&first, "ball", &camera, gif.size),
                draw_without(&last, "ball", &camera, gif.size),
            )
        } else {
            (a, b)
        };
        let (colour, silhouette) = change(&a, &b);
        let without = if thrown { " without the ball" } else { "" };
        eprintln!(
            "{name}{without}: {:.0}% of the subject's pixels changed colour, {:.0}% its silhouette",
            100.0 * colour,
            100.0 * silhouette
        );
        assert!(
            colour >= MOVED.0 && silhouette >= MOVED.1,
            "{name}{without}: the subject barely moved: {colour:.2} of its pixels changed colour, \
             {silhouette:.2} its silhouette"
        );
    }
}

/// The measure of motion is not trivially met: the unstruck pyramid, drawn as the struck one's
/// GIF is, stands still.
#[test]
fn a_still_subject_shows_no_motion() {
    let gif = Gif {
        shot: Shot {
            steps: 0,
            ..Shot::new("pyramid")
        },
        ..GIFS[0]
    };
    let (first, last, camera) = gif_ends(&gif);
    let (a, b) = (
        draw(&first, &camera, gif.size),
        draw(&last, &camera, gif.size),
    );
    let (colour, silhouette) = change(&a, &b);
    eprintln!(
        "pyramid, not struck: {:.1}% of its pixels changed colour, {:.1}% its silhouette",
        100.0 * colour,
        100.0 * silhouette
    );
    assert!(
        colour < STILL && silhouette < STILL,
        "the still pyramid changed: {colour:.3} of its pixels' colour, {silhouette:.3} its silhouette"
    );
}
