//! Robots from their own files. URDF ([`PhysicsWorld::load_urdf`]) and MJCF
//! ([`PhysicsWorld::load_mjcf`]) are read into one tree of links and joints, checked whole,
//! and built into the world in one go — links welded by fixed joints become one body, every
//! other joint a Kea joint, every collision geometry a collider. The [`Robot`] that comes back
//! names its links and joints and reads and writes its joint coordinates as one vector.
//!
//! ```
//! use kea3d::prelude::*;
//! use kea3d::robot::UrdfOptions;
//!
//! let urdf = r#"<robot name="pendulum">
//!   <link name="base"/>
//!   <link name="arm">
//!     <inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
//!       <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
//!   </link>
//!   <joint name="swing" type="continuous">
//!     <parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
//!   </joint>
//! </robot>"#;
//! let mut world = PhysicsWorld::new();
//! world.set_gravity([0.0, 0.0, -9.81])?;
//! let options = UrdfOptions { fixed_base: true, ..UrdfOptions::default() };
//! let robot = world.load_urdf_str(urdf, "pendulum.urdf", &options)?;
//! robot.set_joint_positions(&mut world, &[0.5])?;
//! assert!((robot.joint_positions(&world)?[0] - 0.5).abs() < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod actuator;
mod build;
mod colliders;
mod error;
mod inertia_check;
mod mesh;
mod mjcf;
mod mjcf_actuators;
mod mjcf_defaults;
mod mjcf_equality;
mod mjcf_geom;
mod mjcf_include;
mod mjcf_joints;
mod mjcf_option;
mod mjcf_pairs;
mod mjcf_soft;
mod mjcf_tendon;
mod model;
mod readouts;
mod spec;
mod tendons;
mod urdf;
mod xml;

pub use actuator::UNCAPPED_MOTOR_FORCE;
pub use error::ImportError;
pub use mjcf_actuators::{ActuatorKind, ActuatorSpec};
pub use model::{Robot, RobotJoint, RobotLink, RobotTendon};
pub use readouts::LinkState;
pub use spec::{JointType, Pose};

use crate::PhysicsWorld;
use kea::{Quat, Vec3};
use std::path::{Path, PathBuf};

/// How a URDF file is loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfOptions {
    /// Weld the root link to the world (an arm on a table); else it is free (PyBullet's
    /// default; its pose then leads the joint position vector). Default false.
    pub fixed_base: bool,
    /// Where the root link's frame is placed, m.
    pub base_position: Vec3,
    /// How the root link is turned.
    pub base_rotation: Quat,
    /// Folders to find meshes in (after the file's own folder): where `package://` names
    /// point.
    pub mesh_search_path: Vec<PathBuf>,
    /// Meshes as triangle meshes instead of their convex hulls (default: hulls).
    pub meshes_as_trimesh: bool,
    /// Let the robot's links collide with each other (those a joint joins never do); off by
    /// default, as in PyBullet, since many files' meshes overlap at rest.
    pub self_collision: bool,
}

impl Default for UrdfOptions {
    fn default() -> Self {
        Self {
            fixed_base: false,
            base_position: Vec3::ZERO,
            base_rotation: Quat::IDENTITY,
            mesh_search_path: Vec::new(),
            meshes_as_trimesh: false,
            self_collision: false,
        }
    }
}

/// How an MJCF file is loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfOptions {
    /// Folders to find meshes in, after the file's `compiler meshdir`.
    pub mesh_search_path: Vec<PathBuf>,
    /// Meshes as triangle meshes instead of their convex hulls (MuJoCo collides hulls).
    pub meshes_as_trimesh: bool,
    /// Let bodies collide with each other as `contype`/`conaffinity` allow (MuJoCo's rule;
    /// bodies a joint joins never do). Default true.
    pub self_collision: bool,
}

impl Default for MjcfOptions {
    fn default() -> Self {
        Self {
            mesh_search_path: Vec::new(),
            meshes_as_trimesh: false,
            self_collision: true,
        }
    }
}

impl PhysicsWorld {
    /// Loads a URDF robot: links become bodies (with the file's mass, centre of mass and full
    /// inertia), joints Kea joints (with limits, damping and friction), collision geometry
    /// colliders. Gravity is the world's: URDF files are z-up, so set it along −z. On error,
    /// which names the file, line and element, nothing is added.
    pub fn load_urdf(
        &mut self,
        path: impl AsRef<Path>,
        options: &UrdfOptions,
    ) -> Result<Robot, ImportError> {
        let path = path.as_ref();
        let spec = urdf::read(path, options)?;
        self.build_robot(&spec, path, Vec3::ZERO, options.self_collision)
    }

    /// [`PhysicsWorld::load_urdf`] from text; `name` stands for the file in errors and relative
    /// mesh paths.
    pub fn load_urdf_str(
        &mut self,
        text: &str,
        name: impl AsRef<Path>,
        options: &UrdfOptions,
    ) -> Result<Robot, ImportError> {
        let path = name.as_ref();
        let spec = urdf::parse(text, path, options)?;
        self.build_robot(&spec, path, Vec3::ZERO, options.self_collision)
    }

    /// Loads an MJCF model (MuJoCo's format): its `worldbody` tree, joints, geometry,
    /// defaults and actuators. Its `option` sets the world's gravity (−9.81 along z by
    /// default) and integrator (MuJoCo's default, Euler, when it names none), its geoms'
    /// `solref`/`solimp` the contact model of trees in reduced coordinates
    /// ([`kea::WorldSettings::reduced_contacts`]: a robot on a fixed or planar base stays
    /// reduced while it touches the ground), floating roots reduced too
    /// ([`kea::WorldSettings::reduced_free_trees`]; lone free bodies too,
    /// [`kea::WorldSettings::reduced_lone_bodies`], unless it asks for `implicitfast`), and its
    /// `timestep` is the robot's [`Robot::timestep`]; options Kea does not model are named in
    /// [`Robot::skipped`]. On error, which names the file, line and element, nothing is
    /// added.
    pub fn load_mjcf(
        &mut self,
        path: impl AsRef<Path>,
        options: &MjcfOptions,
    ) -> Result<Robot, ImportError> {
        let path = path.as_ref();
        let text = xml::read_text(path)?;
        self.load_mjcf_str(&text, path, options)
    }

    /// [`PhysicsWorld::load_mjcf`] from text; `name` stands for the file.
    pub fn load_mjcf_str(
        &mut self,
        text: &str,
        name: impl AsRef<Path>,
        options: &MjcfOptions,
    ) -> Result<Robot, ImportError> {
        let path = name.as_ref();
        let model = mjcf::parse(text, path, options)?;
        let mut staged = self.clone();
        let option = model.option;
        let contact = model.contact;
        staged
            .dynamics_mut()
            .update_settings(|s| {
                s.gravity = option.gravity;
                s.integrator = option.integrator;
                s.reduced_contacts = Some(contact);
                s.reduced_free_trees = true;
                s.reduced_lone_bodies = !option.implicitfast;
            })
            .map_err(|source| ImportError::World {
                file: path.to_path_buf(),
                line: 0,
                element: "option".into(),
                source: kea_collision::CollisionError::Kea(source),
            })?;
        let mut robot =
            staged.build_robot(&model.spec, path, Vec3::ZERO, options.self_collision)?;
        mjcf_equality::build(&mut staged, &robot, &model.equalities, path)?;
        robot.set_actuators(model.actuators);
        robot.timestep = option.timestep;
        *self = staged;
        Ok(robot)
    }

    /// Loads a scene file's robots (their paths resolved: see `kea_scene::Scene::with_paths_from`),
    /// naming their links' bodies and their joints `robot<i>.<name>` among the world's named
    /// bodies and joints. On error nothing is added.
    pub fn load_scene_robots(
        &mut self,
        robots: &[kea_scene::RobotEntry],
    ) -> Result<Vec<Robot>, ImportError> {
        let mut staged = self.clone();
        let mut loaded = Vec::with_capacity(robots.len());
        for (i, entry) in robots.iter().enumerate() {
            let (file, mjcf) = entry
                .file(i)
                .map_err(|e| ImportError::file(Path::new("scene"), e.to_string()))?;
            let robot = if mjcf {
                staged.load_mjcf(file, &MjcfOptions::default())?
            } else {
                let [x, y, z, w] = entry.rotation;
                let q = kea::math::from_f64(kea::math::DVec3::new(x, y, z));
                let position = kea::math::from_f64(kea::math::DVec3::from_array(entry.position));
                let w = kea::math::from_f64(kea::math::DVec3::splat(w)).x;
                let options = UrdfOptions {
                    fixed_base: entry.fixed_base,
                    base_position: position,
                    base_rotation: Quat::from_xyzw(q.x, q.y, q.z, w).normalize(),
                    ..UrdfOptions::default()
                };
                staged.load_urdf(file, &options)?
            };
            let mut bodies = Vec::new();
            for link in robot.links() {
                if !bodies.iter().any(|(_, b)| *b == link.body) {
                    bodies.push((format!("robot{i}.{}", link.name), link.body));
                }
            }
            let joints: Vec<_> = robot
                .joints()
                .iter()
                .filter_map(|j| j.raw.map(|raw| (format!("robot{i}.{}", j.name), raw)))
                .collect();
            staged.add_names(bodies, joints);
            loaded.push(robot);
        }
        *self = staged;
        Ok(loaded)
    }

    fn build_robot(
        &mut self,
        spec: &spec::RobotSpec,
        path: &Path,
        base: Vec3,
        self_collision: bool,
    ) -> Result<Robot, ImportError> {
        let options = build::BuildOptions {
            base: Pose::new(base, Quat::IDENTITY),
            self_collision,
        };
        build::build(self, spec, path, &options)
    }
}
