//! Shapes: validated constructors over parry geometry, and their mass properties, so that a body
//! can take its mass and inertia from its shapes and a density (the guide's most common mistake,
//! a wrong inertia, made hard to make).

use crate::error::{
    check_aspect, check_extent, check_positive, check_size, check_vec3, CollisionError,
    CollisionResult, SIZE_RANGE,
};
use crate::parry::math::Pose;
use crate::parry::shape::{HeightFieldFlags, SharedShape, TriMesh, TriMeshFlags, TypedShape};
use crate::parry::utils::Array2;
use crate::shape_recipe::Recipe;
use kea::{Mat3, Quat, Real, Vec3};

/// A collision shape in its own frame. Cheap to clone (the geometry is shared).
#[derive(Clone)]
pub struct Shape {
    pub(crate) shared: SharedShape,
    /// How it was made, for snapshots (shared like the geometry).
    pub(crate) recipe: std::sync::Arc<Recipe>,
}

impl std::fmt::Debug for Shape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Shape({})", self.kind_name())
    }
}

impl Shape {
    /// A sphere of `radius` about the origin.
    pub fn sphere(radius: Real) -> CollisionResult<Self> {
        check_size("radius", radius)?;
        Ok(Self::made(
            SharedShape::ball(radius),
            Recipe::Sphere(radius),
        ))
    }

    /// A box with the given half extents, centred on the origin.
    pub fn cuboid(half_extents: Vec3) -> CollisionResult<Self> {
        check_size("half_extents.x", half_extents.x)?;
        check_size("half_extents.y", half_extents.y)?;
        check_size("half_extents.z", half_extents.z)?;
        check_aspect("half_extents", &half_extents.to_array())?;
        Ok(Self::made(
            SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z),
            Recipe::Cuboid(half_extents),
        ))
    }

    /// The half-space below the plane through the origin with unit outward `normal` (static
    /// geometry only: it has no finite mass).
    pub fn plane(normal: Vec3) -> CollisionResult<Self> {
        check_vec3("normal", normal)?;
        let n = normal
            .try_normalize()
            .ok_or_else(|| kea::KeaError::NotUnit {
                arg: "normal",
                value: format!("{normal}"),
                length: kea::math::wide(normal.length()),
            })?;
        Ok(Self::made(SharedShape::halfspace(n), Recipe::Plane(normal)))
    }

    /// A capsule along the y axis: a segment from `-half_height` to `half_height`, swept by
    /// `radius`.
    pub fn capsule(half_height: Real, radius: Real) -> CollisionResult<Self> {
        check_size("half_height", half_height)?;
        check_size("radius", radius)?;
        check_aspect("half_height and radius", &[half_height, radius])?;
        Ok(Self::made(
            SharedShape::capsule_y(half_height, radius),
            Recipe::Capsule(half_height, radius),
        ))
    }

    /// A cylinder along the y axis.
    pub fn cylinder(half_height: Real, radius: Real) -> CollisionResult<Self> {
        check_size("half_height", half_height)?;
        check_size("radius", radius)?;
        check_aspect("half_height and radius", &[half_height, radius])?;
        Ok(Self::made(
            SharedShape::cylinder(half_height, radius),
            Recipe::Cylinder(half_height, radius),
        ))
    }

    /// A cone along the y axis, apex at `+half_height`, base of `radius` at `-half_height`.
    pub fn cone(half_height: Real, radius: Real) -> CollisionResult<Self> {
        check_size("half_height", half_height)?;
        check_size("radius", radius)?;
        check_aspect("half_height and radius", &[half_height, radius])?;
        Ok(Self::made(
            SharedShape::cone(half_height, radius),
            Recipe::Cone(half_height, radius),
        ))
    }

    /// The convex hull of `points`. Fewer than four points, non-finite points, or points that
    /// lie in a plane (no volume) are refused.
    pub fn convex_hull(points: &[Vec3]) -> CollisionResult<Self> {
        if points.len() < 4 {
            return Err(CollisionError::DegenerateShape(format!(
                "a convex hull needs at least 4 points, got {}",
                points.len()
            )));
        }
        for p in points {
            check_extent("points", *p)?;
        }
        let shared = SharedShape::convex_hull(points).ok_or_else(|| {
            CollisionError::DegenerateShape("the convex hull of these points failed".into())
        })?;
        let volume = shared.mass_properties(1.0).mass();
        if volume.is_nan() || volume <= Real::EPSILON * 100.0 {
            return Err(CollisionError::DegenerateShape(format!(
                "the convex hull is flat (volume {volume})"
            )));
        }
        Ok(Self::made(shared, Recipe::ConvexHull(points.to_vec())))
    }

    /// A triangle mesh from vertices and counter-clockwise index triples. Empty meshes,
    /// non-finite vertices, out-of-range indices and degenerate (zero-area) triangles are
    /// refused. Meshes are for static geometry or as a hollow shell; they have no volume.
    pub fn trimesh(vertices: Vec<Vec3>, indices: Vec<[u32; 3]>) -> CollisionResult<Self> {
        if vertices.is_empty() || indices.is_empty() {
            return Err(CollisionError::DegenerateShape(format!(
                "a triangle mesh needs vertices and triangles, got {} and {}",
                vertices.len(),
                indices.len()
            )));
        }
        for v in &vertices {
            check_extent("vertices", *v)?;
        }
        for (t, tri) in indices.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= vertices.len()) {
                return Err(CollisionError::DegenerateShape(format!(
                    "triangle {t} uses vertex {i}, but the mesh has {} vertices",
                    vertices.len()
                )));
            }
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            if (b - a).cross(c - a).length_squared() <= 0.0 {
                return Err(CollisionError::DegenerateShape(format!(
                    "triangle {t} has zero area"
                )));
            }
        }
        // Half-edge topology refuses non-manifold meshes (an edge shared by three triangles, a
        // triangle listed twice); fixed internal edges keep contacts sliding across triangle
        // seams from getting the seam's normal instead of the surface's.
        let flags = TriMeshFlags::HALF_EDGE_TOPOLOGY | TriMeshFlags::FIX_INTERNAL_EDGES;
        let bad = |e: &dyn std::fmt::Display| {
            CollisionError::DegenerateShape(format!("triangle mesh: {e}"))
        };
        let recipe = Recipe::Trimesh(vertices.clone(), indices.clone());
        let mut mesh = TriMesh::new(vertices, indices).map_err(|e| bad(&e))?;
        // (parry's `with_flags` drops a topology error; `set_flags` reports it.)
        mesh.set_flags(flags).map_err(|e| bad(&e))?;
        Ok(Self::made(SharedShape::new(mesh), recipe))
    }

    /// A height field over the x–z plane, centred on the origin: `heights[row][column]`, rows
    /// along z and columns along x, spanning `size.x` by `size.z`, heights scaled by `size.y`.
    pub fn heightfield(heights: &[Vec<Real>], size: Vec3) -> CollisionResult<Self> {
        let rows = heights.len();
        let cols = heights.first().map_or(0, Vec::len);
        if rows < 2 || cols < 2 || heights.iter().any(|r| r.len() != cols) {
            return Err(CollisionError::DegenerateShape(format!(
                "a height field needs at least 2×2 samples in equal rows, got {rows} rows"
            )));
        }
        check_size("size.x", size.x)?;
        check_size("size.y", size.y)?;
        check_size("size.z", size.z)?;
        // parry stores the grid column-major.
        let mut data = Vec::with_capacity(rows * cols);
        for c in 0..cols {
            for row in heights {
                kea_finite("heights", row[c])?;
                if row[c].abs() > SIZE_RANGE.1 / size.y {
                    return Err(kea::KeaError::OutOfRange {
                        arg: "heights",
                        value: kea::error::format_real(row[c]),
                        expected: "each sample times size.y must be within 1e5 m of 0",
                    }
                    .into());
                }
                data.push(row[c]);
            }
        }
        let grid = Array2::new(rows, cols, data);
        let flags = HeightFieldFlags::FIX_INTERNAL_EDGES;
        Ok(Self::made(
            SharedShape::heightfield_with_flags(grid, size, flags),
            Recipe::Heightfield(heights.to_vec(), size),
        ))
    }

    /// A compound of parts, each placed at an offset and orientation in the compound's frame.
    /// Parts must be convex (sphere, box, capsule, cylinder, cone, convex hull).
    pub fn compound(parts: &[(Vec3, Quat, Shape)]) -> CollisionResult<Self> {
        if parts.is_empty() {
            return Err(CollisionError::DegenerateShape(
                "a compound needs parts".into(),
            ));
        }
        let mut list = Vec::with_capacity(parts.len());
        for (i, (offset, rotation, part)) in parts.iter().enumerate() {
            check_extent("parts.offset", *offset)?;
            let rotation = crate::error::check_unit_quat("parts.rotation", *rotation)?;
            if !part.shared.is_convex() {
                return Err(CollisionError::DegenerateShape(format!(
                    "compound part {i} is a {}, but parts must be convex",
                    part.kind_name()
                )));
            }
            list.push((Pose::from_parts(*offset, rotation), part.shared.clone()));
        }
        let recipe = parts
            .iter()
            .map(|(offset, rotation, part)| (*offset, *rotation, (*part.recipe).clone()))
            .collect();
        Ok(Self::made(
            SharedShape::compound(list),
            Recipe::Compound(recipe),
        ))
    }

    fn made(shared: SharedShape, recipe: Recipe) -> Self {
        Self {
            shared,
            recipe: std::sync::Arc::new(recipe),
        }
    }

    /// What kind of shape this is, in words.
    #[must_use]
    pub fn kind_name(&self) -> &'static str {
        match self.shared.as_typed_shape() {
            TypedShape::Ball(_) => "sphere",
            TypedShape::Cuboid(_) => "box",
            TypedShape::HalfSpace(_) => "plane",
            TypedShape::Capsule(_) => "capsule",
            TypedShape::Cylinder(_) => "cylinder",
            TypedShape::Cone(_) => "cone",
            TypedShape::ConvexPolyhedron(_) => "convex hull",
            TypedShape::TriMesh(_) => "triangle mesh",
            TypedShape::HeightField(_) => "height field",
            TypedShape::Compound(_) => "compound",
            _ => "shape",
        }
    }

    /// Whether the shape encloses a volume (and so can give a body its mass).
    #[must_use]
    pub fn has_volume(&self) -> bool {
        !matches!(
            self.shared.as_typed_shape(),
            TypedShape::HalfSpace(_) | TypedShape::TriMesh(_) | TypedShape::HeightField(_)
        )
    }

    /// Mass, centre of mass and inertia of the shape filled with `density` (kg/m³).
    pub fn mass_properties(&self, density: Real) -> CollisionResult<MassProperties> {
        MassProperties::of_shapes(&[(Vec3::ZERO, Quat::IDENTITY, self.clone())], density)
    }

    /// The parry geometry, for queries this crate does not wrap.
    #[must_use]
    pub fn parry_shape(&self) -> &SharedShape {
        &self.shared
    }
}

/// Mass properties of one or several shapes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Total mass.
    pub mass: Real,
    /// Centre of mass, in the frame the shapes were placed in.
    pub center_of_mass: Vec3,
    /// Inertia tensor about the centre of mass, axes of that frame.
    pub inertia: Mat3,
}

impl MassProperties {
    /// The combined mass properties of shapes placed at offsets and orientations, all with
    /// `density`. A Kea body's position is its centre of mass: place its colliders at
    /// `offset − center_of_mass`.
    pub fn of_shapes(parts: &[(Vec3, Quat, Shape)], density: Real) -> CollisionResult<Self> {
        check_positive("density", density)?;
        if parts.is_empty() {
            return Err(CollisionError::DegenerateShape("no shapes to weigh".into()));
        }
        let mut total: Option<crate::parry::mass_properties::MassProperties> = None;
        for (offset, rotation, shape) in parts {
            check_vec3("offset", *offset)?;
            let rotation = crate::error::check_unit_quat("rotation", *rotation)?;
            if !shape.has_volume() {
                return Err(CollisionError::DegenerateShape(format!(
                    "a {} has no volume, so no mass",
                    shape.kind_name()
                )));
            }
            let mp = shape
                .shared
                .mass_properties(density)
                .transform_by(&Pose::from_parts(*offset, rotation));
            total = Some(match total {
                Some(t) => t + mp,
                None => mp,
            });
        }
        let total = total.expect("parts is not empty");
        Ok(Self {
            mass: total.mass(),
            center_of_mass: total.local_com,
            inertia: total.reconstruct_inertia_matrix(),
        })
    }
}

fn kea_finite(arg: &'static str, v: Real) -> CollisionResult<()> {
    crate::error::check_finite(arg, v)
}
