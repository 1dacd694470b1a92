//! Small analytic contact generators shared by the physics tests (the collision crate is a
//! later layer; the guide's own tutorials write contacts by hand like this).
#![allow(dead_code)]
// Test helpers spell out every contact setting at the call site, on purpose.
#![allow(clippy::too_many_arguments)]

use kea::{
    BodyHandle, ConstraintHandle, Contact, ContactParams, Real, Routing, SolverMode, Vec3, World,
};

/// True when the tests run in double precision.
pub const F64: bool = cfg!(feature = "f64");

/// Both solver paths, for scenarios that must hold in each.
pub const PATHS: [SolverMode; 2] = [SolverMode::Exact, SolverMode::Iterative];

/// A world with default parameters whose islands all go to `mode`'s path.
pub fn world_on(mode: SolverMode, bodies: usize, constraints: usize) -> World {
    let mut w = World::with_capacity(bodies, constraints).unwrap();
    w.update_settings(|s| {
        s.routing = Routing {
            mode,
            ..Default::default()
        }
    })
    .unwrap();
    w
}

/// Removes the given contacts and empties the list (the guide's bounce.c pattern).
pub fn clear_contacts(world: &mut World, contacts: &mut Vec<ConstraintHandle>) {
    for c in contacts.drain(..) {
        world.destroy_constraint(c).unwrap();
    }
}

/// Contacts between the corners of a box and the plane `n·x = offset` (n unit, pointing out of
/// the plane), for every corner closer than `margin` (negative penetration = speculative gap).
pub fn box_plane_contacts(
    world: &mut World,
    body: BodyHandle,
    half_extents: Vec3,
    n: Vec3,
    offset: Real,
    margin: Real,
    params: ContactParams,
    direction: Option<Vec3>,
    out: &mut Vec<ConstraintHandle>,
) {
    let b = world.body(body).unwrap().clone();
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                let local = half_extents * Vec3::new(sx, sy, sz);
                let p = b.point_to_world(local);
                let dist = n.dot(p) - offset;
                if dist < margin {
                    let mut c = Contact::new(p, n, -dist).unwrap();
                    c.set_params(params).unwrap();
                    c.set_direction(direction).unwrap();
                    out.push(world.create_contact(body, None, c).unwrap());
                }
            }
        }
    }
}

/// [`box_plane_contacts`] against the ground `y = 0` with a 1 cm speculative margin.
pub fn ground_box_contacts(
    world: &mut World,
    body: BodyHandle,
    half_extents: Vec3,
    params: ContactParams,
    direction: Option<Vec3>,
    out: &mut Vec<ConstraintHandle>,
) {
    box_plane_contacts(
        world,
        body,
        half_extents,
        Vec3::Y,
        0.0,
        0.01,
        params,
        direction,
        out,
    );
}

/// One contact between a sphere and the plane `y = 0` when closer than `margin`.
pub fn sphere_ground_contact(
    world: &mut World,
    body: BodyHandle,
    radius: Real,
    margin: Real,
    params: ContactParams,
    out: &mut Vec<ConstraintHandle>,
) {
    let p = world.body(body).unwrap().position();
    let dist = p.y - radius;
    if dist < margin {
        let mut c = Contact::new(Vec3::new(p.x, 0.0, p.z), Vec3::Y, -dist).unwrap();
        c.set_params(params).unwrap();
        out.push(world.create_contact(body, None, c).unwrap());
    }
}

/// Contacts between a box's corners and a plane that persist from step to step (a contact is
/// updated while its corner stays close, as a collision layer does), so their handles — and
/// the iterative path's warm start — carry over.
#[derive(Default)]
pub struct BoxPlaneContacts {
    corners: [Option<ConstraintHandle>; 8],
    /// The body whose plane it is (`None`: the static world).
    other: Option<BodyHandle>,
}

impl BoxPlaneContacts {
    /// Contacts against a plane of body `other` (for a box resting on another box).
    pub fn against(other: BodyHandle) -> Self {
        Self {
            corners: [None; 8],
            other: Some(other),
        }
    }

    /// Updates the contacts of box `body` (half extents `half`) resting on the top face of box
    /// `self.other` (same half extents), face normal along the lower box's +y.
    pub fn update_on_box(
        &mut self,
        world: &mut World,
        body: BodyHandle,
        half: Vec3,
        margin: Real,
        params: ContactParams,
    ) {
        let lower = world
            .body(self.other.expect("a box to rest on"))
            .unwrap()
            .clone();
        let n = lower.orientation() * Vec3::Y;
        let offset = n.dot(lower.position()) + half.y;
        self.update(world, body, half, n, offset, margin, params, None);
    }

    /// Creates, updates or removes the corner contacts for the current pose.
    pub fn update(
        &mut self,
        world: &mut World,
        body: BodyHandle,
        half_extents: Vec3,
        n: Vec3,
        offset: Real,
        margin: Real,
        params: ContactParams,
        direction: Option<Vec3>,
    ) {
        let b = world.body(body).unwrap().clone();
        let mut k = 0;
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    let p = b.point_to_world(half_extents * Vec3::new(sx, sy, sz));
                    let dist = n.dot(p) - offset;
                    match (dist < margin, self.corners[k]) {
                        (true, Some(h)) => {
                            let c = world.contact_mut(h).unwrap();
                            c.set_position(p).unwrap();
                            c.set_normal(n).unwrap();
                            c.set_penetration(-dist).unwrap();
                            c.set_params(params).unwrap();
                            c.set_direction(direction).unwrap();
                        }
                        (true, None) => {
                            let mut c = Contact::new(p, n, -dist).unwrap();
                            c.set_params(params).unwrap();
                            c.set_direction(direction).unwrap();
                            self.corners[k] =
                                Some(world.create_contact(body, self.other, c).unwrap());
                        }
                        (false, Some(h)) => {
                            world.destroy_constraint(h).unwrap();
                            self.corners[k] = None;
                        }
                        (false, None) => {}
                    }
                    k += 1;
                }
            }
        }
    }

    /// The live contacts.
    pub fn handles(&self) -> impl Iterator<Item = ConstraintHandle> + '_ {
        self.corners.iter().flatten().copied()
    }
}

/// Largest distance between the two anchors of any ball joint of `joints`.
pub fn max_gap(world: &World, joints: &[kea::JointHandle<kea::BallJoint>]) -> Real {
    joints
        .iter()
        .map(|&j| {
            let joint = j.get(world).unwrap();
            let [b1, b2] = world.constraint_bodies(j).unwrap();
            let a1 = world
                .body(b1.unwrap())
                .unwrap()
                .point_to_world(joint.local_anchor1);
            let a2 = match b2 {
                Some(b) => world.body(b).unwrap().point_to_world(joint.local_anchor2),
                None => joint.local_anchor2,
            };
            (a1 - a2).length()
        })
        .fold(0.0, Real::max)
}
