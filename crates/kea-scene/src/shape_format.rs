//! The scene format's plain geometry: vectors and shapes, which bodies, colliders, joints and
//! groups all use (`format.rs`, `joint_format.rs`).

use kea::Real;
use serde::{Deserialize, Serialize};

/// A 3-vector, `[x, y, z]`.
pub type V3 = [Real; 3];

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
    /// A triangle mesh (a surface, for static geometry or bodies given a mass and inertia).
    Mesh {
        /// The vertices.
        vertices: Vec<V3>,
        /// Vertex index triples, counter-clockwise seen from outside.
        triangles: Vec<[u32; 3]>,
    },
    /// A height field over x–z: `heights[row][column]`, rows along z.
    HeightField {
        /// The samples.
        heights: Vec<Vec<Real>>,
        /// Extent in x and z, and the height scale.
        size: V3,
    },
}

/// Serde's skip test for a flag that is off.
pub(crate) fn is_false(v: &bool) -> bool {
    !*v
}
