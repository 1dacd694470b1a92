//! Contact events per collider pair: a pair *begins* touching when one of its contact points
//! comes within [`CollisionWorld::touch_distance`](crate::CollisionWorld::touch_distance) of
//! overlap, *persists* while it stays so, and *ends* when none does (or a collider goes away).
//! Speculative contacts of a pair that is still apart do not count as touching.

use crate::collider::ColliderHandle;

/// What happened to a pair this step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ContactEventKind {
    /// The pair started touching this step.
    Began,
    /// The pair was touching last step and still is.
    Persisted,
    /// The pair stopped touching this step.
    Ended,
}

/// One event of the last contact update.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactEvent {
    /// What happened.
    pub kind: ContactEventKind,
    /// The two colliders, in slot order.
    pub colliders: [ColliderHandle; 2],
}
