//! A loaded robot: its links and joints by name, and its joint coordinates as one vector in
//! the file's joint order (MuJoCo's `qpos` and `qvel`), read from and written to the world's
//! bodies by forward kinematics.

use super::spec::{Coordinate, JointType, Pose};
use super::xml::above;
use crate::{PhysicsWorld, Result};
use kea::{
    BodyHandle, ConstraintHandle, Hinge, JointHandle, KeaError, Mat3, Planar, Quat, Real, Vec3,
};
use kea_collision::ColliderHandle;

/// A link of a loaded robot.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RobotLink {
    /// The link's name in the file.
    pub name: String,
    /// The body that carries it (links welded together share one).
    pub body: BodyHandle,
    /// The link's frame in its body's frame.
    pub offset: Pose,
    /// The link's own mass, kg (a welded link's too: its body carries the sum).
    #[serde(default)]
    pub mass: Real,
    /// Its own centre of mass, link frame.
    #[serde(default)]
    pub center_of_mass: Vec3,
    /// Its own inertia about that centre, link axes.
    #[serde(default)]
    pub inertia: Mat3,
    /// The colliders made of its geometry.
    #[serde(default)]
    pub colliders: Vec<ColliderHandle>,
}

/// A joint of a loaded robot.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RobotJoint {
    /// The joint's name in the file (for a joint made of several of the file's joints, the
    /// first one's).
    pub name: String,
    /// The file's joints it stands for (MJCF: two slides and a hinge in one body).
    pub parts: Vec<String>,
    /// Its type.
    pub kind: JointType,
    /// The Kea joint (`None` for a fixed or free joint).
    pub raw: Option<ConstraintHandle>,
    /// Indices into [`Robot::links`].
    pub parent_link: usize,
    /// The link it moves.
    pub child_link: usize,
    pub(crate) origin: Pose,
    pub(crate) anchor: Vec3,
    pub(crate) coords: Vec<Coordinate>,
    /// Its first entry in the joint position vector.
    pub first_position: usize,
    /// Its first entry in the joint velocity vector.
    pub first_velocity: usize,
}

impl RobotJoint {
    /// Lower and upper limit of each coordinate, where the file gives them.
    #[must_use]
    pub fn limits(&self) -> Vec<Option<(Real, Real)>> {
        self.coords.iter().map(|c| c.limits).collect()
    }

    /// The largest actuator force or torque of each coordinate, where the file gives one.
    #[must_use]
    pub fn efforts(&self) -> Vec<Option<Real>> {
        self.coords.iter().map(|c| c.effort).collect()
    }

    /// Its entries in the joint position vector.
    fn positions(&self) -> std::ops::Range<usize> {
        self.first_position..self.first_position + self.kind.position_count()
    }

    /// Its entries in the joint velocity vector.
    fn velocities(&self) -> std::ops::Range<usize> {
        self.first_velocity..self.first_velocity + self.kind.velocity_count()
    }
}

/// A tendon of a loaded robot.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RobotTendon {
    /// Its name in the file.
    pub name: String,
    /// The world's tendon.
    pub handle: kea::TendonHandle,
    /// The file's length where Kea's is 0 (`Σ c·ref`).
    pub offset: Real,
}

/// A robot loaded into a [`PhysicsWorld`]: see [`PhysicsWorld::load_urdf`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Robot {
    name: String,
    links: Vec<RobotLink>,
    joints: Vec<RobotJoint>,
    /// Links, parents first.
    order: Vec<usize>,
    /// Each link's joint (index into `joints`; `None` for the world link).
    joint_of: Vec<Option<usize>>,
    positions: usize,
    velocities: usize,
    skipped: Vec<String>,
    pub(crate) actuators: Vec<super::mjcf_actuators::ActuatorSpec>,
    pub(crate) timestep: Option<Real>,
    /// Its fixed tendons (`tendons.rs`).
    #[serde(default)]
    pub(crate) tendons: Vec<RobotTendon>,
}

impl Robot {
    /// A robot of these links and joints (each joint knowing its place in the joint vectors);
    /// `order` lists the links parents first. Each link's joint and the vectors' lengths
    /// follow from the joints.
    pub(crate) fn new(
        name: String,
        links: Vec<RobotLink>,
        joints: Vec<RobotJoint>,
        order: Vec<usize>,
        skipped: Vec<String>,
    ) -> Self {
        let mut joint_of = vec![None; links.len()];
        for (k, j) in joints.iter().enumerate() {
            joint_of[j.child_link] = Some(k);
        }
        let (positions, velocities) = joints.last().map_or((0, 0), |j| {
            (
                j.first_position + j.kind.position_count(),
                j.first_velocity + j.kind.velocity_count(),
            )
        });
        Self {
            name,
            links,
            joints,
            order,
            joint_of,
            positions,
            velocities,
            skipped,
            actuators: Vec::new(),
            timestep: None,
            tendons: Vec::new(),
        }
    }

    /// The step the model asks for, s: MJCF's `option timestep` (MuJoCo's default, 0.002 s,
    /// where the file names none); `None` for URDF, which has no step.
    #[must_use]
    pub fn timestep(&self) -> Option<Real> {
        self.timestep
    }

    /// The robot's name in the file.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its links; link 0 is the world (what the robot's fixed base is welded to).
    #[must_use]
    pub fn links(&self) -> &[RobotLink] {
        &self.links
    }

    /// Its joints in the file's order (fixed ones included, with no coordinates).
    #[must_use]
    pub fn joints(&self) -> &[RobotJoint] {
        &self.joints
    }

    /// A link by name.
    #[must_use]
    pub fn link(&self, name: &str) -> Option<&RobotLink> {
        self.links.iter().find(|l| l.name == name)
    }

    /// The body carrying a link, by the link's name.
    #[must_use]
    pub fn body(&self, name: &str) -> Option<BodyHandle> {
        self.link(name).map(|l| l.body)
    }

    /// A joint by name (or by the name of one of its parts).
    #[must_use]
    pub fn joint(&self, name: &str) -> Option<&RobotJoint> {
        self.joints
            .iter()
            .find(|j| j.name == name || j.parts.iter().any(|p| p == name))
    }

    /// Length of the joint position vector (MuJoCo's `nq`).
    #[must_use]
    pub fn position_count(&self) -> usize {
        self.positions
    }

    /// Length of the joint velocity vector (MuJoCo's `nv`).
    #[must_use]
    pub fn velocity_count(&self) -> usize {
        self.velocities
    }

    /// What the importer left out, and why (file, line, element).
    #[must_use]
    pub fn skipped(&self) -> &[String] {
        &self.skipped
    }

    /// A link's frame in the world now.
    pub fn link_pose(&self, world: &PhysicsWorld, link: usize) -> Result<Pose> {
        let l = self
            .links
            .get(link)
            .ok_or_else(|| out_of_range("link", link, self.links.len()))?;
        let body = Pose::new(world.position(l.body)?, world.rotation(l.body)?);
        Ok(body.then(&l.offset))
    }

    /// The joint positions in the file's joint order: an angle (rad) or travel (m) per
    /// coordinate, a quaternion (w, x, y, z) per ball joint, position and quaternion per free
    /// joint — MuJoCo's `qpos` layout.
    pub fn joint_positions(&self, world: &PhysicsWorld) -> Result<Vec<Real>> {
        let mut q = vec![0.0; self.positions];
        self.joint_positions_into(world, &mut q)?;
        Ok(q)
    }

    /// [`Robot::joint_positions`] written into `q`, which must hold
    /// [`Robot::position_count`] entries: no allocation (a batch reads every world's row in
    /// place). On an error `q` is partly written.
    pub fn joint_positions_into(&self, world: &PhysicsWorld, q: &mut [Real]) -> Result<()> {
        check_len("q", q, self.positions)?;
        let mut last = None;
        for j in self.moving_joints() {
            let frames = self.frames(world, j, &mut last)?;
            self.read_position(world, j, frames, &mut q[j.positions()])?;
        }
        Ok(())
    }

    /// [`Robot::joint_positions_into`] and [`Robot::joint_velocities_into`] in one pass, each
    /// link's pose found once for both (a batch reads both after every step).
    pub fn joint_state_into(
        &self,
        world: &PhysicsWorld,
        q: &mut [Real],
        v: &mut [Real],
    ) -> Result<()> {
        check_len("q", q, self.positions)?;
        check_len("v", v, self.velocities)?;
        let mut last = None;
        for j in self.moving_joints() {
            let frames = self.frames(world, j, &mut last)?;
            self.read_position(world, j, frames, &mut q[j.positions()])?;
            self.read_velocity(world, j, frames, &mut v[j.velocities()])?;
        }
        Ok(())
    }

    /// The joints that have coordinates (all but fixed ones), in the file's order.
    fn moving_joints(&self) -> impl Iterator<Item = &RobotJoint> {
        self.joints.iter().filter(|j| j.kind != JointType::Fixed)
    }

    /// The joint velocities in the file's joint order (MuJoCo's `qvel`: a free joint's linear
    /// velocity in the world frame and angular velocity in its body's frame; a ball joint's
    /// relative angular velocity in the child's frame).
    pub fn joint_velocities(&self, world: &PhysicsWorld) -> Result<Vec<Real>> {
        let mut v = vec![0.0; self.velocities];
        self.joint_velocities_into(world, &mut v)?;
        Ok(v)
    }

    /// [`Robot::joint_velocities`] written into `v`, which must hold
    /// [`Robot::velocity_count`] entries: no allocation. On an error `v` is partly written.
    pub fn joint_velocities_into(&self, world: &PhysicsWorld, v: &mut [Real]) -> Result<()> {
        check_len("v", v, self.velocities)?;
        let mut last = None;
        for j in self.moving_joints() {
            let frames = self.frames(world, j, &mut last)?;
            self.read_velocity(world, j, frames, &mut v[j.velocities()])?;
        }
        Ok(())
    }

    /// The parent's frame the child moves in (the child's frame at coordinates 0), and the
    /// child's frame, in the world now. `last` is the link whose pose was found last, and that
    /// pose: reused when it is this joint's parent (a chain finds each link's pose once).
    fn frames(
        &self,
        world: &PhysicsWorld,
        j: &RobotJoint,
        last: &mut Option<(usize, Pose)>,
    ) -> Result<(Pose, Pose)> {
        let parent = match *last {
            Some((link, pose)) if link == j.parent_link => pose,
            _ => self.link_pose(world, j.parent_link)?,
        };
        let child = self.link_pose(world, j.child_link)?;
        *last = Some((j.child_link, child));
        Ok((parent.then(&j.origin), child))
    }

    fn read_position(
        &self,
        world: &PhysicsWorld,
        j: &RobotJoint,
        (zero, child): (Pose, Pose),
        out: &mut [Real],
    ) -> Result<()> {
        let delta = zero.inverse().then(&child);
        match j.kind {
            JointType::Free => {
                let r = child.rotation;
                out.copy_from_slice(&[
                    child.translation.x,
                    child.translation.y,
                    child.translation.z,
                    r.w,
                    r.x,
                    r.y,
                    r.z,
                ]);
            }
            JointType::Ball => {
                let r = delta.rotation;
                out.copy_from_slice(&[r.w, r.x, r.y, r.z]);
            }
            JointType::Revolute | JointType::Continuous => {
                let c = &j.coords[0];
                let tracked = match j.raw {
                    Some(raw) => {
                        let d = world.dynamics();
                        JointHandle::<Hinge>::try_from_raw(d, raw)?.angle(d)?
                    }
                    None => 0.0,
                };
                out[0] = unwrap_about(delta.rotation, c.axis, tracked) + c.reference;
            }
            JointType::Prismatic => {
                let c = &j.coords[0];
                out[0] = delta.translation.dot(c.axis) + c.reference;
            }
            JointType::Planar | JointType::Slide2 => {
                let mut travel = delta.translation;
                if j.kind == JointType::Planar {
                    let c = &j.coords[2];
                    let tracked = match j.raw {
                        Some(raw) => {
                            let d = world.dynamics();
                            JointHandle::<Planar>::try_from_raw(d, raw)?
                                .get(d)?
                                .coordinates()[2]
                        }
                        None => 0.0,
                    };
                    out[2] = unwrap_about(delta.rotation, c.axis, tracked) + c.reference;
                    travel -= j.anchor - delta.rotation * j.anchor;
                }
                for (o, c) in out.iter_mut().zip(&j.coords[..2]) {
                    *o = travel.dot(c.axis) + c.reference;
                }
            }
            JointType::Fixed => {}
        }
        Ok(())
    }

    fn read_velocity(
        &self,
        world: &PhysicsWorld,
        j: &RobotJoint,
        (zero, child_frame): (Pose, Pose),
        out: &mut [Real],
    ) -> Result<()> {
        let parent = self.links[j.parent_link].body;
        let child = self.links[j.child_link].body;
        let (vp, wp, cp) = motion(world, parent)?;
        let (_, wc, _) = motion(world, child)?;
        let anchor = child_frame.point(j.anchor);
        let rel_point = vc_at(world, child, anchor)? - (vp + wp.cross(anchor - cp));
        let rel_spin = wc - wp;
        match j.kind {
            JointType::Free => {
                let origin_v = vc_at(world, child, child_frame.translation)?;
                let w_body = child_frame.rotation.inverse() * wc;
                out.copy_from_slice(&[
                    origin_v.x, origin_v.y, origin_v.z, w_body.x, w_body.y, w_body.z,
                ]);
            }
            JointType::Ball => {
                let w = child_frame.rotation.inverse() * rel_spin;
                out.copy_from_slice(&[w.x, w.y, w.z]);
            }
            JointType::Revolute | JointType::Continuous => {
                out[0] = rel_spin.dot(child_frame.rotation * j.coords[0].axis);
            }
            JointType::Prismatic | JointType::Planar | JointType::Slide2 => {
                let travels = if j.kind == JointType::Prismatic { 1 } else { 2 };
                for (o, c) in out.iter_mut().zip(&j.coords[..travels]) {
                    *o = rel_point.dot(zero.rotation * c.axis);
                }
                if j.kind == JointType::Planar {
                    out[2] = rel_spin.dot(zero.rotation * j.coords[2].axis);
                }
            }
            JointType::Fixed => {}
        }
        Ok(())
    }

    /// Re-poses the robot to joint positions `q` (the layout of [`Robot::joint_positions`]) by
    /// forward kinematics from its base, keeping every body's velocity. Errors, changing
    /// nothing, on a vector of the wrong length or with a non-finite entry.
    pub fn set_joint_positions(&self, world: &mut PhysicsWorld, q: &[Real]) -> Result<()> {
        check_vector("q", q, self.positions)?;
        let mut pose: Vec<Pose> = (0..self.links.len())
            .map(|l| self.link_pose(world, l))
            .collect::<Result<_>>()?;
        let mut staged = world.clone();
        for &link in &self.order[1..] {
            let Some(ji) = self.joint_of[link] else {
                continue;
            };
            let j = &self.joints[ji];
            let qj = &q[j.first_position..j.first_position + j.kind.position_count()];
            let zero = pose[j.parent_link].then(&j.origin);
            pose[link] = match j.kind {
                JointType::Fixed => zero,
                JointType::Free => {
                    let r = quat_from(&qj[3..7], "q")?;
                    Pose::new(Vec3::new(qj[0], qj[1], qj[2]), r)
                }
                _ => zero.then(&self.joint_motion(j, qj)?),
            };
            if j.kind != JointType::Fixed {
                // A moving link heads its body: its frame is the body's.
                let body = self.links[link].body;
                staged.set_position(body, pose[link].translation)?;
                staged.set_rotation(body, pose[link].rotation)?;
            }
            if let (Some(raw), Some(angle)) = (j.raw, self.turn(j, qj)) {
                let d = staged.dynamics_mut();
                if j.kind == JointType::Planar {
                    JointHandle::<Planar>::try_from_raw(&*d, raw)?.rebase_turn(d, angle)?;
                } else {
                    JointHandle::<Hinge>::try_from_raw(&*d, raw)?.rebase_angle(d, angle)?;
                }
            }
        }
        *world = staged;
        Ok(())
    }

    /// The child's frame in the zero frame for coordinates `qj`.
    fn joint_motion(&self, j: &RobotJoint, qj: &[Real]) -> Result<Pose> {
        let c = &j.coords;
        let about = |axis: Vec3, angle: Real| {
            let r = Quat::from_axis_angle(axis, angle);
            Pose::new(j.anchor - r * j.anchor, r)
        };
        Ok(match j.kind {
            JointType::Revolute | JointType::Continuous => about(c[0].axis, qj[0] - c[0].reference),
            JointType::Prismatic => Pose::new(c[0].axis * (qj[0] - c[0].reference), Quat::IDENTITY),
            JointType::Ball => {
                let r = quat_from(qj, "q")?;
                Pose::new(j.anchor - r * j.anchor, r)
            }
            JointType::Slide2 | JointType::Planar => {
                let travel =
                    c[0].axis * (qj[0] - c[0].reference) + c[1].axis * (qj[1] - c[1].reference);
                let turn = if j.kind == JointType::Planar {
                    about(c[2].axis, qj[2] - c[2].reference)
                } else {
                    Pose::IDENTITY
                };
                Pose::new(travel, Quat::IDENTITY).then(&turn)
            }
            JointType::Fixed | JointType::Free => Pose::IDENTITY,
        })
    }

    /// The Kea joint's tracked turn for coordinates `qj` (hinges and planar joints).
    fn turn(&self, j: &RobotJoint, qj: &[Real]) -> Option<Real> {
        match j.kind {
            JointType::Revolute | JointType::Continuous => Some(qj[0] - j.coords[0].reference),
            JointType::Planar => Some(qj[2] - j.coords[2].reference),
            _ => None,
        }
    }

    /// Sets the bodies' velocities to joint velocities `v` (the layout of
    /// [`Robot::joint_velocities`]), from the base out; a fixed base stays at rest. Errors,
    /// changing nothing, on a vector of the wrong length or with a non-finite entry.
    pub fn set_joint_velocities(&self, world: &mut PhysicsWorld, v: &[Real]) -> Result<()> {
        check_vector("v", v, self.velocities)?;
        let mut staged = world.clone();
        for &link in &self.order[1..] {
            let Some(ji) = self.joint_of[link] else {
                continue;
            };
            let j = &self.joints[ji];
            if j.kind == JointType::Fixed {
                continue;
            }
            let vj = &v[j.first_velocity..j.first_velocity + j.kind.velocity_count()];
            let parent = self.links[j.parent_link].body;
            let child = self.links[link].body;
            let (vp, wp, cp) = motion(&staged, parent)?;
            let (zero, frame) = self.frames(&staged, j, &mut None)?;
            let com = staged.body(child)?.position();
            let anchor = frame.point(j.anchor);
            let carried = vp + wp.cross(com - cp);
            let (lin, ang) = match j.kind {
                JointType::Free => {
                    let w = frame.rotation * Vec3::new(vj[3], vj[4], vj[5]);
                    let origin_v = Vec3::new(vj[0], vj[1], vj[2]);
                    (origin_v + w.cross(com - frame.translation), w)
                }
                JointType::Ball => {
                    let w = wp + frame.rotation * Vec3::new(vj[0], vj[1], vj[2]);
                    (carried + (w - wp).cross(com - anchor), w)
                }
                JointType::Revolute | JointType::Continuous => {
                    let spin = frame.rotation * j.coords[0].axis * vj[0];
                    (carried + spin.cross(com - anchor), wp + spin)
                }
                JointType::Prismatic => (carried + zero.rotation * j.coords[0].axis * vj[0], wp),
                JointType::Slide2 | JointType::Planar => {
                    let slide =
                        zero.rotation * (j.coords[0].axis * vj[0] + j.coords[1].axis * vj[1]);
                    if j.kind == JointType::Planar {
                        let spin = zero.rotation * j.coords[2].axis * vj[2];
                        (carried + slide + spin.cross(com - anchor), wp + spin)
                    } else {
                        (carried + slide, wp)
                    }
                }
                JointType::Fixed => unreachable!("skipped above"),
            };
            staged.set_linear_velocity(child, lin)?;
            staged.set_angular_velocity(child, ang)?;
        }
        *world = staged;
        Ok(())
    }
}

/// A body's linear velocity, angular velocity and centre of mass (zeros for a static body).
fn motion(world: &PhysicsWorld, h: BodyHandle) -> Result<(Vec3, Vec3, Vec3)> {
    let b = world.body(h)?;
    Ok((b.linear_velocity(), b.angular_velocity(), b.position()))
}

/// Velocity of a world point moving with body `h`.
fn vc_at(world: &PhysicsWorld, h: BodyHandle, p: Vec3) -> Result<Vec3> {
    let (v, w, c) = motion(world, h)?;
    Ok(v + w.cross(p - c))
}

/// The turn of `r` about unit `axis`, unwrapped to lie within π of `near`.
fn unwrap_about(r: Quat, axis: Vec3, near: Real) -> Real {
    let raw = 2.0 * Vec3::new(r.x, r.y, r.z).dot(axis).atan2(r.w);
    near + kea::constraint::joint::wrap_angle(raw - near)
}

fn quat_from(q: &[Real], arg: &'static str) -> Result<Quat> {
    let r = Quat::from_xyzw(q[1], q[2], q[3], q[0]);
    let len = r.length();
    if !above(len, 1e-6) {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("{q:?}"),
            expected: "a quaternion (w, x, y, z) of non-zero length",
        }
        .into());
    }
    Ok(r / len)
}

/// Refuses a vector of the wrong length or with a non-finite entry, naming it.
pub(crate) fn check_vector(arg: &'static str, x: &[Real], len: usize) -> Result<()> {
    check_len(arg, x, len)?;
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("entry {i} = {}", x[i]),
            expected: "finite numbers",
        }
        .into());
    }
    Ok(())
}

/// Checks that `x` has one entry per joint coordinate.
fn check_len(arg: &'static str, x: &[Real], len: usize) -> Result<()> {
    if x.len() != len {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("{} entries", x.len()),
            expected:
                "one entry per joint coordinate (the robot's position_count or velocity_count)",
        }
        .into());
    }
    Ok(())
}

fn out_of_range(arg: &'static str, i: usize, len: usize) -> crate::Error {
    KeaError::OutOfRange {
        arg,
        value: format!("{i}"),
        expected: if len == 0 {
            "no entries"
        } else {
            "an index below the count"
        },
    }
    .into()
}
