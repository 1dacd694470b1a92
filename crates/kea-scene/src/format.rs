//! The scene format, version 1: plain data that serde reads from and writes to JSON. Every field
//! that has a default may be left out; unknown fields are errors (a typo must not pass silently).

use crate::joint_format::{GroupSpec, JointSpec};
use crate::shape_format::is_false;
use kea::Real;
use serde::{Deserialize, Serialize};

/// The format version this crate reads and writes.
pub const VERSION: u32 = 1;

pub use crate::shape_format::{ShapeSpec, V3};

/// A whole scene.
///
/// ```
/// use kea_scene::{build, Scene};
///
/// let scene = Scene::from_json(r#"{
///   "version": 1,
///   "world": { "gravity": [0.0, -9.81, 0.0] },
///   "static": [ { "shape": { "plane": { "normal": [0.0, 1.0, 0.0] } } } ],
///   "bodies": [ { "name": "box", "density": 500.0, "position": [0.0, 1.0, 0.0],
///                 "shapes": [ { "shape": { "box": { "half_extents": [0.25, 0.25, 0.25] } } } ] } ]
/// }"#)?;
/// let built = build(&scene)?;
/// let b = built.body("box").expect("named in the file");
/// let y = built.world.body(b)?.position().y;
/// assert_eq!(y, 1.0); // built, not stepped: `kea3d::PhysicsWorld::from_scene` steps it
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Must be [`VERSION`].
    pub version: u32,
    /// World parameters.
    #[serde(default)]
    pub world: WorldSpec,
    /// Named materials; material 0 (`"default"`) always exists.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub materials: Vec<MaterialSpec>,
    /// Contact parameters of pairs of materials, overriding the combine rules.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub material_pairs: Vec<MaterialPairSpec>,
    /// Static geometry.
    #[serde(default, rename = "static", skip_serializing_if = "Vec::is_empty")]
    pub statics: Vec<ColliderSpec>,
    /// Bodies, each with its shapes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<BodySpec>,
    /// Joints between named bodies (or a body and the world).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointSpec>,
    /// Repeated structures, expanded when the scene is built.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub groups: Vec<GroupSpec>,
    /// Robots from their own files (URDF, MJCF), loaded by the layer that owns the world.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub robots: Vec<crate::robots::RobotEntry>,
}

/// World parameters (see `kea::WorldDef`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WorldSpec {
    /// Gravity, m/s².
    pub gravity: V3,
    /// Constraint softness ε.
    pub epsilon: Real,
    /// Error reduction γ.
    pub gamma: Real,
    /// `"hybrid"`, `"exact"`, `"iterative"` or `"split"`.
    pub solver: SolverSpec,
    /// How the reduced-coordinate path integrates its trees: `"rk4"` (the default),
    /// `"euler"` or `"implicit"` (`kea::Integrator`).
    #[serde(skip_serializing_if = "is_rk4")]
    pub integrator: IntegratorSpec,
    /// Put resting islands to sleep (the guide's auto-disable).
    pub sleep: bool,
    /// Most bodies (0: as many as the scene needs).
    pub max_bodies: usize,
    /// Most constraints, contacts included (0: 16 per body, at least 256).
    pub max_constraints: usize,
    /// When a body counts as resting, for `sleep` (default: kea's thresholds).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sleep_thresholds: Option<SleepSpec>,
    /// Position-projection passes after each exact step, 0 to 16 (default 0).
    #[serde(skip_serializing_if = "is_zero_u32")]
    pub projection_iterations: u32,
    /// Substeps of the whole step, 1 to 64 (default 1): each step runs this many steps of
    /// `dt / n`, collision included.
    #[serde(default = "one_u32", skip_serializing_if = "is_one_u32")]
    pub world_substeps: u32,
    /// Pivoting iteration cap per LCP (default: kea's, 100).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_lcp_iterations: Option<u32>,
    /// Coulomb re-solve cap per island (default: kea's, 16).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_friction_passes: Option<u32>,
    /// Rows of the largest island to reserve exact-solver memory for (default: kea's, 256).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_island_rows: Option<usize>,
    /// Which islands the hybrid solver sends to the exact path (default: kea's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub routing: Option<RoutingSpec>,
    /// Settings of the iterative path (default: kea's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iterative: Option<IterativeSpec>,
    /// Softness of contacts without their own, mass-independent (default: kea's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_spring: Option<SpringSpec>,
    /// Speeds beyond which an island is quarantined as runaway (default: kea's, 1e4 m/s and
    /// 1e4 rad/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_limits: Option<SpeedLimitsSpec>,
}

/// Runaway speeds (`kea::SpeedLimits`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedLimitsSpec {
    /// Largest linear speed, m/s (> 0).
    pub linear: Real,
    /// Largest angular speed, rad/s (> 0).
    pub angular: Real,
}

/// A mass-independent spring (`kea::Spring`): frequency, Hz, and damping ratio.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// Natural frequency, Hz (> 0).
    pub hertz: Real,
    /// Damping ratio (≥ 0).
    pub damping_ratio: Real,
}

/// When a body counts as resting (`kea::DemSettings`); an island rests once all its bodies have.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SleepSpec {
    /// Speed below which a body may rest, m/s.
    pub velocity: Real,
    /// Spin below which a body may rest, rad/s.
    pub angular_velocity: Real,
    /// Acceleration below which a body may rest, m/s².
    pub acceleration: Real,
    /// Angular acceleration below which a body may rest, rad/s².
    pub angular_acceleration: Real,
    /// Time an island must have rested before it sleeps, s.
    pub time: Real,
    /// Applied force that wakes a sleeping body, N.
    pub force: Real,
    /// Applied torque that wakes a sleeping body, N·m.
    pub torque: Real,
}

impl Default for SleepSpec {
    fn default() -> Self {
        let d = kea::DemSettings::default();
        Self {
            velocity: d.velocity_threshold,
            angular_velocity: d.angular_velocity_threshold,
            acceleration: d.acceleration_threshold,
            angular_acceleration: d.angular_acceleration_threshold,
            time: d.alive_window,
            force: d.force_threshold,
            torque: d.torque_threshold,
        }
    }
}

/// Hybrid routing thresholds (`kea::Routing`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RoutingSpec {
    /// Largest island, in rows, solved exactly.
    pub max_exact_rows: u32,
    /// Largest island, in bodies, solved exactly.
    pub max_exact_bodies: u32,
    /// An iterative island goes back to exact below this fraction of the limits, in (0, 1].
    pub hysteresis: Real,
    /// A small island of contacts only goes exact when a contact joins masses differing by
    /// more than this ratio (≥ 1; a very large number: never).
    pub mass_ratio: Real,
    /// An island of contacts only that joins at least this many bodies without a loop (a
    /// column of boxes) goes exact (≥ 1; a very large number: never).
    pub stack_bodies: u32,
    /// Largest tree of hinges and sliders on the static world, in links, stepped in reduced
    /// coordinates (0: never).
    pub max_reduced_links: u32,
}

impl Default for RoutingSpec {
    fn default() -> Self {
        let d = kea::Routing::default();
        Self {
            max_exact_rows: d.max_exact_rows,
            max_exact_bodies: d.max_exact_bodies,
            hysteresis: d.hysteresis,
            mass_ratio: d.mass_ratio,
            stack_bodies: d.stack_bodies,
            max_reduced_links: d.max_reduced_links,
        }
    }
}

/// Settings of the iterative path (`kea::IterativeParams`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IterativeSpec {
    /// Substeps per step (≥ 1).
    pub substeps: u32,
    /// Sweeps per substep with error correction (≥ 1).
    pub iterations: u32,
    /// Sweeps per substep without it.
    pub relax_iterations: u32,
    /// Fastest penetration correction, m/s (> 0).
    pub max_correction_speed: Real,
}

impl Default for IterativeSpec {
    fn default() -> Self {
        let d = kea::IterativeParams::default();
        Self {
            substeps: d.substeps,
            iterations: d.iterations,
            relax_iterations: d.relax_iterations,
            max_correction_speed: d.max_correction_speed,
        }
    }
}

impl Default for WorldSpec {
    fn default() -> Self {
        Self {
            gravity: [0.0, -9.81, 0.0],
            epsilon: 0.01,
            gamma: 0.2,
            solver: SolverSpec::Hybrid,
            integrator: IntegratorSpec::Rk4,
            sleep: false,
            max_bodies: 0,
            max_constraints: 0,
            sleep_thresholds: None,
            projection_iterations: 0,
            world_substeps: 1,
            max_lcp_iterations: None,
            max_friction_passes: None,
            max_island_rows: None,
            routing: None,
            iterative: None,
            contact_spring: None,
            speed_limits: None,
        }
    }
}

/// Which solver path handles islands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverSpec {
    /// By structure: piles iterative, joints among contacts split, small joint islands exact,
    /// big ones split.
    #[default]
    Hybrid,
    /// Every island exact.
    Exact,
    /// Every island iterative.
    Iterative,
    /// Every island with joints split (joints direct inside the substeps, contacts iterative).
    Split,
}

/// How the reduced-coordinate path integrates (`kea::Integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum IntegratorSpec {
    /// Classic fourth-order Runge–Kutta.
    #[default]
    Rk4,
    /// Semi-implicit Euler, damping and servos implicit.
    Euler,
    /// Euler with the Coriolis forces implicit too.
    Implicit,
}

impl From<IntegratorSpec> for kea::Integrator {
    fn from(spec: IntegratorSpec) -> Self {
        match spec {
            IntegratorSpec::Rk4 => Self::RungeKutta4,
            IntegratorSpec::Euler => Self::Euler,
            IntegratorSpec::Implicit => Self::Implicit,
        }
    }
}

fn is_rk4(spec: &IntegratorSpec) -> bool {
    *spec == IntegratorSpec::Rk4
}

/// A named material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Its name, used by colliders.
    pub name: String,
    /// Coulomb μ (default 0.5): the kinetic one when `static_friction` is given.
    #[serde(default = "half")]
    pub friction: Real,
    /// A static μ (≥ `friction`) that holds surfaces at rest until they slide (default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_friction: Option<Real>,
    /// Restitution (default 0).
    #[serde(default)]
    pub restitution: Real,
    /// Slowest approach that bounces, m/s (default 0.1).
    #[serde(default = "tenth")]
    pub restitution_threshold: Real,
    /// Contact softness ε (default: the world's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub softness: Option<Real>,
    /// Slip, m/s per N (default 0).
    #[serde(default, skip_serializing_if = "is_zero1")]
    pub slip: Real,
    /// Largest adhesive force, N (default 0).
    #[serde(default, skip_serializing_if = "is_zero1")]
    pub adhesion: Real,
}

/// The contact parameters of one pair of materials; a field left out takes the value the
/// combine rules give the pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialPairSpec {
    /// First material's name.
    pub a: String,
    /// Second material's name (may equal `a`).
    pub b: String,
    /// Coulomb μ (0: frictionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<Real>,
    /// Restitution.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Real>,
    /// Slowest approach that bounces, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution_threshold: Option<Real>,
    /// Contact softness ε.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub softness: Option<Real>,
    /// Slip along the two friction directions, m/s per N.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slip: Option<[Real; 2]>,
    /// Largest adhesive force, N.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adhesion: Option<Real>,
    /// Conveyor speed of `a`'s surface relative to `b`'s along the two friction directions,
    /// m/s (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slide: Option<[Real; 2]>,
    /// A fixed world direction for the first friction direction, so that `slide[0]` runs along
    /// it (a conveyor belt); `slide[1]` then runs along `normal × direction`, the normal
    /// pointing from `b` to `a`. Need not be unit; must not be zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slide_direction: Option<V3>,
}

fn half() -> Real {
    0.5
}
fn tenth() -> Real {
    0.1
}

/// A shape placed on a body (or in the world, for static geometry).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderSpec {
    /// The geometry.
    pub shape: ShapeSpec,
    /// Offset from the body's centre of mass (or world position), m.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub offset: V3,
    /// Orientation in the body's frame (or the world's), a unit quaternion `[x, y, z, w]`
    /// (default identity): a tilted ramp, a rotated part of a body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<[Real; 4]>,
    /// Material name (default `"default"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

/// A body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// A unique name, used by joints.
    pub name: String,
    /// Its shapes (at least one, unless `mass` is given).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shapes: Vec<ColliderSpec>,
    /// Density, kg/m³, for mass and inertia from the shapes (default 1000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<Real>,
    /// Mass, kg, overriding the density (inertia is scaled to match).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<Real>,
    /// Position of the centre of mass, m.
    pub position: V3,
    /// Orientation as a quaternion `[x, y, z, w]` (default identity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<[Real; 4]>,
    /// Linear velocity, m/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub velocity: V3,
    /// Angular velocity, rad/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub angular_velocity: V3,
    /// Linear and angular velocity damping.
    #[serde(default, skip_serializing_if = "is_zero2")]
    pub damping: [Real; 2],
    /// Inertia about the centre of mass in the body frame, kg·m², instead of the shapes': the
    /// diagonal `[ixx, iyy, izz]` or a full symmetric matrix `[[…], […], […]]` (rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<InertiaSpec>,
    /// A fast-spin axis in the body frame (a wheel's axle): rotation about it is integrated as
    /// its own exact rotation. Need not be unit; must not be zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fast_spin_axis: Option<V3>,
    /// Whether the body moves (default true). A disabled body stays where it is and acts as
    /// fixed for joints and contacts (the guide's `MdtBodyDisable`).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    /// Solve this body's island exactly whatever its size, in hybrid mode (vehicles, ragdolls).
    #[serde(default, skip_serializing_if = "is_false")]
    pub prefer_exact: bool,
}

/// An explicit inertia tensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum InertiaSpec {
    /// The principal moments `[ixx, iyy, izz]` along the body axes.
    Diagonal(V3),
    /// The full symmetric matrix, row by row.
    Full([V3; 3]),
}

pub(crate) fn is_zero(v: &V3) -> bool {
    *v == [0.0; 3]
}
fn is_zero2(v: &[Real; 2]) -> bool {
    *v == [0.0; 2]
}
fn is_zero1(v: &Real) -> bool {
    *v == 0.0
}
fn is_zero_u32(v: &u32) -> bool {
    *v == 0
}
fn is_true(v: &bool) -> bool {
    *v
}
fn yes() -> bool {
    true
}

fn one_u32() -> u32 {
    1
}

fn is_one_u32(x: &u32) -> bool {
    *x == 1
}
