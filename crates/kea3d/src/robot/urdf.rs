//! URDF (the ROS robot description): links with their inertial frames and collision geometry,
//! joined by `revolute`, `continuous`, `prismatic`, `fixed`, `floating` and `planar` joints
//! with limits and dynamics. Visual geometry, materials, transmissions and Gazebo tags are not
//! physics and are passed over; `mimic` and `safety_controller` are reported as skipped.

use super::mesh;
use super::spec::{
    Coordinate, GeomShape, GeomSpec, Inertial, JointSpec, JointType, LinkSpec, Pose, RobotSpec,
    WORLD,
};
use super::xml::{child, children, rpy, Source};
use super::{ImportError, UrdfOptions};
use kea::{JointDynamics, Mat3, Real, Vec3};
use roxmltree::Node;
use std::path::Path;

/// Reads a URDF file into a robot spec.
pub(crate) fn read(file: &Path, options: &UrdfOptions) -> Result<RobotSpec, ImportError> {
    let text = super::xml::read_text(file)?;
    parse(&text, file, options)
}

/// Parses URDF text; `file` names it in errors and anchors relative mesh paths.
pub(crate) fn parse(
    text: &str,
    file: &Path,
    options: &UrdfOptions,
) -> Result<RobotSpec, ImportError> {
    let text = super::xml::tidy(text);
    let doc = super::xml::parse_document(&text, file)?;
    let src = Source { file, doc: &doc };
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" {
        return Err(src.error(robot, "a URDF file's root element must be <robot>"));
    }
    let mut spec = RobotSpec::new(robot.attribute("name").unwrap_or("robot"), false);
    let mut world_link = false;
    for link in children(robot, "link") {
        let name = src.required(link, "name")?;
        if name == WORLD && !world_link {
            // ROS's convention: a link named "world" is the world, and a joint to it fixes
            // the robot's base. Its geometry is static.
            world_link = true;
            spec.links[0].geoms = read_link(&src, link, options, &mut spec.skipped)?.geoms;
            continue;
        }
        if spec.links.iter().skip(1).any(|l| l.name == name) || name == WORLD {
            return Err(src.error(link, format!("a second link named \"{name}\"")));
        }
        let read = read_link(&src, link, options, &mut spec.skipped)?;
        spec.links.push(read);
    }
    if spec.links.len() == 1 {
        return Err(src.error(robot, "the robot has no <link>"));
    }
    for joint in children(robot, "joint") {
        let j = read_joint(&src, joint, &spec)?;
        if let Some(note) = empty_limits(&src, joint, &j)? {
            spec.skipped.push(note);
        }
        if spec.joints.iter().any(|o| o.name == j.name) {
            return Err(src.error(joint, format!("a second joint named \"{}\"", j.name)));
        }
        if let Some(other) = spec.joints.iter().find(|o| o.child == j.child) {
            return Err(src.error(
                joint,
                format!(
                    "link \"{}\" already has a parent joint (\"{}\"): a URDF is a tree, and a \
                     second parent would close a loop",
                    spec.links[j.child].name, other.name
                ),
            ));
        }
        for tag in ["mimic", "safety_controller", "calibration"] {
            if let Some(n) = child(joint, tag) {
                spec.skipped.push(format!(
                    "{}:{}: <{tag}> of joint \"{}\": not supported, left out",
                    file.display(),
                    src.line(n),
                    j.name
                ));
            }
        }
        spec.joints.push(j);
    }
    attach_root(&src, robot, &mut spec, options, world_link)?;
    Ok(spec)
}

/// Hangs the root link (the one link no joint has as child) from the world: welded at the
/// base pose, or free. Refuses a file whose joints do not make one tree.
fn attach_root(
    src: &Source<'_>,
    robot: Node<'_, '_>,
    spec: &mut RobotSpec,
    options: &UrdfOptions,
    world_link: bool,
) -> Result<(), ImportError> {
    let roots: Vec<usize> = (1..spec.links.len())
        .filter(|&l| !spec.joints.iter().any(|j| j.child == l))
        .collect();
    let root = match roots.as_slice() {
        [] if world_link => 0,
        [r] => *r,
        [] => {
            return Err(src.error(
                robot,
                "every link has a parent joint: the joints make a loop",
            ))
        }
        many => {
            let names: Vec<&str> = many.iter().map(|&l| spec.links[l].name.as_str()).collect();
            return Err(src.error(
                robot,
                format!(
                    "the links do not make one tree: {} have no parent joint",
                    names.join(", ")
                ),
            ));
        }
    };
    // Every link must hang from the root (a loop among the others leaves them unreached).
    let mut reached = vec![false; spec.links.len()];
    let mut stack = vec![root];
    while let Some(l) = stack.pop() {
        reached[l] = true;
        stack.extend(
            spec.joints
                .iter()
                .filter(|j| j.parent == l)
                .map(|j| j.child),
        );
    }
    if let Some(l) = (1..spec.links.len()).find(|&l| !reached[l]) {
        return Err(src.error(
            robot,
            format!(
                "link \"{}\" is on a loop of joints, not on the tree from \"{}\"",
                spec.links[l].name, spec.links[root].name
            ),
        ));
    }
    if root == 0 {
        return Ok(()); // the file welds its base to the world itself
    }
    let base = Pose::new(options.base_position, options.base_rotation.normalize());
    let name = format!("{}_base", spec.links[root].name);
    spec.joints.insert(
        0,
        JointSpec {
            name: name.clone(),
            line: 0,
            parts: vec![name],
            kind: if options.fixed_base {
                JointType::Fixed
            } else {
                JointType::Free
            },
            parent: 0,
            child: root,
            origin: base,
            anchor: Vec3::ZERO,
            coords: Vec::new(),
        },
    );
    Ok(())
}

/// An `<origin xyz rpy>` child as a pose (identity without one).
fn origin(src: &Source<'_>, node: Node<'_, '_>) -> Result<Pose, ImportError> {
    let Some(o) = child(node, "origin") else {
        return Ok(Pose::IDENTITY);
    };
    let xyz = src.vec3(o, "xyz")?.unwrap_or(Vec3::ZERO);
    let [r, p, y] = src.numbers::<3>(o, "rpy")?.unwrap_or([0.0; 3]);
    Ok(Pose::new(xyz, rpy(r, p, y)))
}

/// A link; what the report should say about it goes to `notes`.
fn read_link(
    src: &Source<'_>,
    link: Node<'_, '_>,
    options: &UrdfOptions,
    notes: &mut Vec<String>,
) -> Result<LinkSpec, ImportError> {
    let name = src.required(link, "name")?.to_string();
    let inertial = match child(link, "inertial") {
        None => Inertial::NONE,
        Some(node) => read_inertial(src, node, notes)?,
    };
    let mut geoms = Vec::new();
    for c in children(link, "collision") {
        let pose = origin(src, c)?;
        let Some(g) = child(c, "geometry") else {
            return Err(src.error(c, "<collision> without <geometry>"));
        };
        let Some(shape) = g.children().find(|n| n.is_element()) else {
            return Err(src.error(g, "<geometry> names no shape"));
        };
        geoms.push(GeomSpec {
            shape: read_shape(src, shape, options)?,
            pose,
            groups: 1,
            mask: u32::MAX,
            friction: None,
            condim: None,
            density: None,
            mass: None,
            skin: 0.0,
        });
    }
    Ok(LinkSpec {
        name,
        line: src.line(link),
        inertial: Some(inertial),
        geoms,
    })
}

/// A link's `<inertial>`. A tensor no body can have is refused; one breaking only the
/// triangle inequality is kept, as PyBullet does, and named in `notes` (the load report).
fn read_inertial(
    src: &Source<'_>,
    node: Node<'_, '_>,
    notes: &mut Vec<String>,
) -> Result<Inertial, ImportError> {
    let frame = origin(src, node)?;
    let mass = match child(node, "mass") {
        Some(m) => src
            .non_negative(m, "value")?
            .ok_or_else(|| src.error(m, "the attribute `value` is missing (the mass, kg)"))?,
        None => 0.0,
    };
    let inertia = match child(node, "inertia") {
        None => Mat3::ZERO,
        Some(i) => {
            let get = |a: &str| src.number(i, a).map(|v| v.unwrap_or(0.0));
            let (xx, xy, xz, yy, yz, zz) = (
                get("ixx")?,
                get("ixy")?,
                get("ixz")?,
                get("iyy")?,
                get("iyz")?,
                get("izz")?,
            );
            if xx < 0.0 || yy < 0.0 || zz < 0.0 {
                return Err(src.error(
                    i,
                    format!("a negative moment of inertia: ixx {xx}, iyy {yy}, izz {zz}"),
                ));
            }
            let tensor = Mat3::from_cols(
                Vec3::new(xx, xy, xz),
                Vec3::new(xy, yy, yz),
                Vec3::new(xz, yz, zz),
            );
            match super::inertia_check::check(tensor) {
                Err(reason) => return Err(src.error(i, reason)),
                Ok(Some(note)) => notes.push(format!(
                    "{}:{}: <inertia>: {note}: kept as given (PyBullet reads it; MuJoCo refuses it)",
                    src.file.display(),
                    src.line(i)
                )),
                Ok(None) => {}
            }
            let r = Mat3::from_quat(frame.rotation);
            r * tensor * r.transpose()
        }
    };
    Ok(Inertial {
        mass,
        com: frame.translation,
        inertia,
    })
}

fn positive(src: &Source<'_>, node: Node<'_, '_>, attr: &str) -> Result<Real, ImportError> {
    src.required(node, attr)?;
    match src.number(node, attr)? {
        Some(v) if v > 0.0 => Ok(v),
        v => Err(src.error(
            node,
            format!("`{attr}` = {}: must be > 0", v.unwrap_or(0.0)),
        )),
    }
}

fn read_shape(
    src: &Source<'_>,
    shape: Node<'_, '_>,
    options: &UrdfOptions,
) -> Result<GeomShape, ImportError> {
    Ok(match shape.tag_name().name() {
        "box" => {
            src.required(shape, "size")?;
            let size = src.vec3(shape, "size")?.unwrap_or(Vec3::ONE);
            if size.min_element() <= 0.0 {
                return Err(src.error(shape, format!("`size` = {size}: every side must be > 0")));
            }
            GeomShape::Cuboid(size * 0.5)
        }
        "sphere" => GeomShape::Sphere(positive(src, shape, "radius")?),
        "cylinder" => GeomShape::Cylinder {
            radius: positive(src, shape, "radius")?,
            half_length: 0.5 * positive(src, shape, "length")?,
        },
        // PyBullet's extension: the plane z = 0 of the collision frame (its `normal` turns it).
        "plane" => {
            let normal = src.direction(shape, "normal")?.unwrap_or(Vec3::Z);
            if (normal - Vec3::Z).length() > 1e-6 {
                return Err(src.error(shape, format!("a plane's normal {normal} must be 0 0 1 (turn it with the collision's origin)")));
            }
            GeomShape::Plane
        }
        "capsule" => GeomShape::Capsule {
            radius: positive(src, shape, "radius")?,
            half_length: 0.5 * positive(src, shape, "length")?,
        },
        "mesh" => {
            let name = src.required(shape, "filename")?;
            let scale = src.vec3(shape, "scale")?.unwrap_or(Vec3::ONE);
            let path = mesh::resolve(name, src.file, &options.mesh_search_path).ok_or_else(|| {
                src.error(shape, format!("mesh \"{name}\" not found (looked beside the file and in the search path)"))
            })?;
            let m = mesh::load(&path, scale).map_err(|e| src.error(shape, e.to_string()))?;
            if options.meshes_as_trimesh {
                GeomShape::Mesh(m.vertices, m.triangles)
            } else {
                GeomShape::Hull(m.vertices, m.triangles)
            }
        }
        other => {
            return Err(src.error(
                shape,
                format!("geometry <{other}> is not a URDF shape (box, cylinder, sphere, mesh)"),
            ))
        }
    })
}

fn read_joint(
    src: &Source<'_>,
    joint: Node<'_, '_>,
    spec: &RobotSpec,
) -> Result<JointSpec, ImportError> {
    let name = src.required(joint, "name")?.to_string();
    let kind = match src.required(joint, "type")? {
        "revolute" => JointType::Revolute,
        "continuous" => JointType::Continuous,
        "prismatic" => JointType::Prismatic,
        "fixed" => JointType::Fixed,
        "floating" => JointType::Free,
        "planar" => JointType::Planar,
        // PyBullet's extension: a ball joint.
        "spherical" => JointType::Ball,
        other => {
            return Err(src.error(
                joint,
                format!("joint type \"{other}\" is not a URDF joint type (revolute, continuous, prismatic, fixed, floating, planar; spherical as PyBullet reads it)"),
            ))
        }
    };
    let link_of = |tag: &'static str| -> Result<usize, ImportError> {
        let node =
            child(joint, tag).ok_or_else(|| src.error(joint, format!("<{tag}> is missing")))?;
        let link = src.required(node, "link")?;
        spec.links
            .iter()
            .position(|l| l.name == link)
            .ok_or_else(|| src.error(node, format!("no link named \"{link}\"")))
    };
    let (parent, child_link) = (link_of("parent")?, link_of("child")?);
    if parent == child_link {
        return Err(src.error(joint, "a joint cannot join a link to itself"));
    }
    if child_link == 0 {
        return Err(src.error(joint, "the world link cannot be a joint's child"));
    }
    let c = read_coordinate(src, joint, kind)?;
    let axis = c.axis;
    let coords = match kind {
        JointType::Revolute | JointType::Continuous | JointType::Prismatic => vec![c],
        JointType::Planar => {
            // Travel along two directions in the plane normal to the axis, and the turn.
            let (e1, e2) = kea::math::orthonormal_basis(axis);
            vec![
                Coordinate {
                    axis: e1,
                    limits: None,
                    ..c
                },
                Coordinate {
                    axis: e2,
                    limits: None,
                    ..c
                },
                Coordinate { limits: None, ..c },
            ]
        }
        _ => Vec::new(),
    };
    Ok(JointSpec {
        parts: vec![name.clone()],
        name,
        line: src.line(joint),
        kind,
        parent,
        child: child_link,
        origin: origin(src, joint)?,
        anchor: Vec3::ZERO,
        coords,
    })
}

/// A revolute or prismatic joint's `<limit>` whose `lower` is not below its `upper` (but for
/// both left at 0): the joint is left unlimited, as PyBullet reads it, and the report says so.
fn empty_limits(
    src: &Source<'_>,
    joint: Node<'_, '_>,
    j: &JointSpec,
) -> Result<Option<String>, ImportError> {
    let Some(limit) = child(joint, "limit") else {
        return Ok(None);
    };
    if !matches!(j.kind, JointType::Revolute | JointType::Prismatic) {
        return Ok(None);
    }
    let (lower, upper) = (src.number(limit, "lower")?, src.number(limit, "upper")?);
    if lower.is_none() && upper.is_none() {
        return Ok(None);
    }
    let (lower, upper) = (lower.unwrap_or(0.0), upper.unwrap_or(0.0));
    Ok((lower >= upper).then(|| {
        format!(
            "{}:{}: <limit> of joint \"{}\": lower {lower} is not below upper {upper}: the joint is unlimited (PyBullet's reading)",
            src.file.display(),
            src.line(limit),
            j.name
        )
    }))
}

/// A joint's axis (in its frame: the child's), limits, effort and speed, and dynamics.
fn read_coordinate(
    src: &Source<'_>,
    joint: Node<'_, '_>,
    kind: JointType,
) -> Result<Coordinate, ImportError> {
    let moves_along_axis = !matches!(kind, JointType::Fixed | JointType::Free);
    let axis = match child(joint, "axis") {
        Some(a) if moves_along_axis => src.direction(a, "xyz")?.unwrap_or(Vec3::X),
        _ => Vec3::X,
    };
    let mut c = Coordinate::along(axis);
    if let Some(limit) = child(joint, "limit") {
        let lower = src.number(limit, "lower")?.unwrap_or(0.0);
        let upper = src.number(limit, "upper")?.unwrap_or(0.0);
        if matches!(kind, JointType::Revolute | JointType::Prismatic) && lower < upper {
            c.limits = Some((lower, upper));
        }
        c.effort = src.non_negative(limit, "effort")?;
        c.speed = src.non_negative(limit, "velocity")?;
    }
    if let Some(d) = child(joint, "dynamics") {
        c.dynamics = JointDynamics {
            armature: 0.0,
            stiffness: 0.0,
            rest: 0.0,
            damping: src.non_negative(d, "damping")?.unwrap_or(0.0),
            friction: src.non_negative(d, "friction")?.unwrap_or(0.0),
            soft_limit: None,
        };
    }
    Ok(c)
}
