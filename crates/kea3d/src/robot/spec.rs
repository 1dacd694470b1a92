//! A robot as a file describes it, before it is built: links (mass, inertia, collision
//! geometry) joined into a tree by joints, every frame given in its parent's. Both importers
//! read into this; [`super::build`] turns it into bodies, colliders and joints.

use kea::{JointDynamics, Mat3, Quat, Real, Vec3};

/// A rigid transform: rotate, then translate.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    /// Translation, m.
    pub translation: Vec3,
    /// Rotation (unit).
    pub rotation: Quat,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// No motion.
    pub const IDENTITY: Self = Self {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
    };

    /// A pose from its parts.
    #[must_use]
    pub fn new(translation: Vec3, rotation: Quat) -> Self {
        Self {
            translation,
            rotation,
        }
    }

    /// `self ∘ other`: `other` given in this pose's frame, expressed in the outer frame.
    #[must_use]
    pub fn then(&self, other: &Pose) -> Pose {
        Pose {
            translation: self.translation + self.rotation * other.translation,
            rotation: (self.rotation * other.rotation).normalize(),
        }
    }

    /// The inverse transform.
    #[must_use]
    pub fn inverse(&self) -> Pose {
        let r = self.rotation.inverse();
        Pose {
            translation: -(r * self.translation),
            rotation: r,
        }
    }

    /// A point of this frame in the outer frame.
    #[must_use]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.translation + self.rotation * p
    }
}

/// Mass properties of a link in its own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Inertial {
    pub mass: Real,
    /// Centre of mass, link frame.
    pub com: Vec3,
    /// Inertia about the centre of mass, link axes.
    pub inertia: Mat3,
}

impl Inertial {
    pub const NONE: Self = Self {
        mass: 0.0,
        com: Vec3::ZERO,
        inertia: Mat3::ZERO,
    };

    /// The mass properties of `self` and `other` (placed by `pose` in this frame) together.
    /// A massless part adds nothing, whatever inertia its file gives it (as in MuJoCo).
    pub fn merged(&self, other: &Inertial, pose: &Pose) -> Inertial {
        if other.mass <= 0.0 {
            return *self;
        }
        let m = self.mass + other.mass;
        if m <= 0.0 {
            return Inertial::NONE;
        }
        let r = Mat3::from_quat(pose.rotation);
        let other_com = pose.point(other.com);
        let other_inertia = r * other.inertia * r.transpose();
        let com = (self.com * self.mass + other_com * other.mass) / m;
        let inertia = self.inertia
            + parallel_axis(self.mass, self.com - com)
            + other_inertia
            + parallel_axis(other.mass, other_com - com);
        Inertial {
            mass: m,
            com,
            inertia,
        }
    }
}

/// The inertia a point mass `m` at `d` from the centre adds.
fn parallel_axis(m: Real, d: Vec3) -> Mat3 {
    let outer = Mat3::from_cols(d * d.x, d * d.y, d * d.z);
    (Mat3::IDENTITY * d.length_squared() - outer) * m
}

/// A collision shape as files give them (cylinders and capsules along z).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum GeomShape {
    Cuboid(Vec3),
    Sphere(Real),
    /// Along z.
    Cylinder {
        radius: Real,
        half_length: Real,
    },
    /// Along z.
    Capsule {
        radius: Real,
        half_length: Real,
    },
    /// The convex hull of these points; the mesh's triangles where they came from one (a flat
    /// mesh, whose hull has no volume, collides as that mesh instead).
    Hull(Vec<Vec3>, Vec<[u32; 3]>),
    /// A triangle mesh.
    Mesh(Vec<Vec3>, Vec<[u32; 3]>),
    /// The plane z = 0 of its frame, solid below.
    Plane,
}

/// One collision geometry of a link.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GeomSpec {
    pub shape: GeomShape,
    /// In the link's frame.
    pub pose: Pose,
    /// Collision groups and mask (MJCF `contype`, `conaffinity`).
    pub groups: u32,
    pub mask: u32,
    pub friction: Option<Real>,
    /// MJCF's contact dimensionality (1: frictionless, 3: sliding friction); `Some` pairs the
    /// geometry by MuJoCo's rule (`mjcf_pairs`), `None` (URDF) by Kea's combine rule.
    pub condim: Option<u32>,
    /// Mass from this geometry when the link has no inertial: density or mass (MJCF).
    pub density: Option<Real>,
    pub mass: Option<Real>,
    /// How far from the shape its contacts act, m (MJCF's `margin − gap`): the collider is
    /// the shape grown by it, so two such geometries rest the sum of theirs apart, as in
    /// MuJoCo. Mass comes from the shape itself.
    pub skin: Real,
}

/// A link.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LinkSpec {
    pub name: String,
    /// Its element's line in the file, for errors (0: none, the world).
    pub line: u32,
    /// Given mass properties; `None`: from the geometry's density (MJCF without `inertial`).
    pub inertial: Option<Inertial>,
    pub geoms: Vec<GeomSpec>,
}

/// The kinds of joint the importers read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum JointType {
    /// Rotation about an axis, with limits.
    Revolute,
    /// Rotation about an axis, no limits.
    Continuous,
    /// Translation along an axis.
    Prismatic,
    /// Welded: the link is merged into its parent's body.
    Fixed,
    /// Free motion (URDF `floating`, MJCF `free`): 7 positions (x, y, z, qw, qx, qy, qz) and 6
    /// velocities (linear in the world frame, angular in the body's), as MuJoCo orders them.
    Free,
    /// Rotation about a point: 4 positions (a quaternion) and 3 velocities (body frame).
    Ball,
    /// Motion in a plane and rotation about its normal (URDF `planar`; MJCF two slides and a
    /// hinge in one body): 3 coordinates.
    Planar,
    /// Motion in a plane, no rotation (MJCF two slides in one body): 2 coordinates.
    Slide2,
}

impl JointType {
    /// Entries in the joint position vector.
    #[must_use]
    pub fn position_count(self) -> usize {
        match self {
            Self::Fixed => 0,
            Self::Revolute | Self::Continuous | Self::Prismatic => 1,
            Self::Slide2 => 2,
            Self::Planar => 3,
            Self::Ball => 4,
            Self::Free => 7,
        }
    }

    /// Entries in the joint velocity vector.
    #[must_use]
    pub fn velocity_count(self) -> usize {
        match self {
            Self::Ball => 3,
            Self::Free => 6,
            other => other.position_count(),
        }
    }
}

/// One scalar coordinate of a joint: its axis, stops and dynamics.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Coordinate {
    /// Unit axis in the child's frame.
    pub axis: Vec3,
    pub limits: Option<(Real, Real)>,
    /// Largest actuator force (URDF `effort`).
    pub effort: Option<Real>,
    /// Largest speed (URDF `velocity`).
    pub speed: Option<Real>,
    pub dynamics: JointDynamics,
    /// The coordinate's value in the file's pose (MJCF `ref`).
    pub reference: Real,
}

impl Coordinate {
    pub fn along(axis: Vec3) -> Self {
        Self {
            axis,
            limits: None,
            effort: None,
            speed: None,
            dynamics: JointDynamics::default(),
            reference: 0.0,
        }
    }
}

/// A joint: a child link placed in its parent's frame, free to move as its type says.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct JointSpec {
    pub name: String,
    /// Its element's line in the file, for errors (0: made by the reader, a base joint).
    pub line: u32,
    /// Names of the file's joints this one stands for (MJCF: several in one body).
    pub parts: Vec<String>,
    pub kind: JointType,
    pub parent: usize,
    pub child: usize,
    /// The child's frame in the parent's at the file's pose.
    pub origin: Pose,
    /// The joint's point in the child's frame.
    pub anchor: Vec3,
    /// Its coordinates, in order (a planar joint: two slides then the turn).
    pub coords: Vec<Coordinate>,
}

/// A whole robot file. Link 0 is the world (static; MJCF's `worldbody` geometry); the
/// robot's root hangs from it by a fixed joint (a fixed base) or a free one.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RobotSpec {
    pub name: String,
    pub links: Vec<LinkSpec>,
    /// In the file's order; each link but the world is the child of exactly one.
    pub joints: Vec<JointSpec>,
    /// What was left out and why, one line each (file, line, element).
    pub skipped: Vec<String>,
    /// Geometry's `groups`/`mask` are MuJoCo's `contype`/`conaffinity` (a pair collides if
    /// either's type meets the other's affinity) rather than Kea's groups and mask.
    pub mujoco_filter: bool,
    /// MJCF's `<compiler settotalmass>`: every moving link's mass and inertia scaled so that
    /// they sum to this, kg.
    pub total_mass: Option<Real>,
    /// Links carried between one MJCF body's joints (`mjcf_joints::chain`): no geometry, and
    /// the nearest real links on either side do not collide with each other.
    pub chain_links: Vec<usize>,
    /// MJCF's fixed tendons that act.
    pub tendons: Vec<TendonSpec>,
}

/// A fixed tendon as its file gives it: lengths in the file's coordinates (`Σ c·q`).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TendonSpec {
    pub name: String,
    pub line: u32,
    /// The file's joint names and their coefficients.
    pub terms: Vec<(String, Real)>,
    pub stiffness: Real,
    pub damping: Real,
    /// `None`: MuJoCo's default, the length at the joints' `springref`.
    pub spring_length: Option<[Real; 2]>,
    pub range: Option<[Real; 2]>,
    pub soft: kea::SoftLimit,
}

impl RobotSpec {
    /// A robot with only the world link, its geometry filtered by Kea's rule or MuJoCo's.
    pub fn new(name: &str, mujoco_filter: bool) -> Self {
        Self {
            name: name.to_string(),
            links: vec![LinkSpec {
                name: WORLD.to_string(),
                line: 0,
                inertial: Some(Inertial::NONE),
                geoms: Vec::new(),
            }],
            joints: Vec::new(),
            skipped: Vec::new(),
            mujoco_filter,
            total_mass: None,
            chain_links: Vec::new(),
            tendons: Vec::new(),
        }
    }
}

/// Name of the world link.
pub(crate) const WORLD: &str = "world";

/// +1, or −1 where Kea's coordinate `k` of a joint runs against the file's: a planar joint's
/// second travel is Kea's `normal × first` (the normal being the turn's axis), which the file's
/// second slide may point against.
pub(crate) fn kea_sign(kind: JointType, coords: &[Coordinate], k: usize) -> Real {
    if kind == JointType::Planar && k == 1 {
        let second = coords[2].axis.cross(coords[0].axis);
        if second.dot(coords[1].axis) < 0.0 {
            return -1.0;
        }
    }
    1.0
}
