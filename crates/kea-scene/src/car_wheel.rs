//! Building a car wheel joint: chassis and wheel, suspension, steering and drive.

use crate::bodies::v3;
use crate::error::SceneError;
use crate::joint_format::JointKind;
use crate::joint_limits::{placed, set_limits};
use kea::{BodyHandle, ConstraintHandle, World};

/// Creates the car wheel `kind` (a [`JointKind::CarWheel`]) between chassis `b1` and wheel
/// `b2`.
pub(crate) fn create(
    mut w: &mut World,
    kind: &JointKind,
    b1: BodyHandle,
    b2: Option<BodyHandle>,
    place: &str,
) -> Result<ConstraintHandle, SceneError> {
    let JointKind::CarWheel {
        steering_axis,
        axle,
        suspension: [k, d],
        suspension_limits,
        steerable,
        steering_limits,
        steering_motor,
        drive,
    } = kind
    else {
        unreachable!("called for car wheels only");
    };
    let Some(wheel) = b2 else {
        return Err(SceneError::at(
            format!("{place}.body2"),
            "a car wheel needs the wheel as body2",
        ));
    };
    if !steerable && (steering_limits.is_some() || steering_motor.is_some()) {
        return Err(SceneError::at(
            format!("{place}.steerable"),
            "steering limits or a steering motor need \"steerable\": true",
        ));
    }
    let h = w
        .create_joint(
            b1,
            Some(wheel),
            kea::JointSpec::car_wheel(v3(*steering_axis), v3(*axle), *k, *d),
        )
        .map_err(|e| placed(place, e))?;
    let j = h.wheel_mut(&mut w).map_err(|e| placed(place, e))?;
    j.steering_locked = !steerable;
    if let Some(l) = suspension_limits {
        set_limits(
            j.suspension_limit_mut(),
            l,
            &format!("{place}.suspension_limits"),
        )?;
    }
    if let Some(l) = steering_limits {
        set_limits(
            j.steering_limit_mut(),
            l,
            &format!("{place}.steering_limits"),
        )?;
    }
    if let Some([speed, torque]) = steering_motor {
        j.steering_limit_mut()
            .set_motor(*speed, *torque)
            .map_err(|e| SceneError::at(format!("{place}.steering_motor"), e))?;
    }
    if let Some([speed, torque]) = drive {
        j.drive_mut()
            .set_motor(*speed, *torque)
            .map_err(|e| SceneError::at(format!("{place}.drive"), e))?;
    }
    Ok(h.into())
}
