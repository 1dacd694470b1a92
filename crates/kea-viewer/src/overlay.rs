//! Text over the view: the statistics overlay (O) and the F1 help, which `Panels` shows and
//! hides and whose text it composes (what the window draws, and what tests read).

use crate::app::App;
use crate::keys::{Action, BINDINGS, HELD};
use macroquad::color::Color;
use macroquad::input::KeyCode;
use macroquad::shapes::draw_rectangle;
use macroquad::text::draw_text;
use std::fmt::Write as _;

/// Where the last frame's time went.
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameTimes {
    /// Steps taken for the frame.
    pub steps: u32,
    /// Time in those steps.
    pub stepping: std::time::Duration,
    /// Time building and submitting the triangles and overlays.
    pub drawing: std::time::Duration,
    /// Triangles drawn.
    pub triangles: usize,
    /// Frames per second, as the window measures them.
    pub fps: i32,
}

/// The text panels over the view: the statistics (key O, shown at first) and the help (F1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Panels {
    /// The statistics overlay is shown.
    pub stats: bool,
    /// The help is shown.
    pub help: bool,
}

impl Default for Panels {
    fn default() -> Self {
        Self {
            stats: true,
            help: false,
        }
    }
}

impl Panels {
    /// Answers an action: the help's toggles the help, the overlay's the statistics. Returns
    /// whether it was one of theirs.
    pub fn act(&mut self, action: Action) -> bool {
        match action {
            Action::Help => self.help = !self.help,
            Action::Overlay => self.stats = !self.stats,
            _ => return false,
        }
        true
    }

    /// Answers a key press through the key table, as the window does.
    pub fn press(&mut self, key: KeyCode) -> bool {
        BINDINGS
            .iter()
            .filter(|b| b.key == key)
            .any(|b| self.act(b.action))
    }

    /// The blocks of text shown now, top first: the statistics, then the help.
    #[must_use]
    pub fn text(&self, app: &App, frame: &FrameTimes) -> Vec<Vec<String>> {
        let mut blocks = Vec::new();
        if self.stats {
            blocks.push(stats_lines(app, frame));
        }
        if self.help {
            blocks.push(help_lines());
        }
        blocks
    }

    /// Draws the shown blocks in the top-left corner, one under the other.
    pub fn draw(&self, app: &App, frame: &FrameTimes) {
        let mut y = 8.0;
        for block in self.text(app, frame) {
            y = draw_block(&block, 8.0, y) + 8.0;
        }
    }
}

const LINE: f32 = 18.0;
const SIZE: f32 = 18.0;

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1000.0
}

/// The statistics lines: frame rate, step time per stage, bodies, contacts and rows.
#[must_use]
pub fn stats_lines(app: &App, frame: &FrameTimes) -> Vec<String> {
    let t = &app.timings;
    let s = &t.stats;
    let world = app.physics.dynamics();
    let contacts = world.contacts().count();
    let mut lines = Vec::with_capacity(8);
    let state = if app.paused { "paused" } else { "running" };
    lines.push(format!(
        "{} fps | step {} ({:.4} s) | {state}",
        frame.fps,
        app.step_count(),
        app.dt()
    ));
    lines.push(format!(
        "frame: {} steps {:.1} ms, drawing {:.1} ms ({} triangles)",
        frame.steps,
        ms(frame.stepping),
        ms(frame.drawing),
        frame.triangles
    ));
    lines.push(format!(
        "step {:.2} ms: collision {:.2}, rows {:.2}, islands {:.2}, exact {:.2}, iterative {:.2}, projection {:.2}",
        ms(t.total),
        ms(t.collision),
        ms(s.time_gather),
        ms(s.solver.time_islands),
        ms(s.solver.time_solve_exact),
        ms(s.solver.time_solve_iterative),
        ms(s.time_projection),
    ));
    let mut line = format!(
        "bodies {} awake, {} asleep | contacts {contacts} | rows {} | islands {} ({} exact, {} iterative)",
        s.bodies, s.sleeping_bodies, s.rows, s.solver.islands, s.solver.exact_islands, s.solver.iterative_islands,
    );
    if s.broken_joints > 0 {
        let _ = write!(line, " | {} joints broke", s.broken_joints);
    }
    lines.push(line);
    if let Some(m) = &app.message {
        lines.push(m.clone());
    }
    lines.push("F1: help".to_string());
    lines
}

/// The help lines, one per key and mouse action.
#[must_use]
pub fn help_lines() -> Vec<String> {
    let mut lines = vec!["Kea Viewer keys".to_string()];
    lines.extend(
        BINDINGS
            .iter()
            .map(|b| format!("{:<8} {}", b.label, b.help)),
    );
    lines.extend(HELD.iter().map(|(k, h)| format!("{k}: {h}")));
    lines
}

/// Draws lines on a dark box at (x, y); returns the box's lower edge.
fn draw_block(lines: &[String], x: f32, y: f32) -> f32 {
    let height = LINE * lines.len() as f32 + 8.0;
    let width = lines.iter().map(|l| l.len()).max().unwrap_or(0) as f32 * 8.6 + 12.0;
    draw_rectangle(x, y, width, height, Color::new(0.0, 0.0, 0.0, 0.55));
    for (i, l) in lines.iter().enumerate() {
        let baseline = y + LINE * (i as f32 + 1.0);
        draw_text(l, x + 6.0, baseline, SIZE, Color::new(1.0, 1.0, 1.0, 1.0));
    }
    y + height
}

/// A note at the bottom of the window (a screenshot written, a reload), with a red
/// "REC n" mark while a recording runs.
pub fn draw_toast(text: &str, recording: Option<u32>) {
    let y = macroquad::window::screen_height() - 16.0;
    if !text.is_empty() {
        draw_block(&[text.to_string()], 8.0, y - LINE - 8.0);
    }
    if let Some(frames) = recording {
        let x = macroquad::window::screen_width() - 120.0;
        macroquad::shapes::draw_circle(x, 20.0, 7.0, Color::new(0.9, 0.1, 0.1, 1.0));
        draw_text(
            format!("REC {frames}").as_str(),
            x + 14.0,
            26.0,
            SIZE,
            Color::new(0.9, 0.1, 0.1, 1.0),
        );
    }
}
