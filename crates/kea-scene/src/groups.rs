//! Groups: repeated structures (pyramids, grids, chains, ragdolls) expanded into named bodies
//! and joints when the scene is built.

use crate::bodies::{add_body, v3, BuiltScene};
use crate::error::SceneError;
use crate::format::{BodySpec, ColliderSpec, ShapeSpec, V3};
use crate::joint_format::{GroupSpec, JointKind, LimitSpec, OneCoordinateSpec};
use crate::joints::{create, name_joint};
use kea::{BodyHandle, Quat, Real, Vec3};

/// How many bodies a group expands into.
pub(crate) fn group_size(g: &GroupSpec) -> usize {
    match g {
        GroupSpec::Pyramid { base, .. } => (*base as usize).saturating_mul(*base as usize + 1) / 2,
        GroupSpec::Chain { links, .. } => *links as usize,
        GroupSpec::Grid { counts, .. } => counts
            .iter()
            .fold(1_usize, |n, &c| n.saturating_mul(c as usize)),
        GroupSpec::Ragdoll { .. } => RAGDOLL_PARTS.len(),
    }
}

/// A body of one shape at its centre, at rest: what groups are made of.
fn one_shape_body(name: String, shape: ShapeSpec, density: Real, position: V3) -> BodySpec {
    BodySpec {
        name,
        shapes: vec![ColliderSpec {
            shape,
            offset: [0.0; 3],
            orientation: None,
            material: None,
        }],
        density: Some(density),
        mass: None,
        position,
        orientation: None,
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        damping: [0.0; 2],
        inertia: None,
        fast_spin_axis: None,
        enabled: true,
        prefer_exact: false,
    }
}

/// Adds group `index`: its bodies and joints, named `<kind><index>.<i>` (a ragdoll's
/// `ragdoll<index>.<part>`).
pub(crate) fn add_group(
    built: &mut BuiltScene,
    g: &GroupSpec,
    index: usize,
    place: &str,
) -> Result<(), SceneError> {
    expand_group(built, g, index, place).map_err(|e| field_of_group(e, g, place))
}

/// Re-places an error from building a group's bodies on the group's own field: the bodies'
/// places (`.shapes[0].shape`, `.shapes`) do not exist in the file.
fn field_of_group(e: SceneError, g: &GroupSpec, place: &str) -> SceneError {
    let SceneError::Invalid { place: at, message } = e else {
        return e;
    };
    let (kind, shape_field) = match g {
        GroupSpec::Pyramid { .. } => ("pyramid", "half_extent"),
        GroupSpec::Grid { .. } => ("grid", "shape"),
        GroupSpec::Chain { .. } => ("chain", "radius"),
        GroupSpec::Ragdoll { .. } => ("ragdoll", "scale"),
    };
    let field = match at.strip_prefix(place) {
        Some(".shapes[0].shape") => Some(shape_field),
        Some(".shapes" | ".mass") => Some("density"),
        Some(".orientation") => Some("orientation"),
        Some(".name") => None,
        _ => return SceneError::Invalid { place: at, message },
    };
    let place = match field {
        Some(f) => format!("{place}.{kind}.{f}"),
        None => format!("{place}.{kind}"),
    };
    SceneError::Invalid { place, message }
}

fn expand_group(
    built: &mut BuiltScene,
    g: &GroupSpec,
    index: usize,
    place: &str,
) -> Result<(), SceneError> {
    let named = |kind: &str, i: usize| format!("{kind}{index}.{i}");
    match *g {
        GroupSpec::Pyramid {
            base,
            half_extent,
            density,
            origin,
        } => add_pyramid(built, base, half_extent, density, origin, index, place)?,
        GroupSpec::Grid {
            ref shape,
            counts,
            spacing,
            density,
            origin,
        } => {
            let (nx, ny) = (counts[0] as usize, counts[1] as usize);
            for i in 0..nx * ny * counts[2] as usize {
                let cell = [i % nx, (i / nx) % ny, i / (nx * ny)];
                let spec = one_shape_body(
                    named("grid", i),
                    shape.clone(),
                    density,
                    std::array::from_fn(|k| origin[k] + cell[k] as Real * spacing[k]),
                );
                add_body(built, &spec, &[], place)?;
            }
        }
        GroupSpec::Chain {
            links,
            spacing,
            radius,
            density,
            origin,
        } => {
            let link = |i| named("chain", i);
            add_chain(
                built,
                links,
                spacing,
                ShapeSpec::Sphere { radius },
                density,
                origin,
                &link,
                place,
            )?;
        }
        GroupSpec::Ragdoll {
            origin,
            orientation,
            scale,
            density,
        } => {
            let q = orientation.unwrap_or([0.0, 0.0, 0.0, 1.0]);
            let pose = Pose {
                origin: v3(origin),
                rotation: Quat::from_xyzw(q[0], q[1], q[2], q[3]),
                scale,
            };
            add_ragdoll(built, &pose, density, &format!("ragdoll{index}"), place)?;
        }
    }
    Ok(())
}

/// One capsule of the ragdoll: name, centre, half height, radius, whether it lies along x.
type Part = (&'static str, [Real; 3], Real, Real, bool);

/// The figure at scale 1, pelvis centre at the origin, facing +z (its left is +x).
const RAGDOLL_PARTS: [Part; 11] = [
    ("pelvis", [0.0, 0.0, 0.0], 0.08, 0.1, true),
    ("torso", [0.0, 0.35, 0.0], 0.12, 0.13, false),
    ("head", [0.0, 0.8, 0.0], 0.03, 0.1, false),
    ("left_upper_arm", [0.27, 0.4, 0.0], 0.1, 0.05, false),
    ("left_lower_arm", [0.27, 0.105, 0.0], 0.1, 0.045, false),
    ("right_upper_arm", [-0.27, 0.4, 0.0], 0.1, 0.05, false),
    ("right_lower_arm", [-0.27, 0.105, 0.0], 0.1, 0.045, false),
    ("left_upper_leg", [0.1, -0.28, 0.0], 0.14, 0.07, false),
    ("left_lower_leg", [0.1, -0.7, 0.0], 0.15, 0.06, false),
    ("right_upper_leg", [-0.1, -0.28, 0.0], 0.14, 0.07, false),
    ("right_lower_leg", [-0.1, -0.7, 0.0], 0.15, 0.06, false),
];

/// How a ragdoll joint bends: a ball joint's cone and symmetric twist, or a hinge about the
/// figure's x axis with its limits.
#[derive(Clone, Copy)]
enum Bend {
    Ball { cone: Real, twist: Real },
    Hinge { lower: Real, upper: Real },
}

/// The joints: name, child (body 1), parent (body 2), anchor at scale 1, how it bends.
const RAGDOLL_JOINTS: [(&str, &str, &str, [Real; 3], Bend); 10] = [
    (
        "waist",
        "torso",
        "pelvis",
        [0.0, 0.1, 0.0],
        Bend::Ball {
            cone: 0.4,
            twist: 0.3,
        },
    ),
    (
        "neck",
        "head",
        "torso",
        [0.0, 0.66, 0.0],
        Bend::Ball {
            cone: 0.5,
            twist: 0.5,
        },
    ),
    (
        "left_shoulder",
        "left_upper_arm",
        "torso",
        [0.27, 0.55, 0.0],
        Bend::Ball {
            cone: 1.4,
            twist: 0.6,
        },
    ),
    (
        "right_shoulder",
        "right_upper_arm",
        "torso",
        [-0.27, 0.55, 0.0],
        Bend::Ball {
            cone: 1.4,
            twist: 0.6,
        },
    ),
    (
        "left_elbow",
        "left_lower_arm",
        "left_upper_arm",
        [0.27, 0.25, 0.0],
        Bend::Hinge {
            lower: -2.5,
            upper: 0.05,
        },
    ),
    (
        "right_elbow",
        "right_lower_arm",
        "right_upper_arm",
        [-0.27, 0.25, 0.0],
        Bend::Hinge {
            lower: -2.5,
            upper: 0.05,
        },
    ),
    (
        "left_hip",
        "left_upper_leg",
        "pelvis",
        [0.1, -0.07, 0.0],
        Bend::Ball {
            cone: 1.0,
            twist: 0.3,
        },
    ),
    (
        "right_hip",
        "right_upper_leg",
        "pelvis",
        [-0.1, -0.07, 0.0],
        Bend::Ball {
            cone: 1.0,
            twist: 0.3,
        },
    ),
    (
        "left_knee",
        "left_lower_leg",
        "left_upper_leg",
        [0.1, -0.49, 0.0],
        Bend::Hinge {
            lower: -0.05,
            upper: 2.4,
        },
    ),
    (
        "right_knee",
        "right_lower_leg",
        "right_upper_leg",
        [-0.1, -0.49, 0.0],
        Bend::Hinge {
            lower: -0.05,
            upper: 2.4,
        },
    ),
];

/// Where a ragdoll stands: its origin, orientation and scale.
struct Pose {
    origin: Vec3,
    rotation: Quat,
    scale: Real,
}

impl Pose {
    fn point(&self, p: [Real; 3]) -> Vec3 {
        self.origin + self.rotation * (Vec3::from(p) * self.scale)
    }
    fn to_v3(v: Vec3) -> V3 {
        [v.x, v.y, v.z]
    }
}

/// Adds a ragdoll's bodies `prefix.part` and joints `prefix.joint`.
fn add_ragdoll(
    built: &mut BuiltScene,
    pose: &Pose,
    density: Real,
    prefix: &str,
    place: &str,
) -> Result<(), SceneError> {
    if !(pose.scale.is_finite() && pose.scale > 0.0) {
        return Err(SceneError::at(
            format!("{place}.ragdoll.scale"),
            format!("must be > 0, got {}", pose.scale),
        ));
    }
    let along_x = Quat::from_rotation_z(std::f64::consts::FRAC_PI_2 as Real);
    for (name, centre, half_height, radius, lying) in RAGDOLL_PARTS {
        let q = if lying {
            pose.rotation * along_x
        } else {
            pose.rotation
        };
        let shape = ShapeSpec::Capsule {
            half_height: half_height * pose.scale,
            radius: radius * pose.scale,
        };
        let mut spec = one_shape_body(
            format!("{prefix}.{name}"),
            shape,
            density,
            Pose::to_v3(pose.point(centre)),
        );
        spec.orientation = Some([q.x, q.y, q.z, q.w]);
        spec.prefer_exact = true;
        add_body(built, &spec, &[], place)?;
    }
    for (name, child, parent, anchor, bend) in RAGDOLL_JOINTS {
        let body = |part: &str| -> BodyHandle {
            built
                .body(&format!("{prefix}.{part}"))
                .expect("the ragdoll's parts were just added")
        };
        let (b1, b2) = (body(child), body(parent));
        let anchor = Pose::to_v3(pose.point(anchor));
        let kind = match bend {
            Bend::Ball { cone, twist } => JointKind::Ball {
                anchor,
                cone: Some(cone),
                twist: Some(LimitSpec::Hard([-twist, twist])),
                limit_axis: None,
            },
            Bend::Hinge { lower, upper } => JointKind::Hinge(OneCoordinateSpec {
                anchor,
                axis: Pose::to_v3(pose.rotation * Vec3::X),
                limits: Some(LimitSpec::Hard([lower, upper])),
                motor: None,
            }),
        };
        let h = create(built, &kind, b1, Some(b2), place)?;
        name_joint(built, format!("{prefix}.{name}"), h, place)?;
    }
    Ok(())
}

/// A chain of `links` bodies of `shape` hanging from `origin` along −y, each ball-jointed to the
/// one above (the first to the world); bodies and joints are named `name(i)`.
#[allow(clippy::too_many_arguments)]
fn add_chain(
    built: &mut BuiltScene,
    links: u32,
    spacing: Real,
    shape: ShapeSpec,
    density: Real,
    origin: V3,
    name: &dyn Fn(usize) -> String,
    place: &str,
) -> Result<(), SceneError> {
    let mut previous: Option<BodyHandle> = None;
    for i in 0..links as usize {
        let centre = [
            origin[0],
            origin[1] - spacing * (i as Real + 0.5),
            origin[2],
        ];
        let spec = one_shape_body(name(i), shape.clone(), density, centre);
        add_body(built, &spec, &[], place)?;
        let h = built.bodies.last().expect("just added").1;
        let anchor = Vec3::new(centre[0], centre[1] + 0.5 * spacing, centre[2]);
        let j = built
            .world
            .create_joint(h, previous, kea::JointSpec::ball(anchor))
            .map_err(|e| SceneError::at(place, e))?;
        name_joint(built, name(i), j, place)?;
        previous = Some(h);
    }
    Ok(())
}

/// A pyramid of `base` cubes in its bottom row, named `pyramid<index>.<i>`.
fn add_pyramid(
    built: &mut BuiltScene,
    base: u32,
    half_extent: Real,
    density: Real,
    origin: V3,
    index: usize,
    place: &str,
) -> Result<(), SceneError> {
    let mut made = 0;
    let edge = 2.0 * half_extent;
    for layer in 0..base {
        let n = base - layer;
        for i in 0..n {
            let x = origin[0] + (i as Real - (n as Real - 1.0) * 0.5) * edge;
            let y = origin[1] + half_extent + layer as Real * edge;
            let cube = ShapeSpec::Box {
                half_extents: [half_extent; 3],
            };
            let name = format!("pyramid{index}.{made}");
            let spec = one_shape_body(name, cube, density, [x, y, origin[2]]);
            add_body(built, &spec, &[], place)?;
            made += 1;
        }
    }
    Ok(())
}
