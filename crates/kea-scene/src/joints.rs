//! Building joints: bodies looked up and checked, each type created with its limits and motors,
//! breaking thresholds set, keyframed paths checked, and kea's errors placed on the field they
//! are about.

use crate::bodies::{unit, v3, BuiltScene};
use crate::error::SceneError;
use crate::joint_format::{JointKind, JointSpec, LimitSpec, OneCoordinateSpec};
use crate::joint_limits::{placed, set_limits, set_motor};
use crate::paths::{check_path, PathDriver};
use kea::{BodyHandle, ConstraintHandle, KeaError, Limit, Real, SingleLimit, Vec3, World};

/// Records a joint's name, refusing one already taken.
pub(crate) fn name_joint(
    built: &mut BuiltScene,
    name: String,
    h: impl Into<ConstraintHandle>,
    place: &str,
) -> Result<(), SceneError> {
    let h = h.into();
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
            let h = w
                .create_joint(b1, b2, kea::JointSpec::ball(v3(*anchor)))
                .map_err(at)?;
            ball_limits(w, h, b1, kind, place)?;
            h.raw()
        }
        JointKind::Hinge(c) => {
            let spec = kea::JointSpec::hinge(v3(c.anchor), v3(c.axis));
            one_coordinate(w, (b1, b2), spec, c, place)?
        }
        JointKind::Prismatic(c) => {
            let spec = kea::JointSpec::prismatic(v3(c.anchor), v3(c.axis));
            one_coordinate(w, (b1, b2), spec, c, place)?
        }
        JointKind::Fixed { anchor } => {
            plain(w, (b1, b2), kea::JointSpec::fixed(v3(*anchor)), place)?
        }
        JointKind::FixedPath {
            anchor,
            fixed_orientation,
            path,
        } => {
            check_path(path, place)?;
            let spec = kea::JointSpec::fixed_path(v3(*anchor), *fixed_orientation);
            let h = w.create_joint(b1, b2, spec).map_err(at)?;
            if !path.is_empty() {
                let keys = path.clone();
                built.paths.0.push(PathDriver { joint: h, keys });
            }
            h.raw()
        }
        JointKind::Universal {
            anchor,
            axis1,
            axis2,
        } => {
            let spec = kea::JointSpec::universal(v3(*anchor), v3(*axis1), v3(*axis2));
            plain(w, (b1, b2), spec, place)?
        }
        JointKind::Linear1 { anchor, normal } => plain(
            w,
            (b1, b2),
            kea::JointSpec::linear1(v3(*anchor), v3(*normal)),
            place,
        )?,
        JointKind::Linear2 { anchor, direction } => {
            let spec = kea::JointSpec::linear2(v3(*anchor), v3(*direction));
            plain(w, (b1, b2), spec, place)?
        }
        JointKind::CarWheel { .. } => crate::car_wheel::create(w, kind, b1, b2, place)?,
    };
    Ok(h)
}

/// Creates a joint that takes nothing more than its spec.
fn plain<J: kea::JointKind>(
    w: &mut World,
    (b1, b2): (BodyHandle, Option<BodyHandle>),
    spec: kea::JointSpec<J>,
    place: &str,
) -> Result<ConstraintHandle, SceneError> {
    let h = w.create_joint(b1, b2, spec).map_err(|e| placed(place, e))?;
    Ok(h.raw())
}

/// Creates a hinge or a slider and sets its limits and motor from the scene.
fn one_coordinate<J: kea::OneCoordinate>(
    w: &mut World,
    (b1, b2): (BodyHandle, Option<BodyHandle>),
    spec: kea::JointSpec<J>,
    scene: &OneCoordinateSpec,
    place: &str,
) -> Result<ConstraintHandle, SceneError> {
    let h = w.create_joint(b1, b2, spec).map_err(|e| placed(place, e))?;
    let limit = h.limit_mut(w).map_err(|e| placed(place, e))?;
    coordinate(limit, scene.limits.as_ref(), scene.motor, place)?;
    Ok(h.raw())
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
    h: kea::JointHandle<kea::BallJoint>,
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
    h.set_limit_axes(w, axis, orthogonal)
        .map_err(|e| placed(place, e))?;
    let limits = h.limits_mut(w).map_err(|e| placed(place, e))?;
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
