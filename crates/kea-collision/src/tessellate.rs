//! Triangles of every shape, for renderers and debug drawing: `Shape::triangles` in the shape's
//! own frame; `CollisionWorld::colliders` and `collider_pose` place them in the world.

use crate::collision_world::{collider_pose, ColliderDef, ColliderHandle, CollisionWorld};
use crate::parry::math::Pose;
use crate::parry::shape::{SharedShape, TypedShape};
use crate::shape::Shape;
use kea::{Quat, Vec3, World};

/// Half the side of the square drawn for a plane, m.
pub const PLANE_HALF_SIZE: kea::Real = 20.0;

impl Shape {
    /// The shape as a triangle list in its own frame: vertices and counter-clockwise (seen from
    /// outside) index triples. Curved shapes are subdivided into 16 segments around; a plane is
    /// a square of side `2 × PLANE_HALF_SIZE` through the origin, in 16 × 16 cells.
    #[must_use]
    pub fn triangles(&self) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        self.triangles_with_segments(16)
    }

    /// [`Shape::triangles`] with curved shapes cut into `segments` around (at least 4), for
    /// viewers that draw many bodies at once.
    #[must_use]
    pub fn triangles_with_segments(&self, segments: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let n = segments.max(4);
        append(
            &self.shared,
            &Pose::IDENTITY,
            n,
            &mut vertices,
            &mut indices,
        );
        (vertices, indices)
    }
}

fn append(
    shape: &SharedShape,
    pose: &Pose,
    n: u32,
    vertices: &mut Vec<Vec3>,
    indices: &mut Vec<[u32; 3]>,
) {
    let (v, i): (Vec<Vec3>, Vec<[u32; 3]>) = match shape.as_typed_shape() {
        TypedShape::Ball(s) => s.to_trimesh(n, n),
        TypedShape::Cuboid(s) => s.to_trimesh(),
        TypedShape::Capsule(s) => s.to_trimesh(n, n / 2),
        TypedShape::Cylinder(s) => s.to_trimesh(n),
        TypedShape::Cone(s) => s.to_trimesh(n),
        TypedShape::ConvexPolyhedron(s) => s.to_trimesh(),
        TypedShape::TriMesh(s) => (s.vertices().to_vec(), s.indices().to_vec()),
        TypedShape::HeightField(s) => s.to_trimesh(),
        TypedShape::HalfSpace(s) => {
            // A grid of small squares rather than one big one, so that a renderer that drops
            // triangles reaching behind its camera loses only the squares that do.
            let n = s.normal;
            let (t1, t2) = n.any_orthonormal_pair();
            let (t1, t2) = if t1.cross(t2).dot(n) < 0.0 {
                (t2, t1)
            } else {
                (t1, t2)
            };
            let cells = 16u32;
            let step = 2.0 * PLANE_HALF_SIZE / cells as kea::Real;
            let mut v = Vec::new();
            for j in 0..=cells {
                for i in 0..=cells {
                    let (a, b) = (i as kea::Real * step, j as kea::Real * step);
                    v.push(t1 * (a - PLANE_HALF_SIZE) + t2 * (b - PLANE_HALF_SIZE));
                }
            }
            let mut tris = Vec::new();
            for j in 0..cells {
                for i in 0..cells {
                    let k = j * (cells + 1) + i;
                    tris.push([k, k + 1, k + cells + 2]);
                    tris.push([k, k + cells + 2, k + cells + 1]);
                }
            }
            (v, tris)
        }
        TypedShape::Compound(c) => {
            for (part_pose, part) in c.shapes() {
                append(part, &(*pose * *part_pose), n, vertices, indices);
            }
            return;
        }
        _ => return,
    };
    let base = vertices.len() as u32;
    vertices.extend(v.into_iter().map(|p| pose.transform_point(p)));
    indices.extend(i.into_iter().map(|t| t.map(|k| k + base)));
}

impl CollisionWorld {
    /// Every collider, in slot order.
    pub fn colliders(&self) -> impl Iterator<Item = (ColliderHandle, &ColliderDef)> + '_ {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            let c = s.collider.as_ref()?;
            Some((
                crate::collision_world::handle_of(&self.slots, i as u32),
                &c.def,
            ))
        })
    }

    /// Where a collider is in the world now: position and orientation of its shape's frame.
    pub fn collider_pose(
        &self,
        world: &World,
        h: ColliderHandle,
    ) -> crate::CollisionResult<(Vec3, Quat)> {
        let def = self.collider(h)?;
        let pose = collider_pose(world, def);
        Ok((pose.translation, pose.rotation))
    }
}
