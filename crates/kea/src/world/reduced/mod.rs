//! The reduced-coordinate path of a step: trees of hinges, sliders and ball joints hanging from
//! the static world, stepped in their joint coordinates ([`crate::articulation`]) instead of as
//! bodies held together by constraint rows.
//!
//! A tree qualifies, step by step, when (hybrid routing, [`crate::Routing::max_reduced_links`]):
//! its bodies are awake, dynamic, undamped and plain (no fast-spin axis); they are joined by
//! enabled hinges and prismatic joints with hard stops (no restitution), motors, joint
//! dynamics and actuators (servos without a force cap), planar joints whose coordinates'
//! limits are such (the moving side the link), or ball joints without limits, none
//! breakable and none with its own γ; at most `max_reduced_links` coordinates (a ball joint
//! counts three); exactly one of those
//! joints holds the tree to the static world or a disabled body, and the joints make no loop;
//! and nothing else touches its bodies — no other joint, and no contact unless the world's
//! [`crate::WorldSettings::reduced_contacts`] is set and the contact is plain and between a
//! link and a base or two links of the tree (`qualify.rs`): those are solved in the tree's
//! joint space (`crate::articulation`'s contacts, MuJoCo's soft model), their forces written
//! back to the contacts and counted in the joints' reactions. A tree that stops qualifying
//! (a link touches something else) goes to the maximal path in the same step.
//!
//! The tree is built (`build.rs`) from the bodies and joints where they are: coordinates
//! measured from there, each link's frame put where its joint holds it (a drift off the joint
//! is taken out). It is kept from step to step — its coordinates and rates in `f64`, the
//! bodies written from them by forward kinematics — for as long as nothing else moves its
//! bodies: each step the bodies and joints are compared, bit for bit, with what the last step
//! wrote, and the tree is built again from them if anything differs (a user's edit, a step on
//! the maximal path, a restored snapshot). The world's state stays in its bodies and joints;
//! the kept tree only saves rebuilding it, so clones and snapshots step on the same bits.
//!
//! Each step the joints' stops, motors, dynamics and actuators, the bodies' applied forces and
//! the gravity are read again; the joints keep their tracked coordinate and rate, and their
//! reactions come from Newton–Euler at the accelerations the step took. Nothing is written
//! until the solver has accepted the rest of the world: an `Err` step leaves the world as it
//! was.

mod build;
mod commit;
mod contacts;
mod convert;
mod frames;
mod kept;
mod qualify;
#[cfg(feature = "serde")]
mod saved;
mod tendons;

#[cfg(feature = "serde")]
pub(crate) use saved::SavedTree;

use super::World;
use crate::articulation::{ArticulatedTree, TreeLink};
use crate::body::Motion;
use crate::math::{wide, Mat3, Quat, Real, Vec3};
use crate::solver::{Reaction, SolverMode};
use crate::union_find::UnionFind;
use crate::world::constraint_entry::ConstraintKind;
use build::{coordinates_of, drive, limit_of};
use contacts::TreeContacts;
use convert::{d3, dq, rq, v3};
use glam::DVec3;
use qualify::Role;

/// One link of a tree: its body and joint slots and how the joint's coordinate maps to the
/// tree's (`tree = sign · (joint − at)`).
#[derive(Debug, Clone, Copy)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct LinkPlan {
    body: u32,
    joint: u32,
    parent: Option<u32>,
    /// +1 when the link is the joint's first body, −1 when its second.
    sign: f64,
    /// The joint's coordinate where the tree was built, and its rate then.
    at: f64,
    rate: f64,
    /// A ball joint: three hinges in the tree (its coordinate and rate unused).
    #[cfg_attr(feature = "serde", serde(default))]
    ball: bool,
    /// A planar joint: two sliders and, if it turns, a hinge in the tree; `at` and `rate` are
    /// its first travel's, these its second travel's and its turn's (value, rate, value, rate).
    #[cfg_attr(feature = "serde", serde(default))]
    planar: Option<[f64; 4]>,
    /// A floating tree's root: no joint (`joint` is [`FREE_ROOT`]); six coordinates, three
    /// travels and three turns, before its link.
    #[cfg_attr(feature = "serde", serde(default))]
    free: bool,
}

/// The joint slot a floating tree's root plan names: none.
const FREE_ROOT: u32 = u32::MAX;

/// How far a kept floating tree's root may turn from where its chart was centred, rad: past
/// it the tree is built again, centred again (the chart is singular at a quarter turn).
const CHART_LIMIT: f64 = 0.5;

/// What a step left in a link's body and joint: a kept tree is stepped again only while its
/// bodies and joints still read so.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Mark {
    position: Vec3,
    orientation: Quat,
    linear_velocity: Vec3,
    angular_velocity: Vec3,
    mass: Real,
    inertia: Mat3,
    coordinate: Real,
    /// A planar joint's second travel and turn (0 for a hinge or a slider; absent in older
    /// snapshots, which kept no planar tree).
    #[cfg_attr(feature = "serde", serde(default))]
    more: [Real; 2],
}

/// A link's state after the tree's step, committed once the step succeeds.
#[derive(Debug, Clone, Copy)]
struct LinkResult {
    body: u32,
    joint: u32,
    motion: Motion,
    coordinate: Real,
    rate: Real,
    /// A planar joint's second travel and its turn (value, rate).
    more: [(Real, Real); 2],
    reaction: [Reaction; 2],
}

/// A tree kept from step to step.
///
/// `repr(C)`, what travels with a world first (to `tree`, whose own travelling fields lead
/// it): a batch's worker trades exactly these with each world's tree, so they lie in a few
/// cache lines of the world's, not across it.
#[derive(Clone, Default)]
#[repr(C)]
struct CachedTree {
    /// The joint that holds it to its base.
    base_joint: u32,
    /// Stepped in the step in flight.
    stepped: bool,
    /// Holds a ball joint or a floating root: built again every step, its chart centred
    /// (see `build.rs`), never kept.
    rebuilt_each_step: bool,
    /// The joint revision it was built at; 0: stale (built again before use).
    revision: u64,
    plan: Vec<LinkPlan>,
    /// Per plan entry, the tree link that carries its body (a ball joint's third hinge), and
    /// the first of its joint's links (a planar joint's first slider).
    link_of: Vec<usize>,
    first_link: Vec<usize>,
    /// Per plan entry, the impulse (world frame) a ball joint gave its body at the joint's
    /// point when the tree was built (its velocity as the joint allows it), and that point
    /// from the body's centre: part of the joint's reaction in the step that follows.
    kick: Vec<(DVec3, DVec3)>,
    /// Its coordinates and rates now.
    q: Vec<f64>,
    qd: Vec<f64>,
    /// What the last committed step left in each link's body and joint.
    marks: Vec<Mark>,
    tree: ArticulatedTree,
    // Scratch.
    /// Its coordinates and rates after the step in flight.
    q_next: Vec<f64>,
    qd_next: Vec<f64>,
    /// Per plan entry, its subtree's net force in the step in flight.
    subtree: Vec<DVec3>,
    /// The tree's links while it is built.
    building: Vec<TreeLink>,
    /// Its results in the step in flight: `results[first..first + plan.len()]`.
    first: usize,
}

/// The reduced path's buffers, reused every step.
#[derive(Clone, Default)]
#[repr(C)]
pub(super) struct ReducedScratch {
    // `repr(C)`: the kept trees and their caches first, which a held world trades (see
    // `World`).
    /// Kept trees, per joint slot the kept tree it is the base joint of, and per body slot
    /// the kept floating tree it is the root of. Boxed: a trade of states moves trees
    /// between these lists and a world's, and a tree is over a kilobyte (a batch's closed
    /// loop copied two each trade, a sixth of its cache misses).
    #[allow(clippy::vec_box)]
    trees: Vec<Box<CachedTree>>,
    /// Trees a trade of states left over (`kept.rs`), with their step scratch, for the next
    /// trade to take before making new ones.
    #[allow(clippy::vec_box)]
    spare_trees: Vec<Box<CachedTree>>,
    tree_of: Vec<u32>,
    floating_of: Vec<u32>,
    /// The joint revision last looked at, and whether the world then held any hinge or slider.
    candidates: Option<(u64, bool)>,
    /// After a step whose trees' joints were every constraint of the world: the joint
    /// revision and their number.
    alone: Option<(u64, usize)>,
    /// Per body slot: stepped here this step, so the solver leaves it out.
    pub(super) reduced: Vec<bool>,
    role: Vec<Role>,
    sets: UnionFind,
    /// Per set root: links, joints between links, joints to a base, whether blocked, and
    /// the joint that holds it to its base.
    links: Vec<u32>,
    inner_joints: Vec<u32>,
    base_joints: Vec<u32>,
    set_blocked: Vec<bool>,
    base_joint: Vec<u32>,
    /// The roots of the sets that qualify this step.
    roots: Vec<u32>,
    /// Joints between links: (body, joint, other body), sorted (`World::link_adjacency`).
    adjacency: Vec<(u32, u32, u32)>,
    /// The slots of the joints a tree may take, ascending, as of joint revision
    /// `joint_slots_of` (`qualify.rs`).
    joint_slots: Vec<u32>,
    joint_slots_of: Option<u64>,
    /// Kept trees' models, for the next tree built with the same geometry to share (a
    /// batch's worker builds every world's robot on one model).
    shared_models: crate::articulation::SharedModels,
    tau: Vec<f64>,
    results: Vec<LinkResult>,
    /// Per set root, its first body: a floating tree's root link.
    root_body: Vec<u32>,
    /// The trees' contacts in joint space (`contacts.rs`).
    contacts: TreeContacts,
    /// The tendons of the tree in flight (`tendons.rs`): their indices, their form in its
    /// coordinates and their terms, and per joint slot its plan entry + 1 (scratch, zeros).
    tendon_ids: Vec<u32>,
    /// Whether the step in flight works out the joints' reactions (`World::step_many`).
    pub(super) reactions: bool,
    tree_tendons: Vec<crate::articulation::TreeTendon>,
    tendon_terms: Vec<(usize, f64)>,
    plan_of_joint: Vec<u32>,
}

impl World {
    /// Steps every tree that qualifies by `h` into the scratch, marking its bodies for the
    /// solver to leave out. Returns the number of trees.
    pub(super) fn step_reduced_trees(&mut self, h: Real) -> u32 {
        let n = self.bodies.slot_count();
        let r = &mut self.scratch.reduced;
        r.reduced.clear();
        r.reduced.resize(n, false);
        r.results.clear();
        r.contacts.results.clear();
        for t in &mut r.trees {
            t.stepped = false;
        }
        self.scratch.tendon_reduced.clear();
        self.scratch
            .tendon_reduced
            .resize(self.tendons.len(), false);
        let limit = self.settings.routing.max_reduced_links;
        if self.settings.routing.mode != SolverMode::Hybrid
            || limit == 0
            || !(self.has_reducible_joints() || self.lone_bodies_reduce())
        {
            self.forget_unstepped_trees();
            return 0;
        }
        if self.trees_alone() {
            // Nothing but the kept trees' joints in the world, and nothing changed: step
            // them again without looking at the rest.
            let mut stepped = 0;
            for index in 0..self.scratch.reduced.trees.len() {
                if self.scratch.reduced.trees[index].revision == self.joint_revision {
                    if !self.advance_tree(index, h) {
                        self.discard_reduced_trees();
                        self.scratch.reduced.alone = None;
                        return self.step_reduced_trees(h);
                    }
                    stepped += 1;
                }
            }
            return stepped;
        }
        self.find_trees(limit);
        let mut adjacency_ready = false;
        let mut stepped = 0;
        let mut links = 0;
        for k in 0..self.scratch.reduced.roots.len() {
            let root = self.scratch.reduced.roots[k];
            let Some(index) = self.kept_tree(root, &mut adjacency_ready) else {
                continue;
            };
            if self.advance_tree(index, h) {
                stepped += 1;
                links += self.scratch.reduced.trees[index].plan.len();
            } else {
                self.scratch.reduced.trees[index].revision = 0;
            }
        }
        self.forget_unstepped_trees();
        // When the trees' joints are all the world's constraints, the next step may skip
        // the search while nothing changes.
        let kept = self
            .scratch
            .reduced
            .trees
            .iter()
            .all(|t| !(t.stepped && t.rebuilt_each_step));
        self.scratch.reduced.alone = (kept && stepped > 0 && links == self.constraints.len())
            .then_some((self.joint_revision, links));
        stepped
    }

    /// Whether the last step's trees are still all there is: the same joints and no other
    /// constraint (no contact has come), each tree untouched, its bodies still links and its
    /// base still a base, its joints still reducible.
    fn trees_alone(&self) -> bool {
        let r = &self.scratch.reduced;
        let Some((revision, count)) = r.alone else {
            return false;
        };
        if revision != self.joint_revision || count != self.constraints.len() {
            return false;
        }
        r.trees
            .iter()
            .filter(|t| t.revision == self.joint_revision)
            .all(|t| {
                t.plan.len() <= self.settings.routing.max_reduced_links as usize
                    && self.untouched(t)
                    && t.plan.iter().all(|p| {
                        let b = self.bodies.at(p.body as usize);
                        let e = self.constraints.at(p.joint as usize);
                        let base = match (p.parent, e) {
                            (None, Some(e)) => {
                                let other = e.bodies[usize::from(p.sign > 0.0)];
                                other.is_none_or(|h| {
                                    self.bodies.get(h).is_ok_and(|b| !b.enabled && !b.sleeping)
                                })
                            }
                            _ => true,
                        };
                        b.is_some_and(|b| b.enabled && !b.sleeping && qualify::plain(b))
                            && e.is_some_and(|e| e.enabled && qualify::tree_joint(e))
                            && base
                    })
            })
    }

    /// The kept tree for set `root`, built again unless its bodies and joints read as the
    /// last step left them.
    fn kept_tree(&mut self, root: u32, adjacency_ready: &mut bool) -> Option<usize> {
        let floating = self.scratch.reduced.base_joints[root as usize] == 0;
        let base_joint = if floating {
            FREE_ROOT
        } else {
            self.scratch.reduced.base_joint[root as usize]
        };
        let r = &self.scratch.reduced;
        // A floating tree is found by its root body (its chart is re-centred past
        // `CHART_LIMIT` by building it again: `commit_reduced_trees`).
        let root_body = r.root_body[root as usize];
        let kept = if floating {
            r.floating_of.get(root_body as usize)
        } else {
            r.tree_of.get(base_joint as usize)
        };
        if let Some(i) = kept.map(|&i| i as usize).filter(|&i| {
            r.trees.get(i).is_some_and(|t| {
                t.base_joint == base_joint
                    && t.plan
                        .first()
                        .is_some_and(|p| !floating || p.body == root_body)
                    && t.revision == self.joint_revision
                    && self.untouched(t)
            })
        }) {
            return Some(i);
        }
        if !*adjacency_ready {
            self.link_adjacency();
            *adjacency_ready = true;
        }
        // A stale tree's buffers are reused; a new one is made only when none is free.
        let r = &mut self.scratch.reduced;
        let index = match r.trees.iter().position(|t| t.revision == 0 && !t.stepped) {
            Some(i) => i,
            None => {
                r.hold_trees(r.trees.len() + 1);
                r.trees.len() - 1
            }
        };
        // Taken out while the world builds it (no copy: a box moves), put back in its place.
        let mut tree = r.trees.swap_remove(index);
        let built = self.build_tree(root, &mut tree);
        let r = &mut self.scratch.reduced;
        r.trees.push(tree);
        let last = r.trees.len() - 1;
        r.trees.swap(index, last);
        let tree = &mut r.trees[index];
        // A tree built again every step (a ball joint's) is not shared: a planar root's
        // travels, measured in its turned link's axes, change its model as it turns, and a
        // shared model that changes is copied.
        if built && !tree.rebuilt_each_step {
            r.shared_models.share(&mut tree.tree);
        }
        if !built {
            r.trees[index].revision = 0;
            return None;
        }
        r.trees[index].marks.clear();
        if floating {
            if r.floating_of.len() <= root_body as usize {
                r.floating_of
                    .resize(self.bodies.slot_count().max(root_body as usize + 1), 0);
            }
            r.floating_of[root_body as usize] = index as u32;
            return Some(index);
        }
        if r.tree_of.len() <= base_joint as usize {
            r.tree_of
                .resize(self.constraint_bodies.len().max(base_joint as usize + 1), 0);
        }
        r.tree_of[base_joint as usize] = index as u32;
        Some(index)
    }

    /// Whether a kept tree's bodies and joints read as its last step left them.
    fn untouched(&self, t: &CachedTree) -> bool {
        t.marks.len() == t.plan.len()
            && t.plan.iter().zip(&t.marks).all(|(p, m)| {
                let body = self.bodies.at(p.body as usize);
                if p.free {
                    return body.is_some_and(|b| *m == mark(b, [0.0; 3]));
                }
                let joint = self.constraints.at(p.joint as usize);
                match (body, joint) {
                    (Some(b), Some(e)) => *m == mark(b, coordinates_of(e)),
                    _ => false,
                }
            })
    }

    /// Trees not stepped this step are stale: their bodies may move elsewhere.
    fn forget_unstepped_trees(&mut self) {
        for t in &mut self.scratch.reduced.trees {
            if !t.stepped {
                t.revision = 0;
            }
        }
    }

    /// Steps kept tree `index` by `h` into the results; false (nothing kept) if its inertia is
    /// singular or anything comes out non-finite.
    fn advance_tree(&mut self, index: usize, h: Real) -> bool {
        let gravity = d3(self.settings.gravity);
        let r = &mut self.scratch.reduced;
        let t = &mut r.trees[index];
        let (bodies, constraints) = (&self.bodies, &self.constraints);
        t.tree.ensure_workspace();
        t.tree.set_gravity(gravity);
        t.tree.set_integrator(self.settings.integrator);
        r.tau.clear();
        r.tau.resize(t.tree.len(), 0.0);
        for (k, p) in t.plan.iter().enumerate() {
            let link = t.link_of[k];
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            let turn = dq(b.orientation).inverse();
            if t.tree
                .set_external(link, turn * d3(b.torque), turn * d3(b.force))
                .is_err()
            {
                return false;
            }
            if p.free {
                // A floating root: no joint to drive; its links' drives are none, written
                // here as every other link's is (a tree's drives do not travel in a trade).
                for l in t.first_link[k]..=link {
                    t.tree.clear_drive(l);
                }
                continue;
            }
            let entry = constraints
                .at(p.joint as usize)
                .expect("planned joints are live");
            if let (Some(more), ConstraintKind::Planar(j)) = (p.planar, &entry.kind) {
                // Its coordinates each on its own tree link, from the first.
                let first = t.first_link[k];
                for c in 0..=link - first {
                    let at = if c == 0 { p.at } else { more[2 * c - 2] };
                    let coordinate = LinkPlan {
                        at,
                        sign: 1.0,
                        ..*p
                    };
                    let limit = j.limit(c).expect("three coordinates");
                    r.tau[first + c] = drive(limit, &coordinate, t.tree.drive_mut(first + c));
                }
            } else if !p.ball {
                r.tau[link] = drive(limit_of(entry), p, t.tree.drive_mut(link));
            }
        }
        self.tree_tendons(index);
        let (bodies, constraints) = (&self.bodies, &self.constraints);
        let r = &mut self.scratch.reduced;
        let model = self.settings.reduced_contacts.unwrap_or_default();
        r.contacts.gather(&r.trees[index], bodies, constraints);
        let t = &mut r.trees[index];
        if t.tree
            .set_contacts_by_valid_model(&r.contacts.tree, model)
            .is_err()
        {
            return false;
        }
        t.q_next.clone_from(&t.q);
        t.qd_next.clone_from(&t.qd);
        let h64 = wide(h);
        let want_reactions = r.reactions;
        if t.tree
            .step_with_reactions(&mut t.q_next, &mut t.qd_next, &r.tau, h64, want_reactions)
            .is_err()
        {
            return false;
        }
        t.tree.forward(&t.q_next, &t.qd_next);
        let contacts_from = r.contacts.record(&t.tree, constraints);
        t.first = r.results.len();
        for (k, p) in t.plan.iter().enumerate() {
            let link = t.link_of[k];
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            let (position, rotation) = t.tree.frame(link);
            let [w, v] = t.tree.velocity(link);
            let (linear_velocity, angular_velocity) = (v3(rotation * v), v3(rotation * w));
            r.results.push(LinkResult {
                body: p.body,
                joint: p.joint,
                motion: Motion {
                    position: v3(position),
                    orientation: rq(rotation),
                    linear_velocity,
                    angular_velocity,
                    linear_acceleration: (linear_velocity - b.linear_velocity) / h,
                    angular_acceleration: (angular_velocity - b.angular_velocity) / h,
                },
                coordinate: (p.at + p.sign * t.q_next[t.first_link[k]]) as Real,
                rate: (p.sign * t.qd_next[t.first_link[k]]) as Real,
                more: p.planar.map_or([(0.0, 0.0); 2], |m| {
                    let (first, q, qd) = (t.first_link[k], &t.q_next, &t.qd_next);
                    let value = |c: usize, at: f64| (at + q[first + c]) as Real;
                    let turn = if first + 2 <= link {
                        (value(2, m[2]), qd[first + 2] as Real)
                    } else {
                        (m[2] as Real, 0.0)
                    };
                    [(value(1, m[0]), qd[first + 1] as Real), turn]
                }),
                // Filled below, once every link's acceleration is known.
                reaction: [Reaction::default(); 2],
            });
        }
        // Each joint's force on its link, exactly: what its subtree's bodies' momenta took
        // in the step less their weights and applied forces (Newton on the subtree), so that
        // a body's joints account for m a − m g − f to round-off; the torques are Newton–
        // Euler's at the step's start. Skipped (zero) where the next step overwrites them.
        t.subtree.clear();
        t.subtree.resize(t.plan.len(), DVec3::ZERO);
        for k in (0..t.plan.len()).rev().filter(|_| want_reactions) {
            let p = &t.plan[k];
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            let a = r.results[t.first + k].motion.linear_acceleration;
            let own = d3(a * b.mass - self.settings.gravity * b.mass - b.force)
                - r.contacts.on_link[t.link_of[k]];
            let sum = t.subtree[k] + own;
            t.subtree[k] = sum;
            if let Some(parent) = p.parent {
                t.subtree[parent as usize] += sum;
            }
            if p.free {
                continue; // no joint holds a floating root
            }
            let [n, _] = with_kick(t, k, b, h64);
            let f = dq(b.orientation).inverse() * sum;
            let parent = p
                .parent
                .and_then(|k| bodies.at(t.plan[k as usize].body as usize));
            r.results[t.first + k].reaction = reactions([n, f], b, parent, p.sign);
        }
        let finite = r.results[t.first..].iter().all(|x| {
            let m = &x.motion;
            m.position.is_finite()
                && m.orientation.is_finite()
                && m.linear_velocity.is_finite()
                && m.angular_velocity.is_finite()
                && x.coordinate.is_finite()
                && x.reaction
                    .iter()
                    .all(|y| y.force.is_finite() && y.torque.is_finite())
        });
        if !finite {
            r.results.truncate(t.first);
            r.contacts.results.truncate(contacts_from);
            return false;
        }
        for p in &t.plan {
            r.reduced[p.body as usize] = true;
        }
        t.stepped = true;
        self.mark_tree_tendons();
        true
    }

    /// Forgets a step's trees (the step failed): nothing was written, and the kept trees
    /// still hold the state before it.
    pub(super) fn discard_reduced_trees(&mut self) {
        let r = &mut self.scratch.reduced;
        r.results.clear();
        r.contacts.results.clear();
        r.reduced.iter_mut().for_each(|x| *x = false);
        for t in &mut r.trees {
            t.stepped = false;
        }
    }

    /// Bodies the reduced path stepped this step.
    pub(super) fn reduced_body_count(&self) -> u32 {
        self.scratch.reduced.results.len() as u32
    }
}

/// What a step leaves in a body and its joint's coordinate.
fn mark(b: &crate::body::Body, [coordinate, second, turn]: [Real; 3]) -> Mark {
    Mark {
        position: b.position,
        orientation: b.orientation,
        linear_velocity: b.linear_velocity,
        angular_velocity: b.angular_velocity,
        mass: b.mass,
        inertia: b.inertia,
        coordinate,
        more: [second, turn],
    }
}

/// The wrench plan entry `k`'s joint passed to its link in the step (link coordinates), with
/// the build's impulse at a ball joint's point spread over the step `h`.
fn with_kick(t: &CachedTree, k: usize, b: &crate::body::Body, h: f64) -> [DVec3; 2] {
    let [mut n, mut f] = t.tree.reaction(t.link_of[k]);
    if let Some(&(impulse, lever)) = t.kick.get(k) {
        let to_link = dq(b.orientation).inverse();
        f += to_link * (impulse / h);
        n += to_link * (lever.cross(impulse) / h);
    }
    [n, f]
}

/// The joint's reactions on its two bodies from the wrench it passed to the link (link
/// coordinates at the step's start: torque about the link's centre, force): the link's side
/// is body 1 when `sign > 0`; the parent link's side gets the opposite wrench about its
/// centre (the static world or a base gets none).
fn reactions(
    [n, f]: [glam::DVec3; 2],
    link: &crate::body::Body,
    parent: Option<&crate::body::Body>,
    sign: f64,
) -> [Reaction; 2] {
    let turn = dq(link.orientation);
    let (force, torque) = (v3(turn * f), v3(turn * n));
    let mut out = [Reaction::default(); 2];
    let (child, other) = if sign > 0.0 { (0, 1) } else { (1, 0) };
    out[child] = Reaction { force, torque };
    if let Some(pb) = parent {
        let lever = link.position - pb.position;
        out[other] = Reaction {
            force: -force,
            torque: -(torque + lever.cross(force)),
        };
    }
    out
}
