//! A scene in Rapier (rapier3d 0.36, its default parameters), stepped and measured.

use crate::scenes::{JointKind, Quality, Scene, Shape, Static};
use crate::Outcome;
use rapier3d::prelude::*;
use std::time::{Duration, Instant};

/// The scene built in Rapier.
pub struct RapierScene {
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    ccd: CCDSolver,
    pipeline: PhysicsPipeline,
    params: IntegrationParameters,
    handles: Vec<(RigidBodyHandle, Vector)>,
    joints: Vec<(Option<RigidBodyHandle>, Vector, RigidBodyHandle, Vector)>,
}

fn v(a: [f32; 3]) -> Vector {
    Vector::new(a[0], a[1], a[2])
}

impl RapierScene {
    pub fn build(scene: &Scene) -> Self {
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let mut impulse_joints = ImpulseJointSet::new();
        for s in &scene.statics {
            let (collider, position) = match *s {
                Static::Ground => (
                    ColliderBuilder::halfspace(rapier3d::na::Unit::new_unchecked(Vector::Y)),
                    Vector::ZERO,
                ),
                Static::Cuboid { half, position } => (
                    ColliderBuilder::cuboid(half[0], half[1], half[2]),
                    v(position),
                ),
            };
            let g = bodies.insert(RigidBodyBuilder::fixed().translation(position));
            colliders.insert_with_parent(collider, g, &mut bodies);
        }
        let mut handles = Vec::new();
        for b in &scene.bodies {
            let collider = match b.shape {
                Shape::Cuboid(h) => ColliderBuilder::cuboid(h[0], h[1], h[2]),
                Shape::Ball(r) => ColliderBuilder::ball(r),
                Shape::CapsuleX(hh, r) => ColliderBuilder::capsule_x(hh, r),
                Shape::CapsuleY(hh, r) => ColliderBuilder::capsule_y(hh, r),
            }
            .density(b.density);
            let h = bodies.insert(
                RigidBodyBuilder::dynamic()
                    .translation(v(b.position))
                    .can_sleep(scene.sleep),
            );
            colliders.insert_with_parent(collider, h, &mut bodies);
            handles.push((h, v(b.position)));
        }
        let mut joints = Vec::new();
        for j in &scene.joints {
            let anchor = v(j.anchor);
            let b = handles[j.b].0;
            let local_b = anchor - handles[j.b].1;
            let (a, local_a) = match j.a {
                Some(i) => (handles[i].0, anchor - handles[i].1),
                None => {
                    let fixed = bodies.insert(RigidBodyBuilder::fixed());
                    (fixed, anchor)
                }
            };
            let joint = rapier_joint(j.kind, local_a, local_b);
            impulse_joints.insert(a, b, joint, true);
            joints.push((j.a.map(|i| handles[i].0), local_a, b, local_b));
        }
        Self {
            bodies,
            colliders,
            impulse_joints,
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            islands: IslandManager::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            ccd: CCDSolver::new(),
            pipeline: PhysicsPipeline::new(),
            params: IntegrationParameters::default(),
            handles,
            joints,
        }
    }

    pub fn step(&mut self) {
        self.pipeline.step(
            Vector::new(0.0, -9.81, 0.0),
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
    }

    pub fn joint_gap(&self) -> f64 {
        let at = |h: Option<RigidBodyHandle>, p: Vector| match h {
            Some(h) => self.bodies[h].position().transform_point(p),
            None => p,
        };
        self.joints
            .iter()
            .map(|&(a, pa, b, pb)| (at(a, pa) - at(Some(b), pb)).length() as f64)
            .fold(0.0, f64::max)
    }

    pub fn displacement(&self) -> f64 {
        self.handles
            .iter()
            .map(|&(h, p0)| (self.bodies[h].translation() - p0).length() as f64)
            .fold(0.0, f64::max)
    }

    /// Every body's orientation, `[x, y, z, w]`, in the scene's order.
    pub fn orientations(&self) -> Vec<[f64; 4]> {
        self.handles
            .iter()
            .map(|&(h, _)| {
                let q = self.bodies[h].rotation();
                [q.x as f64, q.y as f64, q.z as f64, q.w as f64]
            })
            .collect()
    }

    pub fn energy(&self) -> f64 {
        self.handles
            .iter()
            .map(|&(h, _)| self.bodies[h].kinetic_energy() as f64)
            .sum()
    }
}

/// Builds `scene`, settles it, times its steps; returns ms/step and the quality figure.
pub fn run(scene: &Scene) -> Outcome {
    let mut s = RapierScene::build(scene);
    for _ in 0..scene.settle {
        s.step();
    }
    let mut gap: f64 = 0.0;
    let hinges = crate::scenes::has_hinges(scene);
    let start = s.orientations();
    let mut overrun: f64 = 0.0;
    let mut total = Duration::ZERO;
    for _ in 0..scene.steps {
        let t = Instant::now();
        s.step();
        total += t.elapsed();
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
    }
    let quality = match scene.quality {
        Quality::Displacement => s.displacement(),
        Quality::Energy => s.energy(),
        Quality::JointGap => gap,
    };
    Outcome {
        ms: total.as_secs_f64() * 1e3 / scene.steps as f64,
        hash: 0,
        quality,
        stages_ms: [0.0; 3],
        failed: None,
        overrun,
    }
}

/// The Rapier joint of a scene joint with its anchors in each body's frame; jointed bodies do
/// not collide, as in Kea.
fn rapier_joint(kind: JointKind, local_a: Vector, local_b: Vector) -> GenericJoint {
    match kind {
        JointKind::Ball => SphericalJointBuilder::new()
            .local_anchor1(local_a)
            .local_anchor2(local_b)
            .contacts_enabled(false)
            .into(),
        JointKind::LimitedBall { axis, cone, twist } => {
            // The joint's x axis along the limb: twist about it, swing about the others.
            let turn = Rotation::from_rotation_arc(Vector::X, v(axis));
            SphericalJointBuilder::new()
                .local_frame1(Pose::from_parts(local_a, turn))
                .local_frame2(Pose::from_parts(local_b, turn))
                .limits(JointAxis::AngX, [-twist, twist])
                .limits(JointAxis::AngY, [-cone, cone])
                .limits(JointAxis::AngZ, [-cone, cone])
                .contacts_enabled(false)
                .into()
        }
        JointKind::Hinge { axis, lower, upper } => RevoluteJointBuilder::new(v(axis))
            .local_anchor1(local_a)
            .local_anchor2(local_b)
            .limits([lower, upper])
            .contacts_enabled(false)
            .into(),
    }
}
