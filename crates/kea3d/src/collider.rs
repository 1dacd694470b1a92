//! The collider builder: a shape, where it sits on its body, how heavy and how grippy it is.

use kea::{Quat, Real, Vec3};
use kea_collision::{CollisionResult, MaterialId, Shape, Surface};

/// Density a collider has unless told otherwise: water's, 1000 kg/m³.
pub const DEFAULT_DENSITY: Real = 1000.0;

/// A collider to insert, made with a builder:
/// `Collider::cuboid([0.5, 0.5, 0.5]).density(500.0).friction(0.8)`.
///
/// A shape whose arguments are bad is reported when the collider is inserted, with the
/// argument's name and value.
///
/// ```
/// use kea3d::prelude::*;
///
/// let mut world = PhysicsWorld::new();
/// let body = world.insert_body(Body::dynamic())?;
/// // A 1 m cube of density 500 kg/m³ weighs 500 kg.
/// world.insert_collider(Collider::cuboid([0.5, 0.5, 0.5]).density(500.0).friction(0.8), Some(body))?;
/// assert!((world.dynamics().body(body)?.mass() - 500.0).abs() < 1e-3);
/// // Bad arguments are refused by name when the collider is inserted.
/// let e = world.insert_collider(Collider::ball(-1.0), Some(body)).unwrap_err();
/// assert!(e.to_string().contains("radius"), "{e}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
#[must_use]
pub struct Collider {
    pub(crate) shape: CollisionResult<Shape>,
    /// Where the shape sits in the collider's own frame (a capsule between two points, a
    /// capsule along x): placed in the body by `offset` and `rotation`.
    pub(crate) shape_offset: Vec3,
    pub(crate) shape_rotation: Quat,
    pub(crate) offset: Vec3,
    pub(crate) rotation: Quat,
    pub(crate) mass: ColliderMass,
    pub(crate) surface: Option<Surface>,
    pub(crate) material: Option<MaterialId>,
    pub(crate) groups: u32,
    pub(crate) mask: u32,
}

/// How a collider weighs in on its body's mass.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) enum ColliderMass {
    Density(Real),
    Mass(Real),
}

impl Collider {
    /// A collider of any [`Shape`].
    pub fn new(shape: Shape) -> Self {
        Self::from_result(Ok(shape))
    }

    pub(crate) fn from_result(shape: CollisionResult<Shape>) -> Self {
        Self {
            shape,
            shape_offset: Vec3::ZERO,
            shape_rotation: Quat::IDENTITY,
            offset: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            mass: ColliderMass::Density(DEFAULT_DENSITY),
            surface: None,
            material: None,
            groups: 1,
            mask: u32::MAX,
        }
    }

    /// A box of these half-extents, m.
    pub fn cuboid(half_extents: impl Into<Vec3>) -> Self {
        Self::from_result(Shape::cuboid(half_extents.into()))
    }

    /// A sphere of this radius, m.
    pub fn ball(radius: Real) -> Self {
        Self::from_result(Shape::sphere(radius))
    }

    /// A capsule along the body's y axis: a cylinder of `half_height` capped by hemispheres.
    pub fn capsule_y(half_height: Real, radius: Real) -> Self {
        Self::from_result(Shape::capsule(half_height, radius))
    }

    /// A capsule along the body's x axis.
    pub fn capsule_x(half_height: Real, radius: Real) -> Self {
        Self::capsule_y(half_height, radius)
            .shaped(Vec3::ZERO, Quat::from_rotation_z(-kea::PI_REAL / 2.0))
    }

    /// A capsule along the body's z axis.
    pub fn capsule_z(half_height: Real, radius: Real) -> Self {
        Self::capsule_y(half_height, radius)
            .shaped(Vec3::ZERO, Quat::from_rotation_x(kea::PI_REAL / 2.0))
    }

    /// A capsule whose axis runs from `a` to `b` (body frame), any direction.
    pub fn capsule(a: impl Into<Vec3>, b: impl Into<Vec3>, radius: Real) -> Self {
        let (a, b) = (a.into(), b.into());
        let axis = b - a;
        let len = axis.length();
        let rotation = if len > 0.0 && len.is_finite() {
            Quat::from_rotation_arc(Vec3::Y, axis / len)
        } else {
            Quat::IDENTITY
        };
        Self::capsule_y(0.5 * len, radius).shaped((a + b) * 0.5, rotation)
    }

    fn shaped(mut self, offset: Vec3, rotation: Quat) -> Self {
        self.shape_offset = offset;
        self.shape_rotation = rotation;
        self
    }

    /// The shape's placement in its body's frame: the shape's own placement (for capsules
    /// made between points or along x or z), then `translation` and `rotation`.
    pub(crate) fn placement(&self) -> (Vec3, Quat) {
        (
            self.offset + self.rotation * self.shape_offset,
            self.rotation * self.shape_rotation,
        )
    }

    /// A cylinder along the body's y axis.
    pub fn cylinder(half_height: Real, radius: Real) -> Self {
        Self::from_result(Shape::cylinder(half_height, radius))
    }

    /// A cone along the body's y axis, apex up.
    pub fn cone(half_height: Real, radius: Real) -> Self {
        Self::from_result(Shape::cone(half_height, radius))
    }

    /// The convex hull of these points.
    pub fn convex_hull(points: &[Vec3]) -> Self {
        Self::from_result(Shape::convex_hull(points))
    }

    /// A triangle mesh (no volume: for static or kinematic geometry, or with an explicit
    /// body mass).
    pub fn trimesh(vertices: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Self {
        Self::from_result(Shape::trimesh(vertices, indices))
    }

    /// A height field: rows of heights over `size.x` × `size.z`, scaled by `size.y`.
    pub fn heightfield(heights: &[Vec<Real>], size: impl Into<Vec3>) -> Self {
        Self::from_result(Shape::heightfield(heights, size.into()))
    }

    /// A half-space below the plane through the origin with this normal (static only).
    pub fn halfspace(normal: impl Into<Vec3>) -> Self {
        Self::from_result(Shape::plane(normal.into()))
    }

    /// Where the collider's origin sits in its body's frame, m (a capsule made between two
    /// points keeps them about this origin).
    pub fn translation(mut self, offset: impl Into<Vec3>) -> Self {
        self.offset = offset.into();
        self
    }

    /// The collider's orientation in its body's frame: any unit quaternion (a capsule along
    /// x or z, or between two points, turns with it).
    pub fn rotation(mut self, rotation: Quat) -> Self {
        self.rotation = rotation;
        self
    }

    /// Density, kg/m³ (default [`DEFAULT_DENSITY`]).
    pub fn density(mut self, density: Real) -> Self {
        self.mass = ColliderMass::Density(density);
        self
    }

    /// This collider's mass, kg, instead of a density.
    pub fn mass(mut self, mass: Real) -> Self {
        self.mass = ColliderMass::Mass(mass);
        self
    }

    /// Coulomb friction coefficient (default 0.5).
    pub fn friction(mut self, friction: Real) -> Self {
        self.surface.get_or_insert_with(Surface::default).friction = friction;
        self
    }

    /// A static friction coefficient (≥ the friction, which is then the kinetic one): the
    /// surface holds at rest until it slides (`kea::FrictionModel::StaticKinetic`).
    pub fn static_friction(mut self, static_friction: Real) -> Self {
        self.surface
            .get_or_insert_with(Surface::default)
            .static_friction = Some(static_friction);
        self
    }

    /// Coefficient of restitution (default 0).
    pub fn restitution(mut self, restitution: Real) -> Self {
        self.surface
            .get_or_insert_with(Surface::default)
            .restitution = restitution;
        self
    }

    /// A whole surface description (friction, restitution, softness, slip, adhesion).
    pub fn surface(mut self, surface: Surface) -> Self {
        self.surface = Some(surface);
        self
    }

    /// A material of the world's table, by id (it wins over a surface set here).
    pub fn material(mut self, material: MaterialId) -> Self {
        self.material = Some(material);
        self
    }

    /// Collision groups (bits) it belongs to and the groups it collides with.
    pub fn collision_groups(mut self, groups: u32, mask: u32) -> Self {
        self.groups = groups;
        self.mask = mask;
        self
    }
}

impl From<Shape> for Collider {
    fn from(shape: Shape) -> Self {
        Self::new(shape)
    }
}
