//! The window and its loop: input, fixed-dt stepping, drawing, screenshots.

use crate::app::App;
use crate::convert::{to_f64, to_mq, to_real};
use crate::draw::{checker_texture, gizmos, sky, Eye, Painter, Toggles};
use crate::gizmos::typical_weight;
use crate::keys::{Action, BINDINGS};
use crate::orbit::OrbitCamera;
use crate::overlay::{draw_toast, FrameTimes, Panels};
use crate::record::{recorded_size, shrink, Recorder};
use crate::reload::SceneFile;
use crate::ViewerOptions;
use kea::{BodyHandle, Real, Vec3};
use macroquad::camera::{set_camera, set_default_camera, Camera3D};
use macroquad::input::{
    is_key_down, is_key_pressed, is_key_released, is_mouse_button_down, is_mouse_button_pressed,
    is_mouse_button_released, mouse_position, mouse_wheel, KeyCode, MouseButton,
};
use macroquad::texture::get_screen_data;
use macroquad::window::{clear_background, next_frame, screen_height, screen_width};
use macroquad::Window;

/// Opens the window and runs until it closes.
pub fn open(app: App, options: ViewerOptions) {
    let conf = macroquad::conf::Conf {
        miniquad_conf: macroquad::miniquad::conf::Conf {
            window_title: options.title.clone(),
            window_width: i32::try_from(options.width).unwrap_or(1024),
            window_height: i32::try_from(options.height).unwrap_or(720),
            ..Default::default()
        },
        draw_call_vertex_capacity: crate::draw::BATCH_VERTICES + 1000,
        draw_call_index_capacity: crate::draw::BATCH_VERTICES + 1000,
        ..Default::default()
    };
    Window::from_config(conf, run_loop(app, options));
}

/// Everything the loop keeps between frames.
struct Session {
    app: App,
    options: ViewerOptions,
    camera: OrbitCamera,
    painter: Painter,
    toggles: Toggles,
    panels: Panels,
    dragging: bool,
    last_mouse: (f32, f32),
    quit: bool,
    frame: u64,
    times: FrameTimes,
    /// The body the camera follows.
    follow: Option<BodyHandle>,
    /// A note shown for a few seconds (a screenshot written, a reload).
    toast: Option<(String, std::time::Instant)>,
    recorder: Option<Recorder>,
    scene_file: Option<SceneFile>,
    /// A typical body's weight, N, and the length its force gets in the contact gizmos, m.
    force_scale: (Real, Real),
    started: std::time::Instant,
}

impl Session {
    fn say(&self, what: &str) {
        if self.options.report {
            println!("{what} step={}", self.app.step_count());
            use std::io::Write as _;
            let _ = std::io::stdout().flush();
        }
    }

    /// Shows `what` on screen for a few seconds and reports it.
    fn tell(&mut self, what: String) {
        self.say(&what);
        self.toast = Some((what, std::time::Instant::now()));
    }

    /// What the new scene needs: the painter's caches, the force scale, the car to follow.
    fn after_build(&mut self) {
        self.painter.clear();
        self.force_scale = force_scale(&self.app);
        self.follow = self.app.chassis();
    }

    fn reload(&mut self) {
        let Some(file) = &mut self.scene_file else {
            self.tell("reload: this scene has no file".into());
            return;
        };
        let loaded = file.read().and_then(|spec| self.app.replace(spec));
        let path = file.path().display().to_string();
        match loaded {
            Ok(()) => {
                self.after_build();
                self.tell(format!("reloaded {path}"));
            }
            Err(e) => {
                self.app.message = Some(format!("reload failed, kept the old scene: {e}"));
                self.tell("reload failed (see above)".into());
            }
        }
    }

    fn toggle_recording(&mut self) {
        match self.recorder.take() {
            Some(r) => match r.finish() {
                Ok((path, frames)) => {
                    self.tell(format!("recorded {} ({frames} frames)", path.display()));
                }
                Err(e) => self.tell(format!("recording failed: {e}")),
            },
            None => {
                let (w, h, _) = recorded_size(screen_width() as u32, screen_height() as u32);
                match Recorder::start(&self.options.recording, w, h) {
                    Ok(r) => {
                        self.recorder = Some(r);
                        self.tell(format!("recording to {}", self.options.recording.display()));
                    }
                    Err(e) => self.tell(format!("cannot record: {e}")),
                }
            }
        }
    }

    fn capture(&mut self) {
        let Some(r) = &mut self.recorder else { return };
        if r.due() {
            let (_, _, factor) = recorded_size(screen_width() as u32, screen_height() as u32);
            r.push(shrink(&screen_image(), factor));
        }
        if r.is_full() {
            self.toggle_recording();
        }
    }

    /// Moves the camera's target towards the followed body (half the way in ~0.1 s).
    fn follow_subject(&mut self, frame_seconds: Real) {
        let Some(b) = self.follow else { return };
        let Some((x, _)) = self.app.body_pose(b) else {
            self.follow = None;
            return;
        };
        let k = 1.0 - (-7.0 * frame_seconds.clamp(0.0, 0.25)).exp();
        self.camera.target += (x - self.camera.target) * k;
    }

    fn act(&mut self, action: Action) {
        match action {
            Action::Help | Action::Overlay => {
                self.panels.act(action);
            }
            Action::Pause => {
                self.app.paused = !self.app.paused;
                self.say(if self.app.paused { "paused" } else { "resumed" });
            }
            Action::Step => {
                self.app.paused = true;
                self.app.step_once();
                self.say("stepped");
            }
            Action::Reset => {
                self.app.reset();
                self.after_build();
                self.say("reset");
            }
            Action::Reload => self.reload(),
            Action::Record => self.toggle_recording(),
            Action::Follow => {
                self.follow = match self.follow {
                    Some(_) => None,
                    None => self.app.subject(),
                };
                match self.follow {
                    Some(b) => self.tell(format!("following body {}", b.index())),
                    None => self.tell("not following".into()),
                }
            }
            Action::Shoot => {
                let eye = self.camera.eye();
                self.app.shoot(eye, self.camera.forward());
                self.say(&format!(
                    "shot bodies={}",
                    self.app.physics.dynamics().body_count()
                ));
            }
            Action::Contacts => self.toggles.contacts = !self.toggles.contacts,
            Action::Joints => self.toggles.joints = !self.toggles.joints,
            Action::Islands => self.toggles.islands = !self.toggles.islands,
            Action::Sleeping => self.toggles.sleeping = !self.toggles.sleeping,
            Action::Shadows => self.toggles.shadows = !self.toggles.shadows,
            Action::Screenshot => {} // taken once the frame is drawn
            Action::Quit => self.quit = true,
        }
    }

    fn mouse_ray(&self) -> Vec3 {
        let (x, y) = mouse_position();
        self.camera.ray(
            to_real(f64::from(x)),
            to_real(f64::from(y)),
            to_real(f64::from(screen_width())),
            to_real(f64::from(screen_height())),
        )
    }

    fn handle_mouse(&mut self) {
        let (x, y) = mouse_position();
        let (dx, dy) = (x - self.last_mouse.0, y - self.last_mouse.1);
        self.last_mouse = (x, y);
        if is_mouse_button_pressed(MouseButton::Left) {
            let ray = self.mouse_ray();
            self.dragging = self.app.begin_drag(self.camera.eye(), ray);
            if self.dragging {
                self.say("grabbed");
            }
        }
        if is_mouse_button_released(MouseButton::Left) && self.dragging {
            self.app.end_drag();
            self.dragging = false;
            self.say("released");
        }
        let (dx, dy) = (to_real(f64::from(dx)), to_real(f64::from(dy)));
        let shift = is_key_down(KeyCode::LeftShift) || is_key_down(KeyCode::RightShift);
        let left = is_mouse_button_down(MouseButton::Left);
        if self.dragging && left {
            let ray = self.mouse_ray();
            self.app
                .drag_to(self.camera.eye(), ray, self.camera.forward());
        } else if is_mouse_button_down(MouseButton::Middle)
            || (shift && (left || is_mouse_button_down(MouseButton::Right)))
        {
            self.camera.pan(dx, dy, to_real(f64::from(screen_height())));
        } else if left || is_mouse_button_down(MouseButton::Right) {
            self.camera.orbit(dx, dy);
        }
        let wheel = mouse_wheel().1;
        if wheel != 0.0 {
            self.camera.zoom(to_real(f64::from(wheel.signum())));
        }
    }

    /// Arrow keys drive the scene's car wheels while held; releasing them brakes to a stop.
    /// Scenes whose wheels are never touched keep the motors they were built with.
    fn handle_car_keys(&mut self) {
        if !self.app.has_wheels() {
            return;
        }
        const KEYS: [KeyCode; 4] = [KeyCode::Up, KeyCode::Down, KeyCode::Left, KeyCode::Right];
        let held = KEYS.iter().any(|k| is_key_down(*k));
        if !held && !KEYS.iter().any(|k| is_key_released(*k)) {
            return;
        }
        let axis = |plus: KeyCode, minus: KeyCode| -> Real {
            Real::from(u8::from(is_key_down(plus))) - Real::from(u8::from(is_key_down(minus)))
        };
        let throttle = axis(KeyCode::Up, KeyCode::Down);
        let steer = axis(KeyCode::Left, KeyCode::Right);
        self.app.drive(throttle, steer);
    }

    fn draw(&mut self) {
        clear_background(sky());
        let eye = self.camera.eye();
        set_camera(&Camera3D {
            position: to_mq(eye),
            target: to_mq(self.camera.target),
            up: macroquad::math::Vec3::Y,
            fovy: to_f64(self.camera.fov_y) as f32,
            ..Default::default()
        });
        let view = Eye {
            position: eye,
            target: self.camera.target,
        };
        self.times.triangles = self.painter.draw_scene(&self.app, view, self.toggles);
        let (weight, length) = self.force_scale;
        let g = gizmos(&self.app, eye, self.toggles, weight, length);
        self.painter.draw_on_top(&g.pieces);
        set_default_camera();
        self.panels.draw(&self.app, &self.times);
        let recording = self.recorder.as_ref().map(Recorder::frames);
        if let Some((text, since)) = &self.toast {
            if since.elapsed().as_secs_f32() < 3.0 {
                draw_toast(text, recording);
            } else {
                self.toast = None;
            }
        } else if recording.is_some() {
            draw_toast("", recording);
        }
    }

    fn screenshot(&mut self) {
        let path = self.options.screenshot.clone();
        match screen_image().write_png(&path) {
            Ok(()) => self.tell(format!("screenshot {}", path.display())),
            Err(e) => {
                let message = format!("screenshot failed: {e}");
                eprintln!("kea view: {message}");
                self.app.message = Some(message.clone());
                self.tell(message);
            }
        }
    }
}

/// A typical body's weight and the length a force of that weight gets: a quarter tile.
fn force_scale(app: &crate::App) -> (Real, Real) {
    let world = app.physics.dynamics();
    let tile = kea_render::scene_tile(world, app.physics.collision());
    (typical_weight(world), 0.25 * tile)
}

/// The frame buffer as an image (rows come bottom-up from OpenGL).
fn screen_image() -> kea_render::Image {
    let data = get_screen_data();
    let (w, h) = (u32::from(data.width), u32::from(data.height));
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in (0..h).rev() {
        for x in 0..w {
            let i = ((y * w + x) * 4) as usize;
            pixels.push([data.bytes[i], data.bytes[i + 1], data.bytes[i + 2]]);
        }
    }
    kea_render::Image {
        width: w,
        height: h,
        pixels,
    }
}

/// An exponential average over about ten frames, so the overlay's figures can be read.
fn smooth(average: std::time::Duration, now: std::time::Duration) -> std::time::Duration {
    average.mul_f64(0.9) + now.mul_f64(0.1)
}

async fn run_loop(app: App, options: ViewerOptions) {
    let camera = OrbitCamera::framing(app.physics.dynamics());
    let scene_file = options.scene_file.as_deref().map(SceneFile::new);
    let mut s = Session {
        app,
        options,
        camera,
        painter: Painter::new(Some(checker_texture())),
        toggles: Toggles {
            shadows: true,
            ..Toggles::default()
        },
        panels: Panels::default(),
        dragging: false,
        last_mouse: mouse_position(),
        quit: false,
        frame: 0,
        times: FrameTimes::default(),
        follow: None,
        toast: None,
        recorder: None,
        scene_file,
        force_scale: (1.0, 1.0),
        started: std::time::Instant::now(),
    };
    s.after_build();
    s.say("ready");
    while !s.quit {
        let mut screenshot = false;
        for b in BINDINGS {
            if is_key_pressed(b.key) {
                screenshot |= b.action == Action::Screenshot;
                s.act(b.action);
            }
        }
        if s.scene_file.as_mut().is_some_and(SceneFile::changed) {
            s.reload();
        }
        s.handle_mouse();
        s.handle_car_keys();
        let start = std::time::Instant::now();
        let frame_seconds = macroquad::time::get_frame_time();
        s.times.steps = s.app.advance(f64::from(frame_seconds));
        s.times.fps = macroquad::time::get_fps();
        s.follow_subject(to_real(f64::from(frame_seconds)));
        let stepped = std::time::Instant::now();
        s.times.stepping = smooth(s.times.stepping, stepped - start);
        s.draw();
        s.times.drawing = smooth(s.times.drawing, stepped.elapsed());
        if screenshot {
            s.screenshot();
        }
        s.capture();
        s.frame += 1;
        if s.options.frames.is_some_and(|n| s.frame >= n) {
            s.quit = true;
        }
        next_frame().await;
    }
    if s.recorder.is_some() {
        s.toggle_recording(); // a recording under way is written on quit
    }
    let seconds = s.started.elapsed().as_secs_f64().max(1e-3);
    s.say(&format!(
        "quit fps={:.1} frames={}",
        s.frame as f64 / seconds,
        s.frame
    ));
}
