//! The scene format, version 1: plain data that serde reads from and writes to JSON. Every field
//! that has a default may be left out; unknown fields are errors (a typo must not pass silently).

use kea::Real;
use serde::{Deserialize, Serialize};

/// The format version this crate reads and writes.
pub const VERSION: u32 = 1;

/// A 3-vector, `[x, y, z]`.
pub type V3 = [Real; 3];

/// A whole scene.
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
    /// `"hybrid"`, `"exact"` or `"iterative"`.
    pub solver: SolverSpec,
    /// Put resting islands to sleep (the guide's auto-disable).
    pub sleep: bool,
    /// Most bodies (0: as many as the scene needs).
    pub max_bodies: usize,
    /// Most constraints, contacts included (0: 16 per body, at least 256).
    pub max_constraints: usize,
}

impl Default for WorldSpec {
    fn default() -> Self {
        Self {
            gravity: [0.0, -9.81, 0.0],
            epsilon: 0.01,
            gamma: 0.2,
            solver: SolverSpec::Hybrid,
            sleep: false,
            max_bodies: 0,
            max_constraints: 0,
        }
    }
}

/// Which solver path handles islands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverSpec {
    /// Small islands exact, big ones iterative.
    #[default]
    Hybrid,
    /// Every island exact.
    Exact,
    /// Every island iterative.
    Iterative,
}

/// A named material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Its name, used by colliders.
    pub name: String,
    /// Coulomb μ (default 0.5).
    #[serde(default = "half")]
    pub friction: Real,
    /// Restitution (default 0).
    #[serde(default)]
    pub restitution: Real,
    /// Slowest approach that bounces, m/s (default 0.1).
    #[serde(default = "tenth")]
    pub restitution_threshold: Real,
}

fn half() -> Real {
    0.5
}
fn tenth() -> Real {
    0.1
}

/// A shape, tagged by kind: `{"sphere": {"radius": 0.5}}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A sphere.
    Sphere {
        /// Radius, m.
        radius: Real,
    },
    /// A box.
    Box {
        /// Half extents, m.
        half_extents: V3,
    },
    /// A half-space below the plane through the collider's origin (static only).
    Plane {
        /// Outward normal.
        normal: V3,
    },
    /// A capsule along y.
    Capsule {
        /// Half the segment's length, m.
        half_height: Real,
        /// Radius, m.
        radius: Real,
    },
    /// A cylinder along y.
    Cylinder {
        /// Half height, m.
        half_height: Real,
        /// Radius, m.
        radius: Real,
    },
    /// A cone along y, apex up.
    Cone {
        /// Half height, m.
        half_height: Real,
        /// Base radius, m.
        radius: Real,
    },
    /// The convex hull of points.
    ConvexHull {
        /// The points.
        points: Vec<V3>,
    },
    /// A height field over x–z: `heights[row][column]`, rows along z.
    HeightField {
        /// The samples.
        heights: Vec<Vec<Real>>,
        /// Extent in x and z, and the height scale.
        size: V3,
    },
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
}

/// A joint between `body1` and `body2` (absent: the world), anchors and axes in world frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum JointSpec {
    /// Ball and socket.
    Ball {
        /// First body's name.
        body1: String,
        /// Second body's name, or none for the world.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        body2: Option<String>,
        /// Anchor, world frame.
        anchor: V3,
    },
    /// Hinge, with an optional motor.
    Hinge {
        /// First body's name.
        body1: String,
        /// Second body's name, or none for the world.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        body2: Option<String>,
        /// Anchor, world frame.
        anchor: V3,
        /// Axis, world frame.
        axis: V3,
        /// Limits `[lower, upper]`, rad (hard stops).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        limits: Option<[Real; 2]>,
        /// Motor `[desired speed, maximum torque]`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        motor: Option<[Real; 2]>,
    },
    /// Prismatic (slider).
    Prismatic {
        /// First body's name.
        body1: String,
        /// Second body's name, or none for the world.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        body2: Option<String>,
        /// Anchor, world frame.
        anchor: V3,
        /// Axis, world frame.
        axis: V3,
    },
    /// Weld.
    Fixed {
        /// First body's name.
        body1: String,
        /// Second body's name, or none for the world.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        body2: Option<String>,
        /// Anchor, world frame.
        anchor: V3,
    },
}

/// A repeated structure, tagged by kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum GroupSpec {
    /// A pyramid of cubes in the x–y plane, standing on y = `origin.y`.
    Pyramid {
        /// Cubes in the bottom row.
        base: u32,
        /// Half the cube's edge, m.
        half_extent: Real,
        /// Density, kg/m³.
        density: Real,
        /// Centre of the bottom row's base.
        origin: V3,
    },
    /// Copies of one shape on a regular 3D grid (a ball pit, a wall of bricks).
    Grid {
        /// The shape of every body.
        shape: ShapeSpec,
        /// Bodies along x, y and z.
        counts: [u32; 3],
        /// Distance between neighbours along x, y and z, m.
        spacing: V3,
        /// Density, kg/m³.
        density: Real,
        /// Centre of the first body.
        origin: V3,
    },
    /// A chain of spheres joined by ball joints, hanging from `origin` (fixed to the world) along −y.
    Chain {
        /// Links.
        links: u32,
        /// Distance between link centres, m.
        spacing: Real,
        /// Link radius, m.
        radius: Real,
        /// Density, kg/m³.
        density: Real,
        /// The top anchor.
        origin: V3,
    },
}

fn is_zero(v: &V3) -> bool {
    *v == [0.0; 3]
}
fn is_zero2(v: &[Real; 2]) -> bool {
    *v == [0.0; 2]
}
