//! Building joints: bodies looked up and checked, each type created with its limits and motors,
//! breaking thresholds set, keyframed paths checked, and kea's errors placed on the field they
//! are about.

use crate::build::{unit, v3, BuiltScene};
use crate::error::SceneError;
use crate::joint_format::{JointKind, JointSpec, LimitSpec};
use kea::{BodyHandle, ConstraintHandle, KeaError, Limit, Real, SingleLimit, Vec3, World};

/// A scene's fixed-path joints with keyframed paths: before each step, every path is set to its
/// position now, with the velocity that reaches its next position at the end of the step.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct ScenePaths(pub(crate) Vec<PathDriver>);

impl ScenePaths {
    /// For a step of `dt` starting at scene time `time`: each path joint, where its path is now,
    /// and the velocity that takes it to where the path is at the end of the step (the values
    /// for [`World::set_path`], which the stepping pipeline writes).
    pub fn samples(
        &self,
        time: Real,
        dt: Real,
    ) -> impl Iterator<Item = (ConstraintHandle, Vec3, Vec3)> + '_ {
        self.0.iter().map(move |p| {
            let (position, velocity) = p.sample(time, dt);
            (p.joint, position, velocity)
        })
    }

    /// Whether the scene has no keyframed paths.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A fixed-path joint driven along keyframes `[t, x, y, z]` (world frame).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct PathDriver {
    /// The joint.
    pub joint: ConstraintHandle,
    /// Keyframes, t strictly increasing.
    keys: Vec<[Real; 4]>,
}

impl PathDriver {
    /// The path point at time `t`: linear between keyframes, held outside them.
    fn at(&self, t: Real) -> Vec3 {
        let p = |k: &[Real; 4]| Vec3::new(k[1], k[2], k[3]);
        let first = &self.keys[0];
        if t <= first[0] {
            return p(first);
        }
        for w in self.keys.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            if t <= b[0] {
                let s = (t - a[0]) / (b[0] - a[0]);
                return p(a).lerp(p(b), s);
            }
        }
        p(self.keys.last().expect("at least one keyframe"))
    }

    /// Where the path is at `t` and the velocity that takes it to where it is at `t + dt`.
    pub fn sample(&self, t: Real, dt: Real) -> (Vec3, Vec3) {
        let (a, b) = (self.at(t), self.at(t + dt));
        let v = if dt > 0.0 { (b - a) / dt } else { Vec3::ZERO };
        (a, v)
    }
}

/// Checks keyframes: finite, t strictly increasing.
fn check_path(keys: &[[Real; 4]], place: &str) -> Result<(), SceneError> {
    for (k, key) in keys.iter().enumerate() {
        if !key.iter().all(|x| x.is_finite()) {
            return Err(SceneError::at(
                format!("{place}.path[{k}]"),
                format!("must be finite, got {key:?}"),
            ));
        }
        if k > 0 && key[0] <= keys[k - 1][0] {
            return Err(SceneError::at(
                format!("{place}.path[{k}]"),
                format!(
                    "keyframe times must increase: t = {} after t = {}",
                    key[0],
                    keys[k - 1][0]
                ),
            ));
        }
    }
    Ok(())
}

/// The scene field a kea argument error is about, if it names one.
fn field_of(e: &KeaError) -> Option<&'static str> {
    let arg = match e {
        KeaError::NonFinite { arg, .. }
        | KeaError::OutOfRange { arg, .. }
        | KeaError::NotUnit { arg, .. } => *arg,
        _ => return None,
    };
    Some(match arg {
        "k" | "d" => "suspension",
        "max_force" => "break_force",
        "max_torque" => "break_torque",
        "primary" => "limit_axis",
        other => other,
    })
}

/// A kea error at `place`, or at the field it names.
pub(crate) fn placed(place: &str, e: KeaError) -> SceneError {
    match field_of(&e) {
        Some(f) => SceneError::at(format!("{place}.{f}"), e),
        None => SceneError::at(place, e),
    }
}

/// Records a joint's name, refusing one already taken.
pub(crate) fn name_joint(
    built: &mut BuiltScene,
    name: String,
    h: ConstraintHandle,
    place: &str,
) -> Result<(), SceneError> {
    if built.joint(&name).is_some() {
        return Err(SceneError::at(
            place,
            format!("a joint named \"{name}\" already exists"),
        ));
    }
    built.joint_index.insert(name.clone(), built.joints.len());
    built.joints.push((name, h));
    Ok(())
}

/// Sets a [`Limit`]'s stops from the scene's form.
pub(crate) fn set_limits(
    limit: &mut Limit,
    spec: &LimitSpec,
    place: &str,
) -> Result<(), SceneError> {
    let (lower, upper) = match spec {
        LimitSpec::Hard([lo, hi]) => (SingleLimit::hard(*lo, 0.0), SingleLimit::hard(*hi, 0.0)),
        LimitSpec::Stops(s) => match s.stiffness {
            Some(k) => (
                SingleLimit::soft(s.lower, k, s.damping),
                SingleLimit::soft(s.upper, k, s.damping),
            ),
            None => (
                SingleLimit::hard(s.lower, s.restitution),
                SingleLimit::hard(s.upper, s.restitution),
            ),
        },
    };
    limit
        .set_limits(lower, upper)
        .map_err(|e| SceneError::at(place, e))
}

/// Sets a [`Limit`]'s motor `[speed, max force]` if given.
fn set_motor(limit: &mut Limit, motor: Option<[Real; 2]>, place: &str) -> Result<(), SceneError> {
    if let Some([speed, force]) = motor {
        limit
            .set_motor(speed, force)
            .map_err(|e| SceneError::at(place, e))?;
    }
    Ok(())
}

/// Limits and motor given for a coordinate, at `place.limits` and `place.motor`.
fn coordinate(
    limit: &mut Limit,
    limits: Option<&LimitSpec>,
    motor: Option<[Real; 2]>,
    place: &str,
) -> Result<(), SceneError> {
    if let Some(l) = limits {
        set_limits(limit, l, &format!("{place}.limits"))?;
    }
    set_motor(limit, motor, &format!("{place}.motor"))
}

/// Looks up the joint's bodies: body 1 must exist, body 2 too if named, and differ.
fn bodies(
    built: &BuiltScene,
    j: &JointSpec,
    place: &str,
) -> Result<(BodyHandle, Option<BodyHandle>), SceneError> {
    let find = |field: &str, name: &str| {
        built.body(name).ok_or_else(|| {
            SceneError::at(
                format!("{place}.{field}"),
                format!("no body named \"{name}\""),
            )
        })
    };
    let b1 = find("body1", &j.body1)?;
    let b2 = j.body2.as_deref().map(|n| find("body2", n)).transpose()?;
    if j.body2.as_deref() == Some(j.body1.as_str()) {
        return Err(SceneError::at(
            format!("{place}.body2"),
            format!("the joint names body \"{}\" twice", j.body1),
        ));
    }
    Ok((b1, b2))
}

/// Adds joint `index` of the scene.
pub(crate) fn add_joint(
    built: &mut BuiltScene,
    j: &JointSpec,
    index: usize,
    place: &str,
) -> Result<(), SceneError> {
    let (b1, b2) = bodies(built, j, place)?;
    for (field, value) in [
        ("break_force", j.break_force),
        ("break_torque", j.break_torque),
    ] {
        if let Some(v) = value {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SceneError::at(
                    format!("{place}.{field}"),
                    format!("must be finite and ≥ 0, got {v}"),
                ));
            }
        }
    }
    let h = create(built, &j.kind, b1, b2, place)?;
    let w = &mut built.world;
    if j.break_force.is_some() || j.break_torque.is_some() {
        w.set_breakable(h, j.break_force, j.break_torque)
            .map_err(|e| placed(place, e))?;
    }
    let name = j.name.clone().unwrap_or_else(|| format!("joint{index}"));
    name_joint(built, name, h, &format!("{place}.name"))
}

/// Creates the joint of kind `kind` between `b1` and `b2` with its limits and motors.
pub(crate) fn create(
    built: &mut BuiltScene,
    kind: &JointKind,
    b1: BodyHandle,
    b2: Option<BodyHandle>,
    place: &str,
) -> Result<ConstraintHandle, SceneError> {
    let w = &mut built.world;
    let at = |e: KeaError| placed(place, e);
    let h = match kind {
        JointKind::Ball { anchor, .. } => {
            let h = w.create_ball_joint(b1, b2, v3(*anchor)).map_err(at)?;
            ball_limits(w, h, b1, kind, place)?;
            h
        }
        JointKind::Hinge {
            anchor,
            axis,
            limits,
            motor,
        } => {
            let h = w.create_hinge(b1, b2, v3(*anchor), v3(*axis)).map_err(at)?;
            let limit = w.hinge_limit_mut(h).map_err(at)?;
            coordinate(limit, limits.as_ref(), *motor, place)?;
            h
        }
        JointKind::Prismatic {
            anchor,
            axis,
            limits,
            motor,
        } => {
            let h = w
                .create_prismatic(b1, b2, v3(*anchor), v3(*axis))
                .map_err(at)?;
            let limit = w.prismatic_limit_mut(h).map_err(at)?;
            coordinate(limit, limits.as_ref(), *motor, place)?;
            h
        }
        JointKind::Fixed { anchor } => w.create_fixed_joint(b1, b2, v3(*anchor)).map_err(at)?,
        JointKind::FixedPath {
            anchor,
            fixed_orientation,
            path,
        } => {
            check_path(path, place)?;
            let h = w
                .create_fixed_path(b1, b2, v3(*anchor), *fixed_orientation)
                .map_err(at)?;
            if !path.is_empty() {
                built.paths.0.push(PathDriver {
                    joint: h,
                    keys: path.clone(),
                });
            }
            h
        }
        JointKind::Universal {
            anchor,
            axis1,
            axis2,
        } => w
            .create_universal_joint(b1, b2, v3(*anchor), v3(*axis1), v3(*axis2))
            .map_err(at)?,
        JointKind::Linear1 { anchor, normal } => w
            .create_linear1(b1, b2, v3(*anchor), v3(*normal))
            .map_err(at)?,
        JointKind::Linear2 { anchor, direction } => w
            .create_linear2(b1, b2, v3(*anchor), v3(*direction))
            .map_err(at)?,
        JointKind::CarWheel { .. } => crate::car_wheel::create(w, kind, b1, b2, place)?,
    };
    Ok(h)
}

/// The default limit axis of a ball joint: from the anchor towards body 1's centre (the limb's
/// own axis), or +y when the anchor is at the centre.
fn default_limit_axis(w: &World, b1: BodyHandle, anchor: Vec3) -> Result<Vec3, SceneError> {
    let centre = w.body(b1).map_err(|e| SceneError::at("", e))?.position();
    Ok((centre - anchor).try_normalize().unwrap_or(Vec3::Y))
}

/// Sets up the cone and twist limits of ball joint `h` (body 1 `b1`) given by `kind`, if any.
fn ball_limits(
    w: &mut World,
    h: ConstraintHandle,
    b1: BodyHandle,
    kind: &JointKind,
    place: &str,
) -> Result<(), SceneError> {
    let JointKind::Ball {
        anchor,
        cone,
        twist,
        limit_axis,
    } = kind
    else {
        return Ok(());
    };
    if cone.is_none() && twist.is_none() {
        return Ok(());
    }
    let axis = match limit_axis {
        Some(a) => unit(*a, &format!("{place}.limit_axis"))?,
        None => default_limit_axis(w, b1, v3(*anchor))?,
    };
    let orthogonal = axis.any_orthonormal_vector();
    w.set_ball_limit_axes(h, axis, orthogonal)
        .map_err(|e| placed(place, e))?;
    let limits = w.ball_limits_mut(h).map_err(|e| placed(place, e))?;
    if let Some(c) = *cone {
        if !(c.is_finite() && c > 0.0) {
            return Err(SceneError::at(
                format!("{place}.cone"),
                format!("must be > 0, got {c}"),
            ));
        }
        // The cone angle is ≥ 0; its lower stop sits out of reach.
        let (lower, upper) = (SingleLimit::hard(-1.0, 0.0), SingleLimit::hard(c, 0.0));
        limits
            .cone
            .set_limits(lower, upper)
            .map_err(|e| SceneError::at(format!("{place}.cone"), e))?;
    }
    if let Some(t) = twist {
        set_limits(&mut limits.twist, t, &format!("{place}.twist"))?;
    }
    Ok(())
}
