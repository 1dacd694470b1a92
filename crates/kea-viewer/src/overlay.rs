//! Text over the view: the statistics overlay and the F1 help.

use crate::app::App;
use crate::keys::{BINDINGS, HELD};
use macroquad::color::Color;
use macroquad::shapes::draw_rectangle;
use macroquad::text::draw_text;
use macroquad::time::get_fps;
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
        get_fps(),
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

/// Draws the statistics in the top-left corner.
pub fn draw_stats(app: &App, frame: &FrameTimes) {
    let lines = stats_lines(app, frame);
    draw_block(&lines, 8.0, 8.0);
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

/// Draws the help under the statistics.
pub fn draw_help() {
    draw_block(&help_lines(), 8.0, 150.0);
}

fn draw_block(lines: &[String], x: f32, y: f32) {
    let height = LINE * lines.len() as f32 + 8.0;
    let width = lines.iter().map(|l| l.len()).max().unwrap_or(0) as f32 * 8.6 + 12.0;
    draw_rectangle(x, y, width, height, Color::new(0.0, 0.0, 0.0, 0.55));
    for (i, l) in lines.iter().enumerate() {
        let baseline = y + LINE * (i as f32 + 1.0);
        draw_text(l, x + 6.0, baseline, SIZE, Color::new(1.0, 1.0, 1.0, 1.0));
    }
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
