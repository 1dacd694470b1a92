//! Joints and contacts drawn as solid gizmos a few pixels thick: joint anchors, axes and the
//! range their limits allow; contact points with their normals as long as the force they
//! carry. Built as coloured triangles (no window needed, so they are tested), drawn on top of
//! the scene.

use crate::app::App;
use kea::{BodyHandle, JointRange, Quat, Real, Vec3};
use kea_render::rod;

/// A coloured triangle.
pub type Piece = ([Vec3; 3], [u8; 3]);

/// Body 1's anchor.
pub const ANCHOR1: [u8; 3] = [255, 140, 0];
/// Body 2's (or the world's) anchor.
pub const ANCHOR2: [u8; 3] = [255, 230, 40];
/// A joint's axes.
pub const AXIS: [u8; 3] = [60, 120, 255];
/// The range a limit allows.
pub const RANGE: [u8; 3] = [40, 200, 90];
/// Where a limited coordinate is now.
pub const NOW: [u8; 3] = [250, 250, 250];
/// A contact point and its normal force.
pub const CONTACT: [u8; 3] = [230, 30, 30];

/// Half-width of gizmo lines as a share of their distance from the eye (about 1.5 pixels in a
/// 720-pixel window).
pub const WIDTH: Real = 0.0016;
/// Length of joint axes and radius of ranges, as a share of their distance from the eye.
pub const SIZE: Real = 0.035;
/// Longest contact normal, in multiples of the length a force of one typical weight gets.
pub const MAX_FORCE_LENGTH: Real = 3.0;

/// Gizmo triangles for one frame, sized for an eye at `eye`.
pub struct Gizmos {
    eye: Vec3,
    /// The triangles.
    pub pieces: Vec<Piece>,
}

impl Gizmos {
    /// No gizmos yet, for an eye at `eye`.
    #[must_use]
    pub fn new(eye: Vec3) -> Self {
        Self {
            eye,
            pieces: Vec::new(),
        }
    }

    fn scale(&self, p: Vec3) -> Real {
        (p - self.eye).length().max(1e-3)
    }

    /// A line from `a` to `b`, a few pixels thick.
    pub fn line(&mut self, a: Vec3, b: Vec3, colour: [u8; 3]) {
        let radius = WIDTH * self.scale(0.5 * (a + b));
        self.pieces
            .extend(rod(a, b, radius).into_iter().map(|t| (t, colour)));
    }

    /// A point: three short crossing rods.
    pub fn point(&mut self, p: Vec3, colour: [u8; 3]) {
        let r = 4.0 * WIDTH * self.scale(p);
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let radius = 2.0 * WIDTH * self.scale(p);
            self.pieces.extend(
                rod(p - axis * r, p + axis * r, radius)
                    .into_iter()
                    .map(|t| (t, colour)),
            );
        }
    }

    /// Every enabled joint of the app's scene at the drawn (interpolated) poses.
    pub fn joints(&mut self, app: &App) {
        let world = app.physics.dynamics();
        for (h, bodies) in world.enabled_joints() {
            let Ok(Some(sketch)) = world.joint_sketch(h) else {
                continue;
            };
            // The sketch is at the bodies' stepped poses; carry it to the drawn ones.
            let moved = |b: Option<BodyHandle>, p: Vec3| relocate(app, b, p, false);
            let turned = |b: Option<BodyHandle>, v: Vec3| relocate(app, b, v, true);
            let anchors = [
                moved(bodies[0], sketch.anchors[0]),
                moved(bodies[1], sketch.anchors[1]),
            ];
            for (b, (anchor, colour)) in bodies
                .iter()
                .zip([(anchors[0], ANCHOR1), (anchors[1], ANCHOR2)])
            {
                if let Some((centre, _)) = b.and_then(|b| app.body_pose(b)) {
                    self.line(centre, anchor, colour);
                }
                self.point(anchor, colour);
            }
            let size = SIZE * self.scale(anchors[1]);
            // Axes are fixed in body 2, except the first of a universal joint or a wheel.
            let first = match sketch.kind {
                "universal joint" | "car wheel joint" => bodies[0],
                _ => bodies[1],
            };
            let axis_body = [first, bodies[1]];
            let axes = [
                sketch.axes[0].map(|a| turned(axis_body[0], a)),
                sketch.axes[1].map(|a| turned(axis_body[1], a)),
            ];
            for a in axes.iter().flatten() {
                self.line(anchors[1] - *a * size, anchors[1] + *a * size, AXIS);
            }
            match sketch.range {
                Some(JointRange::Angle { zero, stops, now }) => {
                    let axis = axes[0].unwrap_or(Vec3::Y);
                    let zero = turned(bodies[1], zero);
                    self.arc(anchors[1], axis, zero, stops, size);
                    let pointer = Quat::from_axis_angle(axis, now) * zero;
                    self.line(anchors[1], anchors[1] + pointer * size * 1.2, NOW);
                }
                Some(JointRange::Slide { stops, now }) => {
                    let axis = axes[0].unwrap_or(Vec3::Y);
                    let (lo, hi) = (anchors[1] + axis * stops.0, anchors[1] + axis * stops.1);
                    self.line(lo, hi, RANGE);
                    self.point(lo, RANGE);
                    self.point(hi, RANGE);
                    self.point(anchors[1] + axis * now, NOW);
                }
                Some(JointRange::Cone {
                    axis,
                    half_angle,
                    now,
                }) => {
                    let (axis, now) = (turned(bodies[1], axis), turned(bodies[0], now));
                    self.cone(anchors[1], axis, half_angle, size);
                    self.line(anchors[1], anchors[1] + now * size * 1.2, NOW);
                }
                None => {}
            }
        }
    }

    /// An arc about `axis` through `anchor` from angle `stops.0` to `stops.1`, measured from
    /// `zero`, with spokes at its ends.
    fn arc(&mut self, anchor: Vec3, axis: Vec3, zero: Vec3, stops: (Real, Real), radius: Real) {
        let (lo, hi) = (
            stops.0.max(-4.0 * kea::PI_REAL),
            stops.1.min(4.0 * kea::PI_REAL),
        );
        let segments = ((hi - lo).abs() / 0.15).ceil().clamp(2.0, 96.0) as u32;
        let at = |k: u32| {
            let angle = lo + (hi - lo) * k as Real / segments as Real;
            anchor + Quat::from_axis_angle(axis, angle) * zero * radius
        };
        for k in 0..segments {
            self.line(at(k), at(k + 1), RANGE);
        }
        self.line(anchor, at(0), RANGE);
        self.line(anchor, at(segments), RANGE);
    }

    /// A cone of `half_angle` about `axis` from `anchor`, `length` long.
    fn cone(&mut self, anchor: Vec3, axis: Vec3, half_angle: Real, length: Real) {
        let side = axis.any_orthonormal_vector();
        let rim = |k: u32| {
            let around = Quat::from_axis_angle(axis, k as Real * kea::PI_REAL / 6.0);
            anchor + around * (Quat::from_axis_angle(side, half_angle) * axis) * length
        };
        for k in 0..12 {
            self.line(rim(k), rim(k + 1), RANGE);
            if k % 3 == 0 {
                self.line(anchor, rim(k), RANGE);
            }
        }
    }

    /// Every contact point, with a line along its normal as long as its normal force: a force
    /// of `weight` newtons gets `length` metres, up to [`MAX_FORCE_LENGTH`] times that.
    pub fn contacts(&mut self, app: &App, weight: Real, length: Real) {
        for (_, contact, _) in app.physics.dynamics().contacts() {
            let n = contact.normal();
            for (point, force) in contact.points().iter().zip(contact.forces()) {
                let p = point.position;
                self.point(p, CONTACT);
                let reach = force_length(force.normal, weight, length);
                if reach > 0.0 {
                    self.line(p, p + n * reach, CONTACT);
                }
            }
        }
    }
}

/// The length of a contact normal carrying `force` N, where a force of `weight` N gets
/// `length` m: in proportion, capped at [`MAX_FORCE_LENGTH`] times `length`, zero for a pull.
#[must_use]
pub fn force_length(force: Real, weight: Real, length: Real) -> Real {
    let weight = if weight > 0.0 { weight } else { 1.0 };
    (force / weight).clamp(0.0, MAX_FORCE_LENGTH) * length
}

/// A point (or, with `direction`, a vector) of body `b` at its stepped pose, carried to its
/// drawn pose.
fn relocate(app: &App, b: Option<BodyHandle>, p: Vec3, direction: bool) -> Vec3 {
    let Some(b) = b else { return p };
    let (Some((x, q)), Ok(body)) = (app.body_pose(b), app.physics.dynamics().body(b)) else {
        return p;
    };
    let turn = q * body.orientation().inverse();
    if direction {
        turn * p
    } else {
        x + turn * (p - body.position())
    }
}

/// The weight of the scene's median body, N (1 N in weightlessness): the force the contact
/// gizmos draw at their reference length.
#[must_use]
pub fn typical_weight(world: &kea::World) -> Real {
    let mut masses: Vec<Real> = world
        .bodies()
        .map(|(_, b)| b.mass())
        .filter(|m| m.is_finite() && *m > 0.0)
        .collect();
    if masses.is_empty() {
        return 1.0;
    }
    masses.sort_by(Real::total_cmp);
    let g = world.settings().gravity.length();
    let weight = masses[masses.len() / 2] * g;
    if weight > 0.0 {
        weight
    } else {
        1.0
    }
}
