//! Contact manifolds of a pair of shapes, generated without touching the heap once warm.
//!
//! parry's per-pair generators are used where they work in place (balls, box-box,
//! capsule-capsule, box-triangle), on one scratch manifold cleared before every call: parry
//! clones a manifold's old points to match warm starts, which Kea does itself by feature id, so
//! a cleared manifold turns that clone into nothing. Where parry allocates on every call, the
//! generator does the work itself with reused buffers:
//!
//! * a plane against a polyhedral shape (box, hull, capsule, cylinder, cone): the support
//!   feature of the shape towards the plane, vertex by vertex;
//! * two polyhedral shapes otherwise (GJK, then EPA when they overlap, on an EPA kept here
//!   rather than a fresh one per call; then parry's feature clipping);
//! * a height field or triangle mesh against a convex shape: the triangles under the shape's
//!   box, each as its own manifold (its triangle index as the sub-shape), with the triangle's
//!   pseudo-normals (parry's internal-edge fix) bending or dropping normals that come from an
//!   edge shared with a neighbour;
//! * a compound: each of its parts under the other shape's box, as above, each part's
//!   manifolds brought back into the compound's frame.
//!
//! Two meshes, a mesh against a plane, or two planes get no contacts.
//!
//! Output: manifolds in the pair's frames: points in each collider's own frame, the normal in
//! the first collider's frame pointing from it to the second, and separations (`dist < 0`:
//! overlap), parry's convention.

use crate::parry::bounding_volume::BoundingVolume;
use crate::parry::math::{Pose, Vector};
use crate::parry::query::details::{
    contact_manifold_ball_ball, contact_manifold_capsule_capsule, contact_manifold_convex_ball,
    contact_manifold_cuboid_cuboid, contact_manifold_cuboid_triangle, NormalConstraints,
    NormalConstraintsPair,
};
use crate::parry::query::epa::EPA;
use crate::parry::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use crate::parry::query::ContactManifold;
use crate::parry::query::TrackedContact;
use crate::parry::shape::{
    PackedFeatureId, PolygonalFeature, Shape as ParryShape, ShapeType, Triangle,
};
use kea::{Real, Vec3};

/// Most points one generated manifold keeps before reduction (a box face clipped against
/// another gives up to eight).
pub(crate) const MAX_GEN_POINTS: usize = 8;

/// One generated point.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GenPoint {
    /// On the first shape, in its collider's frame.
    pub local_a: Vec3,
    /// On the second shape, in its collider's frame.
    pub local_b: Vec3,
    /// Separation along the normal (negative: overlap).
    pub dist: Real,
    /// Feature id (stable while the same features touch).
    pub id: u32,
}

/// One generated manifold.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GenManifold {
    /// Sub-shape (triangle) of each side, 0 for simple shapes.
    pub sub: (u32, u32),
    /// Normal in the first collider's frame, from the first shape towards the second.
    pub normal_a: Vec3,
    pub count: usize,
    pub points: [GenPoint; MAX_GEN_POINTS],
}

impl GenManifold {
    pub(crate) fn points(&self) -> &[GenPoint] {
        &self.points[..self.count]
    }

    fn push(&mut self, p: GenPoint) {
        if self.count < MAX_GEN_POINTS {
            self.points[self.count] = p;
            self.count += 1;
        }
    }
}

/// The generator's reusable buffers.
pub(crate) struct Generator {
    scratch: ContactManifold<(), ()>,
    epa: EPA,
    feature: [PolygonalFeature; 2],
    /// The manifolds of the last [`Generator::generate`].
    pub out: Vec<GenManifold>,
}

/// Buffers only: a clone starts with fresh ones (parry's EPA cannot be cloned), which changes
/// no result.
impl Clone for Generator {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Default for Generator {
    fn default() -> Self {
        let mut scratch = ContactManifold::new();
        scratch.points.reserve(2 * MAX_GEN_POINTS);
        Self {
            scratch,
            epa: warmed_epa(),
            feature: [PolygonalFeature::new(), PolygonalFeature::new()],
            out: Vec::with_capacity(16),
        }
    }
}

/// An EPA whose buffers have grown as far as any query takes them: two balls deep in each
/// other, whose round supports never let the expansion converge, run it to parry's cap of 100
/// iterations. Without it a warm world allocated the first time a deeper overlap needed more
/// faces than any before (a car's wheel on a heightfield, seconds in).
fn warmed_epa() -> EPA {
    let mut epa = EPA::new();
    let ball = crate::parry::shape::Ball::new(1.0);
    let pos12 = Pose::from_translation(Vector::new(0.31, 0.17, 0.05));
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(&pos12, &ball, &ball, Vector::X));
    if gjk::closest_points(&pos12, &ball, &ball, 0.0, true, &mut simplex) == GJKResult::Intersection
    {
        let _ = epa.closest_points(&pos12, &ball, &ball, &simplex);
    }
    epa
}

/// Packs parry's two feature ids into one (a point keeps it while the same features touch).
fn feature_id(f1: u32, f2: u32) -> u32 {
    f1.wrapping_mul(0x9E37_79B1) ^ f2.rotate_left(16)
}

fn is_mesh(t: ShapeType) -> bool {
    matches!(t, ShapeType::HeightField | ShapeType::TriMesh)
}

/// The normal constraints (a mesh triangle's pseudo-normals) of each shape of a pair.
type Normals<'a> = (
    Option<&'a dyn NormalConstraints>,
    Option<&'a dyn NormalConstraints>,
);

/// A pair of shapes: `b` placed at `pos12` in `a`'s frame, with each one's normal constraints
/// (a mesh triangle's pseudo-normals).
#[derive(Clone, Copy)]
struct ShapePair<'a> {
    a: &'a dyn ParryShape,
    b: &'a dyn ParryShape,
    pos12: Pose,
    normals: Normals<'a>,
}

impl<'a> ShapePair<'a> {
    fn new(a: &'a dyn ParryShape, b: &'a dyn ParryShape, pos12: &Pose) -> Self {
        Self {
            a,
            b,
            pos12: *pos12,
            normals: (None, None),
        }
    }

    /// The same pair as (`b`, `a`).
    fn swapped(&self) -> Self {
        Self {
            a: self.b,
            b: self.a,
            pos12: self.pos12.inverse(),
            normals: (self.normals.1, self.normals.0),
        }
    }
}

impl Generator {
    /// Generates the manifolds of shape `a` at `pose_a` against shape `b` at `pose_b`, for
    /// points closer than `prediction`, into [`Generator::out`]. Returns false for a pair of
    /// shapes it cannot collide.
    pub(crate) fn generate(
        &mut self,
        a: &dyn ParryShape,
        pose_a: &Pose,
        b: &dyn ParryShape,
        pose_b: &Pose,
        prediction: Real,
    ) -> bool {
        self.out.clear();
        self.pair(ShapePair::new(a, b, &pose_a.inv_mul(pose_b)), prediction)
    }

    /// Appends the manifolds of `a` against `b` (placed at `pos12` in `a`'s frame) to
    /// [`Generator::out`], in `a`'s frame. False for a pair of shapes it cannot collide.
    fn pair(&mut self, pair: ShapePair<'_>, prediction: Real) -> bool {
        let (a, b) = (pair.a, pair.b);
        let (ta, tb) = (a.shape_type(), b.shape_type());
        if ta == ShapeType::Compound {
            return self.compound(pair, prediction);
        }
        if tb == ShapeType::Compound {
            return self.swapped(pair, prediction);
        }
        let mesh_a = is_mesh(ta);
        let mesh_b = is_mesh(tb);
        let plane_a = ta == ShapeType::HalfSpace;
        let plane_b = tb == ShapeType::HalfSpace;
        if (mesh_a || plane_a) && (mesh_b || plane_b) {
            return false;
        }
        if mesh_a {
            return self.mesh(pair, prediction);
        }
        if mesh_b {
            return self.swapped(pair, prediction);
        }
        match self.convex(pair, prediction) {
            Some(m) => {
                if m.count > 0 {
                    self.out.push(m);
                }
                true
            }
            None => false,
        }
    }

    /// [`Generator::pair`] computed as (`b`, `a`) and turned back to the pair's order.
    fn swapped(&mut self, pair: ShapePair<'_>, prediction: Real) -> bool {
        let start = self.out.len();
        let ok = self.pair(pair.swapped(), prediction);
        for m in &mut self.out[start..] {
            flip(m, &pair.pos12);
        }
        ok
    }

    /// Each part of compound `comp` under `other`'s box, against `other` placed at `pos12`:
    /// the parts' manifolds, brought into the compound's frame (the part's index as its
    /// sub-shape).
    fn compound(&mut self, pair: ShapePair<'_>, prediction: Real) -> bool {
        let (comp, other, pos12) = (pair.a, pair.b, &pair.pos12);
        let Some(parts) = comp.as_composite_shape() else {
            return false;
        };
        let local_box = other.compute_aabb(pos12).loosened(prediction);
        let mut any = false;
        for id in parts.bvh().intersect_aabb(&local_box) {
            parts.map_part_at(id, &mut |part_pose, part, _| {
                let start = self.out.len();
                let at = part_pose.copied().unwrap_or(Pose::IDENTITY);
                any |= self.pair(ShapePair::new(part, other, &at.inv_mul(pos12)), prediction);
                for m in &mut self.out[start..] {
                    m.normal_a = at.rotation * m.normal_a;
                    for p in &mut m.points[..m.count] {
                        p.local_a = at.transform_point(p.local_a);
                    }
                    m.sub.0 = id;
                }
            });
        }
        any || parts.bvh().leaf_count() == 0
    }

    /// Manifold of two convex shapes (or a plane and a convex shape), `pos12` placing `b` in
    /// `a`'s frame. `None` when unsupported.
    fn convex(&mut self, pair: ShapePair<'_>, prediction: Real) -> Option<GenManifold> {
        let ShapePair {
            a,
            b,
            ref pos12,
            normals,
        } = pair;
        let (ta, tb) = (a.shape_type(), b.shape_type());
        match (ta, tb) {
            (ShapeType::Ball, ShapeType::Ball) => {
                let (b1, b2) = (a.as_ball()?, b.as_ball()?);
                Some(self.generated(prediction, |m| {
                    contact_manifold_ball_ball(pos12, b1, b2, prediction, m)
                }))
            }
            (_, ShapeType::Ball) => {
                let ball = b.as_ball()?;
                Some(self.generated(prediction, |m| {
                    contact_manifold_convex_ball(
                        pos12, a, ball, normals.0, normals.1, prediction, m, false,
                    )
                }))
            }
            (ShapeType::Ball, _) => self.convex_swapped(pair, prediction),
            (ShapeType::HalfSpace, _) => self.plane_convex(a, b, pos12, prediction),
            (_, ShapeType::HalfSpace) => {
                let mut m = self.plane_convex(b, a, &pos12.inverse(), prediction)?;
                flip(&mut m, pos12);
                Some(m)
            }
            (ShapeType::Cuboid, ShapeType::Cuboid) => {
                let (c1, c2) = (a.as_cuboid()?, b.as_cuboid()?);
                Some(self.generated(prediction, |m| {
                    contact_manifold_cuboid_cuboid(pos12, c1, c2, prediction, m)
                }))
            }
            (ShapeType::Capsule, ShapeType::Capsule) => {
                let (c1, c2) = (a.as_capsule()?, b.as_capsule()?);
                Some(self.generated(prediction, |m| {
                    contact_manifold_capsule_capsule(pos12, c1, c2, prediction, m)
                }))
            }
            (ShapeType::Cuboid, ShapeType::Triangle) => {
                let (cuboid, triangle) = (a.as_cuboid()?, b.as_triangle()?);
                Some(self.generated(prediction, |m| {
                    contact_manifold_cuboid_triangle(
                        pos12,
                        &pos12.inverse(),
                        cuboid,
                        triangle,
                        normals.0,
                        normals.1,
                        prediction,
                        m,
                        false,
                    )
                }))
            }
            (ShapeType::Triangle, ShapeType::Cuboid) => self.convex_swapped(pair, prediction),
            _ => self.pfm_pfm(pair, prediction),
        }
    }

    /// [`Generator::convex`] computed as (`b`, `a`) and turned back to the pair's order.
    fn convex_swapped(&mut self, pair: ShapePair<'_>, prediction: Real) -> Option<GenManifold> {
        let mut m = self.convex(pair.swapped(), prediction)?;
        flip(&mut m, &pair.pos12);
        Some(m)
    }

    /// Runs one of parry's generators (`run`) on the cleared scratch manifold and takes its
    /// points closer than `prediction` (see the module docs for why it is cleared).
    fn generated(
        &mut self,
        prediction: Real,
        run: impl FnOnce(&mut ContactManifold<(), ()>),
    ) -> GenManifold {
        self.scratch.clear();
        run(&mut self.scratch);
        self.take_scratch(prediction)
    }

    /// Copies the scratch manifold's points closer than `prediction` out (parry's frames are
    /// the pair's frames here; some of its generators keep farther points).
    fn take_scratch(&mut self, prediction: Real) -> GenManifold {
        let mut m = GenManifold {
            normal_a: self.scratch.local_n1,
            ..Default::default()
        };
        for p in self.scratch.points.iter().filter(|p| p.dist <= prediction) {
            m.push(GenPoint {
                local_a: p.local_p1,
                local_b: p.local_p2,
                dist: p.dist,
                id: feature_id(p.fid1.0, p.fid2.0),
            });
        }
        m
    }

    /// A plane (`a`, a half-space through its origin) against a convex shape `b`.
    fn plane_convex(
        &mut self,
        a: &dyn ParryShape,
        b: &dyn ParryShape,
        pos12: &Pose,
        prediction: Real,
    ) -> Option<GenManifold> {
        let n = a.as_halfspace()?.normal;
        if b.shape_type() == ShapeType::Ball {
            return self.convex(ShapePair::new(a, b, pos12), prediction);
        }
        let (pfm, radius) = b.as_polygonal_feature_map()?;
        // The plane's normal in b's frame, and b's deepest feature against it.
        let n_b = pos12.rotation.inverse() * -n;
        let f = &mut self.feature[0];
        pfm.local_support_feature(n_b, f);
        let mut m = GenManifold {
            normal_a: n,
            ..Default::default()
        };
        for k in 0..f.num_vertices {
            // The vertex pushed out by the rounding radius, towards the plane.
            let local_b = f.vertices[k] + n_b * radius;
            let in_a = pos12.transform_point(local_b);
            let dist = in_a.dot(n);
            if dist <= prediction {
                m.push(GenPoint {
                    local_a: in_a - n * dist,
                    local_b,
                    dist,
                    id: feature_id(u32::MAX, f.vids[k].0),
                });
            }
        }
        Some(m)
    }

    /// Two polyhedral shapes (capsules, cylinders, cones, hulls, triangles), by GJK and, when
    /// they overlap, EPA on the generator's own EPA, then parry's feature clipping.
    fn pfm_pfm(&mut self, pair: ShapePair<'_>, prediction: Real) -> Option<GenManifold> {
        let ShapePair {
            a,
            b,
            ref pos12,
            normals,
        } = pair;
        let (pfm1, r1) = a.as_polygonal_feature_map()?;
        let (pfm2, r2) = b.as_polygonal_feature_map()?;
        let total = prediction + r1 + r2;
        let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
        let mut simplex = VoronoiSimplex::new();
        simplex.reset(CsoPoint::from_shapes(pos12, pfm1, pfm2, dir));
        let mut result = gjk::closest_points(pos12, pfm1, pfm2, total, true, &mut simplex);
        if result == GJKResult::Intersection {
            result = match self.epa.closest_points(pos12, pfm1, pfm2, &simplex) {
                Some((p1, p2, n)) => GJKResult::ClosestPoints(p1, p2, n),
                None => GJKResult::NoIntersection(Vector::X),
            };
        }
        let GJKResult::ClosestPoints(p1, p2_1, dir) = result else {
            return Some(GenManifold::default());
        };
        let mut local_n1 = dir;
        let mut local_n2 = pos12.rotation.inverse() * -dir;
        // A triangle's internal edges: the normal corrected towards the face, or dropped.
        if !normals.project_local_normals(pos12, &mut local_n1, &mut local_n2) {
            return Some(GenManifold::default());
        }
        let corrected = normals.0.is_some() || normals.1.is_some();
        let unconstrained = (p2_1 - p1).dot(dir);
        let [f1, f2] = &mut self.feature;
        pfm1.local_support_feature_toward(local_n1, p1, f1);
        pfm2.local_support_feature_toward(local_n2, pos12.inverse_transform_point(p2_1), f2);
        self.scratch.clear();
        PolygonalFeature::contacts(
            pos12,
            &pos12.inverse(),
            local_n1,
            local_n2,
            f1,
            f2,
            &mut self.scratch,
            false,
        );
        if self.scratch.points.is_empty() && local_n1 == dir {
            // Features that clip to nothing (a vertex against a face): the GJK points.
            let dist = (p2_1 - p1).dot(local_n1);
            self.scratch.points.push(TrackedContact::new(
                p1,
                pos12.inverse_transform_point(p2_1),
                PackedFeatureId::UNKNOWN,
                PackedFeatureId::UNKNOWN,
                dist,
            ));
        }
        let mut m = GenManifold {
            normal_a: local_n1,
            ..Default::default()
        };
        for p in &self.scratch.points {
            let dist = p.dist - r1 - r2;
            // A corrected normal can make a depth far deeper than the shapes' own overlap
            // (the other shape reaches far along it): such points are dropped, as parry does.
            let diverged =
                corrected && unconstrained < 0.0 && p.dist < 0.0 && p.dist < 5.0 * unconstrained;
            if dist <= prediction && !diverged {
                m.push(GenPoint {
                    local_a: p.local_p1 + local_n1 * r1,
                    local_b: p.local_p2 + local_n2 * r2,
                    dist,
                    id: feature_id(p.fid1.0, p.fid2.0),
                });
            }
        }
        Some(m)
    }

    /// A height field or mesh `mesh` against a convex shape `other` placed at `pos12` in the
    /// mesh's frame: one manifold per touching triangle (its index as the sub-shape), each
    /// with the triangle's pseudo-normals so that its internal edges make no contacts.
    fn mesh(&mut self, pair: ShapePair<'_>, prediction: Real) -> bool {
        let (mesh, other, pos12) = (pair.a, pair.b, &pair.pos12);
        let local_box = other.compute_aabb(pos12).loosened(prediction);
        let visit = |g: &mut Generator,
                     id: u32,
                     tri: &Triangle,
                     normals: Option<&dyn NormalConstraints>| {
            let pair = ShapePair {
                normals: (normals, None),
                ..ShapePair::new(tri, other, pos12)
            };
            if let Some(mut m) = g.convex(pair, prediction) {
                if m.count > 0 {
                    m.sub = (id, 0);
                    g.out.push(m);
                }
            }
        };
        match mesh.shape_type() {
            ShapeType::HeightField => {
                let Some(hf) = mesh.as_heightfield() else {
                    return false;
                };
                hf.map_elements_in_local_aabb(&local_box, &mut |id, tri| {
                    let normals = hf.triangle_normal_constraints(id);
                    visit(
                        self,
                        id,
                        tri,
                        normals.as_ref().map(|n| n as &dyn NormalConstraints),
                    );
                });
            }
            ShapeType::TriMesh => {
                let Some(trimesh) = mesh.as_trimesh() else {
                    return false;
                };
                for id in trimesh.bvh().intersect_aabb(&local_box) {
                    let tri = trimesh.triangle(id);
                    let normals = trimesh.triangle_normal_constraints(id);
                    visit(
                        self,
                        id,
                        &tri,
                        normals.as_ref().map(|n| n as &dyn NormalConstraints),
                    );
                }
            }
            _ => return false,
        }
        true
    }
}

/// Swaps the roles of the two shapes of a manifold computed as (b, a) with `pos12` placing b
/// in a's frame: the normal is brought into a's frame and reversed.
fn flip(m: &mut GenManifold, pos12: &Pose) {
    // `m` was computed with b first: its normal is in b's frame, from b to a.
    m.normal_a = pos12.rotation * -m.normal_a;
    for p in &mut m.points[..m.count] {
        std::mem::swap(&mut p.local_a, &mut p.local_b);
    }
    m.sub = (m.sub.1, m.sub.0);
}
