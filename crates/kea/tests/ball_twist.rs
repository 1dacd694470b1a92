//! A ball joint's twist limit between bodies whose frames differ (a limb on a pelvis lying
//! across it): the twist is measured about the limb's own axis and the stop holds, on every
//! path, also inside the substeps where the joint is written again at the present poses and
//! the parent, disabled, is not among the solver's bodies.

mod common;
use common::{world_on, PATHS};
use kea::{inertia, BodyDef, BodyHandle, Quat, Real, SingleLimit, SolverMode, Vec3, World};

/// The paths a user can force, split islands (joints re-written every substep) included.
const EVERY_PATH: [SolverMode; 3] = [PATHS[0], PATHS[1], SolverMode::Split];

/// A 1 kg box (half extents 0.3, 0.2, 0.1) as `def` places it, enabled or not.
fn add_box(world: &mut World, def: BodyDef) -> BodyHandle {
    let inertia = inertia::solid_box(1.0, Vec3::new(0.3, 0.2, 0.1)).unwrap();
    world.create_body(&BodyDef { inertia, ..def }).unwrap()
}

#[test]
fn twist_limit_holds_when_the_bodies_frames_differ() {
    // Split: the stop read the parent as the world's frame (turned 90° from it) inside the
    // substeps, and settled at 0.5265 rad.
    for mode in EVERY_PATH {
        let mut world = world_on(mode, 4, 8);
        // The parent is turned 90° about z and held still (disabled).
        let parent = add_box(
            &mut world,
            BodyDef {
                orientation: Quat::from_rotation_z(kea::PI_REAL / 2.0),
                enabled: false,
                ..Default::default()
            },
        );
        let limb = add_box(
            &mut world,
            BodyDef {
                position: Vec3::new(0.0, -1.0, 0.0),
                ..Default::default()
            },
        );
        let j = world
            .create_joint(limb, Some(parent), kea::JointSpec::ball(Vec3::ZERO))
            .unwrap();
        j.set_limit_axes(&mut world, -Vec3::Y, Vec3::X).unwrap();
        j.limits_mut(&mut world)
            .unwrap()
            .twist
            .set_limits(SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(0.5, 0.0))
            .unwrap();
        for _ in 0..120 {
            world
                .body_mut(limb)
                .unwrap()
                .add_torque(Vec3::new(0.0, 2.0, 0.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        let twist = j.limits_mut(&mut world).unwrap().twist.position();
        let q = world.body(limb).unwrap().orientation();
        let (axis, angle) = q.to_axis_angle();
        let turned: Real = angle * axis.y.signum();
        eprintln!("{mode:?}: twist limit 0.5 rad, twist {twist}, the limb turned {turned} about y");
        assert!((twist.abs() - 0.5).abs() < 5e-3, "{mode:?}: twist {twist}");
        assert!(
            (turned.abs() - 0.5).abs() < 1e-2,
            "{mode:?}: turned {turned}"
        );
    }
}

/// A limb hung by a ball joint from a disabled parent away from the origin and turned: inside
/// the substeps the joint must be written at the parent's pose, not the world's frame (it was
/// not: the limb was thrown 2.5–4 m from its anchor on the iterative and split paths).
#[test]
fn a_joint_to_a_disabled_body_away_from_the_origin_holds_on_every_path() {
    for mode in EVERY_PATH {
        let mut world = world_on(mode, 4, 8);
        let anchor = Vec3::new(3.0, 2.0, 1.0);
        let parent = add_box(
            &mut world,
            BodyDef {
                position: anchor + Vec3::new(0.5, 0.0, 0.0),
                orientation: Quat::from_rotation_y(0.7),
                enabled: false,
                ..Default::default()
            },
        );
        let limb = add_box(
            &mut world,
            BodyDef {
                // Hanging below the anchor, pushed into a gentle swing.
                position: anchor + Vec3::new(0.0, -0.8, 0.0),
                linear_velocity: Vec3::new(0.5, 0.0, 0.3),
                ..Default::default()
            },
        );
        world
            .create_joint(limb, Some(parent), kea::JointSpec::ball(anchor))
            .unwrap();
        let mut worst: Real = 0.0;
        for _ in 0..120 {
            world.step(1.0 / 60.0).unwrap();
            worst = worst.max(world.joint_error());
        }
        // Swinging from the anchor, the limb's centre stays 0.8 m from it.
        let r = (world.body(limb).unwrap().position() - anchor).length();
        eprintln!("{mode:?}: worst joint error {worst}, limb at {r} m from the anchor");
        // Gauss-Seidel (one sweep a substep) lets a swinging pendulum's joint give a little.
        let tolerance = if mode == SolverMode::Iterative {
            5.0e-3
        } else {
            1.0e-3
        };
        assert!(worst < tolerance, "{mode:?}: joint opened by {worst}");
        assert!(
            (r - 0.8).abs() < tolerance,
            "{mode:?}: limb {r} m from the anchor"
        );
    }
}
