//! Colliders: a shape attached to a body (or the static world) and placed in its frame, its
//! generational handle, what the collision world keeps of it between steps, and its box.

use crate::broad_phase::Aabb;
use crate::material::MaterialId;
use crate::parry::math::Pose;
use crate::shape::Shape;
use kea::{BodyHandle, Quat, Real, Vec3};

/// A collider's handle: generational, like Kea's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ColliderHandle {
    pub(crate) index: u32,
    pub(crate) generation: u32,
}

/// What to attach: a shape on a body (or on the static world), placed in the body's frame.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ColliderDef {
    /// The body it moves with; `None` for static geometry.
    pub body: Option<BodyHandle>,
    /// The geometry.
    pub shape: Shape,
    /// Where the shape's origin sits in the body's frame (the body's position is its centre
    /// of mass), or in the world for static geometry.
    pub offset: Vec3,
    /// The shape's orientation in the body's frame.
    pub rotation: Quat,
    /// Its material, an id of the world's [`MaterialTable`](crate::MaterialTable).
    pub material: MaterialId,
    /// Collision groups this collider belongs to (bits).
    pub groups: u32,
    /// Groups it collides with (bits). Two colliders meet only if each one's groups intersect
    /// the other's mask.
    pub mask: u32,
}

impl ColliderDef {
    /// A collider of `shape` on `body` (or static), at the body's centre, material 0, in every
    /// group and colliding with every group.
    #[must_use]
    pub fn new(body: Option<BodyHandle>, shape: Shape) -> Self {
        Self {
            body,
            shape,
            offset: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            material: 0,
            groups: 1,
            mask: u32::MAX,
        }
    }
}

#[derive(Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Collider {
    pub(crate) def: ColliderDef,
    /// Radius of the shape's bounding sphere about the body's centre, for swept bounds.
    pub(crate) reach: Real,
    /// Its leaf in the broad phase's tree, and the fat box stored there.
    pub(crate) leaf: u32,
    pub(crate) fat: Aabb,
    /// Its pose this step, whether it cannot move this step (static, asleep or disabled), and
    /// an upper bound of how fast any of its points moves, m/s: the narrow phase reads these
    /// instead of the world.
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::pose"))]
    pub(crate) pose: Pose,
    pub(crate) still: bool,
    pub(crate) motion: Real,
    /// For a hull or mesh of many points, its box in its own frame (centre, half extents):
    /// each step's box is that one turned (a little larger than the tight box), not a pass
    /// over every point (a robot link's hull of hundreds of points spent a third of a step
    /// there).
    pub(crate) local_box: Option<(Vec3, Vec3)>,
}

impl Collider {
    /// Its box in the world at its pose (`local_box` turned, or the shape's own).
    pub(crate) fn world_box(&self) -> (Vec3, Vec3) {
        match self.local_box {
            Some(b) => turned_box(&self.pose, b),
            None => {
                let aabb = self.def.shape.shared.compute_aabb(&self.pose);
                (aabb.mins, aabb.maxs)
            }
        }
    }
}

/// Hulls and meshes with more points than this take their per-step box from their own.
const TIGHT_BOX_MAX_POINTS: usize = 32;

/// A shape's own box when it has many points (see [`Collider::local_box`]).
pub(crate) fn local_box(shape: &crate::parry::shape::SharedShape) -> Option<(Vec3, Vec3)> {
    let points = shape
        .as_convex_polyhedron()
        .map(|c| c.points().len())
        .or_else(|| shape.as_trimesh().map(|m| m.vertices().len()))?;
    if points <= TIGHT_BOX_MAX_POINTS {
        return None;
    }
    let b = shape.compute_local_aabb();
    Some(((b.mins + b.maxs) * 0.5, (b.maxs - b.mins) * 0.5))
}

/// The world box of a shape whose own box is `(centre, half)`, at `pose`.
fn turned_box(pose: &Pose, (centre, half): (Vec3, Vec3)) -> (Vec3, Vec3) {
    let r = kea::Mat3::from_quat(pose.rotation);
    let abs = kea::Mat3::from_cols(r.x_axis.abs(), r.y_axis.abs(), r.z_axis.abs());
    let c = pose.translation + pose.rotation * centre;
    let h = abs * half;
    (c - h, c + h)
}

#[derive(Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Slot {
    pub(crate) generation: u32,
    pub(crate) collider: Option<Collider>,
}

/// The handle of the collider in slot `i`.
pub(crate) fn handle_of(slots: &[Slot], i: u32) -> ColliderHandle {
    ColliderHandle {
        index: i,
        generation: slots[i as usize].generation,
    }
}

/// Largest coordinate of a box in the broad phase, m: planes are cut there.
pub(crate) const WORLD_BOUND: Real = 1.0e6;
