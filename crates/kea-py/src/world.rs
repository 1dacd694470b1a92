//! `kea.World`: one world, built in code or from a scene file.

use crate::convert::{bad, matrix, no_such, py, quat, real, tuple3, vec3};
use crate::state::{self, JointEntry, JointTag, STATE_WIDTH};
use kea3d::collision::ColliderHandle;
use kea3d::robot::Robot;
use kea3d::{Body, BodyHandle, BodyType, Collider, Joint, PhysicsWorld};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// A world: bodies, colliders and joints, stepped together.
///
/// Bodies, colliders and joints are numbered from 0 in the order they were added (a scene's
/// in scene order). `state()` gives one row of 13 numbers per body: position (3),
/// quaternion x y z w (4), linear velocity (3), angular velocity (3).
#[pyclass(name = "World", module = "kea")]
#[derive(Clone)]
pub struct PyWorld {
    pub(crate) inner: PhysicsWorld,
    pub(crate) bodies: Vec<BodyHandle>,
    pub(crate) colliders: Vec<ColliderHandle>,
    pub(crate) joints: Vec<JointEntry>,
    pub(crate) body_names: Vec<String>,
    pub(crate) joint_names: Vec<String>,
    /// The robot loaded from a URDF or MJCF file, if the world was made from one.
    pub(crate) robot: Option<Robot>,
}

impl PyWorld {
    pub(crate) fn body(&self, index: usize) -> PyResult<BodyHandle> {
        self.bodies
            .get(index)
            .copied()
            .ok_or_else(|| no_such("body", index, self.bodies.len()))
    }

    pub(crate) fn joint(&self, index: usize) -> PyResult<JointEntry> {
        self.joints
            .get(index)
            .copied()
            .ok_or_else(|| no_such("joint", index, self.joints.len()))
    }

    pub(crate) fn from_physics(inner: PhysicsWorld) -> Self {
        let named = inner.named_bodies().to_vec();
        let joints: Vec<(String, JointEntry)> = inner
            .named_joints()
            .iter()
            .map(|(n, raw)| (n.clone(), entry(&inner, *raw)))
            .collect();
        Self {
            bodies: named.iter().map(|&(_, h)| h).collect(),
            body_names: named.into_iter().map(|(n, _)| n).collect(),
            colliders: Vec::new(),
            joints: joints.iter().map(|&(_, j)| j).collect(),
            joint_names: joints.into_iter().map(|(n, _)| n).collect(),
            robot: None,
            inner,
        }
    }
}

impl PyWorld {
    /// A scene's world, its robots' files found from `folder`.
    fn scene_from(text: &str, folder: &std::path::Path) -> PyResult<Self> {
        let value = |e: String| pyo3::exceptions::PyValueError::new_err(e);
        let scene = kea3d::scene::Scene::from_json(text)
            .map_err(|e| value(e.to_string()))?
            .with_paths_from(folder);
        let built = kea3d::scene::build(&scene).map_err(|e| value(e.to_string()))?;
        let mut world = PhysicsWorld::from_scene(built);
        world
            .load_scene_robots(&scene.robots)
            .map_err(|e| value(e.to_string()))?;
        Ok(Self::from_physics(world))
    }
}

/// A joint's entry, tagged with its kind.
pub(crate) fn entry(w: &PhysicsWorld, raw: kea3d::dynamics::ConstraintHandle) -> JointEntry {
    let tag = match w.dynamics().constraint_kind(raw) {
        Ok("hinge") => JointTag::Hinge,
        Ok("prismatic joint") => JointTag::Prismatic,
        _ => JointTag::Other,
    };
    JointEntry { raw, tag }
}

/// A body type by its Python name.
fn body_type(kind: &str) -> PyResult<BodyType> {
    Ok(match kind {
        "dynamic" => BodyType::Dynamic,
        "static" | "fixed" => BodyType::Static,
        "kinematic" | "kinematic_velocity" => BodyType::KinematicVelocity,
        "kinematic_position" => BodyType::KinematicPosition,
        other => {
            return Err(bad(
                "kind",
                format!("{other:?}"),
                "'dynamic', 'static', 'kinematic' or 'kinematic_position'",
            ))
        }
    })
}

/// A collider's shape from its Python description.
#[allow(clippy::too_many_arguments)]
fn shape(
    shape: &str,
    half_extents: Option<[f64; 3]>,
    radius: Option<f64>,
    half_height: Option<f64>,
    normal: Option<[f64; 3]>,
    a: Option<[f64; 3]>,
    b: Option<[f64; 3]>,
) -> PyResult<Collider> {
    let need = |name: &str, v: Option<f64>| {
        v.map(real)
            .ok_or_else(|| bad(name, "None", &format!("a number for a {shape}")))
    };
    Ok(match shape {
        "cuboid" | "box" => {
            Collider::cuboid(vec3(half_extents.ok_or_else(|| {
                bad("half_extents", "None", "three numbers for a cuboid")
            })?))
        }
        "ball" | "sphere" => Collider::ball(need("radius", radius)?),
        "capsule" => match (a, b) {
            (Some(a), Some(b)) => Collider::capsule(vec3(a), vec3(b), need("radius", radius)?),
            _ => Collider::capsule_y(need("half_height", half_height)?, need("radius", radius)?),
        },
        "cylinder" => {
            Collider::cylinder(need("half_height", half_height)?, need("radius", radius)?)
        }
        "cone" => Collider::cone(need("half_height", half_height)?, need("radius", radius)?),
        "halfspace" | "plane" => Collider::halfspace(vec3(normal.unwrap_or([0.0, 1.0, 0.0]))),
        other => {
            return Err(bad(
                "shape",
                format!("{other:?}"),
                "'cuboid', 'ball', 'capsule', 'cylinder', 'cone' or 'halfspace'",
            ))
        }
    })
}

#[pymethods]
impl PyWorld {
    /// An empty world with this gravity (m/s²).
    #[new]
    #[pyo3(signature = (gravity = (0.0, -9.81, 0.0)))]
    fn new(gravity: (f64, f64, f64)) -> PyResult<Self> {
        let mut inner = PhysicsWorld::new();
        py(inner.set_gravity(vec3([gravity.0, gravity.1, gravity.2])))?;
        Ok(Self::from_physics(inner))
    }

    /// A world built from a scene file (JSON, `docs/scene-format.md`); its bodies and joints
    /// are numbered in scene order, and named in `body_names` and `joint_names`.
    #[staticmethod]
    fn from_scene(path: std::path::PathBuf) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path).map_err(|e| {
            pyo3::exceptions::PyOSError::new_err(format!("path = {}: {e}", path.display()))
        })?;
        let folder = path.parent().unwrap_or(std::path::Path::new("."));
        Self::scene_from(&text, folder)
    }

    /// A world built from a scene given as JSON text (robot files relative to the current
    /// folder).
    #[staticmethod]
    fn from_scene_json(text: &str) -> PyResult<Self> {
        Self::scene_from(text, std::path::Path::new("."))
    }

    /// An independent copy of this world at this instant.
    fn copy(&self) -> Self {
        self.clone()
    }

    /// Adds a body; returns its number. `kind` is 'dynamic', 'static', 'kinematic' (moved by
    /// the velocity you set) or 'kinematic_position' (moved to `set_kinematic_target`'s
    /// pose). Its mass comes from its colliders' density unless `mass` is given.
    #[pyo3(signature = (kind = "dynamic", position = [0.0; 3], rotation = [0.0, 0.0, 0.0, 1.0],
        linear_velocity = [0.0; 3], angular_velocity = [0.0; 3], mass = None,
        linear_damping = 0.0, angular_damping = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        kind: &str,
        position: [f64; 3],
        rotation: [f64; 4],
        linear_velocity: [f64; 3],
        angular_velocity: [f64; 3],
        mass: Option<f64>,
        linear_damping: f64,
        angular_damping: f64,
    ) -> PyResult<usize> {
        let mut b = Body::new(body_type(kind)?)
            .position(vec3(position))
            .rotation(quat(rotation))
            .linear_velocity(vec3(linear_velocity))
            .angular_velocity(vec3(angular_velocity))
            .linear_damping(real(linear_damping))
            .angular_damping(real(angular_damping));
        if let Some(m) = mass {
            b = b.mass(real(m));
        }
        let h = py(self.inner.insert_body(b))?;
        self.bodies.push(h);
        self.body_names.push(String::new());
        Ok(self.bodies.len() - 1)
    }

    /// Attaches a collider to `body` (None: static geometry in the world frame); returns its
    /// number. Shapes: 'cuboid' (half_extents), 'ball' (radius), 'capsule' (half_height and
    /// radius along y, or from `a` to `b`), 'cylinder' and 'cone' (half_height, radius, along
    /// y), 'halfspace' (normal, static only). Placed at `translation` and `rotation` in the
    /// body's frame; weighs `density` kg/m³ (or `mass` kg).
    #[pyo3(signature = (body, shape, *, half_extents = None, radius = None, half_height = None,
        normal = None, a = None, b = None, translation = [0.0; 3],
        rotation = [0.0, 0.0, 0.0, 1.0], density = 1000.0, mass = None, friction = None,
        restitution = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_collider(
        &mut self,
        body: Option<usize>,
        shape: &str,
        half_extents: Option<[f64; 3]>,
        radius: Option<f64>,
        half_height: Option<f64>,
        normal: Option<[f64; 3]>,
        a: Option<[f64; 3]>,
        b: Option<[f64; 3]>,
        translation: [f64; 3],
        rotation: [f64; 4],
        density: f64,
        mass: Option<f64>,
        friction: Option<f64>,
        restitution: Option<f64>,
    ) -> PyResult<usize> {
        let parent = body.map(|i| self.body(i)).transpose()?;
        let mut c = self::shape(shape, half_extents, radius, half_height, normal, a, b)?
            .translation(vec3(translation))
            .rotation(quat(rotation))
            .density(real(density));
        if let Some(m) = mass {
            c = c.mass(real(m));
        }
        if let Some(f) = friction {
            c = c.friction(real(f));
        }
        if let Some(e) = restitution {
            c = c.restitution(real(e));
        }
        let h = py(self.inner.insert_collider(c, parent))?;
        self.colliders.push(h);
        Ok(self.colliders.len() - 1)
    }

    /// Joins `body1` to `body2` (None: the world); returns the joint's number. Kinds: 'ball',
    /// 'hinge' and 'prismatic' (about or along `axis`), 'fixed', 'universal' (`axis`,
    /// `axis2`). Anchor and axes are world-frame. Hinges and prismatic joints take
    /// `limits=(lower, upper)` and `motor=(velocity, max_force)`.
    #[pyo3(signature = (kind, body1, body2 = None, *, anchor = [0.0; 3], axis = [0.0, 0.0, 1.0],
        axis2 = None, limits = None, motor = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_joint(
        &mut self,
        kind: &str,
        body1: usize,
        body2: Option<usize>,
        anchor: [f64; 3],
        axis: [f64; 3],
        axis2: Option<[f64; 3]>,
        limits: Option<(f64, f64)>,
        motor: Option<(f64, f64)>,
    ) -> PyResult<usize> {
        let b1 = self.body(body1)?;
        let b2 = body2.map(|i| self.body(i)).transpose()?;
        let (anchor, axis) = (vec3(anchor), vec3(axis));
        let limited = limits.is_some() || motor.is_some();
        if limited && !matches!(kind, "hinge" | "prismatic") {
            return Err(bad(
                "limits",
                format!("{limits:?}, motor = {motor:?}"),
                "a hinge or prismatic joint",
            ));
        }
        let w = &mut self.inner;
        let raw = match kind {
            "ball" => py(w.insert_joint(b1, b2, Joint::ball(anchor)))?.raw(),
            "fixed" => py(w.insert_joint(b1, b2, Joint::fixed(anchor)))?.raw(),
            "universal" => {
                let axis2 = vec3(axis2.ok_or_else(|| bad("axis2", "None", "a second axis"))?);
                py(w.insert_joint(b1, b2, Joint::universal(anchor, axis, axis2)))?.raw()
            }
            "hinge" => {
                let j = with_drive(Joint::hinge(anchor, axis), limits, motor);
                py(w.insert_joint(b1, b2, j))?.raw()
            }
            "prismatic" => {
                let j = with_drive(Joint::prismatic(anchor, axis), limits, motor);
                py(w.insert_joint(b1, b2, j))?.raw()
            }
            other => {
                return Err(bad(
                    "kind",
                    format!("{other:?}"),
                    "'ball', 'hinge', 'prismatic', 'fixed' or 'universal'",
                ))
            }
        };
        self.joints.push(entry(&self.inner, raw));
        self.joint_names.push(String::new());
        Ok(self.joints.len() - 1)
    }

    /// Steps the world `steps` times by `dt` seconds, with the GIL released. Without `dt`,
    /// the step its robot's model asks for (MJCF's `option timestep`, MuJoCo's 0.002 s where
    /// the file names none), else 1/60 s.
    #[pyo3(signature = (dt = None, steps = 1))]
    fn step(&mut self, py_: Python<'_>, dt: Option<f64>, steps: usize) -> PyResult<()> {
        let file_step = self.robot.as_ref().and_then(|r| r.timestep());
        let dt = dt.map_or_else(|| file_step.unwrap_or(1.0 / 60.0), real);
        let inner = &mut self.inner;
        py(py_.detach(|| step_many(inner, dt, steps)))
    }

    /// Every body's state row, as a new (bodies, 13) float64 array.
    fn state<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut out = vec![0.0; self.bodies.len() * STATE_WIDTH];
        py(state::read_bodies(&self.inner, &self.bodies, &mut out))?;
        let flat = PyArray1::from_vec(py_, out);
        flat.reshape([self.bodies.len(), STATE_WIDTH])
    }

    /// Sets every body from a (bodies, 13) array of any real dtype and layout; nothing
    /// changes if a row is bad.
    fn set_state(&mut self, state: &Bound<'_, PyAny>) -> PyResult<()> {
        let (rows, values) = matrix("state", state, STATE_WIDTH)?;
        if rows != self.bodies.len() {
            return Err(bad(
                "state",
                format!("{rows} rows"),
                &format!("shape ({}, {STATE_WIDTH})", self.bodies.len()),
            ));
        }
        py(state::write_bodies(&mut self.inner, &self.bodies, &values))
    }

    /// Position of a body's frame origin, m.
    fn position(&self, body: usize) -> PyResult<(f64, f64, f64)> {
        Ok(tuple3(py(self.inner.position(self.body(body)?))?))
    }

    /// A body's orientation quaternion (x, y, z, w).
    fn rotation(&self, body: usize) -> PyResult<(f64, f64, f64, f64)> {
        let q = py(self.inner.rotation(self.body(body)?))?;
        Ok((
            f64::from(q.x),
            f64::from(q.y),
            f64::from(q.z),
            f64::from(q.w),
        ))
    }

    /// Velocity of a body's centre of mass, m/s.
    fn linear_velocity(&self, body: usize) -> PyResult<(f64, f64, f64)> {
        Ok(tuple3(py(self.inner.linear_velocity(self.body(body)?))?))
    }

    /// A body's angular velocity, rad/s.
    fn angular_velocity(&self, body: usize) -> PyResult<(f64, f64, f64)> {
        Ok(tuple3(py(self.inner.angular_velocity(self.body(body)?))?))
    }

    /// A body's mass, kg.
    fn mass(&self, body: usize) -> PyResult<f64> {
        Ok(f64::from(py(self.inner.body(self.body(body)?))?.mass()))
    }

    /// Sets a body's linear velocity (a kinematic body's drive), m/s.
    fn set_linear_velocity(&mut self, body: usize, velocity: [f64; 3]) -> PyResult<()> {
        let h = self.body(body)?;
        py(self.inner.set_linear_velocity(h, vec3(velocity)))
    }

    /// Adds a force at a body's centre of mass for the next step, N.
    fn add_force(&mut self, body: usize, force: [f64; 3]) -> PyResult<()> {
        let h = self.body(body)?;
        py(self.inner.add_force(h, vec3(force)))
    }

    /// Adds a torque to a body for the next step, N·m.
    fn add_torque(&mut self, body: usize, torque: [f64; 3]) -> PyResult<()> {
        let h = self.body(body)?;
        py(self.inner.add_torque(h, vec3(torque)))
    }

    /// The pose a 'kinematic_position' body reaches at the end of the next step.
    fn set_kinematic_target(
        &mut self,
        body: usize,
        position: [f64; 3],
        rotation: [f64; 4],
    ) -> PyResult<()> {
        let h = self.body(body)?;
        py(self
            .inner
            .set_kinematic_target(h, vec3(position), quat(rotation)))
    }

    /// A hinge's angle (rad) or a prismatic joint's slide (m) after the last step.
    fn joint_position(&self, joint: usize) -> PyResult<f64> {
        let j = self.joint(joint)?;
        Ok(py(state::limit(&self.inner, j))?.map_or(0.0, |l| f64::from(l.position())))
    }

    /// The rate of `joint_position`, rad/s or m/s.
    fn joint_velocity(&self, joint: usize) -> PyResult<f64> {
        let j = self.joint(joint)?;
        Ok(py(state::limit(&self.inner, j))?.map_or(0.0, |l| f64::from(l.velocity())))
    }

    /// Sets the speed of a joint's motor (given when the joint was added), keeping its force.
    fn set_motor(&mut self, joint: usize, velocity: f64) -> PyResult<()> {
        let j = self.joint(joint)?;
        py(state::drive(&mut self.inner, j, velocity))
    }

    /// Gravity, m/s².
    #[getter]
    fn gravity(&self) -> (f64, f64, f64) {
        tuple3(self.inner.gravity())
    }

    /// Time simulated, s.
    #[getter]
    fn time(&self) -> f64 {
        f64::from(self.inner.time())
    }

    /// Number of bodies.
    #[getter]
    fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Number of joints.
    #[getter]
    fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// The scene's body names ('' for bodies added in code).
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.body_names.clone()
    }

    /// The scene's joint names ('' for joints added in code).
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.joint_names.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "kea.World(bodies={}, joints={}, time={})",
            self.bodies.len(),
            self.joints.len(),
            self.inner.time()
        )
    }
}

/// A hinge or slider spec with the limits and motor Python gave, if any.
fn with_drive<J: kea3d::dynamics::OneCoordinate>(
    mut j: Joint<J>,
    limits: Option<(f64, f64)>,
    motor: Option<(f64, f64)>,
) -> Joint<J> {
    if let Some((lo, hi)) = limits {
        j = j.limits(real(lo), real(hi));
    }
    if let Some((v, f)) = motor {
        j = j.motor(real(v), real(f));
    }
    j
}

/// `steps` steps of `dt` (none for 0) by [`PhysicsWorld::step_many`]: the same bits as
/// stepping one by one, the joints' reactions worked out for the last step only.
pub(crate) fn step_many(
    world: &mut PhysicsWorld,
    dt: kea3d::Real,
    steps: usize,
) -> kea3d::Result<()> {
    let mut left = steps;
    while left > 0 {
        let now = left.min(u32::MAX as usize);
        world.step_many(dt, now as u32)?;
        left -= now;
    }
    Ok(())
}
