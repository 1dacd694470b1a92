//! The simulation behind the window: the scene, fixed-dt stepping with interpolation, reset,
//! shooting balls, dragging bodies and driving cars. No drawing and no window here, so it is
//! tested like any other code.

use crate::convert::{to_f64, to_real};
use kea::{BodyDef, BodyHandle, CarWheel, FixedPath, JointHandle, Quat, Real, StepStats, Vec3};
use kea3d::PhysicsWorld;
use kea_collision::{ColliderDef, QueryFilter, Shape};
use kea_scene::{build, Scene};
use std::collections::HashMap;
use std::time::{Duration, Instant};

/// Room for bodies the user adds (shot balls) beyond the scene's own, when the scene lets the
/// capacity follow its size.
pub const SHOT_ROOM: usize = 200;
/// Radius of a shot ball, m.
pub const SHOT_RADIUS: Real = 0.15;
/// Speed of a shot ball, m/s.
pub const SHOT_SPEED: Real = 15.0;
/// Density of a shot ball, kg/m³ (a heavy ball, as in the guide's bounce tutorial).
pub const SHOT_DENSITY: Real = 2000.0;
/// Most steps taken for one drawn frame: a slow frame slows the scene down rather than letting
/// the backlog grow without end.
pub const MAX_STEPS_PER_FRAME: u32 = 8;
/// Most time spent stepping for one drawn frame: a scene whose steps cost more than real time
/// runs in slow motion instead of dragging the frame rate down with it.
pub const STEP_BUDGET: Duration = Duration::from_millis(30);

/// Fastest the held point follows the mouse, m/s: a far jump of the mouse becomes a quick
/// pull, not an impulse that flings the body.
pub const DRAG_SPEED: Real = 8.0;
/// Damping rate of a held body, 1/s: a held body comes to rest under the pointer instead of
/// swinging about the held point for ever.
pub const DRAG_DAMPING: Real = 4.0;

/// A body held by the mouse through a temporary fixed-path joint.
struct Drag {
    joint: JointHandle<FixedPath>,
    body: BodyHandle,
    /// Where the mouse ray meets the drag plane, world frame.
    target: Vec3,
    /// The joint's path point, which follows the target at up to [`DRAG_SPEED`].
    held: Vec3,
    /// The body's own linear and angular damping, restored when it is let go.
    damping: (Real, Real),
}

/// Timings of the last step, for the overlay.
#[derive(Debug, Clone, Copy, Default)]
pub struct Timings {
    /// The world's own report (bodies, rows, solver stages).
    pub stats: StepStats,
    /// Collision detection and contact updates.
    pub collision: Duration,
    /// The whole step, collision included.
    pub total: Duration,
}

/// A running scene.
pub struct App {
    spec: Scene,
    /// The scene's world, stepped through its pipeline.
    pub physics: PhysicsWorld,
    dt: Real,
    /// Stepping stopped (single steps still work).
    pub paused: bool,
    accumulator: f64,
    previous: HashMap<BodyHandle, (Vec3, Quat)>,
    /// What the last step took.
    pub timings: Timings,
    drag: Option<Drag>,
    /// Car-wheel joints, each with the spin sign that rolls the car forwards.
    pub(crate) wheels: Vec<(JointHandle<CarWheel>, Real)>,
    /// The last problem a user action ran into (a full world, a failed step), for the overlay.
    pub message: Option<String>,
    /// The body the mouse last grabbed (the camera can follow it).
    pub last_grabbed: Option<BodyHandle>,
}

impl App {
    /// Builds `spec`, with room for shot balls, stepping by `dt`.
    pub fn new(spec: Scene, dt: Real) -> Result<Self, String> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(format!("dt must be finite and > 0, got {dt}"));
        }
        let physics = build_with_room(&spec)?;
        let mut app = Self {
            spec,
            physics,
            dt,
            paused: false,
            accumulator: 0.0,
            previous: HashMap::new(),
            timings: Timings::default(),
            drag: None,
            wheels: Vec::new(),
            message: None,
            last_grabbed: None,
        };
        app.after_build();
        Ok(app)
    }

    /// The fixed step, s.
    #[must_use]
    pub fn dt(&self) -> Real {
        self.dt
    }

    /// Steps taken since the scene was (re)built.
    #[must_use]
    pub fn step_count(&self) -> u64 {
        self.physics.dynamics().step_count()
    }

    /// Rebuilds the scene as it was loaded (the guide's Enter key).
    pub fn reset(&mut self) {
        match build_with_room(&self.spec) {
            Ok(physics) => self.install(physics),
            Err(e) => self.message = Some(e),
        }
    }

    /// Replaces the scene with `spec` (a reloaded file), as if the Viewer had been opened on
    /// it. A scene that does not build is an error and the running scene is kept.
    pub fn replace(&mut self, spec: Scene) -> Result<(), String> {
        let physics = build_with_room(&spec)?;
        self.spec = spec;
        self.install(physics);
        Ok(())
    }

    /// Runs a freshly built scene from its start.
    fn install(&mut self, physics: PhysicsWorld) {
        self.physics = physics;
        self.previous.clear();
        self.drag = None;
        self.accumulator = 0.0;
        self.message = None;
        self.after_build();
    }

    /// The body a camera should follow: the car's chassis if the scene has a car, else the
    /// body last grabbed, else the heaviest body; `None` in a scene without bodies.
    #[must_use]
    pub fn subject(&self) -> Option<BodyHandle> {
        let world = self.physics.dynamics();
        if let Some(chassis) = self.chassis() {
            return Some(chassis);
        }
        if let Some(b) = self.last_grabbed.filter(|b| world.body(*b).is_ok()) {
            return Some(b);
        }
        world
            .bodies()
            .filter(|(_, b)| b.mass().is_finite())
            .max_by(|a, b| a.1.mass().total_cmp(&b.1.mass()).then(b.0.cmp(&a.0)))
            .map(|(h, _)| h)
    }

    /// The chassis of the scene's car: body 1 of its first car-wheel joint.
    #[must_use]
    pub fn chassis(&self) -> Option<BodyHandle> {
        let (h, _) = self.wheels.first()?;
        self.physics.dynamics().constraint_bodies(*h).ok()?[0]
    }

    fn after_build(&mut self) {
        self.last_grabbed = None;
        self.snapshot();
        self.wheels = kea_render::car::car_wheels(self.physics.dynamics());
        self.timings = Timings::default();
    }

    /// Car-wheel joints, which the throttle and steering keys drive.
    #[must_use]
    pub fn wheels(&self) -> Vec<JointHandle<CarWheel>> {
        self.wheels.iter().map(|(h, _)| *h).collect()
    }

    /// Whether the scene has car wheels to drive.
    #[must_use]
    pub fn has_wheels(&self) -> bool {
        !self.wheels.is_empty()
    }

    /// Advances by `frame_seconds` of real time in fixed steps (none while paused); returns the
    /// steps taken. What is left over is kept for the next frame and for interpolation.
    pub fn advance(&mut self, frame_seconds: f64) -> u32 {
        if self.paused {
            return 0;
        }
        self.accumulator += frame_seconds.clamp(0.0, 0.25);
        let mut steps = 0;
        let dt = to_f64(self.dt);
        let start = Instant::now();
        let mut behind = false;
        while self.accumulator >= dt {
            if steps == MAX_STEPS_PER_FRAME || start.elapsed() > STEP_BUDGET {
                behind = true;
                break;
            }
            self.accumulator -= dt;
            if !self.step_once() {
                break;
            }
            steps += 1;
        }
        if behind {
            self.accumulator = self.accumulator.min(dt); // drop the backlog: slow motion
        }
        steps
    }

    /// Takes one step now (the single-step key); false if the step failed (the scene then
    /// pauses and the message says why).
    pub fn step_once(&mut self) -> bool {
        self.snapshot();
        if let Some(d) = &mut self.drag {
            let reach = d.target - d.held;
            let moved = reach.clamp_length_max(DRAG_SPEED * self.dt);
            d.held += moved;
            let _ = d.joint.set_path(&mut self.physics, d.held, moved / self.dt);
        }
        let start = Instant::now();
        match self.physics.step(self.dt) {
            Ok(stats) => {
                let total = start.elapsed();
                self.timings = Timings {
                    stats,
                    collision: total.saturating_sub(stats.time_total),
                    total,
                };
                true
            }
            Err(e) => {
                self.paused = true;
                self.message = Some(format!("step failed: {e}"));
                false
            }
        }
    }

    /// How far drawing is between the last two steps, 0..1.
    #[must_use]
    pub fn alpha(&self) -> Real {
        if self.paused {
            return 1.0;
        }
        to_real(self.accumulator / to_f64(self.dt)).clamp(0.0, 1.0)
    }

    fn snapshot(&mut self) {
        for (h, b) in self.physics.dynamics().bodies() {
            self.previous.insert(h, (b.position(), b.orientation()));
        }
    }

    /// A body's pose for drawing: between its pose before and after the last step.
    #[must_use]
    pub fn body_pose(&self, h: BodyHandle) -> Option<(Vec3, Quat)> {
        let b = self.physics.dynamics().body(h).ok()?;
        let now = (b.position(), b.orientation());
        let Some(before) = self.previous.get(&h) else {
            return Some(now);
        };
        let a = self.alpha();
        Some((before.0.lerp(now.0, a), before.1.slerp(now.1, a)))
    }

    /// Fires a ball from `origin` along `direction` (the guide's bounce tutorial's `shoot`).
    pub fn shoot(&mut self, origin: Vec3, direction: Vec3) {
        if let Err(e) = self.try_shoot(origin, direction) {
            self.message = Some(format!("cannot shoot: {e}"));
        }
    }

    fn try_shoot(&mut self, origin: Vec3, direction: Vec3) -> Result<(), String> {
        let shape = Shape::sphere(SHOT_RADIUS).map_err(|e| e.to_string())?;
        let mass = shape
            .mass_properties(SHOT_DENSITY)
            .map_err(|e| e.to_string())?;
        let def = BodyDef {
            mass: mass.mass,
            inertia: mass.inertia,
            position: origin,
            linear_velocity: direction.normalize_or_zero() * SHOT_SPEED,
            ..BodyDef::default()
        };
        let (world, collision) = self.physics.layers_mut();
        let body = world.create_body(&def).map_err(|e| e.to_string())?;
        let collider = ColliderDef::new(Some(body), shape);
        if let Err(e) = collision.add_collider(world, collider) {
            let _ = world.destroy_body(body);
            return Err(e.to_string());
        }
        self.previous.insert(body, (origin, Quat::IDENTITY));
        Ok(())
    }

    /// Grabs the body under the ray from `origin` along `direction`, holding it at the hit
    /// point with a fixed-path joint; false if the ray hits no body.
    pub fn begin_drag(&mut self, origin: Vec3, direction: Vec3) -> bool {
        self.end_drag();
        let hit = self.physics.collision().cast_ray(
            self.physics.dynamics(),
            &kea_collision::RayCast::new(origin, direction, 1.0e4),
            QueryFilter::default(),
        );
        let Ok(Some(hit)) = hit else { return false };
        let Ok(def) = self.physics.collision().collider(hit.collider) else {
            return false;
        };
        let Some(body) = def.body else { return false };
        let world = self.physics.dynamics_mut();
        let _ = world.wake_body(body);
        match world.create_joint(body, None, kea::JointSpec::fixed_path(hit.point, false)) {
            Ok(joint) => {
                self.last_grabbed = Some(body);
                let damping = hold_damping(world, body);
                self.drag = Some(Drag {
                    joint,
                    body,
                    target: hit.point,
                    held: hit.point,
                    damping,
                });
                true
            }
            Err(e) => {
                self.message = Some(format!("cannot grab: {e}"));
                false
            }
        }
    }

    /// The held point, if a body is held.
    #[must_use]
    pub fn drag_point(&self) -> Option<Vec3> {
        self.drag.as_ref().map(|d| d.target)
    }

    /// Moves the held point to where the ray meets the plane through the held point facing
    /// `view_direction`.
    pub fn drag_to(&mut self, origin: Vec3, direction: Vec3, view_direction: Vec3) {
        let Some(d) = &mut self.drag else { return };
        let denominator = direction.dot(view_direction);
        if denominator.abs() < 1.0e-6 {
            return;
        }
        let t = (d.target - origin).dot(view_direction) / denominator;
        if t > 0.0 {
            d.target = origin + direction * t;
        }
    }

    /// Lets go of the held body.
    pub fn end_drag(&mut self) {
        if let Some(d) = self.drag.take() {
            let world = self.physics.dynamics_mut();
            let _ = world.destroy_constraint(d.joint);
            if let Ok(b) = world.body_mut(d.body) {
                let _ = b.set_linear_damping(d.damping.0);
                let _ = b.set_angular_damping(d.damping.1);
            }
        }
    }
}

/// Damps a body about to be held (mass and inertia times [`DRAG_DAMPING`]) and returns its
/// own damping, to restore on release.
fn hold_damping(world: &mut kea::World, body: BodyHandle) -> (Real, Real) {
    let Ok(b) = world.body_mut(body) else {
        return (0.0, 0.0);
    };
    let own = (b.linear_damping(), b.angular_damping());
    let inertia = b.inertia();
    let largest = inertia.x_axis.x.max(inertia.y_axis.y).max(inertia.z_axis.z);
    let _ = b.set_linear_damping(own.0 + DRAG_DAMPING * b.mass());
    let _ = b.set_angular_damping(own.1 + DRAG_DAMPING * largest);
    own
}

/// Builds `spec` into a world to step; when its world sizes itself (`max_bodies` 0), leaves
/// room for [`SHOT_ROOM`] more bodies and their contacts (as far as the scene limits allow).
fn build_with_room(spec: &Scene) -> Result<PhysicsWorld, String> {
    let built = |spec: &Scene| {
        let mut world = build(spec)
            .map(PhysicsWorld::from_scene)
            .map_err(|e| e.to_string())?;
        world
            .load_scene_robots(&spec.robots)
            .map_err(|e| e.to_string())?;
        Ok::<_, String>(world)
    };
    if spec.world.max_bodies != 0 {
        return built(spec);
    }
    let needed = kea_scene::body_count(spec);
    let mut roomy = spec.clone();
    roomy.world.max_bodies = (needed + SHOT_ROOM).min(kea_scene::MAX_BODIES.max(needed));
    if roomy.world.max_constraints == 0 {
        roomy.world.max_constraints = roomy
            .world
            .max_bodies
            .saturating_mul(16)
            .clamp(256, kea_scene::MAX_CONSTRAINTS);
    }
    built(&roomy)
}
