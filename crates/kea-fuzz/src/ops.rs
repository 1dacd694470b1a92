//! The operations the driver draws: every part of the public API a user reaches, with values
//! from [`Rng`]. Each returns whether Kea accepted it.

use crate::random::Rng;
use kea::{
    BallJoint, BodyDef, BodyHandle, ConstraintHandle, Contact, ContactPoint, FixedPath, Hinge,
    JointHandle, Mat3, Prismatic, Real, Routing, SingleLimit, SolverMode, SpeedLimits, Vec3, World,
    WorldDef,
};
use kea3d::PhysicsWorld;
use kea_collision::{ColliderDef, ColliderHandle, CollisionWorld, QueryFilter, Shape, ShapeCast};

/// One world under test, with the handles made in it (some stale on purpose).
pub struct Sandbox {
    /// The world, stepped through its pipeline as an application steps it.
    physics: PhysicsWorld,
    bodies: Vec<BodyHandle>,
    joints: Vec<ConstraintHandle>,
    colliders: Vec<ColliderHandle>,
    tendons: Vec<kea::TendonHandle>,
    /// A world that steps this one's state by trading states with it (a batch's worker).
    worker: PhysicsWorld,
    /// After a traded step: a copy of the world from before it, the step, and what the
    /// trade answered, for [`Sandbox::verify_traded_step`].
    traded: Option<(PhysicsWorld, Real, Outcome)>,
}

/// What an operation did: accepted, refused, or (for a query) answered.
pub type Outcome = Result<(), String>;

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

impl Sandbox {
    /// A fresh world with a ground plane.
    pub fn new(rng: &mut Rng) -> Self {
        let def = WorldDef {
            max_bodies: 8 + rng.below(40),
            max_constraints: 16 + rng.below(200),
            ..WorldDef::default()
        };
        let world = World::new(def).expect("ordinary capacities are accepted");
        let mut collision = CollisionWorld::new();
        let ground = Shape::plane(Vec3::Y).expect("a plane");
        let ground = collision
            .add_collider(&world, ColliderDef::new(None, ground))
            .expect("a static plane");
        Self {
            physics: PhysicsWorld::from_parts(world, collision),
            bodies: Vec::new(),
            joints: Vec::new(),
            colliders: vec![ground],
            tendons: Vec::new(),
            worker: PhysicsWorld::new(),
            traded: None,
        }
    }

    /// A fresh world ([`Sandbox::new`]) that keeps this one's worker, so that the worker
    /// goes on to step other worlds' states, as a batch's worker steps many worlds.
    #[must_use]
    pub fn renew(self, rng: &mut Rng) -> Self {
        Self {
            worker: self.worker,
            ..Self::new(rng)
        }
    }

    /// The dynamics layer.
    pub fn world(&self) -> &World {
        self.physics.dynamics()
    }

    /// The collision layer.
    pub fn collision(&self) -> &CollisionWorld {
        self.physics.collision()
    }

    fn body(&self, rng: &mut Rng) -> Option<BodyHandle> {
        (!self.bodies.is_empty()).then(|| self.bodies[rng.below(self.bodies.len())])
    }

    fn other(&self, rng: &mut Rng) -> Option<BodyHandle> {
        if rng.chance(0.3) {
            None
        } else {
            self.body(rng)
        }
    }

    fn joint(&self, rng: &mut Rng) -> Option<ConstraintHandle> {
        (!self.joints.is_empty()).then(|| self.joints[rng.below(self.joints.len())])
    }

    /// Draws one operation and runs it; returns its name and outcome.
    pub fn operate(&mut self, rng: &mut Rng) -> (&'static str, Outcome) {
        match rng.below(100) {
            0..=11 => ("create_body", self.create_body(rng)),
            12..=14 => ("destroy_body", self.destroy_body(rng)),
            15..=24 => ("set_body", self.set_body(rng)),
            25..=36 => ("create_joint", self.create_joint(rng)),
            37..=44 => ("set_joint", self.set_joint(rng)),
            45..=46 => ("create_contact", self.create_contact(rng)),
            47..=48 => ("update_contact", self.update_contact(rng)),
            49..=58 => ("add_collider", self.add_collider(rng)),
            59..=60 => ("remove_collider", self.remove_collider(rng)),
            61..=68 => ("query", self.query(rng)),
            69..=92 => ("step", self.step(rng)),
            _ => ("settings", self.settings(rng)),
        }
    }

    fn create_body(&mut self, rng: &mut Rng) -> Outcome {
        let mass = rng.real(0.1, 50.0);
        let d = rng.real(0.01, 5.0);
        let def = BodyDef {
            mass,
            inertia: Mat3::from_diagonal(Vec3::new(d, rng.real(0.01, 5.0), rng.real(0.01, 5.0))),
            position: rng.vec3(-5.0, 5.0),
            orientation: rng.rotation(),
            linear_velocity: rng.vec3(-5.0, 5.0),
            angular_velocity: rng.vec3(-5.0, 5.0),
            linear_damping: if rng.chance(0.8) {
                0.0
            } else {
                rng.real(0.0, 2.0)
            },
            fast_spin_axis: rng.chance(0.1).then(|| rng.direction()),
            ..BodyDef::default()
        };
        let h = self.physics.dynamics_mut().create_body(&def).map_err(err)?;
        self.bodies.push(h);
        Ok(())
    }

    fn destroy_body(&mut self, rng: &mut Rng) -> Outcome {
        let b = self.body(rng).ok_or("no body")?;
        // The handle stays in the list: later calls with it must be refused as stale.
        self.physics.dynamics_mut().destroy_body(b).map_err(err)
    }

    fn set_body(&mut self, rng: &mut Rng) -> Outcome {
        let b = self.body(rng).ok_or("no body")?;
        let choice = rng.below(9);
        let body = self.physics.dynamics_mut().body_mut(b).map_err(err)?;
        match choice {
            0 => body.set_mass(rng.real(0.1, 50.0)),
            1 => body.set_inertia(Mat3::from_diagonal(rng.vec3(0.01, 5.0))),
            2 => body.set_position(rng.vec3(-5.0, 5.0)),
            3 => body.set_orientation(rng.rotation()),
            4 => body.set_linear_velocity(rng.vec3(-20.0, 20.0)),
            5 => body.set_angular_velocity(rng.vec3(-20.0, 20.0)),
            6 => body.add_force(rng.vec3(-100.0, 100.0)),
            7 => {
                body.set_enabled(rng.chance(0.7));
                Ok(())
            }
            _ => body.set_fast_spin_axis(rng.chance(0.5).then(|| rng.direction())),
        }
        .map_err(err)
    }

    fn create_joint(&mut self, rng: &mut Rng) -> Outcome {
        let a = self.body(rng).ok_or("no body")?;
        let b = self.other(rng);
        let anchor = rng.vec3(-5.0, 5.0);
        let w = self.physics.dynamics_mut();
        let h = match rng.below(9) {
            0 => w
                .create_joint(a, b, kea::JointSpec::ball(anchor))
                .map(JointHandle::raw),
            1 => w
                .create_joint(a, b, kea::JointSpec::hinge(anchor, rng.direction()))
                .map(JointHandle::raw),
            2 => w
                .create_joint(a, b, kea::JointSpec::prismatic(anchor, rng.direction()))
                .map(JointHandle::raw),
            3 => w
                .create_joint(a, b, kea::JointSpec::fixed(anchor))
                .map(JointHandle::raw),
            4 => {
                let axis1 = rng.direction();
                let axis2 = axis1.any_orthonormal_vector();
                let axis2 = if rng.chance(0.9) {
                    axis2
                } else {
                    rng.direction()
                };
                w.create_joint(a, b, kea::JointSpec::universal(anchor, axis1, axis2))
                    .map(JointHandle::raw)
            }
            5 => w
                .create_joint(a, b, kea::JointSpec::linear1(anchor, rng.direction()))
                .map(JointHandle::raw),
            6 => w
                .create_joint(a, b, kea::JointSpec::linear2(anchor, rng.direction()))
                .map(JointHandle::raw),
            7 => w
                .create_joint(a, b, kea::JointSpec::fixed_path(anchor, rng.chance(0.5)))
                .map(JointHandle::raw),
            _ => {
                let wheel = b.ok_or("no wheel")?;
                let steer = rng.direction();
                let axle = steer.any_orthonormal_vector();
                w.create_joint(
                    a,
                    Some(wheel),
                    kea::JointSpec::car_wheel(
                        steer,
                        axle,
                        rng.real(10.0, 1e4),
                        rng.real(0.0, 100.0),
                    ),
                )
                .map(JointHandle::raw)
            }
        }
        .map_err(err)?;
        self.joints.push(h);
        Ok(())
    }

    fn set_joint(&mut self, rng: &mut Rng) -> Outcome {
        let j = self.joint(rng).ok_or("no joint")?;
        let w = self.physics.dynamics_mut();
        let lower = SingleLimit::hard(rng.real(-2.0, 0.0), rng.real(0.0, 1.0));
        let upper = if rng.chance(0.5) {
            SingleLimit::hard(rng.real(0.0, 2.0), rng.real(0.0, 1.0))
        } else {
            SingleLimit::soft(rng.real(0.0, 2.0), rng.real(1.0, 1e4), rng.real(0.0, 10.0))
        };
        match rng.below(12) {
            10 => return self.add_tendon(rng),
            11 => {
                let t = (!self.tendons.is_empty())
                    .then(|| self.tendons[rng.below(self.tendons.len())])
                    .ok_or("no tendon")?;
                return w.remove_tendon(t).map_err(err);
            }
            0 => JointHandle::<Hinge>::from_raw(j)
                .limit_mut(w)
                .and_then(|l| l.set_limits(lower, upper)),
            1 => JointHandle::<Hinge>::from_raw(j)
                .limit_mut(w)
                .and_then(|l| l.set_motor(rng.real(-10.0, 10.0), rng.real(0.0, 1e3))),
            2 => JointHandle::<Prismatic>::from_raw(j)
                .limit_mut(w)
                .and_then(|l| l.set_limits(lower, upper)),
            3 => w.set_breakable(j, Some(rng.real(0.0, 1e3)), None),
            4 => w.set_constraint_enabled(j, rng.chance(0.6)),
            5 => JointHandle::<FixedPath>::from_raw(j).set_path(
                w,
                rng.vec3(-5.0, 5.0),
                rng.vec3(-2.0, 2.0),
            ),
            6 => JointHandle::<BallJoint>::from_raw(j).set_limit_axes(
                w,
                rng.direction(),
                rng.direction(),
            ),
            7 => w.set_constraint_gamma(j, Some(rng.real(0.0, 1.0))),
            8 => w.reset_constraint(j),
            _ => w.destroy_constraint(j),
        }
        .map_err(err)
    }

    /// A fixed tendon over one to three of the joints (any kind, any coordinate: most are
    /// refused), with a spring, a damper and a range drawn wide.
    fn add_tendon(&mut self, rng: &mut Rng) -> Outcome {
        let mut terms = Vec::new();
        for _ in 0..1 + rng.below(3) {
            let joint = self.joint(rng).ok_or("no joint")?;
            terms.push(kea::TendonTerm {
                joint,
                coordinate: rng.below(4),
                coefficient: rng.real(-3.0, 3.0),
            });
        }
        let lo = rng.real(-2.0, 0.5);
        let tendon = kea::FixedTendon {
            terms,
            stiffness: rng.real(0.0, 1e3),
            damping: rng.real(0.0, 50.0),
            spring_length: [lo, lo + rng.real(0.0, 1.0)],
            range: rng.chance(0.5).then(|| [lo, rng.real(-0.5, 2.0)]),
            soft: kea::SoftLimit {
                solref: [rng.real(0.001, 0.1), rng.real(0.1, 2.0)],
                ..kea::SoftLimit::default()
            },
        };
        let h = self
            .physics
            .dynamics_mut()
            .add_tendon(tendon)
            .map_err(err)?;
        self.tendons.push(h);
        Ok(())
    }

    fn create_contact(&mut self, rng: &mut Rng) -> Outcome {
        let a = self.body(rng).ok_or("no body")?;
        let b = self.other(rng);
        let n = 1 + rng.below(4);
        let points: Vec<ContactPoint> = (0..n)
            .map(|i| ContactPoint {
                position: rng.vec3(-5.0, 5.0),
                penetration: rng.real(-0.05, 0.05),
                id: i as u32,
                to_second: Vec3::ZERO,
            })
            .collect();
        let contact = Contact::with_points(rng.direction(), &points).map_err(err)?;
        let h = self
            .physics
            .dynamics_mut()
            .create_contact(a, b, contact)
            .map_err(err)?;
        self.joints.push(h);
        Ok(())
    }

    /// Moves a hand-made contact (or tries a joint's handle) to a new normal and points, now
    /// and then with a normal off unit length or a point out of range: a refusal must leave
    /// the world as it was.
    fn update_contact(&mut self, rng: &mut Rng) -> Outcome {
        let h = self.joint(rng).ok_or("no constraint")?;
        let mut normal = rng.direction();
        if rng.chance(0.3) {
            normal *= rng.real(0.5, 1.5);
        }
        let n = 1 + rng.below(4);
        let points: Vec<ContactPoint> = (0..n)
            .map(|i| ContactPoint {
                position: if rng.chance(0.1) {
                    Vec3::splat(rng.odd())
                } else {
                    rng.vec3(-5.0, 5.0)
                },
                penetration: rng.real(-0.05, 0.05),
                id: rng.below(6) as u32 + i as u32,
                to_second: Vec3::ZERO,
            })
            .collect();
        self.physics
            .dynamics_mut()
            .contact_mut(h)
            .and_then(|c| c.update(normal, &points))
            .map_err(err)
    }

    fn shape(rng: &mut Rng) -> Result<Shape, String> {
        let s = match rng.below(10) {
            0 => Shape::sphere(rng.size()),
            1 => Shape::cuboid(Vec3::new(rng.size(), rng.size(), rng.size())),
            2 => Shape::capsule(rng.size(), rng.size()),
            3 => Shape::cylinder(rng.size(), rng.size()),
            4 => Shape::cone(rng.size(), rng.size()),
            5 => {
                let points: Vec<Vec3> =
                    (0..4 + rng.below(8)).map(|_| rng.vec3(-1.0, 1.0)).collect();
                Shape::convex_hull(&points)
            }
            6 => {
                let v: Vec<Vec3> = (0..4).map(|_| rng.vec3(-3.0, 3.0)).collect();
                Shape::trimesh(v, vec![[0, 1, 2], [0, 2, 3]])
            }
            7 => {
                let (rows, cols) = (2 + rng.below(8), 2 + rng.below(8));
                let heights: Vec<Vec<Real>> = (0..rows)
                    .map(|_| (0..cols).map(|_| rng.real(-0.5, 0.5)).collect())
                    .collect();
                let size = Vec3::new(rng.real(1.0, 20.0), rng.real(0.1, 2.0), rng.real(1.0, 20.0));
                Shape::heightfield(&heights, size)
            }
            8 => {
                let part = Shape::cuboid(Vec3::splat(rng.size())).map_err(err)?;
                let other = Shape::sphere(rng.size()).map_err(err)?;
                Shape::compound(&[
                    (rng.vec3(-1.0, 1.0), rng.rotation(), part),
                    (rng.vec3(-1.0, 1.0), rng.rotation(), other),
                ])
            }
            _ => Shape::plane(rng.direction()),
        };
        s.map_err(err)
    }

    fn add_collider(&mut self, rng: &mut Rng) -> Outcome {
        let shape = Self::shape(rng)?;
        let body = self.other(rng);
        let mut def = ColliderDef::new(body, shape);
        def.offset = if rng.chance(0.7) {
            Vec3::ZERO
        } else {
            rng.vec3(-1.0, 1.0)
        };
        def.rotation = if rng.chance(0.7) {
            kea::Quat::IDENTITY
        } else {
            rng.rotation()
        };
        let (w, c) = self.physics.layers_mut();
        let h = c.add_collider(w, def).map_err(err)?;
        self.colliders.push(h);
        Ok(())
    }

    fn remove_collider(&mut self, rng: &mut Rng) -> Outcome {
        if self.colliders.is_empty() {
            return Err("no collider".into());
        }
        let h = self.colliders[rng.below(self.colliders.len())];
        let (w, c) = self.physics.layers_mut();
        c.remove_collider(w, h).map_err(err)
    }

    fn query(&mut self, rng: &mut Rng) -> Outcome {
        let (w, c) = (self.physics.dynamics(), self.physics.collision());
        let filter = QueryFilter::default();
        let ray = |rng: &mut Rng| {
            let origin = rng.vec3(-10.0, 10.0);
            let direction = rng.direction();
            kea_collision::RayCast::new(origin, direction, rng.real(0.0, 100.0))
        };
        match rng.below(5) {
            0 => c.cast_ray(w, &ray(rng), filter).map(drop),
            1 => c.cast_ray_any(w, &ray(rng), filter).map(drop),
            2 => {
                let cast = ShapeCast {
                    shape: Self::shape(rng)?,
                    position: rng.vec3(-10.0, 10.0),
                    rotation: rng.rotation(),
                    velocity: rng.vec3(-10.0, 10.0),
                    max_time: rng.real(0.0, 10.0),
                };
                c.cast_shape(w, &cast, filter).map(drop)
            }
            3 => {
                let shape = Self::shape(rng)?;
                c.overlaps(w, &shape, rng.vec3(-10.0, 10.0), rng.rotation(), filter)
                    .map(drop)
            }
            _ => c
                .project_point(w, rng.vec3(-10.0, 10.0), rng.real(0.0, 100.0), filter)
                .map(drop),
        }
        .map_err(err)
    }

    fn step(&mut self, rng: &mut Rng) -> Outcome {
        let dt = match rng.below(10) {
            0..=6 => 1.0 / 60.0,
            7 => rng.range(1e-4, 0.2),
            8 => rng.range(0.2, 10.0),
            _ => rng.odd(),
        };
        match rng.below(12) {
            0 => self.step_traded(dt),
            1 => {
                // A world that holds only its state (a batch's) steps on its own too.
                self.physics.trim_to_state();
                self.physics.step(dt).map(drop).map_err(err)
            }
            _ => self.physics.step(dt).map(drop).map_err(err),
        }
    }

    /// A step taken by the worker, which trades states with this world, steps, and trades
    /// back (what `kea.Batch` does); a copy from before it is kept for
    /// [`Sandbox::verify_traded_step`].
    fn step_traded(&mut self, dt: Real) -> Outcome {
        let before = self.physics.clone();
        self.worker.swap_state(&mut self.physics);
        let traded = self.worker.step(dt).map(drop).map_err(err);
        self.worker.swap_state(&mut self.physics);
        self.traded = Some((before, dt, traded.clone()));
        traded
    }

    /// After a traded step, takes the same step in place on the copy from before it: both
    /// must accept or refuse alike and leave the same bits (their snapshots). `None` if they
    /// agree (or no traded step is pending), else what differed.
    pub fn verify_traded_step(&mut self) -> Option<String> {
        let (mut alone, dt, traded) = self.traded.take()?;
        let direct = alone.step(dt).map(drop).map_err(err);
        let bits = |w: &PhysicsWorld| w.snapshot().ok().and_then(|s| s.to_binary().ok());
        (direct != traded || bits(&alone) != bits(&self.physics)).then(|| {
            format!(
                "a step traded into a worker differs from the same step in place (dt {dt}): \
                 {direct:?} in place, {traded:?} traded"
            )
        })
    }

    fn settings(&mut self, rng: &mut Rng) -> Outcome {
        let w = self.physics.dynamics_mut();
        match rng.below(12) {
            0 => w.update_settings(|s| s.gravity = rng.vec3(-20.0, 20.0)),
            1 => w.update_settings(|s| s.epsilon = rng.real(0.0, 0.1)),
            2 => w.update_settings(|s| s.gamma = rng.real(0.0, 1.0)),
            3 => {
                let mode = [
                    SolverMode::Hybrid,
                    SolverMode::Exact,
                    SolverMode::Iterative,
                    SolverMode::Split,
                ][rng.below(4)];
                w.update_settings(|s| {
                    s.routing = Routing {
                        mode,
                        ..Routing::default()
                    }
                })
            }
            4 => w.update_settings(|s| s.projection_iterations = rng.below(20) as u32),
            5 => w.update_settings(|s| {
                s.speed_limits = SpeedLimits {
                    linear: rng.real(1.0, 1e4),
                    angular: rng.real(1.0, 1e4),
                }
            }),
            6 => {
                self.physics.collision_mut().margin = rng.real(0.0, 0.1);
                Ok(())
            }
            7 => {
                w.clear_quarantine();
                Ok(())
            }
            // The reduced path's contacts in joint space and floating trees, on or off.
            9 => w.update_settings(|s| {
                s.reduced_contacts = (rng.below(2) == 0).then(kea::SoftLimit::default);
                s.reduced_free_trees = rng.below(2) == 0;
                s.reduced_lone_bodies = rng.below(2) == 0;
            }),
            10 => {
                let integrator = [
                    kea::Integrator::Euler,
                    kea::Integrator::Implicit,
                    kea::Integrator::RungeKutta4,
                ][rng.below(3)];
                w.update_settings(|s| s.integrator = integrator)
            }
            // Sleeping on (thresholds loose enough that bodies fall asleep within a run, and
            // wake when touched, pushed or taken apart) or off.
            11 => w.update_settings(|s| {
                s.dem = if rng.chance(0.7) {
                    kea::DemSettings {
                        mode: kea::DemMode::PartitionAutoDisable,
                        velocity_threshold: rng.real(0.0, 2.0),
                        angular_velocity_threshold: rng.real(0.0, 2.0),
                        acceleration_threshold: rng.real(0.0, 20.0),
                        angular_acceleration_threshold: rng.real(0.0, 20.0),
                        alive_window: rng.real(0.0, 0.5),
                        ..kea::DemSettings::default()
                    }
                } else {
                    kea::DemSettings::default()
                }
            }),
            _ => {
                self.physics.collision_mut().touch_distance = rng.real(0.0, 0.01);
                Ok(())
            }
        }
        .map_err(err)
    }
}
