//! The Kea Viewer: a real-time window onto a scene, built on macroquad (OpenGL through
//! miniquad, which loads X11 and GL at run time, so it builds without system libraries and
//! runs under Xvfb with Mesa).
//!
//! It steps the scene at a fixed dt whatever the frame rate, drawing poses interpolated between
//! the last two steps; it pauses, single-steps and resets (Enter, as in the guide's Viewer);
//! it shoots balls from the camera and drags bodies with the mouse; it draws contacts, joint
//! frames, islands and sleeping bodies on request; and it shows F1 help and an overlay with
//! the frame rate, step time per stage, bodies, contacts and rows. Every key is in
//! [`keys::BINDINGS`].
//!
//! It draws what `kea render` draws, in the same colours: a checkered ground fading into the
//! sky, checkered static geometry, shadows on every static surface and the links of joints.
//! The camera can follow a body (a car's chassis by default), the window can be recorded to a
//! GIF, and the scene file is reloaded when it changes.

#![warn(missing_docs)]

pub mod app;
pub mod car;
mod convert;
pub mod draw;
pub mod gizmos;
pub mod islands;
pub mod keys;
pub mod orbit;
pub mod overlay;
pub mod record;
pub mod reload;
pub mod shadows;
mod window;

pub use app::App;
pub use orbit::OrbitCamera;

use kea::Real;
use kea_scene::Scene;
use std::path::PathBuf;

/// How to open the Viewer.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewerOptions {
    /// The window's title.
    pub title: String,
    /// Window size in pixels.
    pub width: u32,
    /// Window height in pixels.
    pub height: u32,
    /// The fixed step, s.
    pub dt: Real,
    /// Where the screenshot key (P) writes.
    pub screenshot: PathBuf,
    /// Where the record key (G) writes its GIF.
    pub recording: PathBuf,
    /// The scene's file, reloaded by R and whenever it changes (`None`: a built-in scene).
    pub scene_file: Option<PathBuf>,
    /// Print one line on stdout for every user action and its effect (`paused step=12`), for
    /// scripts and tests that drive the Viewer with synthetic key presses.
    pub report: bool,
    /// Close after this many frames (for automated runs).
    pub frames: Option<u64>,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        Self {
            title: "Kea Viewer".to_string(),
            width: 1024,
            height: 720,
            dt: 1.0 / 60.0,
            screenshot: PathBuf::from("kea-screenshot.png"),
            recording: PathBuf::from("kea-recording.gif"),
            scene_file: None,
            report: false,
            frames: None,
        }
    }
}

/// Opens the Viewer on `scene` and returns when its window closes. A scene that does not
/// build is an error before any window opens.
pub fn run(scene: Scene, options: ViewerOptions) -> Result<(), String> {
    if options.width == 0 || options.height == 0 {
        return Err(format!(
            "window size must be positive, got {}x{}",
            options.width, options.height
        ));
    }
    let app = App::new(scene, options.dt)?;
    window::open(app, options);
    Ok(())
}
