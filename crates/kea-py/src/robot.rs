//! `kea.World` from a robot's own file (URDF, MJCF), and its joint coordinates as vectors in
//! the file's joint order (MuJoCo's `qpos` / `qvel`; PyBullet's `resetJointState` for all
//! joints at once).

use crate::convert::{bad, py, vector};
use crate::state::{JointEntry, JointTag};
use crate::world::PyWorld;
use kea3d::robot::{ImportError, JointType, MjcfOptions, Robot, UrdfOptions};
use kea3d::{PhysicsWorld, Quat, Real, Vec3};
use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;

/// An import error as Python's: `OSError` for a file that cannot be read, `ValueError` for
/// what is in it; the message names the file, line and element.
fn import_err(e: ImportError) -> PyErr {
    match e {
        ImportError::File { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

impl PyWorld {
    /// A Python world over a physics world holding `robot`: bodies numbered by link (welded
    /// links share one), joints by the robot's moving joints, in the file's order.
    fn with_robot(inner: PhysicsWorld, robot: Robot) -> Self {
        let mut world = PyWorld::from_physics(inner);
        for link in robot.links() {
            if !world.bodies.contains(&link.body) {
                world.bodies.push(link.body);
                world.body_names.push(link.name.clone());
            }
        }
        for j in robot.joints() {
            if let Some(raw) = j.raw {
                let tag = match j.kind {
                    JointType::Revolute | JointType::Continuous => JointTag::Hinge,
                    JointType::Prismatic => JointTag::Prismatic,
                    _ => JointTag::Other,
                };
                world.joints.push(JointEntry { raw, tag });
                world.joint_names.push(j.name.clone());
            }
        }
        world.robot = Some(robot);
        world
    }

    pub(crate) fn robot(&self) -> PyResult<&Robot> {
        self.robot.as_ref().ok_or_else(no_robot)
    }

    /// Hands an array-like of reals (any dtype and layout) to one of the robot's setters,
    /// which checks its length and values and changes nothing when it refuses.
    fn write_vector(
        &mut self,
        arg: &str,
        x: &Bound<'_, PyAny>,
        set: fn(&Robot, &mut PhysicsWorld, &[Real]) -> kea3d::Result<()>,
    ) -> PyResult<()> {
        let x = reals(&vector(arg, x, None)?);
        let (robot, world) = self.robot_and_world()?;
        py(set(robot, world, &x))
    }

    /// The robot and the world it drives, borrowed apart (no copy of the robot per call).
    fn robot_and_world(&mut self) -> PyResult<(&Robot, &mut PhysicsWorld)> {
        let robot = self.robot.as_ref().ok_or_else(no_robot)?;
        Ok((robot, &mut self.inner))
    }
}

fn no_robot() -> PyErr {
    PyValueError::new_err(
        "this world holds no robot: make it with World.from_urdf or World.from_mjcf",
    )
}

/// A link's position and quaternion (x, y, z, w).
type LinkPose = ((f64, f64, f64), (f64, f64, f64, f64));

fn reals(v: &[f64]) -> Vec<Real> {
    v.iter().map(|&x| crate::convert::real(x)).collect()
}

/// A link's index by name, refused by name.
pub(crate) fn link_index(robot: &Robot, name: &str) -> PyResult<usize> {
    robot
        .links()
        .iter()
        .position(|l| l.name == name)
        .ok_or_else(|| {
            bad(
                "name",
                format!("{name:?}"),
                "the name of one of the robot's links",
            )
        })
}

/// Motor force caps per velocity coordinate: given, or each joint's effort limit (infinite
/// where its file gives none).
pub(crate) fn motor_forces(robot: &Robot, given: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<Real>> {
    let n = robot.velocity_count();
    if let Some(x) = given {
        let f = vector("max_forces", x, Some(n))?;
        if let Some(v) = f.iter().find(|v| **v < 0.0) {
            return Err(bad("max_forces", v, "forces >= 0"));
        }
        return Ok(reals(&f));
    }
    let mut out = vec![Real::INFINITY; n];
    for j in robot.joints() {
        for (k, e) in j.efforts().into_iter().enumerate() {
            if let (Some(e), Some(o)) = (e, out.get_mut(j.first_velocity + k)) {
                *o = e;
            }
        }
    }
    Ok(out)
}

fn search_path(paths: Option<Vec<PathBuf>>) -> Vec<PathBuf> {
    paths.unwrap_or_default()
}

#[pymethods]
impl PyWorld {
    /// A world holding the robot of a URDF file, gravity along −z (the file's convention).
    /// `fixed_base` welds its root link to the world (an arm on a table); else the root is
    /// free and its pose leads the joint vectors. Meshes are found beside the file and in
    /// `mesh_search_path` (where `package://` names point), as convex hulls unless
    /// `meshes_as_trimesh`. Errors name the file, line and element.
    #[staticmethod]
    #[pyo3(signature = (path, fixed_base = false, *, base_position = [0.0; 3],
        base_rotation = [0.0, 0.0, 0.0, 1.0], mesh_search_path = None, self_collision = false,
        meshes_as_trimesh = false, gravity = [0.0, 0.0, -9.81]))]
    #[allow(clippy::too_many_arguments)]
    fn from_urdf(
        path: PathBuf,
        fixed_base: bool,
        base_position: [f64; 3],
        base_rotation: [f64; 4],
        mesh_search_path: Option<Vec<PathBuf>>,
        self_collision: bool,
        meshes_as_trimesh: bool,
        gravity: [f64; 3],
    ) -> PyResult<Self> {
        let mut inner = PhysicsWorld::new();
        py(inner.set_gravity(crate::convert::vec3(gravity)))?;
        let q = crate::convert::quat(base_rotation);
        if !(q.length() > 0.5 && q.is_finite()) {
            return Err(bad(
                "base_rotation",
                format!("{base_rotation:?}"),
                "a unit quaternion (x, y, z, w)",
            ));
        }
        let options = UrdfOptions {
            fixed_base,
            base_position: crate::convert::vec3(base_position),
            base_rotation: q.normalize(),
            mesh_search_path: search_path(mesh_search_path),
            meshes_as_trimesh,
            self_collision,
        };
        let robot = inner.load_urdf(&path, &options).map_err(import_err)?;
        Ok(Self::with_robot(inner, robot))
    }

    /// A world holding the model of an MJCF file (MuJoCo's format): gravity and the step from
    /// its `option` (see `timestep`), its actuators fed by `set_controls`. Errors name the
    /// file, line and element.
    #[staticmethod]
    #[pyo3(signature = (path, *, mesh_search_path = None, self_collision = true,
        meshes_as_trimesh = false))]
    fn from_mjcf(
        path: PathBuf,
        mesh_search_path: Option<Vec<PathBuf>>,
        self_collision: bool,
        meshes_as_trimesh: bool,
    ) -> PyResult<Self> {
        let mut inner = PhysicsWorld::new();
        let options = MjcfOptions {
            mesh_search_path: search_path(mesh_search_path),
            meshes_as_trimesh,
            self_collision,
        };
        let robot = inner.load_mjcf(&path, &options).map_err(import_err)?;
        Ok(Self::with_robot(inner, robot))
    }

    /// The joint positions, a float64 array in the file's joint order: an angle (rad) or
    /// travel (m) per coordinate, a quaternion (w, x, y, z) per ball joint, position and
    /// quaternion per free joint (MuJoCo's `qpos`).
    fn joint_positions<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = py(self.robot()?.joint_positions(&self.inner))?;
        Ok(PyArray1::from_iter(py_, q.into_iter().map(f64::from)))
    }

    /// The joint velocities (MuJoCo's `qvel`: a free joint's linear velocity in the world
    /// frame and angular velocity in its body's frame).
    fn joint_velocities<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = py(self.robot()?.joint_velocities(&self.inner))?;
        Ok(PyArray1::from_iter(py_, v.into_iter().map(f64::from)))
    }

    /// Re-poses the robot to joint positions `q` (any real array-like) by forward kinematics,
    /// keeping velocities. Nothing changes on a bad length or value.
    fn set_joint_positions(&mut self, q: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write_vector("q", q, Robot::set_joint_positions)
    }

    /// Sets the bodies' velocities to joint velocities `v` (any real array-like).
    fn set_joint_velocities(&mut self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write_vector("v", v, Robot::set_joint_velocities)
    }

    /// Applies a force (N) or torque (N·m) along each joint coordinate (the layout of
    /// `joint_velocities`; free and ball joints' entries must be 0) until changed.
    fn set_joint_forces(&mut self, forces: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write_vector("forces", forces, Robot::set_joint_forces)
    }

    /// Feeds the file's actuators one control each (MuJoCo's `ctrl`), clamped to their
    /// control ranges, until changed.
    fn set_controls(&mut self, controls: &Bound<'_, PyAny>) -> PyResult<()> {
        self.write_vector("controls", controls, Robot::set_controls)
    }

    /// Drives each joint coordinate at `velocities` (the layout of `joint_velocities`) with a
    /// motor of at most `max_forces` (one per coordinate; default each joint's effort limit
    /// from its file), until changed. Free and ball joints' entries must be 0.
    #[pyo3(signature = (velocities, max_forces = None))]
    fn set_joint_motors(
        &mut self,
        velocities: &Bound<'_, PyAny>,
        max_forces: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let n = self.robot()?.velocity_count();
        let v = vector("velocities", velocities, Some(n))?;
        let forces = motor_forces(self.robot()?, max_forces)?;
        let (robot, world) = self.robot_and_world()?;
        py(robot.set_joint_motors(world, &reals(&v), &forces))
    }

    /// Splits each step into this many substeps (1 to 64; default 1): finer integration
    /// at that many times the cost.
    fn set_substeps(&mut self, substeps: u32) -> PyResult<()> {
        py(self
            .inner
            .dynamics_mut()
            .update_settings(|s| s.world_substeps = substeps))
    }

    /// How trees in reduced coordinates integrate: "rk4" (the default; an MJCF file's
    /// `option integrator` sets it on load), "euler" or "implicit".
    #[getter]
    fn integrator(&self) -> &'static str {
        match self.inner.dynamics().settings().integrator {
            kea3d::dynamics::Integrator::Euler => "euler",
            kea3d::dynamics::Integrator::Implicit => "implicit",
            kea3d::dynamics::Integrator::RungeKutta4 => "rk4",
        }
    }

    #[setter]
    fn set_integrator(&mut self, name: &str) -> PyResult<()> {
        use kea3d::dynamics::Integrator;
        let integrator = match name {
            "euler" => Integrator::Euler,
            "implicit" => Integrator::Implicit,
            "rk4" => Integrator::RungeKutta4,
            _ => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "argument `integrator`: {:?} is not one of \"euler\", \"implicit\", \"rk4\"",
                    name.chars().take(40).collect::<String>()
                )))
            }
        };
        py(self
            .inner
            .dynamics_mut()
            .update_settings(|s| s.integrator = integrator))
    }

    /// Length of the joint position vector (MuJoCo's `nq`).
    #[getter]
    fn position_count(&self) -> PyResult<usize> {
        Ok(self.robot()?.position_count())
    }

    /// Length of the joint velocity vector (MuJoCo's `nv`).
    #[getter]
    fn velocity_count(&self) -> PyResult<usize> {
        Ok(self.robot()?.velocity_count())
    }

    /// The step the model asks for, s: MJCF's `option timestep` (MuJoCo's default, 0.002 s,
    /// where the file names none), or None (URDF).
    #[getter]
    fn timestep(&self) -> PyResult<Option<f64>> {
        Ok(self.robot()?.timestep().map(f64::from))
    }

    /// The robot's link names, in the file's order (link 0 is the world).
    fn link_names(&self) -> PyResult<Vec<String>> {
        Ok(self
            .robot()?
            .links()
            .iter()
            .map(|l| l.name.clone())
            .collect())
    }

    /// The robot's actuators' names, in the file's order.
    fn actuator_names(&self) -> PyResult<Vec<String>> {
        Ok(self
            .robot()?
            .actuators()
            .iter()
            .map(|a| a.name.clone())
            .collect())
    }

    /// The robot's fixed tendons that act, by name in the file's order (force-free ones are
    /// only reported in `skipped()`).
    fn tendon_names(&self) -> PyResult<Vec<String>> {
        Ok(self
            .robot()?
            .tendons()
            .iter()
            .map(|t| t.name.clone())
            .collect())
    }

    /// Each acting tendon's length in the file's units (MuJoCo's `ten_length`) and its rate,
    /// after the last step, as a list of (length, rate).
    fn tendon_lengths(&self) -> PyResult<Vec<(f64, f64)>> {
        let lengths = py(self.robot()?.tendon_lengths(&self.inner))?;
        Ok(lengths
            .into_iter()
            .map(|(l, v)| (f64::from(l), f64::from(v)))
            .collect())
    }

    /// The control range of each actuator, as an (actuators, 2) list of (low, high); ±inf
    /// where unlimited.
    fn control_ranges(&self) -> PyResult<Vec<(f64, f64)>> {
        Ok(self
            .robot()?
            .actuators()
            .iter()
            .map(|a| {
                a.ctrl_range
                    .map_or((f64::NEG_INFINITY, f64::INFINITY), |(lo, hi)| {
                        (f64::from(lo), f64::from(hi))
                    })
            })
            .collect())
    }

    /// A link's frame in the world: position (3) and quaternion (x, y, z, w).
    fn link_pose(&self, name: &str) -> PyResult<LinkPose> {
        let robot = self.robot()?;
        let index = link_index(robot, name)?;
        let pose = py(robot.link_pose(&self.inner, index))?;
        let (p, q): (Vec3, Quat) = (pose.translation, pose.rotation);
        Ok((
            crate::convert::tuple3(p),
            (
                f64::from(q.x),
                f64::from(q.y),
                f64::from(q.z),
                f64::from(q.w),
            ),
        ))
    }

    /// What the importer left out, and why (file, line, element), one line each.
    fn skipped(&self) -> PyResult<Vec<String>> {
        Ok(self.robot()?.skipped().to_vec())
    }
}
