//! The window and its loop: input, fixed-dt stepping, drawing, screenshots.

use crate::app::App;
use crate::convert::{to_f64, to_mq, to_real};
use crate::draw::{draw_contacts, draw_drag, draw_joints, Painter, Toggles};
use crate::keys::{Action, BINDINGS};
use crate::orbit::OrbitCamera;
use crate::overlay::{draw_help, draw_stats, FrameTimes};
use crate::ViewerOptions;
use kea::{Real, Vec3};
use kea_render::SKY;
use macroquad::camera::{set_camera, set_default_camera, Camera3D};
use macroquad::color::Color;
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
    help: bool,
    overlay: bool,
    dragging: bool,
    last_mouse: (f32, f32),
    quit: bool,
    frame: u64,
    times: FrameTimes,
}

impl Session {
    fn say(&self, what: &str) {
        if self.options.report {
            println!("{what} step={}", self.app.step_count());
            use std::io::Write as _;
            let _ = std::io::stdout().flush();
        }
    }

    fn act(&mut self, action: Action) {
        match action {
            Action::Help => self.help = !self.help,
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
                self.painter.clear();
                self.say("reset");
            }
            Action::Shoot => {
                let eye = self.camera.eye();
                self.app.shoot(eye, self.camera.forward());
                self.say(&format!(
                    "shot bodies={}",
                    self.app.scene.world.body_count()
                ));
            }
            Action::Contacts => self.toggles.contacts = !self.toggles.contacts,
            Action::Joints => self.toggles.joints = !self.toggles.joints,
            Action::Islands => self.toggles.islands = !self.toggles.islands,
            Action::Sleeping => self.toggles.sleeping = !self.toggles.sleeping,
            Action::Shadows => self.toggles.shadows = !self.toggles.shadows,
            Action::Overlay => self.overlay = !self.overlay,
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
        let [r, g, b] = SKY.map(|c| f32::from(c) / 255.0);
        clear_background(Color::new(r, g, b, 1.0));
        let eye = self.camera.eye();
        set_camera(&Camera3D {
            position: to_mq(eye),
            target: to_mq(self.camera.target),
            up: macroquad::math::Vec3::Y,
            fovy: to_f64(self.camera.fov_y) as f32,
            ..Default::default()
        });
        self.times.triangles = self.painter.draw_scene(&self.app, eye, self.toggles);
        if self.toggles.contacts {
            draw_contacts(&self.app);
        }
        if self.toggles.joints {
            draw_joints(&self.app);
        }
        draw_drag(&self.app);
        set_default_camera();
        if self.overlay {
            draw_stats(&self.app, &self.times);
        }
        if self.help {
            draw_help();
        }
    }

    fn screenshot(&mut self) {
        let path = &self.options.screenshot;
        match write_screenshot(path) {
            Ok(()) => self.say(&format!("screenshot {}", path.display())),
            Err(e) => {
                let message = format!("screenshot failed: {e}");
                eprintln!("kea view: {message}");
                self.say(&message);
                self.app.message = Some(message);
            }
        }
    }
}

/// Reads the frame buffer and writes it as PNG (rows come bottom-up from OpenGL).
fn write_screenshot(path: &std::path::Path) -> Result<(), String> {
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
    .write_png(path)
}

/// An exponential average over about ten frames, so the overlay's figures can be read.
fn smooth(average: std::time::Duration, now: std::time::Duration) -> std::time::Duration {
    average.mul_f64(0.9) + now.mul_f64(0.1)
}

async fn run_loop(app: App, options: ViewerOptions) {
    let camera = OrbitCamera::framing(&app.scene.world);
    let mut s = Session {
        app,
        options,
        camera,
        painter: Painter::new(),
        toggles: Toggles {
            shadows: true,
            ..Toggles::default()
        },
        help: false,
        overlay: true,
        dragging: false,
        last_mouse: mouse_position(),
        quit: false,
        frame: 0,
        times: FrameTimes::default(),
    };
    s.say("ready");
    while !s.quit {
        let mut screenshot = false;
        for b in BINDINGS {
            if is_key_pressed(b.key) {
                screenshot |= b.action == Action::Screenshot;
                s.act(b.action);
            }
        }
        s.handle_mouse();
        s.handle_car_keys();
        let start = std::time::Instant::now();
        s.times.steps = s.app.advance(f64::from(macroquad::time::get_frame_time()));
        let stepped = std::time::Instant::now();
        s.times.stepping = smooth(s.times.stepping, stepped - start);
        s.draw();
        s.times.drawing = smooth(s.times.drawing, stepped.elapsed());
        if screenshot {
            s.screenshot();
        }
        s.frame += 1;
        if s.options.frames.is_some_and(|n| s.frame >= n) {
            s.quit = true;
        }
        next_frame().await;
    }
    s.say("quit");
}
