//! `kea render`: the scene's frame as a PNG, or an animation as a GIF, drawn on the CPU.

use crate::{check_dt, check_output_folder, check_size, load};
use kea::{BodyHandle, Real};
use kea3d::PhysicsWorld;
use std::path::Path;

/// Most GIF frames one command draws.
pub const MAX_FRAMES: u32 = 100_000;

/// Steps a PNG takes by default: the last frame of `kea run`'s default run.
pub const PNG_STEPS: u32 = 600;

/// What `kea render` was asked to draw.
pub struct RenderOptions<'a> {
    /// The scene file.
    pub scene: &'a Path,
    /// The PNG or GIF to write.
    pub out: &'a Path,
    /// Steps before the (first) frame; `None`: [`PNG_STEPS`] for a PNG, 0 for a GIF.
    pub steps: Option<u32>,
    /// Step size, s.
    pub dt: Real,
    /// Image width and height, pixels.
    pub size: (u32, u32),
    /// For a GIF: frames, and steps between them.
    pub frames: (u32, u32),
    /// Throttle and steering in −1..1 driving every car-wheel joint before each step, as the
    /// Viewer's arrow keys do; `None`: the scene's own motors.
    pub throttle: Option<Real>,
    /// See `throttle`.
    pub steer: Option<Real>,
    /// Names of bodies (or groups: `ragdoll1` is every `ragdoll1.*` body) the camera frames
    /// instead of every body.
    pub focus: &'a [String],
}

/// Checks a driving option: a number from −1 to 1.
fn check_control(flag: &str, value: Option<Real>) -> Result<(), String> {
    match value {
        Some(v) if !(v.is_finite() && (-1.0..=1.0).contains(&v)) => {
            Err(format!("{flag} must be a number from -1 to 1, got {v}"))
        }
        _ => Ok(()),
    }
}

/// The bodies `--focus` names: each name is a body's, or a group's prefix (`ragdoll1` for
/// `ragdoll1.pelvis`, …). An error names a name that matches nothing.
fn focus_bodies(
    built: &PhysicsWorld,
    name: &str,
    focus: &[String],
) -> Result<Vec<BodyHandle>, String> {
    let mut picked = Vec::new();
    for f in focus {
        let before = picked.len();
        picked.extend(built.named_bodies().iter().filter_map(|(n, h)| {
            let group = n
                .strip_prefix(f.as_str())
                .is_some_and(|r| r.starts_with('.'));
            (n == f || group).then_some(*h)
        }));
        if picked.len() == before {
            // Name what there is: each body, or each group once (`ragdoll1.*`).
            let mut known: Vec<String> = Vec::new();
            for (n, _) in built.named_bodies() {
                let n = n
                    .split_once('.')
                    .map_or(n.clone(), |(g, _)| format!("{g}.*"));
                if !known.contains(&n) {
                    known.push(n);
                }
            }
            let more = known.len().saturating_sub(8);
            known.truncate(8);
            let mut list = known.join(", ");
            if more > 0 {
                list.push_str(&format!(" and {more} more"));
            }
            return Err(format!(
                "--focus {f}: {name} has no body named {f} or {f}.* (it has {list})"
            ));
        }
    }
    Ok(picked)
}

/// Steps `steps` (default: [`PNG_STEPS`] for a PNG, none for a GIF), then writes the frame
/// (PNG) or `frames` frames `every` steps apart (GIF), the camera framed on what the picture
/// shows (for a GIF, on everything the frames show; with `focus`, on the bodies it names).
/// With a throttle or a steering, every car wheel is driven before each step.
pub fn render(o: &RenderOptions<'_>) -> Result<(), String> {
    let gif = check_options(o)?;
    let ((width, height), (frames, every)) = (o.size, o.frames);
    let steps = o.steps.unwrap_or(if gif { 0 } else { PNG_STEPS });
    let (name, mut built) = load(Some(o.scene))?;
    let focus = focus_bodies(&built, &name, o.focus)?;
    let drive = driving(o, &built, &name)?;
    let mut stepper = Stepper {
        name: &name,
        dt: o.dt,
        drive: drive.as_ref(),
        taken: 0,
    };
    let subject = |built: &PhysicsWorld| {
        let keep = |b| focus.is_empty() || focus.contains(&b);
        kea_render::subject_points(built.dynamics(), built.collision(), keep)
    };
    stepper.step(&mut built, steps)?;
    let mut points = subject(&built);
    if gif {
        // Frame the whole animation: step a copy through it first. The same steps again
        // cannot fail where the copy did not (results are the same bits), so the step count
        // in errors can run on.
        let mut ahead = built.clone();
        for _ in 1..frames {
            stepper.step(&mut ahead, every)?;
            points.extend(subject(&ahead));
        }
    }
    let aspect = width as Real / height as Real;
    let camera = kea_render::Camera::framing_points(&points, aspect, 0.15);
    let draw = |built: &PhysicsWorld| {
        kea_render::render(built.dynamics(), built.collision(), &camera, width, height)
    };
    if !gif {
        draw(&built).write_png(o.out)?;
        println!(
            "wrote {} ({width}×{height}) after {steps} steps",
            o.out.display()
        );
        return Ok(());
    }
    // Play at the simulation's own speed (GIF delays are in hundredths of a second).
    let delay = (f64::from(every) * kea::math::wide(o.dt) * 100.0)
        .round()
        .clamp(2.0, 65535.0) as u16;
    let mut animation = kea_render::GifWriter::new(width, height, delay)?;
    for f in 0..frames {
        if f > 0 {
            stepper.step(&mut built, every)?;
        }
        animation.push(&draw(&built))?;
    }
    kea_render::write_file(o.out, &animation.finish()?)?;
    println!(
        "wrote {} ({width}×{height}, {frames} frames)",
        o.out.display()
    );
    Ok(())
}

/// Checks every option before anything runs; whether the output is a GIF.
fn check_options(o: &RenderOptions<'_>) -> Result<bool, String> {
    let ((width, height), (frames, every)) = (o.size, o.frames);
    check_dt(o.dt)?;
    let gif = match o.out.extension().and_then(|e| e.to_str()) {
        Some("png") => false,
        Some("gif") => true,
        _ => return Err(format!("--out {}: write a .png or a .gif", o.out.display())),
    };
    check_size(width, height)?;
    check_control("--throttle", o.throttle)?;
    check_control("--steer", o.steer)?;
    check_output_folder(Some(o.out), "--out")?;
    if gif {
        if !(1..=MAX_FRAMES).contains(&frames) {
            return Err(format!("--frames must be 1 to {MAX_FRAMES}, got {frames}"));
        }
        if every == 0 {
            return Err("--every must be at least 1, got 0".into());
        }
    }
    Ok(gif)
}

/// The car's driving: (throttle, steer) and the wheels they drive, if either was given.
/// `--steer` alone steers with the throttle at 0, which brakes, as the Viewer does with no key
/// held.
type Drive = (Real, Real, kea_render::car::Wheels);

fn driving(
    o: &RenderOptions<'_>,
    built: &PhysicsWorld,
    name: &str,
) -> Result<Option<Drive>, String> {
    let (t, s) = (o.throttle, o.steer);
    if t.is_none() && s.is_none() {
        return Ok(None);
    }
    let wheels = kea_render::car::car_wheels(built.dynamics());
    if wheels.is_empty() {
        let flag = if t.is_some() { "--throttle" } else { "--steer" };
        return Err(format!("{flag}: {name} has no car-wheel joint to drive"));
    }
    Ok(Some((t.unwrap_or(0.0), s.unwrap_or(0.0), wheels)))
}

/// Steps a scene, driving its car first if asked, counting the steps for its errors.
struct Stepper<'a> {
    name: &'a str,
    dt: Real,
    drive: Option<&'a Drive>,
    taken: u64,
}

impl Stepper<'_> {
    fn step(&mut self, built: &mut PhysicsWorld, n: u32) -> Result<(), String> {
        let name = self.name;
        for _ in 0..n {
            self.taken += 1;
            let taken = self.taken;
            if let Some((throttle, steer, wheels)) = self.drive {
                kea_render::car::drive(built.dynamics_mut(), wheels, *throttle, *steer)
                    .map_err(|e| format!("{name}: step {taken}: cannot drive the car: {e}"))?;
            }
            built
                .step(self.dt)
                .map_err(|e| format!("{name}: step {taken}: {e}"))?;
        }
        Ok(())
    }
}
