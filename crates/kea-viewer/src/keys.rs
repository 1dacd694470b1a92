//! Every key the Viewer answers, in one table that both the input handling and the F1 help
//! read, so the help can never miss a key.

use macroquad::input::KeyCode;

/// What a key press does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Show or hide the help.
    Help,
    /// Pause or resume stepping.
    Pause,
    /// Take one step (and stay paused).
    Step,
    /// Rebuild the scene as loaded.
    Reset,
    /// Fire a ball from the camera.
    Shoot,
    /// Draw contact points and normals scaled by force.
    Contacts,
    /// Draw joint anchors, axes and limits.
    Joints,
    /// Colour bodies by island.
    Islands,
    /// Grey out sleeping bodies.
    Sleeping,
    /// Draw shadows on the ground.
    Shadows,
    /// Show or hide the statistics overlay.
    Overlay,
    /// Write a screenshot.
    Screenshot,
    /// Start or stop recording the window to a GIF.
    Record,
    /// Follow a body with the camera, or stop following.
    Follow,
    /// Reload the scene file.
    Reload,
    /// Close the Viewer.
    Quit,
}

/// A key press and what it does.
pub struct Binding {
    /// The key.
    pub key: KeyCode,
    /// How the help names it.
    pub label: &'static str,
    /// What it does.
    pub action: Action,
    /// The help's description.
    pub help: &'static str,
}

/// The key presses, in help order.
#[rustfmt::skip]
pub const BINDINGS: &[Binding] = &[
    Binding { key: KeyCode::F1, label: "F1", action: Action::Help, help: "show / hide this help" },
    Binding { key: KeyCode::Space, label: "Space", action: Action::Pause, help: "pause / resume" },
    Binding { key: KeyCode::S, label: "S", action: Action::Step, help: "single step (pauses)" },
    Binding { key: KeyCode::Enter, label: "Enter", action: Action::Reset, help: "reset the scene" },
    Binding { key: KeyCode::B, label: "B", action: Action::Shoot, help: "shoot a ball from the camera" },
    Binding { key: KeyCode::C, label: "C", action: Action::Contacts, help: "contacts: points, normals as long as their force" },
    Binding { key: KeyCode::J, label: "J", action: Action::Joints, help: "joints: anchors, axes and limit ranges" },
    Binding { key: KeyCode::I, label: "I", action: Action::Islands, help: "colour by island" },
    Binding { key: KeyCode::Z, label: "Z", action: Action::Sleeping, help: "grey out sleeping bodies" },
    Binding { key: KeyCode::H, label: "H", action: Action::Shadows, help: "shadows" },
    Binding { key: KeyCode::F, label: "F", action: Action::Follow, help: "camera follows the car, the grabbed or the heaviest body" },
    Binding { key: KeyCode::R, label: "R", action: Action::Reload, help: "reload the scene file (also when it changes)" },
    Binding { key: KeyCode::O, label: "O", action: Action::Overlay, help: "statistics overlay" },
    Binding { key: KeyCode::P, label: "P", action: Action::Screenshot, help: "screenshot (PNG)" },
    Binding { key: KeyCode::G, label: "G", action: Action::Record, help: "start / stop recording a GIF" },
    Binding { key: KeyCode::Escape, label: "Esc", action: Action::Quit, help: "quit" },
];

/// Help lines for the mouse and the held keys.
pub const HELD: &[(&str, &str)] = &[
    (
        "left drag on a body",
        "pull it (a temporary fixed-path joint)",
    ),
    ("left / right drag", "orbit the camera"),
    ("middle drag, Shift+drag", "pan"),
    ("wheel", "zoom"),
    ("Up / Down", "car: throttle / reverse"),
    ("Left / Right", "car: steer"),
];
