//! The scene format's joints (every joint type of the guide, with limits, motors and breaking
//! thresholds) and groups (repeated structures expanded when the scene is built).

use crate::shape_format::{is_false, ShapeSpec, V3};
use kea::Real;
use serde::{Deserialize, Serialize};

/// A joint between `body1` and `body2` (absent: the world), anchors and axes in world frame, at
/// the bodies' initial poses. The fields every joint has are here; the `type` and the fields of
/// that type are in [`JointKind`], written in the same JSON object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointSpec {
    /// The joint type and its own fields.
    #[serde(flatten)]
    pub kind: JointKind,
    /// A unique name (default `joint<index>`), for [`crate::BuiltScene::joint`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// First body's name (a car wheel's chassis).
    pub body1: String,
    /// Second body's name, or none for the world (a car wheel's wheel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body2: Option<String>,
    /// Force on body 1, N, above which the joint breaks (disables itself).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub break_force: Option<Real>,
    /// Torque on body 1, N·m, above which the joint breaks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub break_torque: Option<Real>,
}

/// The fields of a joint with one coordinate, a hinge's angle or a slider's distance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OneCoordinateSpec {
    /// Anchor, world frame.
    pub anchor: V3,
    /// Axis, world frame.
    pub axis: V3,
    /// Limits on the coordinate, rad or m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<LimitSpec>,
    /// Motor `[desired speed rad/s or m/s, maximum torque N·m or force N]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motor: Option<[Real; 2]>,
}

/// A joint's type with the fields of that type, tagged by `type`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum JointKind {
    /// Ball and socket, with optional cone and twist limits.
    Ball {
        /// Anchor, world frame.
        anchor: V3,
        /// Largest angle between the limit axis of the two bodies, rad (a hard stop).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        cone: Option<Real>,
        /// Twist about the limit axis `[lower, upper]`, rad, or a soft/bouncy limit.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        twist: Option<LimitSpec>,
        /// The limit axis (world frame; default: from the anchor to body 1's centre).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        limit_axis: Option<V3>,
    },
    /// Hinge, with optional limits and motor on its angle (rad, rad/s, N·m).
    Hinge(OneCoordinateSpec),
    /// Prismatic (slider), with optional limits and motor on its distance (m, m/s, N).
    Prismatic(OneCoordinateSpec),
    /// Weld.
    Fixed {
        /// Anchor, world frame.
        anchor: V3,
    },
    /// A point of body 1 driven along a path (fixed in body 2, or the world).
    FixedPath {
        /// The driven point, world frame; the path starts here.
        anchor: V3,
        /// Also hold the bodies' relative orientation.
        #[serde(default, skip_serializing_if = "is_false")]
        fixed_orientation: bool,
        /// Keyframes `[t, x, y, z]` (s, then the world position of the anchor point),
        /// t increasing, linearly interpolated and held before the first and after the last.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        path: Vec<[Real; 4]>,
    },
    /// Universal joint.
    Universal {
        /// Anchor, world frame.
        anchor: V3,
        /// Body 1's axis, world frame.
        axis1: V3,
        /// Body 2's axis, world frame (⊥ `axis1`).
        axis2: V3,
    },
    /// A point of body 1 kept on a plane fixed in body 2.
    Linear1 {
        /// The point, world frame.
        anchor: V3,
        /// The plane's normal, world frame.
        normal: V3,
    },
    /// A point of body 1 kept on a line fixed in body 2 (cylindrical joint).
    Linear2 {
        /// The point, world frame.
        anchor: V3,
        /// The line's direction, world frame.
        direction: V3,
    },
    /// Car wheel: `body1` the chassis, `body2` the wheel, attached at the wheel's centre.
    CarWheel {
        /// Steering axis, world frame (the suspension slides along it).
        steering_axis: V3,
        /// Axle, world frame (⊥ `steering_axis`).
        axle: V3,
        /// Suspension `[stiffness N/m, damping N·s/m]`.
        suspension: [Real; 2],
        /// Suspension travel limits, m (positive along the steering axis).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        suspension_limits: Option<LimitSpec>,
        /// Whether the wheel steers (default: steering locked straight).
        #[serde(default, skip_serializing_if = "is_false")]
        steerable: bool,
        /// Steering lock: limits on the steering angle, rad.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        steering_limits: Option<LimitSpec>,
        /// Steering motor `[desired speed rad/s, maximum torque N·m]`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        steering_motor: Option<[Real; 2]>,
        /// Drive motor about the axle `[desired spin rad/s, maximum torque N·m]`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        drive: Option<[Real; 2]>,
    },
}

/// Limits on a joint coordinate: `[lower, upper]` hard stops, or an object with soft or bouncy
/// stops.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum LimitSpec {
    /// Hard stops `[lower, upper]` that do not bounce.
    Hard([Real; 2]),
    /// Stops with a stiffness and damping (soft) or a restitution (hard).
    Stops(StopsSpec),
}

/// Two stops sharing their stiffness, damping and restitution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopsSpec {
    /// Lower stop.
    pub lower: Real,
    /// Upper stop.
    pub upper: Real,
    /// Spring stiffness of soft stops (absent: hard stops).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<Real>,
    /// Damping of soft stops.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub damping: Real,
    /// Restitution of hard stops.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub restitution: Real,
}

fn is_zero(v: &Real) -> bool {
    *v == 0.0
}
fn one() -> Real {
    1.0
}
fn is_one(v: &Real) -> bool {
    *v == 1.0
}
fn human_density() -> Real {
    1000.0
}
fn is_human_density(v: &Real) -> bool {
    *v == 1000.0
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
    /// A human figure of eleven capsules standing along +y and facing +z, 1.84 m tall at scale
    /// 1: ball joints with cone and twist limits at the waist, neck, shoulders and hips, hinges
    /// with limits at the elbows and knees.
    Ragdoll {
        /// Centre of the pelvis.
        origin: V3,
        /// Orientation of the whole figure `[x, y, z, w]` (default upright).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        orientation: Option<[Real; 4]>,
        /// Size relative to the 1.84 m figure (default 1).
        #[serde(default = "one", skip_serializing_if = "is_one")]
        scale: Real,
        /// Density, kg/m³ (default 1000).
        #[serde(default = "human_density", skip_serializing_if = "is_human_density")]
        density: Real,
    },
}
