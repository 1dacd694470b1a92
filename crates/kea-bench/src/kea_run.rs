//! A scene in Kea (kea + kea-collision, stepped through kea3d's pipeline), built and measured.

use crate::scenes::{JointKind, Quality, Scene, Shape, Static};
use crate::Outcome;
use kea::{
    BodyDef, BodyHandle, ConstraintHandle, DemMode, DemSettings, Mat3, Quat, Real, SingleLimit,
    StepStats, Vec3, World, WorldDef,
};
use kea3d::PhysicsWorld;
use kea_collision::{ColliderDef, CollisionWorld, Shape as KeaShape};
use std::time::{Duration, Instant};

/// A Kea real as `f64` (the identity when Kea is built in `f64`).
#[allow(clippy::useless_conversion)]
fn wide(x: Real) -> f64 {
    f64::from(x)
}

fn v(a: [f32; 3]) -> Vec3 {
    Vec3::new(a[0] as Real, a[1] as Real, a[2] as Real)
}

/// The scene built in Kea.
pub struct KeaScene {
    physics: PhysicsWorld,
    bodies: Vec<(BodyHandle, Vec3)>,
    /// Joints as (body a or world, local anchor on a, body b, local anchor on b).
    joints: Vec<(Option<BodyHandle>, Vec3, BodyHandle, Vec3)>,
    last: StepStats,
}

impl KeaScene {
    pub fn build(scene: &Scene) -> Self {
        let n = scene.bodies.len();
        let mut world = world_for(scene);
        let mut collision = CollisionWorld::new();
        collision.reserve(n + scene.statics.len());
        for s in &scene.statics {
            let def = match *s {
                Static::Ground => ColliderDef::new(None, KeaShape::plane(Vec3::Y).expect("plane")),
                Static::Cuboid { half, position } => {
                    let mut d = ColliderDef::new(None, KeaShape::cuboid(v(half)).expect("box"));
                    d.offset = v(position);
                    d
                }
            };
            collision.add_collider(&world, def).expect("static");
        }
        let bodies: Vec<_> = scene
            .bodies
            .iter()
            .map(|b| (add_body(&mut world, &mut collision, b), v(b.position)))
            .collect();
        let mut joints = Vec::new();
        for j in &scene.joints {
            let a = j.a.map(|i| bodies[i].0);
            let b = bodies[j.b].0;
            add_joint(&mut world, a, b, v(j.anchor), j.kind);
            let local = |h: Option<BodyHandle>| match h {
                Some(h) => world.body(h).expect("body").point_to_local(v(j.anchor)),
                None => v(j.anchor),
            };
            joints.push((a, local(a), b, local(Some(b))));
        }
        Self {
            physics: PhysicsWorld::from_parts(world, collision),
            bodies,
            joints,
            last: StepStats::default(),
        }
    }

    /// One step; the error, if Kea refused it.
    pub fn step(&mut self) -> Result<(), String> {
        self.last = self.physics.step(1.0 / 60.0).map_err(|e| e.to_string())?;
        Ok(())
    }

    /// Largest joint gap now, m.
    pub fn joint_gap(&self) -> f64 {
        let at = |h: Option<BodyHandle>, p: Vec3| match h {
            Some(h) => self
                .physics
                .dynamics()
                .body(h)
                .expect("body")
                .point_to_world(p),
            None => p,
        };
        self.joints
            .iter()
            .map(|&(a, pa, b, pb)| wide((at(a, pa) - at(Some(b), pb)).length()))
            .fold(0.0, f64::max)
    }

    pub fn displacement(&self) -> f64 {
        self.bodies
            .iter()
            .map(|&(h, p0)| {
                wide((self.physics.dynamics().body(h).expect("body").position() - p0).length())
            })
            .fold(0.0, f64::max)
    }

    /// A hash of every body's position and orientation bits (equal runs give equal hashes).
    pub fn state_hash(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for &(b, _) in &self.bodies {
            let body = self.physics.dynamics().body(b).expect("body");
            let (p, q) = (body.position(), body.orientation());
            for x in [p.x, p.y, p.z, q.x, q.y, q.z, q.w] {
                x.to_bits().hash(&mut h);
            }
        }
        h.finish()
    }

    pub fn energy(&self) -> f64 {
        wide(self.physics.dynamics().kinetic_energy())
    }

    /// Every body's orientation, `[x, y, z, w]`, in the scene's order.
    pub fn orientations(&self) -> Vec<[f64; 4]> {
        self.bodies
            .iter()
            .map(|&(h, _)| {
                let q = self.physics.dynamics().body(h).expect("body").orientation();
                [wide(q.x), wide(q.y), wide(q.z), wide(q.w)]
            })
            .collect()
    }

    /// The last step's stage times: solver, broad phase, narrow phase.
    pub fn stages(&self) -> [Duration; 3] {
        [
            self.last.solver.time_solve,
            self.last.collision.time_broad_phase,
            self.last.collision.time_narrow_phase,
        ]
    }
}

/// Joins body `b` to `a` (or the world) at `anchor` as `kind` says.
fn add_joint(
    mut world: &mut World,
    a: Option<BodyHandle>,
    b: BodyHandle,
    anchor: Vec3,
    kind: JointKind,
) -> ConstraintHandle {
    let hard = |x: f32| SingleLimit::hard(x as Real, 0.0);
    match kind {
        JointKind::Ball => world
            .create_joint(b, a, kea::JointSpec::ball(anchor))
            .expect("ball joint")
            .into(),
        JointKind::LimitedBall { axis, cone, twist } => {
            let h = world
                .create_joint(b, a, kea::JointSpec::ball(anchor))
                .expect("ball joint");
            let axis = v(axis);
            h.set_limit_axes(&mut world, axis, axis.any_orthonormal_vector())
                .expect("limit axes");
            let limits = h.limits_mut(&mut world).expect("limits");
            // The cone angle is never negative: its lower stop is out of reach.
            limits
                .cone
                .set_limits(hard(-1.0), hard(cone))
                .expect("cone");
            limits
                .twist
                .set_limits(hard(-twist), hard(twist))
                .expect("twist");
            h.into()
        }
        JointKind::Hinge { axis, lower, upper } => {
            let h = world
                .create_joint(b, a, kea::JointSpec::hinge(anchor, v(axis)))
                .expect("hinge");
            h.limit_mut(&mut world)
                .expect("hinge limit")
                .set_limits(hard(lower), hard(upper))
                .expect("limits");
            h.into()
        }
    }
}

/// Builds `scene`, settles it, times its steps; returns ms/step and the quality figure.
pub fn run(scene: &Scene) -> Outcome {
    let mut s = KeaScene::build(scene);
    let mut failed = None;
    for k in 0..scene.settle {
        if let Err(e) = s.step() {
            failed = Some(format!("settling step {k}: {e}"));
            break;
        }
    }
    let mut gap: f64 = 0.0;
    let hinges = crate::scenes::has_hinges(scene);
    let start = s.orientations();
    let mut overrun: f64 = 0.0;
    let mut stages = [Duration::ZERO; 3];
    let mut total = Duration::ZERO;
    let mut steps = 0;
    while steps < scene.steps && failed.is_none() {
        let t = Instant::now();
        let stepped = s.step();
        total += t.elapsed();
        if let Err(e) = stepped {
            failed = Some(format!("step {steps}: {e}"));
            break;
        }
        steps += 1;
        if scene.quality == Quality::JointGap {
            gap = gap.max(s.joint_gap());
        }
        if hinges {
            overrun = overrun.max(crate::scenes::hinge_overrun(
                scene,
                &start,
                &s.orientations(),
            ));
        }
        for (t, d) in stages.iter_mut().zip(s.stages()) {
            *t += d;
        }
    }
    let steps = steps.max(1) as f64;
    let ms = total.as_secs_f64() * 1e3 / steps;
    let quality = match scene.quality {
        Quality::Displacement => s.displacement(),
        Quality::Energy => s.energy(),
        Quality::JointGap => gap,
    };
    Outcome {
        ms,
        quality,
        hash: s.state_hash(),
        stages_ms: stages.map(|d| d.as_secs_f64() * 1e3 / steps),
        failed,
        overrun,
    }
}

/// The world for a scene: room for its bodies, joints and their contacts; the solver path a
/// `KEA_BENCH_MODE` forces (or the scene asks for); sleeping if the scene sleeps.
fn world_for(scene: &Scene) -> World {
    let n = scene.bodies.len();
    let mut world = World::new(WorldDef {
        max_bodies: n + 1,
        // Room for fast bodies' speculative contacts (a whipped chain's links meet many).
        max_constraints: 32 * n + scene.joints.len() + 64,
        ..Default::default()
    })
    .expect("world");
    let forced = match std::env::var("KEA_BENCH_MODE").as_deref() {
        Ok("split") => Some(kea::SolverMode::Split),
        Ok("exact") => Some(kea::SolverMode::Exact),
        Ok("iterative") => Some(kea::SolverMode::Iterative),
        _ if scene.kea_exact => Some(kea::SolverMode::Exact),
        _ => None,
    };
    world
        .update_settings(|s| {
            if let Some(mode) = forced {
                s.routing = kea::Routing {
                    mode,
                    ..Default::default()
                };
            }
            if scene.sleep {
                s.dem = DemSettings {
                    mode: DemMode::PartitionAutoDisable,
                    ..Default::default()
                };
            }
        })
        .expect("settings");
    world
}

/// A scene body and its collider; Kea's capsules lie along y: turned onto x, with the inertia
/// turned alike.
fn add_body(
    world: &mut World,
    collision: &mut CollisionWorld,
    b: &crate::scenes::Body,
) -> BodyHandle {
    let (shape, rotation) = match b.shape {
        Shape::Cuboid(h) => (KeaShape::cuboid(v(h)), Quat::IDENTITY),
        Shape::Ball(r) => (KeaShape::sphere(r as Real), Quat::IDENTITY),
        Shape::CapsuleX(hh, r) => (
            KeaShape::capsule(hh as Real, r as Real),
            Quat::from_rotation_z(-std::f64::consts::FRAC_PI_2 as Real),
        ),
        Shape::CapsuleY(hh, r) => (KeaShape::capsule(hh as Real, r as Real), Quat::IDENTITY),
    };
    let shape = shape.expect("shape");
    let mp = shape.mass_properties(b.density as Real).expect("mass");
    let r = Mat3::from_quat(rotation);
    let body = world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: r * mp.inertia * r.transpose(),
            position: v(b.position),
            ..Default::default()
        })
        .expect("body");
    let mut def = ColliderDef::new(Some(body), shape);
    def.rotation = rotation;
    collision.add_collider(world, def).expect("collider");
    body
}
