//! `kea render`: the scene's frame as a PNG, or an animation as a GIF, drawn on the CPU.

use crate::{check_dt, check_output_folder, check_size, load};
use kea::Real;
use kea3d::PhysicsWorld;
use std::path::Path;

/// Most GIF frames one command draws.
pub const MAX_FRAMES: u32 = 100_000;

/// Steps a PNG takes by default: the last frame of `kea run`'s default run.
pub const PNG_STEPS: u32 = 600;

/// Steps `steps` (default: [`PNG_STEPS`] for a PNG, none for a GIF), then writes the frame
/// (PNG) or `frames` frames `every` steps apart (GIF), the camera framed on what the picture
/// shows (for a GIF, on everything the frames show).
pub fn render(
    path: &Path,
    out: &Path,
    steps: Option<u32>,
    dt: Real,
    (width, height): (u32, u32),
    (frames, every): (u32, u32),
) -> Result<(), String> {
    check_dt(dt)?;
    let gif = match out.extension().and_then(|e| e.to_str()) {
        Some("png") => false,
        Some("gif") => true,
        _ => return Err(format!("--out {}: write a .png or a .gif", out.display())),
    };
    check_size(width, height)?;
    check_output_folder(Some(out), "--out")?;
    if gif {
        if !(1..=MAX_FRAMES).contains(&frames) {
            return Err(format!("--frames must be 1 to {MAX_FRAMES}, got {frames}"));
        }
        if every == 0 {
            return Err("--every must be at least 1, got 0".into());
        }
    }
    let steps = steps.unwrap_or(if gif { 0 } else { PNG_STEPS });
    let (name, mut built) = load(Some(path))?;
    let mut taken = 0u64;
    let mut step = |built: &mut PhysicsWorld, n: u32| -> Result<(), String> {
        for _ in 0..n {
            taken += 1;
            built
                .step(dt)
                .map_err(|e| format!("{name}: step {taken}: {e}"))?;
        }
        Ok(())
    };
    step(&mut built, steps)?;
    let mut bounds = kea_render::subject_bounds(built.dynamics(), built.collision());
    if gif {
        // Frame the whole animation: step a copy through it first.
        let mut ahead = built.clone();
        for _ in 1..frames {
            step(&mut ahead, every)?;
            bounds.union(&kea_render::subject_bounds(
                ahead.dynamics(),
                ahead.collision(),
            ));
        }
        // The same steps again cannot fail where the copy did not (results are the same
        // bits), so the step count in errors can run on.
    }
    let aspect = width as Real / height as Real;
    let camera = kea_render::Camera::framing_bounds(&bounds, aspect, 0.15);
    let draw = |built: &PhysicsWorld| {
        kea_render::render(built.dynamics(), built.collision(), &camera, width, height)
    };
    if gif {
        // Play at the simulation's own speed (GIF delays are in hundredths of a second).
        let delay = (f64::from(every) * kea::math::wide(dt) * 100.0)
            .round()
            .clamp(2.0, 65535.0) as u16;
        let mut animation = kea_render::GifWriter::new(width, height, delay)?;
        for f in 0..frames {
            if f > 0 {
                step(&mut built, every)?;
            }
            animation.push(&draw(&built))?;
        }
        kea_render::write_file(out, &animation.finish()?)?;
        println!(
            "wrote {} ({width}×{height}, {frames} frames)",
            out.display()
        );
    } else {
        draw(&built).write_png(out)?;
        println!(
            "wrote {} ({width}×{height}) after {steps} steps",
            out.display()
        );
    }
    Ok(())
}
