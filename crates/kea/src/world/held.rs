//! A batch's world held as a compact record beside a model (the model/data split, MuJoCo's
//! `mjModel`/`mjData`): the bodies' and joints' definitions (masses, inertias, frames, stops,
//! dynamics) live once, in the hot worker world that steps every world of the batch; each
//! world keeps only what a step or a batch's writes change in them — each body's pose,
//! velocities, forces and flags, each joint's tracked coordinate, motor, actuator, read-outs
//! and flags — and, whole, the constraint slots that are not the model's joints (contacts).
//!
//! The rest of a world's state (the clock, the awake set, the last step's forces, the kept
//! trees, tendons, quarantine) is traded with the worker as whole buffers, as
//! [`World::swap_state`] trades it. A worker that takes a held world in ([`World::enter`])
//! is then that world, bit for bit; [`World::leave`] records what changed and gives the rest
//! back. A world whose joints no longer match the model's (a joint broke and was removed)
//! is held whole from then on: the record says which.

use super::constraint_entry::{ConstraintEntry, ConstraintKind};
use super::World;
use crate::body::Body;
use crate::constraint::limit::LimitMotion;
use crate::math::{Quat, Real, Vec3};
use crate::solver::{Reaction, SolverPath};

/// A world held beside a model (see the module's text): its state without the model's
/// definitions, made by [`World::held`] and stepped, read and written only through a worker
/// world with the model's definitions ([`World::enter`], [`World::leave`]).
#[derive(Clone)]
pub struct HeldState {
    /// Its state but for its bodies and constraints, which `motion` keeps (the arenas are
    /// then empty), or with them when it is held whole.
    world: World,
    motion: MotionRecord,
}

/// What a held world keeps of its bodies and constraints beside the model's definitions,
/// or nothing: it holds its own.
#[derive(Default)]
struct MotionRecord {
    compact: Option<Compact>,
}

impl Clone for MotionRecord {
    fn clone(&self) -> Self {
        MotionRecord {
            compact: self.compact.clone(),
        }
    }

    /// Reuses the record's buffers (a batch's reset allocates nothing once warm).
    fn clone_from(&mut self, other: &Self) {
        self.compact.clone_from(&other.compact);
    }
}

#[derive(Default)]
struct Compact {
    /// Live body slots, ascending, with their generations, and each one's motion.
    body_slots: Vec<(u32, u32)>,
    bodies: Vec<BodyMotion>,
    body_slot_count: usize,
    /// The model's joints, by slot ascending, each with what changes in it.
    joints: Vec<JointMotion>,
    /// Every other constraint slot (contacts, or empty), ascending: slot, generation, entry.
    others: Vec<(u32, u32, Option<ConstraintEntry>)>,
    /// The constraint arena's shape: slot count, free list, live count, capacity.
    slot_count: usize,
    free: Vec<u32>,
    len: usize,
    capacity: usize,
}

/// What changes in a body (every other field is its definition).
#[derive(Clone, Copy)]
struct BodyMotion {
    position: Vec3,
    orientation: Quat,
    linear_velocity: Vec3,
    angular_velocity: Vec3,
    force: Vec3,
    torque: Vec3,
    linear_acceleration: Vec3,
    angular_acceleration: Vec3,
    rest_time: Real,
    last_path: SolverPath,
    enabled: bool,
    sleeping: bool,
    quarantined: bool,
}

/// What changes in one of the model's joints.
struct JointMotion {
    slot: u32,
    generation: u32,
    enabled: bool,
    last_rows: Option<(u32, u32)>,
    reaction: [Reaction; 2],
    kind: KindMotion,
}

/// What changes in a joint's kind: a hinge's angle and limit, a slider's limit, and for the
/// other kinds (rarer in robots) the whole kind, boxed so that a hinge's record stays small.
enum KindMotion {
    Hinge { angle: Real, limit: LimitMotion },
    Prismatic { limit: LimitMotion },
    Whole(Box<ConstraintKind>),
}

impl BodyMotion {
    fn of(b: &Body) -> Self {
        // Every field named, so that a new one is sorted into definition or motion.
        let Body {
            mass: _,
            inv_mass: _,
            inertia: _,
            inv_inertia: _,
            position,
            orientation,
            transform: _, // follows the pose
            linear_velocity,
            angular_velocity,
            force,
            torque,
            linear_acceleration,
            angular_acceleration,
            linear_damping: _,
            angular_damping: _,
            fast_spin_axis: _,
            enabled,
            user_data: _,
            sleeping,
            rest_time,
            prefer_exact: _,
            last_path,
            quarantined,
            kinematic: _,
        } = *b;
        BodyMotion {
            position,
            orientation,
            linear_velocity,
            angular_velocity,
            force,
            torque,
            linear_acceleration,
            angular_acceleration,
            rest_time,
            last_path,
            enabled,
            sleeping,
            quarantined,
        }
    }

    fn put(&self, b: &mut Body) {
        b.position = self.position;
        b.orientation = self.orientation;
        b.linear_velocity = self.linear_velocity;
        b.angular_velocity = self.angular_velocity;
        b.force = self.force;
        b.torque = self.torque;
        b.linear_acceleration = self.linear_acceleration;
        b.angular_acceleration = self.angular_acceleration;
        b.rest_time = self.rest_time;
        b.last_path = self.last_path;
        b.enabled = self.enabled;
        b.sleeping = self.sleeping;
        b.quarantined = self.quarantined;
        // The transform is made from the pose alone (`Body::update_transform`), always.
        b.update_transform();
    }
}

impl KindMotion {
    fn of(kind: &ConstraintKind) -> Option<Self> {
        Some(match kind {
            ConstraintKind::Contact(_) | ConstraintKind::Custom(_) => return None,
            ConstraintKind::Hinge(h) => KindMotion::Hinge {
                angle: h.angle,
                limit: h.limit.motion(),
            },
            ConstraintKind::Prismatic(p) => KindMotion::Prismatic {
                limit: p.limit.motion(),
            },
            other => KindMotion::Whole(Box::new(other.clone())),
        })
    }

    /// Records `kind`'s motion in place; false if `kind` is not the kind recorded.
    fn record(&mut self, kind: &ConstraintKind) -> bool {
        match (self, kind) {
            (KindMotion::Hinge { angle, limit }, ConstraintKind::Hinge(h)) => {
                (*angle, *limit) = (h.angle, h.limit.motion());
            }
            (KindMotion::Prismatic { limit }, ConstraintKind::Prismatic(p)) => {
                *limit = p.limit.motion();
            }
            (KindMotion::Whole(whole), kind)
                if std::mem::discriminant(&**whole) == std::mem::discriminant(kind) =>
            {
                (**whole).clone_from(kind);
            }
            _ => return false,
        }
        true
    }

    fn put(&self, kind: &mut ConstraintKind) {
        match (self, kind) {
            (KindMotion::Hinge { angle, limit }, ConstraintKind::Hinge(h)) => {
                h.angle = *angle;
                h.limit.set_motion(limit);
            }
            (KindMotion::Prismatic { limit }, ConstraintKind::Prismatic(p)) => {
                p.limit.set_motion(limit);
            }
            (KindMotion::Whole(whole), kind) => kind.clone_from(whole),
            // A worker holds the model's joints in the model's slots (`World::enter`).
            _ => debug_assert!(false, "a held joint's kind differs from the model's"),
        }
    }
}

impl JointMotion {
    fn record(&mut self, generation: u32, e: &ConstraintEntry) -> bool {
        if generation != self.generation || !self.kind.record(&e.kind) {
            return false;
        }
        (self.enabled, self.last_rows, self.reaction) = (e.enabled, e.last_rows, e.reaction);
        true
    }

    fn put(&self, e: &mut ConstraintEntry) {
        (e.enabled, e.last_rows, e.reaction) = (self.enabled, self.last_rows, self.reaction);
        self.kind.put(&mut e.kind);
    }
}

impl Compact {
    /// The layout of `w`'s bodies and joints, with their motion now.
    fn of(w: &World) -> Self {
        let mut c = Compact::default();
        for s in 0..w.bodies.slot_count() {
            if let Some((generation, Some(b))) = w.bodies.raw_slot(s) {
                c.body_slots.push((s as u32, generation));
                c.bodies.push(BodyMotion::of(b));
            }
        }
        c.body_slot_count = w.bodies.slot_count();
        for s in 0..w.constraints.slot_count() {
            let Some((generation, Some(e))) = w.constraints.raw_slot(s) else {
                continue;
            };
            if let Some(kind) = KindMotion::of(&e.kind) {
                c.joints.push(JointMotion {
                    slot: s as u32,
                    generation,
                    enabled: e.enabled,
                    last_rows: e.last_rows,
                    reaction: e.reaction,
                    kind,
                });
            }
        }
        c.record_others(w);
        c
    }

    /// Records `w`'s motion; false if its bodies or joints are no longer laid out as the
    /// model's (nothing it recorded is then of use).
    fn record(&mut self, w: &World) -> bool {
        if w.bodies.slot_count() != self.body_slot_count || w.bodies.len() != self.bodies.len() {
            return false;
        }
        for (m, &(s, generation)) in self.bodies.iter_mut().zip(&self.body_slots) {
            match w.bodies.raw_slot(s as usize) {
                Some((g, Some(b))) if g == generation => *m = BodyMotion::of(b),
                _ => return false,
            }
        }
        for j in &mut self.joints {
            match w.constraints.raw_slot(j.slot as usize) {
                Some((generation, Some(e))) if j.record(generation, e) => {}
                _ => return false,
            }
        }
        self.record_others(w);
        true
    }

    /// Records every constraint slot but the model's joints, and the arena's shape.
    fn record_others(&mut self, w: &World) {
        let arena = &w.constraints;
        let mut k = 0;
        let mut joints = self.joints.iter().map(|j| j.slot as usize).peekable();
        for s in 0..arena.slot_count() {
            if joints.next_if_eq(&s).is_some() {
                continue;
            }
            let (generation, entry) = arena.raw_slot(s).expect("a slot below the count");
            if k == self.others.len() {
                self.others.push((s as u32, generation, entry.cloned()));
            } else {
                let o = &mut self.others[k];
                (o.0, o.1) = (s as u32, generation);
                match (&mut o.2, entry) {
                    (Some(mine), Some(e)) => mine.clone_from(e),
                    (mine, e) => *mine = e.cloned(),
                }
            }
            k += 1;
        }
        self.others.truncate(k);
        let (free, len, capacity) = arena.shape();
        self.free.clear();
        self.free.extend_from_slice(free);
        (self.slot_count, self.len, self.capacity) = (arena.slot_count(), len, capacity);
    }

    /// Whether `w`'s bodies and compact joints have `model`'s definitions (what a worker
    /// must not change: debug builds check it when a world leaves).
    fn same_definitions(w: &World, model: &World) -> bool {
        let bodies = w
            .bodies
            .iter()
            .zip(model.bodies.iter())
            .all(|((_, b), (_, m))| {
                let mut b = b.clone();
                BodyMotion::of(m).put(&mut b);
                b == *m
            });
        let joints = (0..model.constraints.slot_count()).all(|s| {
            let (Some(e), Some(m)) = (w.constraints.at(s), model.constraints.at(s)) else {
                return true;
            };
            let same_entry = (e.bodies, e.gamma) == (m.bodies, m.gamma)
                && (e.break_force, e.break_torque) == (m.break_force, m.break_torque);
            same_entry
                && match (&e.kind, &m.kind) {
                    (ConstraintKind::Hinge(h), ConstraintKind::Hinge(mh)) => {
                        let mut h = *h;
                        h.angle = mh.angle;
                        h.limit.set_motion(&mh.limit.motion());
                        h == *mh
                    }
                    (ConstraintKind::Prismatic(p), ConstraintKind::Prismatic(mp)) => {
                        let mut p = *p;
                        p.limit.set_motion(&mp.limit.motion());
                        p == *mp
                    }
                    _ => true,
                }
        });
        bodies && joints
    }

    /// Puts the recorded motion into `w`, which holds the model's definitions.
    fn put(&self, w: &mut World) {
        for (m, &(s, _)) in self.bodies.iter().zip(&self.body_slots) {
            if let Some(b) = w.bodies.at_mut(s as usize) {
                m.put(b);
            }
        }
        let arena = &mut w.constraints;
        arena.take_shape(self.slot_count, &self.free, self.len, self.capacity);
        for (s, generation, entry) in &self.others {
            arena.set_raw_slot(*s as usize, *generation, entry.as_ref());
        }
        for j in &self.joints {
            if let Some(e) = arena.at_mut(j.slot as usize) {
                j.put(e);
            }
        }
    }
}

impl World {
    /// This world's state as a held one (see [`HeldState`]): its bodies' and joints' motion
    /// recorded beside this world's definitions, and the rest of its state but its step
    /// scratch, for workers made from this world (or a copy of it) to step.
    #[must_use]
    pub fn held(&self) -> HeldState {
        let mut world = self.clone();
        world.trim_to_state();
        let motion = MotionRecord {
            compact: Some(Compact::of(&world)),
        };
        world.bodies = world.bodies.emptied();
        world.constraints = world.constraints.emptied();
        HeldState { world, motion }
    }

    /// Takes `held` in: afterwards this world is that world, bit for bit (stepping it,
    /// reading it or writing it is stepping, reading or writing that world), until
    /// [`World::leave`] gives it back. This world must hold the model's definitions — a
    /// copy of the world `held` was made from, or of one with the same bodies and joints —
    /// and no other held world.
    ///
    /// Between the two, change only what a world's state is (poses, velocities, forces,
    /// motors, actuators, contacts, the clock), or remove joints (the world is then held
    /// whole). A definition changed here (a mass, a joint's frames or stops) would be the
    /// model's for every world this one steps after; debug builds check.
    pub fn enter(&mut self, held: &mut HeldState) {
        match &held.motion.compact {
            Some(c) => {
                self.swap_state_but_arenas(&mut held.world);
                c.put(self);
            }
            None => self.swap_state(&mut held.world),
        }
    }

    /// Gives back the held world taken in by [`World::enter`], with all that changed in it,
    /// and takes back this world's own state. `model` is a world with the model's
    /// definitions: if the held world's joints no longer match them (a joint was removed),
    /// it is held whole from now on and this world takes the model's bodies and joints
    /// again.
    pub fn leave(&mut self, held: &mut HeldState, model: &World) {
        let recorded = held.motion.compact.as_mut().map(|c| c.record(self));
        let h = &mut held.world;
        match recorded {
            Some(true) => {
                debug_assert!(
                    Compact::same_definitions(self, model),
                    "a held world's worker changed a definition the model holds"
                );
                self.swap_state_but_arenas(h);
            }
            Some(false) => {
                held.motion.compact = None;
                h.bodies.copy_from(&self.bodies);
                h.constraints.copy_from(&self.constraints);
                self.bodies.copy_from(&model.bodies);
                self.constraints.copy_from(&model.constraints);
                self.swap_state_but_arenas(h);
            }
            None => self.swap_state(h),
        }
    }
}

impl HeldState {
    /// Becomes a copy of `other`, reusing its buffers (a batch's reset: nothing allocated
    /// once it has held a world as big).
    pub fn copy_from(&mut self, other: &HeldState) {
        self.world.copy_state_only(&other.world);
        self.motion.clone_from(&other.motion);
    }

    /// Whether its bodies and joints are kept beside the model's definitions; else it holds
    /// its own (its joints no longer match the model's).
    #[must_use]
    pub fn is_compact(&self) -> bool {
        self.motion.compact.is_some()
    }

    /// Asks for the cache lines a worker reads first when it takes this world in: the
    /// state at the head of the world (`repr(C)`, see `World`), the buffers it points to,
    /// its kept trees' coordinates and its record (a held-whole world: all of it, as
    /// [`World::prefetch`]). A hint: nothing changes.
    pub fn prefetch(&self) {
        use crate::prefetch::{head, slice};
        use std::mem::offset_of;
        let Some(c) = &self.motion.compact else {
            self.world.prefetch();
            return;
        };
        let w = &self.world;
        let state = offset_of!(World, scratch)
            + offset_of!(super::StepScratch, reduced)
            + offset_of!(super::reduced::ReducedScratch, reduced);
        head(w, state);
        slice(&w.constraint_bodies);
        slice(&w.tree_joint_slots);
        slice(&w.scratch.lambda);
        w.scratch.reduced.prefetch_kept();
        slice(std::slice::from_ref(c));
        slice(&c.bodies);
        slice(&c.joints);
        slice(&c.others);
    }
}

// Copies reuse the buffers (a batch's reset allocates nothing once warm): every field named.
impl Clone for Compact {
    fn clone(&self) -> Self {
        let mut c = Compact::default();
        c.clone_from(self);
        c
    }

    fn clone_from(&mut self, o: &Self) {
        let Compact {
            body_slots,
            bodies,
            body_slot_count,
            joints,
            others,
            slot_count,
            free,
            len,
            capacity,
        } = o;
        self.body_slots.clone_from(body_slots);
        self.bodies.clone_from(bodies);
        self.joints.clone_from(joints);
        self.others.clone_from(others);
        self.free.clone_from(free);
        (self.body_slot_count, self.slot_count) = (*body_slot_count, *slot_count);
        (self.len, self.capacity) = (*len, *capacity);
    }
}

impl Clone for JointMotion {
    fn clone(&self) -> Self {
        JointMotion {
            kind: self.kind.clone(),
            ..*self
        }
    }

    fn clone_from(&mut self, o: &Self) {
        self.kind.clone_from(&o.kind);
        (self.slot, self.generation, self.enabled) = (o.slot, o.generation, o.enabled);
        (self.last_rows, self.reaction) = (o.last_rows, o.reaction);
    }
}

impl Clone for KindMotion {
    fn clone(&self) -> Self {
        match self {
            KindMotion::Hinge { angle, limit } => KindMotion::Hinge {
                angle: *angle,
                limit: *limit,
            },
            KindMotion::Prismatic { limit } => KindMotion::Prismatic { limit: *limit },
            KindMotion::Whole(k) => KindMotion::Whole(k.clone()),
        }
    }

    fn clone_from(&mut self, o: &Self) {
        match (self, o) {
            (KindMotion::Whole(mine), KindMotion::Whole(k)) => (**mine).clone_from(k),
            (mine, o) => *mine = o.clone(),
        }
    }
}
