//! `kea plot`: energy, momentum, joint gap and penetration against time, drawn with plotters
//! into a PNG, each chart's legend in a column beside it and ticks with SI prefixes. Text needs a font: the first of a few common system fonts (or `KEA_FONT`); without
//! one the charts are drawn without labels and a note says so.

use crate::summary::energy;
use kea::math::wide;
use kea::{Real, Vec3};
use kea3d::PhysicsWorld;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;

/// Fonts tried, in order, after `KEA_FONT`.
const FONTS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/Library/Fonts/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// One quantity over time.
pub struct Series {
    /// Legend text.
    pub name: &'static str,
    /// (time s, value) per step.
    pub points: Vec<(f64, f64)>,
}

/// The recorded quantities: energy, momentum and constraint error.
pub struct Record {
    /// Panel titles with their series.
    pub panels: Vec<(&'static str, Vec<Series>)>,
}

fn momentum(built: &PhysicsWorld) -> (Vec3, Vec3) {
    let mut p = Vec3::ZERO;
    let mut l = Vec3::ZERO;
    for (_, b) in built.dynamics().bodies() {
        let pb = b.linear_velocity() * b.mass();
        p += pb;
        l += b.position().cross(pb) + b.angular_momentum();
    }
    (p, l)
}

impl Record {
    /// An empty record.
    pub fn new() -> Self {
        let series = |names: &[&'static str]| {
            names
                .iter()
                .map(|&name| Series {
                    name,
                    points: Vec::new(),
                })
                .collect()
        };
        Self {
            panels: vec![
                ("Energy (J)", series(&["kinetic + potential", "kinetic"])),
                (
                    "Momentum",
                    series(&["|p| (N·s)", "|L| about the origin (N·m·s)"]),
                ),
                ("Joint gap (m)", series(&["largest joint error"])),
                ("Penetration (m)", series(&["deepest contact"])),
            ],
        }
    }

    /// Records the scene at time `t`, with its largest joint error (`World::joint_error`); a
    /// value that is not finite (a scene that blew up) is an error naming it.
    pub fn capture(
        &mut self,
        t: Real,
        built: &PhysicsWorld,
        joint_error: Real,
    ) -> Result<(), String> {
        let (p, l) = momentum(built);
        let kinetic: Real = built
            .dynamics()
            .bodies()
            .map(|(_, b)| b.kinetic_energy())
            .sum();
        let values = [
            [energy(built), kinetic],
            [p.length(), l.length()],
            [joint_error, Real::NAN],
            [
                built.collision().deepest_penetration(built.dynamics()),
                Real::NAN,
            ],
        ];
        for ((_, series), row) in self.panels.iter_mut().zip(values) {
            // Panels of one series leave the second value unused.
            for (s, v) in series.iter_mut().zip(row) {
                if !v.is_finite() {
                    return Err(format!("{} is {v} at t = {t} s: nothing to plot", s.name));
                }
                s.points.push((wide(t), wide(v)));
            }
        }
        Ok(())
    }
}

/// Registers the first font found as "sans-serif"; false if none was found.
fn load_font() -> bool {
    let env = std::env::var("KEA_FONT").ok();
    for path in env.iter().map(String::as_str).chain(FONTS.iter().copied()) {
        if let Ok(bytes) = std::fs::read(path) {
            // plotters keeps fonts for the life of the program.
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                return true;
            }
        }
    }
    false
}

fn range(series: &[Series]) -> (f64, f64) {
    let values = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

const COLOURS: [RGBColor; 2] = [RGBColor(200, 60, 40), RGBColor(40, 90, 200)];

/// Width of the legend column right of each chart, pixels: the legend never covers data.
const LEGEND_WIDTH: u32 = 230;

/// A tick label that reads at a glance: up to three significant digits with an SI prefix
/// (`25k`, `1.5m`, `10µ`, `0`), never `25000.0` or `0.00001`.
pub fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    const PREFIXES: [(f64, &str); 9] = [
        (1e12, "T"),
        (1e9, "G"),
        (1e6, "M"),
        (1e3, "k"),
        (1.0, ""),
        (1e-3, "m"),
        (1e-6, "µ"),
        (1e-9, "n"),
        (1e-12, "p"),
    ];
    let a = v.abs();
    // Values near a prefix's boundary round up into it (999.96 → 1k, not 1000).
    let &(scale, prefix) = PREFIXES
        .iter()
        .find(|(scale, _)| a >= scale * 0.999_95)
        .unwrap_or(&PREFIXES[PREFIXES.len() - 1]);
    let m = v / scale;
    let digits = if m.abs() >= 100.0 {
        0
    } else if m.abs() >= 10.0 {
        1
    } else {
        2
    };
    let text = format!("{m:.digits$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    format!("{text}{prefix}")
}

/// Draws the record into a PNG of `width` × `height`; returns whether it has labels.
pub fn draw(record: &Record, out: &Path, (width, height): (u32, u32)) -> Result<bool, String> {
    let labelled = load_font();
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", out.display());
    // Drawn in memory, then written whole (or not at all) by `write_png`.
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    let labelled = draw_into(record, &mut rgb, (width, height), labelled, &err)?;
    let pixels = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    kea_render::Image {
        width,
        height,
        pixels,
    }
    .write_png(out)?;
    Ok(labelled)
}

fn draw_into(
    record: &Record,
    rgb: &mut [u8],
    (width, height): (u32, u32),
    labelled: bool,
    err: &dyn Fn(&dyn std::fmt::Display) -> String,
) -> Result<bool, String> {
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let panels = root.split_evenly((record.panels.len(), 1));
    let t_end = record.panels[0].1[0]
        .points
        .last()
        .map_or(1.0, |p| p.0)
        .max(1e-6);
    for (panel, (title, series)) in panels.iter().zip(&record.panels) {
        let (lo, hi) = range(series);
        let legend_width = if labelled {
            LEGEND_WIDTH.min(width / 3)
        } else {
            0
        };
        let (area, legend) = panel.split_horizontally(width - legend_width);
        let mut builder = ChartBuilder::on(&area);
        builder.margin(12);
        if labelled {
            builder
                .caption(*title, ("sans-serif", 18))
                .x_label_area_size(28)
                .y_label_area_size(70);
        }
        let mut chart = builder
            .build_cartesian_2d(0.0..t_end, lo..hi)
            .map_err(|e| err(&e))?;
        let mut mesh = chart.configure_mesh();
        let label = |v: &f64| tick(*v);
        // Seconds read best as plain decimals (0.5, not 500m).
        let seconds = |v: &f64| {
            let text = format!("{v:.2}");
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        if labelled {
            mesh.x_desc("time (s)")
                .x_label_formatter(&seconds)
                .y_label_formatter(&label);
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw().map_err(|e| err(&e))?;
        for (k, (s, colour)) in series.iter().zip(COLOURS).enumerate() {
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(|e| err(&e))?;
            if labelled {
                // The legend's own column, beside the chart.
                let y = 40 + 22 * k as i32;
                legend
                    .draw(&PathElement::new(
                        vec![(6, y), (30, y)],
                        colour.stroke_width(3),
                    ))
                    .map_err(|e| err(&e))?;
                legend
                    .draw(&Text::new(s.name, (36, y - 8), ("sans-serif", 15)))
                    .map_err(|e| err(&e))?;
            }
        }
    }
    root.present().map_err(|e| err(&e))?;
    Ok(labelled)
}

#[cfg(test)]
mod tests {
    use super::tick;

    #[test]
    fn ticks_read_with_si_prefixes() {
        assert_eq!(tick(25000.0), "25k");
        assert_eq!(tick(0.00001), "10µ");
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(1.5), "1.5");
        assert_eq!(tick(-0.0025), "-2.5m");
        assert_eq!(tick(999.96), "1k");
        assert_eq!(tick(123456.0), "123k");
        assert_eq!(tick(2.0e-7), "200n");
        assert_eq!(tick(3.0e15), "3000T");
    }
}
