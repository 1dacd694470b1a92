//! Where the camera stands: a pinhole camera, and the framing of a scene's subject (its
//! bodies, their joints' anchors and the static geometry near them) so that it fills the frame
//! less a margin.

use kea::{BodyHandle, Real, Vec3, World};
use kea_collision::CollisionWorld;

/// A pinhole camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Where the eye is.
    pub eye: Vec3,
    /// The point it looks at.
    pub target: Vec3,
    /// Which way is up.
    pub up: Vec3,
    /// Vertical field of view, rad.
    pub fov_y: Real,
}

impl Camera {
    /// A camera that frames every body of `world` by its centre: it looks at the middle of
    /// their positions from above and to the side, far enough to see them all. A quick guess
    /// that knows nothing of shapes; [`Camera::framing_scene`] frames what is drawn.
    #[must_use]
    pub fn framing(world: &World) -> Self {
        let mut bounds = Bounds::EMPTY;
        for (_, b) in world.bodies() {
            bounds.add(b.position());
        }
        if bounds.is_empty() {
            bounds.add(Vec3::ZERO);
        }
        let centre = bounds.centre();
        let radius = bounds.radius().max(2.0);
        let direction = view_direction();
        Self {
            eye: centre + direction * radius * 2.6,
            target: centre,
            up: Vec3::Y,
            fov_y: 0.8,
        }
    }

    /// A camera that frames `bounds` (the scene's subject, see [`subject_bounds`]) in an
    /// image of `aspect` = width / height: [`Camera::framing_points`] of the box's corners.
    #[must_use]
    pub fn framing_bounds(bounds: &Bounds, aspect: Real, margin: Real) -> Self {
        if bounds.is_empty() {
            return Self::framing_points(&[], aspect, margin);
        }
        Self::framing_points(&bounds.corners(), aspect, margin)
    }

    /// A camera that frames `points` (the corners of what a picture shows, see
    /// [`subject_points`]) in an image of `aspect` = width / height, from above and to the
    /// side: the points, as the camera sees them, fill the frame less a margin of `margin` on
    /// each side (0.15 leaves 15% of the half-frame), the tighter of the two directions
    /// touching it. Points that are not finite are left out.
    #[must_use]
    pub fn framing_points(points: &[Vec3], aspect: Real, margin: Real) -> Self {
        let fov_y: Real = 0.8;
        let direction = view_direction();
        let mut b = Bounds::EMPTY;
        points.iter().for_each(|&p| b.add(p));
        if b.is_empty() {
            return Self {
                eye: direction * 4.0,
                target: Vec3::ZERO,
                up: Vec3::Y,
                fov_y,
            };
        }
        let mut points: Vec<Vec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
        // What is too small to see is framed as a box 10 cm across.
        let grow = (Vec3::splat(0.05) - (b.hi - b.lo) * 0.5).max(Vec3::ZERO);
        if grow != Vec3::ZERO {
            b.lo -= grow;
            b.hi += grow;
            points.extend(b.corners());
        }
        let forward = -direction;
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        // Tangents of the half-angles the points may fill.
        let fill = 1.0 - margin.clamp(0.0, 0.9);
        let tan_y = (fov_y * 0.5).tan() * fill;
        let tan_x = (fov_y * 0.5).tan() * aspect.max(0.05) * fill;
        // The nearest distance from `target` at which every point is inside the frame (and
        // ahead of the eye).
        let near = 0.1 * b.radius();
        let distance_for = |target: Vec3| {
            points
                .iter()
                .map(|&p| {
                    let q = p - target;
                    let depth = q.dot(forward);
                    let fit = (q.dot(right).abs() / tan_x).max(q.dot(up).abs() / tan_y);
                    fit.max(near) - depth
                })
                .fold(0.0, Real::max)
        };
        // Perspective shows the near side larger: move the target across the view until the
        // points' picture is centred, then back off until they fit.
        let mut target = b.centre();
        for _ in 0..4 {
            let eye = target - forward * distance_for(target);
            let (mut lo, mut hi) = (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY));
            for &p in &points {
                let q = p - eye;
                let seen = Vec3::new(q.dot(right), q.dot(up), 0.0) / q.dot(forward);
                lo = lo.min(seen);
                hi = hi.max(seen);
            }
            let middle = (lo + hi) * 0.5 * (target - eye).dot(forward);
            target += right * middle.x + up * middle.y;
        }
        Self {
            eye: target - forward * distance_for(target),
            target,
            up: Vec3::Y,
            fov_y,
        }
    }

    /// [`Camera::framing_points`] of the scene's [`subject_points`] (every body) with a 15%
    /// margin.
    #[must_use]
    pub fn framing_scene(world: &World, collision: &CollisionWorld, aspect: Real) -> Self {
        Self::framing_points(&subject_points(world, collision, |_| true), aspect, 0.15)
    }
}

/// Where cameras look from: above, to the right and in front of what they frame.
fn view_direction() -> Vec3 {
    Vec3::new(0.45, 0.8, 1.0).normalize()
}

/// An axis-aligned box that points are added to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Lowest corner.
    pub lo: Vec3,
    /// Highest corner.
    pub hi: Vec3,
}

impl Bounds {
    /// Holds nothing yet.
    pub const EMPTY: Bounds = Bounds {
        lo: Vec3::splat(Real::INFINITY),
        hi: Vec3::splat(Real::NEG_INFINITY),
    };

    /// Grows to hold `p` (a point that is not finite is left out).
    pub fn add(&mut self, p: Vec3) {
        if p.is_finite() {
            self.lo = self.lo.min(p);
            self.hi = self.hi.max(p);
        }
    }

    /// Grows to hold `other`.
    pub fn union(&mut self, other: &Bounds) {
        if !other.is_empty() {
            self.add(other.lo);
            self.add(other.hi);
        }
    }

    /// Whether no point was added.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.lo.x > self.hi.x
    }

    /// The middle.
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        (self.lo + self.hi) * 0.5
    }

    /// The eight corners.
    #[must_use]
    pub fn corners(&self) -> [Vec3; 8] {
        let (lo, hi) = (self.lo, self.hi);
        std::array::from_fn(|k| {
            Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            )
        })
    }

    /// Half the diagonal: the radius of a sphere about the centre that holds the box.
    #[must_use]
    pub fn radius(&self) -> Real {
        (self.hi - self.lo).length() * 0.5
    }
}

/// The box around what a picture of the scene is about (around [`subject_points`] of every
/// body): every collider on a body, and the static geometry near them (steps, walls, a
/// ramp), but not a ground that runs to the horizon. A scene of static geometry only is
/// framed whole.
#[must_use]
pub fn subject_bounds(world: &World, collision: &CollisionWorld) -> Bounds {
    let mut bounds = Bounds::EMPTY;
    for p in subject_points(world, collision, |_| true) {
        bounds.add(p);
    }
    bounds
}

/// What a picture of the bodies that `keep` picks (every body, or one ragdoll of three) is
/// about, as points for [`Camera::framing_points`]: the corners of the boxes around their
/// colliders, the anchors of their joints (to each other, or to the world: a cradle's frame),
/// and the corners of the static geometry near them (steps, walls, a ramp, but not a ground
/// that runs to the horizon). If `keep` picks no body, the static geometry, all of it.
#[must_use]
pub fn subject_points(
    world: &World,
    collision: &CollisionWorld,
    keep: impl Fn(BodyHandle) -> bool,
) -> Vec<Vec3> {
    let (mut dynamic, mut statics, mut points) = (Bounds::EMPTY, Vec::new(), Vec::new());
    for (handle, def) in collision.colliders() {
        let Ok((position, rotation)) = collision.collider_pose(world, handle) else {
            continue;
        };
        if def.body.is_some_and(|b| !keep(b)) {
            continue;
        }
        let (vertices, _) = def.shape.triangles();
        let mut b = Bounds::EMPTY;
        for v in &vertices {
            b.add(position + rotation * *v);
        }
        if b.is_empty() {
            continue;
        }
        if def.body.is_some() {
            dynamic.union(&b);
            points.extend(b.corners());
        } else {
            statics.push(b);
        }
    }
    if dynamic.is_empty() {
        return statics.iter().flat_map(Bounds::corners).collect();
    }
    for (h, bodies) in world.enabled_joints() {
        if !bodies.iter().flatten().any(|&b| keep(b)) {
            continue;
        }
        if let Ok(Some(sketch)) = world.joint_sketch(h) {
            for a in sketch.anchors.into_iter().filter(|a| a.is_finite()) {
                dynamic.add(a);
                points.push(a);
            }
        }
    }
    // Static pieces no bigger than the subject and within its reach join it (a ground slab
    // bigger than the pile on it does not).
    let (centre, reach) = (dynamic.centre(), dynamic.radius().max(0.5));
    for b in &statics {
        if b.radius() <= reach && (b.centre() - centre).length() <= 1.5 * reach {
            points.extend(b.corners());
        }
    }
    points
}
