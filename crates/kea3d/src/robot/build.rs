//! Building a [`RobotSpec`] into a world: links welded by fixed joints become one body, each
//! other joint a Kea joint between bodies, each geometry a collider; the result is a
//! [`Robot`] that knows where every link and coordinate went.

use super::colliders::{collider, collision_filters, placement, shape_of};
use super::mjcf_pairs::PairMaterials;
use super::model::{Robot, RobotJoint, RobotLink};
use super::spec::{kea_sign, GeomSpec, Inertial, JointSpec, JointType, Pose, RobotSpec};
use super::xml::above;
use super::ImportError;
use crate::{Body, Joint, PhysicsWorld};
use kea::{
    BodyHandle, ConstraintHandle, Hinge, JointHandle, Limit, Planar, Prismatic, Real, SingleLimit,
};
use kea_collision::{ColliderHandle, MassProperties};
use std::path::Path;

/// How fast a robot's joint found beyond a stop is brought back, rad/s or m/s (MJCF models
/// start outside their ranges at times; see [`SingleLimit::recovery_speed`]).
const STOP_RECOVERY_SPEED: Real = 0.5;

/// How a spec is built.
pub(crate) struct BuildOptions {
    /// Where the world link sits in the world (the robot's base pose for a fixed base).
    pub base: Pose,
    pub self_collision: bool,
}

/// Builds `spec` into `world`; on error the world is left as it was.
pub(crate) fn build(
    world: &mut PhysicsWorld,
    spec: &RobotSpec,
    file: &Path,
    options: &BuildOptions,
) -> Result<Robot, ImportError> {
    let spec = &settle_massless_roots(spec, file)?;
    let mut scratch = world.clone();
    let robot = build_into(&mut scratch, spec, file, options)?;
    *world = scratch;
    Ok(robot)
}

/// The spec with every free root that weighs nothing (with the links welded to it) welded to
/// the world instead: PyBullet reads a massless base as static (a floor, a table, a tray).
fn settle_massless_roots(spec: &RobotSpec, file: &Path) -> Result<RobotSpec, ImportError> {
    fn welded_mass(spec: &RobotSpec, link: usize) -> crate::Result<Real> {
        let mut m = link_inertial(spec, link)?.mass;
        for j in spec
            .joints
            .iter()
            .filter(|j| j.parent == link && j.kind == JointType::Fixed)
        {
            m += welded_mass(spec, j.child)?;
        }
        Ok(m)
    }
    let mut out = spec.clone();
    for j in &mut out.joints {
        if j.kind != JointType::Free || j.parent != 0 {
            continue;
        }
        let mass = welded_mass(spec, j.child).map_err(|source| ImportError::World {
            file: file.to_path_buf(),
            line: spec.links[j.child].line,
            element: format!("link \"{}\"", spec.links[j.child].name),
            source,
        })?;
        if mass <= 0.0 {
            j.kind = JointType::Fixed;
            out.skipped.push(format!(
                "{}: link \"{}\" weighs nothing: static, as PyBullet reads a massless base",
                file.display(),
                spec.links[j.child].name
            ));
        }
    }
    Ok(out)
}

/// Links in an order where every parent comes before its children, with each link's joint.
fn topological(spec: &RobotSpec) -> (Vec<usize>, Vec<Option<usize>>) {
    let mut parent_joint = vec![None; spec.links.len()];
    for (j, joint) in spec.joints.iter().enumerate() {
        parent_joint[joint.child] = Some(j);
    }
    let mut order = vec![0];
    let mut k = 0;
    while k < order.len() {
        let link = order[k];
        order.extend(
            spec.joints
                .iter()
                .filter(|j| j.parent == link)
                .map(|j| j.child),
        );
        k += 1;
    }
    (order, parent_joint)
}

/// Where every link sits at the file's pose, and which link heads the body it is welded into.
struct Layout {
    /// Links, parents first.
    order: Vec<usize>,
    /// Each link's frame in the world.
    pose: Vec<Pose>,
    /// The link heading each link's body.
    head: Vec<usize>,
}

impl Layout {
    fn of(spec: &RobotSpec, base: Pose) -> Self {
        let (order, parent_joint) = topological(spec);
        let n = spec.links.len();
        let mut pose = vec![Pose::IDENTITY; n];
        let mut head = vec![0usize; n];
        pose[0] = base;
        for &link in &order[1..] {
            let j = &spec.joints[parent_joint[link].expect("every link but the world has a joint")];
            pose[link] = pose[j.parent].then(&j.origin);
            head[link] = if j.kind == JointType::Fixed {
                head[j.parent]
            } else {
                link
            };
        }
        Self { order, pose, head }
    }
}

/// One build in progress: the world it adds to and what it has noted.
struct Builder<'a> {
    world: &'a mut PhysicsWorld,
    spec: &'a RobotSpec,
    file: &'a Path,
    layout: Layout,
    skipped: Vec<String>,
    /// Each link's own mass properties, and the colliders of its geometry.
    own: Vec<Inertial>,
    colliders: Vec<Vec<ColliderHandle>>,
}

impl Builder<'_> {
    /// The world's error on `element`, at `line` of the file.
    fn world_error(&self, element: String, line: u32) -> impl Fn(crate::Error) -> ImportError + '_ {
        move |source| ImportError::World {
            file: self.file.to_path_buf(),
            line,
            element: element.clone(),
            source,
        }
    }

    /// Each body's mass properties and geometry, gathered from its welded links into its head
    /// link's frame; each link's own mass properties are kept in `self.own`.
    #[allow(clippy::type_complexity)]
    fn merged_links(
        &mut self,
    ) -> Result<(Vec<Inertial>, Vec<Vec<(usize, GeomSpec)>>), ImportError> {
        let (spec, l) = (self.spec, &self.layout);
        let n = spec.links.len();
        self.own = vec![Inertial::NONE; n];
        let mut inertial = vec![Inertial::NONE; n];
        let mut geoms: Vec<Vec<(usize, GeomSpec)>> = vec![Vec::new(); n];
        for &link in &l.order {
            let h = l.head[link];
            let in_head = l.pose[h].inverse().then(&l.pose[link]);
            let own = link_inertial(spec, link).map_err(self.world_error(
                format!("link \"{}\"", spec.links[link].name),
                spec.links[link].line,
            ))?;
            inertial[h] = inertial[h].merged(&own, &in_head);
            self.own[link] = own;
            for g in &spec.links[link].geoms {
                let mut g = g.clone();
                g.pose = in_head.then(&g.pose);
                geoms[h].push((link, g));
            }
        }
        if let Some(target) = spec.total_mass {
            // MJCF's `settotalmass`: every body's mass and inertia scaled together (those
            // welded to the world count, as MuJoCo counts them).
            let total: Real = (0..n)
                .filter(|&k| l.head[k] == k)
                .map(|k| inertial[k].mass)
                .sum();
            if above(total, 0.0) {
                let s = target / total;
                for (k, m) in inertial.iter_mut().enumerate() {
                    if l.head[k] == k && k != 0 {
                        m.mass *= s;
                        m.inertia *= s;
                    }
                }
                for (k, m) in self.own.iter_mut().enumerate() {
                    if l.head[k] != 0 {
                        m.mass *= s;
                        m.inertia *= s;
                    }
                }
            }
        }
        Ok((inertial, geoms))
    }

    /// The body a link heading one becomes: static for the world, else its merged mass
    /// properties (a mass under Kea's least raised to it, noted; none refused).
    fn body_for(&mut self, link: usize, m: Inertial) -> Result<Body, ImportError> {
        let pose = self.layout.pose[link];
        if link == 0 {
            return Ok(Body::fixed()
                .position(pose.translation)
                .rotation(pose.rotation));
        }
        let name = &self.spec.links[link].name;
        let mut m = m;
        let floor = kea::error::MASS_RANGE.0;
        if above(m.mass, 0.0) && m.mass < floor {
            self.skipped.push(format!(
                "{}: link \"{name}\" weighs {} kg, below Kea's least mass: made {floor} kg",
                self.file.display(),
                m.mass
            ));
            m.inertia *= floor / m.mass;
            m.mass = floor;
        }
        if !above(m.mass, 0.0) {
            return Err(ImportError::World {
                file: self.file.to_path_buf(),
                line: self.spec.links[link].line,
                element: format!("link \"{name}\""),
                source: kea::KeaError::OutOfRange {
                    arg: "mass",
                    value: format!("{}", m.mass),
                    expected: "a moving link (with the links welded to it) needs a mass > 0",
                }
                .into(),
            });
        }
        Ok(Body::dynamic()
            .position(pose.translation)
            .rotation(pose.rotation)
            .mass(m.mass)
            .inertia(positive_inertia(m.inertia, m.mass))
            .center_of_mass(m.com))
    }

    /// Every body with its colliders; each link's body.
    fn insert_bodies(
        &mut self,
        self_collision: bool,
    ) -> Result<Vec<Option<BodyHandle>>, ImportError> {
        let (inertial, geoms) = self.merged_links()?;
        self.colliders = vec![Vec::new(); self.spec.links.len()];
        let filters = collision_filters(self.spec, &geoms, self_collision);
        let all = geoms.iter().flatten().map(|(_, g)| g);
        let pairs = PairMaterials::add(self.world, all).map_err(|e| ImportError::World {
            file: self.file.to_path_buf(),
            line: 0,
            element: "the geoms' friction".into(),
            source: e,
        })?;
        let mut body_of = vec![None::<BodyHandle>; self.spec.links.len()];
        for k in 0..self.layout.order.len() {
            let link = self.layout.order[k];
            if self.layout.head[link] != link {
                continue;
            }
            let body = self.body_for(link, inertial[link])?;
            let name = format!("link \"{}\"", self.spec.links[link].name);
            let h = self
                .world
                .insert_body(body)
                .map_err(self.world_error(name, self.spec.links[link].line))?;
            body_of[link] = Some(h);
            for (g, (owner, geom)) in geoms[link].iter().enumerate() {
                let line = self.spec.links[*owner].line;
                let owner = &self.spec.links[*owner].name;
                let (mut collider, note) = collider(geom, filters[link][g]);
                if let Some(material) = pairs.of(geom) {
                    collider = collider.material(material);
                }
                if let Some(note) = note {
                    let file = self.file.display();
                    self.skipped.push(format!(
                        "{file}: a collision geometry of link \"{owner}\": {note}"
                    ));
                }
                let element = format!("collision of link \"{owner}\"");
                let c = self
                    .world
                    .insert_collider(collider, Some(h))
                    .map_err(self.world_error(element, line))?;
                self.colliders[geoms[link][g].0].push(c);
            }
        }
        Ok(body_of)
    }

    /// A body whose joints became a chain (`mjcf_joints::chain`) does not collide with its
    /// parent (MuJoCo's parent and child do not; a child of the world does).
    fn exclude_across_chains(&mut self, body_of: &[Option<BodyHandle>]) -> Result<(), ImportError> {
        let spec = self.spec;
        if spec.chain_links.is_empty() {
            return Ok(());
        }
        let parent_of = |link: usize| {
            spec.joints
                .iter()
                .find(|j| j.child == link)
                .map(|j| j.parent)
        };
        for j in &spec.joints {
            if spec.chain_links.contains(&j.child) || !spec.chain_links.contains(&j.parent) {
                continue;
            }
            let mut above = j.parent;
            while spec.chain_links.contains(&above) {
                above = parent_of(above).unwrap_or(0);
            }
            let head = &self.layout.head;
            if let (Some(a), Some(b)) = (body_of[head[above]], body_of[head[j.child]]) {
                if head[above] != 0 && a != b {
                    self.world
                        .exclude_collisions(a, b)
                        .map_err(self.world_error(format!("joint \"{}\"", j.name), j.line))?;
                }
            }
        }
        Ok(())
    }

    /// Every joint in the file's order, with its place in the joint vectors.
    fn insert_joints(
        &mut self,
        body_of: &[Option<BodyHandle>],
    ) -> Result<Vec<RobotJoint>, ImportError> {
        let mut joints = Vec::with_capacity(self.spec.joints.len());
        let (mut nq, mut nv) = (0, 0);
        for j in &self.spec.joints {
            let head = &self.layout.head;
            let raw = if j.kind == JointType::Fixed {
                None
            } else {
                let child = body_of[head[j.child]].expect("a moving link heads its body");
                let pose = self.layout.pose[j.child];
                make_joint(self.world, j, &pose, child, body_of[head[j.parent]])
                    .map_err(self.world_error(format!("joint \"{}\"", j.name), j.line))?
            };
            joints.push(RobotJoint {
                name: j.name.clone(),
                parts: j.parts.clone(),
                kind: j.kind,
                raw,
                parent_link: j.parent,
                child_link: j.child,
                origin: j.origin,
                anchor: j.anchor,
                coords: j.coords.clone(),
                first_position: nq,
                first_velocity: nv,
            });
            nq += j.kind.position_count();
            nv += j.kind.velocity_count();
        }
        Ok(joints)
    }
}

fn build_into(
    world: &mut PhysicsWorld,
    spec: &RobotSpec,
    file: &Path,
    options: &BuildOptions,
) -> Result<Robot, ImportError> {
    let mut b = Builder {
        world,
        spec,
        file,
        layout: Layout::of(spec, options.base),
        skipped: spec.skipped.clone(),
        own: Vec::new(),
        colliders: Vec::new(),
    };
    let body_of = b.insert_bodies(options.self_collision)?;
    let joints = b.insert_joints(&body_of)?;
    b.exclude_across_chains(&body_of)?;
    let tendons = super::tendons::insert_tendons(b.world, spec, &joints, file)?;
    let l = &b.layout;
    let links = (0..spec.links.len())
        .map(|k| RobotLink {
            name: spec.links[k].name.clone(),
            body: body_of[l.head[k]].expect("every head has a body"),
            offset: l.pose[l.head[k]].inverse().then(&l.pose[k]),
            mass: b.own[k].mass,
            center_of_mass: b.own[k].com,
            inertia: b.own[k].inertia,
            colliders: b.colliders[k].clone(),
        })
        .collect();
    let mut robot = Robot::new(spec.name.clone(), links, joints, b.layout.order, b.skipped);
    robot.tendons = tendons;
    Ok(robot)
}

/// A link's own mass properties: given, or from its geometry's density and mass.
fn link_inertial(spec: &RobotSpec, link: usize) -> crate::Result<Inertial> {
    let l = &spec.links[link];
    if let Some(i) = l.inertial {
        return Ok(i);
    }
    let mut total = Inertial::NONE;
    for g in &l.geoms {
        let shape = shape_of(&g.shape)?;
        if !shape.has_volume() {
            continue;
        }
        let (offset, rotation) = placement(g);
        let unit = MassProperties::of_shapes(&[(offset, rotation, shape)], 1.0)?;
        let scale = match (g.mass, g.density) {
            (Some(m), _) => m / unit.mass,
            (None, Some(rho)) => rho,
            (None, None) => crate::DEFAULT_DENSITY,
        };
        let part = Inertial {
            mass: unit.mass * scale,
            com: unit.center_of_mass,
            inertia: unit.inertia * scale,
        };
        total = total.merged(&part, &Pose::IDENTITY);
    }
    Ok(total)
}

/// A link's inertia with its diagonal kept positive (a file's point mass has none).
fn positive_inertia(i: kea::Mat3, mass: Real) -> kea::Mat3 {
    let floor = 1e-9 * mass.max(1e-6);
    let mut out = i;
    for k in 0..3 {
        if !above(out.col(k)[k], floor) {
            let mut c = out.col(k);
            c[k] = floor;
            *out.col_mut(k) = c;
        }
    }
    out
}

/// The Kea joint of a spec joint (`None` for a free one).
fn make_joint(
    world: &mut PhysicsWorld,
    j: &JointSpec,
    child_pose: &Pose,
    child: BodyHandle,
    parent: Option<BodyHandle>,
) -> crate::Result<Option<ConstraintHandle>> {
    let anchor = child_pose.point(j.anchor);
    let axis = |k: usize| (child_pose.rotation * j.coords[k].axis).normalize();
    let raw = match j.kind {
        JointType::Free | JointType::Fixed => return Ok(None),
        JointType::Revolute | JointType::Continuous => world
            .insert_joint(child, parent, Joint::hinge(anchor, axis(0)))?
            .raw(),
        JointType::Prismatic => world
            .insert_joint(child, parent, Joint::prismatic(anchor, axis(0)))?
            .raw(),
        JointType::Ball => world
            .insert_joint(child, parent, Joint::ball(anchor))?
            .raw(),
        JointType::Planar | JointType::Slide2 => {
            let rotates = j.kind == JointType::Planar;
            let normal = if rotates {
                axis(2)
            } else {
                axis(0).cross(axis(1)).normalize()
            };
            world
                .insert_joint(
                    child,
                    parent,
                    Joint::planar(anchor, normal, axis(0), rotates),
                )?
                .raw()
        }
    };
    for (k, c) in j.coords.iter().enumerate() {
        let sign = kea_sign(j.kind, &j.coords, k);
        if let Some(limit) = coordinate_limit(world, raw, j.kind, k)? {
            let mut changed = *limit;
            if let Some((lo, hi)) = c.limits {
                let stop = |at: Real| SingleLimit {
                    recovery_speed: STOP_RECOVERY_SPEED,
                    ..SingleLimit::hard(sign * (at - c.reference), 0.0)
                };
                let (a, b) = if sign > 0.0 { (lo, hi) } else { (hi, lo) };
                changed.set_limits(stop(a), stop(b))?;
            }
            let mut dynamics = c.dynamics;
            dynamics.rest *= sign;
            changed.set_dynamics(dynamics)?;
            *coordinate_limit(world, raw, j.kind, k)?.expect("found above") = changed;
        }
    }
    Ok(Some(raw))
}

/// The limit of coordinate `k` of a joint, where it has one.
pub(crate) fn coordinate_limit(
    world: &mut PhysicsWorld,
    raw: ConstraintHandle,
    kind: JointType,
    k: usize,
) -> crate::Result<Option<&mut Limit>> {
    let w = world.dynamics_mut();
    Ok(match kind {
        JointType::Revolute | JointType::Continuous => {
            Some(JointHandle::<Hinge>::try_from_raw(&*w, raw)?.limit_mut(w)?)
        }
        JointType::Prismatic => {
            Some(JointHandle::<Prismatic>::try_from_raw(&*w, raw)?.limit_mut(w)?)
        }
        JointType::Planar | JointType::Slide2 => {
            Some(JointHandle::<Planar>::try_from_raw(&*w, raw)?.limit_mut(w, k)?)
        }
        _ => None,
    })
}
