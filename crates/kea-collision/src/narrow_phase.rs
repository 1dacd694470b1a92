//! The narrow phase: for every pair with something that moves, the manifolds this step wants
//! (one Kea contact each), generated or moved along with the bodies.
//!
//! Manifold cache. When the second collider's pose relative to the first has changed by less
//! than [`CACHE_DISTANCE`] and [`CACHE_ANGLE`] since the pair's manifolds were generated, and
//! neither collider has turned by more than [`CACHE_ANGLE`], they are not generated again:
//! their points, kept in each collider's own frame, are carried to the colliders' current
//! poses and the separations measured anew (Jolt's body-pair cache). A pile at rest then costs
//! a few transforms per contact instead of a clipping test, and keeps its points (and their
//! warm starts) exactly.
//!
//! Anchor freezing. While a manifold is reused, its normal keeps its world direction and each
//! point keeps the world lever arm it had on each body when generated (each body holds the
//! point at its own place, [`ContactPoint::held_at`]); only the separations follow the
//! bodies. Re-linearising the arms every step under the large warm-started impulses of a tall
//! stack is an energy pump that grows its lean until it falls (Rapier 0.36 freezes its arms for
//! the same reason): with it a 20-box column that leans 2 mm per box topples within 10 s at
//! the default contact stiffness, without it the column sways and stands.

use crate::capacity::reserve_total;
use crate::collider::{Collider, ColliderDef, Slot, WORLD_BOUND};
use crate::manifold_gen::Generator;
use crate::material::MaterialTable;
use crate::pairs::{CachedPoint, Generated, ManifoldCache, PairState};
use crate::parry::math::Pose;
use crate::reduce::reduce;
use kea::cache::prefetch;
use kea::{BodyHandle, ContactPoint, Quat, Real, Vec3, MAX_CONTACT_POINTS};

/// Relative displacement below which a pair's manifolds are moved rather than generated, m.
/// Rapier recycles contacts up to 5 cm; Jolt's body-pair cache stops at 1 mm.
pub const CACHE_DISTANCE: Real = 5.0e-3;
/// Relative rotation below which a pair's manifolds are moved rather than generated, rad.
pub const CACHE_ANGLE: Real = 2.0 * std::f64::consts::PI as Real / 180.0;

/// A manifold the narrow phase wants this step: the contact it should be.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Wanted {
    /// Pair slot.
    pub pair: u32,
    /// Index of the pair's manifold it refreshes, or [`Wanted::NEW`].
    pub existing: u32,
    /// Body 1 and body 2 of the contact, and the contact's normal (from body 2 to body 1).
    pub bodies: (BodyHandle, Option<BodyHandle>),
    pub normal: Vec3,
    pub points: [ContactPoint; MAX_CONTACT_POINTS],
    pub count: u8,
    /// The manifold as generated this step (an index into the narrow phase's `generated`), or
    /// [`Wanted::KEPT`] for a reused one, whose cache stays as it is.
    pub cache: u32,
    /// The pair's parameters changed (or are new): the contact must take them.
    pub refresh: bool,
}

impl Wanted {
    /// A manifold the pair does not have yet.
    pub(crate) const NEW: u32 = u32::MAX;
    /// A reused manifold: its cache does not change.
    pub(crate) const KEPT: u32 = u32::MAX;
}

/// How many pairs ahead the narrow phase fetches.
const PREFETCH_AHEAD: usize = 4;

/// `cos(CACHE_ANGLE / 2)`: rotations whose quaternions' dot product is at least this are
/// within [`CACHE_ANGLE`] of each other (`|q₁·q₀| = cos(θ/2)`).
pub(crate) fn cos_half_cache_angle() -> Real {
    (0.5 * CACHE_ANGLE).cos()
}

/// Whether rotation `now` is within the angle whose half has cosine `cos_half` of `then`.
fn within_angle(then: Quat, now: Quat, cos_half: Real) -> bool {
    now.dot(then).abs() >= cos_half
}

/// Whether a pair whose colliders are now at `a` and `b` may reuse the manifolds generated at
/// `then`: the relative pose barely changed, and neither collider turned much (the frozen
/// normals and lever arms are world vectors).
fn cache_holds(then: &Generated, a: &Pose, b: &Pose, cos_half: Real) -> bool {
    let relative_now = a.inv_mul(b);
    let moved = (relative_now.translation - then.relative.translation).length_squared();
    moved < CACHE_DISTANCE * CACHE_DISTANCE
        && within_angle(then.relative.rotation, relative_now.rotation, cos_half)
        && within_angle(then.a.rotation, a.rotation, cos_half)
        && within_angle(then.b.rotation, b.rotation, cos_half)
}

/// Pairs one narrow-phase worker takes (one rayon task with the `parallel` feature). The
/// generator keeps nothing from one pair to the next, so the chunking changes no result.
pub(crate) const PAIR_CHUNK: usize = 512;

/// With the `parallel` feature, the fewest chunks of pairs that run on the pool's threads.
#[cfg(feature = "parallel")]
pub(crate) const PARALLEL_MIN_CHUNKS: usize = 8;

/// The narrow phase's work on one chunk of pair slots: what it found, and its scratch. Kept
/// between steps so that a warm step allocates nothing.
#[derive(Clone)]
pub(crate) struct NarrowWorker {
    /// The manifolds the chunk's pairs want, in slot order.
    pub wanted: Vec<Wanted>,
    /// The manifolds generated this step, as cached (a `Wanted::cache` indexes here).
    pub generated: Vec<ManifoldCache>,
    /// Pairs to forget (their boxes parted, or the filter now refuses them).
    pub dropped: Vec<u32>,
    /// Pairs whose manifold failed this step (parry panicked, or gave a non-finite point):
    /// they get no contacts this step and are generated again the next.
    pub failed: Vec<u32>,
    generator: Generator,
    reduce_scratch: (Vec<(Vec3, Real)>, Vec<usize>),
    pub(crate) manifolds: u32,
    pub(crate) reused: u32,
    /// Slots of the chunk's live pairs not at rest after this step, ascending.
    pub(crate) unrested: Vec<u32>,
    /// Pairs of the chunk that did not stay at rest (were looked at) this step.
    pub(crate) visited: u32,
}

impl Default for NarrowWorker {
    /// A worker with room for a chunk of pairs with one manifold each, so that a worker added
    /// when pairs grow allocates nothing more once its pairs settle.
    fn default() -> Self {
        Self {
            wanted: Vec::with_capacity(PAIR_CHUNK),
            generated: Vec::with_capacity(PAIR_CHUNK),
            dropped: Vec::with_capacity(PAIR_CHUNK),
            failed: Vec::new(),
            generator: Generator::default(),
            reduce_scratch: (Vec::with_capacity(64), Vec::with_capacity(64)),
            manifolds: 0,
            reused: 0,
            unrested: Vec::with_capacity(PAIR_CHUNK),
            visited: 0,
        }
    }
}

/// What every worker reads.
pub(crate) struct Shared<'a> {
    pub(crate) slots: &'a [Slot],
    /// Per collider slot: still this step (see `CollisionWorld::still`).
    pub(crate) still: &'a [bool],
    /// The jointed pairs changed this step: resting pairs are filtered again.
    pub(crate) jointed_changed: bool,
    pub(crate) jointed: &'a [(BodyHandle, BodyHandle)],
    pub(crate) materials: &'a MaterialTable,
    pub(crate) margin: Real,
    pub(crate) max_points: usize,
    pub(crate) dt: Real,
    pub(crate) cos_half: Real,
}

/// Whether pair `p` rested last step and rests again, with nothing that could part it: both
/// colliders still (so their fat boxes, which only a moving collider's update changes, still
/// overlap as they did) and the jointed pairs unchanged (so the filter still lets it collide).
/// The narrow phase would find it resting again; it is passed without reaching into its
/// colliders (a sleeping pile's pairs cost a flag each).
pub(crate) fn stays_at_rest(shared: &Shared<'_>, p: &PairState) -> bool {
    let (a, b) = p.colliders;
    p.alive
        && p.resting
        && !shared.jointed_changed
        && shared.still[a as usize]
        && shared.still[b as usize]
}

impl NarrowWorker {
    /// Reserves room for a chunk's pairs.
    pub(crate) fn reserve(&mut self, pairs: usize) {
        reserve_total(&mut self.wanted, pairs);
        reserve_total(&mut self.generated, pairs);
        reserve_total(&mut self.dropped, pairs);
        reserve_total(&mut self.unrested, pairs);
    }

    fn begin(&mut self) {
        self.wanted.clear();
        self.generated.clear();
        self.dropped.clear();
        self.failed.clear();
        self.manifolds = 0;
        self.reused = 0;
        self.unrested.clear();
        self.visited = 0;
    }

    /// The narrow phase of the pairs in slots `listed` (ascending) of `pairs`, every other
    /// pair staying at rest: what [`NarrowWorker::run`] over every slot would find.
    pub(crate) fn run_listed(
        &mut self,
        shared: &Shared<'_>,
        listed: &[u32],
        pairs: &mut [PairState],
    ) {
        self.begin();
        for &slot in listed {
            let p = &mut pairs[slot as usize];
            if p.alive && !stays_at_rest(shared, p) {
                self.visit(shared, slot, p);
            }
        }
    }

    /// The narrow phase of the pairs `pairs`, whose first is slot `first`.
    pub(crate) fn run(&mut self, shared: &Shared<'_>, first: u32, pairs: &mut [PairState]) {
        self.begin();
        for i in 0..pairs.len() {
            // Pairs reach into colliders and manifolds all over memory: fetch a few ahead
            // (not for a pair that stays at rest, which reads neither).
            if let Some(ahead) = pairs.get(i + PREFETCH_AHEAD) {
                if !stays_at_rest(shared, ahead) {
                    prefetch(&shared.slots[ahead.colliders.0 as usize]);
                    prefetch(&shared.slots[ahead.colliders.1 as usize]);
                    if let Some(m) = ahead.manifolds.first() {
                        prefetch(m);
                    }
                }
            }
            let p = &mut pairs[i];
            if !p.alive {
                continue;
            }
            if stays_at_rest(shared, p) {
                continue;
            }
            self.visit(shared, first + i as u32, p);
        }
    }

    /// Pair `slot`, which does not stay at rest.
    fn visit(&mut self, shared: &Shared<'_>, slot: u32, p: &mut PairState) {
        self.visited += 1;
        self.pair(shared, slot, p);
        if p.alive && !p.resting {
            self.unrested.push(slot);
        }
        // A resting pair keeps its manifolds and its touching (the events read `touching`
        // for it); the others' are found anew when the wanted manifolds are applied.
        if !p.resting {
            for m in &mut p.manifolds {
                m.seen = false;
            }
            p.touching_now = false;
        }
    }

    /// The narrow phase of pair `slot`.
    fn pair(&mut self, shared: &Shared<'_>, slot: u32, p: &mut PairState) {
        if !p.alive {
            return;
        }
        let (ia, ib) = p.colliders;
        let (Some(a), Some(b)) = (
            &shared.slots[ia as usize].collider,
            &shared.slots[ib as usize].collider,
        ) else {
            self.dropped.push(slot);
            return;
        };
        if !a.fat.overlaps(&b.fat) || !should_collide(shared.jointed, &a.def, &b.def) {
            p.resting = false;
            self.dropped.push(slot);
            return;
        }
        let resting = a.still && b.still;
        p.resting = resting;
        if resting {
            return; // asleep or static: its contacts stay as they are
        }
        // Body 1 of a Kea contact must be a body; the normal points from body 2 to body 1.
        let (body1, body2, flip) = match (a.def.body, b.def.body) {
            (Some(x), y) => (x, y, false),
            (None, Some(y)) => (y, None, true),
            (None, None) => return,
        };
        let (pose_a, pose_b) = (a.pose, b.pose);
        p.flipped = flip;
        let Some(refresh) = refresh_params(shared, p, flip, (&a.def, &b.def)) else {
            return;
        };
        let frame = Frame {
            pair: slot,
            bodies: (body1, body2),
            flip,
            poses: (pose_a, pose_b),
            refresh,
        };
        if p.generated_at
            .is_some_and(|then| cache_holds(&then, &pose_a, &pose_b, shared.cos_half))
        {
            for (k, m) in p.manifolds.iter().enumerate() {
                self.wanted
                    .push(frame.moved(k as u32, &m.cache, Wanted::KEPT));
            }
            self.manifolds += p.manifolds.len() as u32;
            self.reused += p.manifolds.len() as u32;
            return;
        }
        p.generated_at = Some(Generated::new(pose_a, pose_b));
        // Bounded so that a runaway body cannot hand parry an infinite (or NaN) margin.
        let prediction = (shared.margin + shared.dt * (a.motion + b.motion)).min(WORLD_BOUND);
        if self.generate(slot, p, (a, b), prediction) {
            self.keep_generated(shared, p, &frame);
        }
    }

    /// The shapes' manifolds into the generator's output; false (nothing to keep) for shapes
    /// that cannot collide or output that is not trusted (the pair is then generated afresh
    /// next step, its old manifolds dropped).
    fn generate(
        &mut self,
        slot: u32,
        p: &mut PairState,
        (a, b): (&Collider, &Collider),
        prediction: Real,
    ) -> bool {
        let (sa, sb) = (a.def.shared_shape(), b.def.shared_shape());
        let generator = &mut self.generator;
        let generated = crate::guard::guarded(|| {
            generator.generate(sa.as_ref(), &a.pose, sb.as_ref(), &b.pose, prediction)
        });
        let finite = |g: &crate::manifold_gen::GenManifold| {
            g.normal_a.is_finite()
                && g.normal_a.length_squared() > 0.5
                && g.points()
                    .iter()
                    .all(|q| q.local_a.is_finite() && q.local_b.is_finite() && q.dist.is_finite())
        };
        match generated {
            Ok(true) if self.generator.out.iter().all(finite) => true,
            Ok(false) => false, // a pair of shapes that cannot collide (two meshes)
            _ => {
                self.generator.out.clear();
                p.generated_at = None;
                self.failed.push(slot);
                false
            }
        }
    }

    /// Each generated manifold reduced to the pair's point cap and cached, and wanted.
    fn keep_generated(&mut self, shared: &Shared<'_>, p: &PairState, frame: &Frame) {
        let (pose_a, pose_b) = frame.poses;
        let (points, keep) = &mut self.reduce_scratch;
        for g in &self.generator.out {
            points.clear();
            for gp in g.points() {
                let wa = pose_a.transform_point(gp.local_a);
                points.push((wa, -gp.dist));
            }
            let max_points = match p.max_points {
                0 => shared.max_points,
                own => own as usize,
            };
            reduce(points, max_points, keep);
            let existing = p
                .manifolds
                .iter()
                .position(|m| m.cache.sub == g.sub)
                .map_or(Wanted::NEW, |k| k as u32);
            let mut m = ManifoldCache {
                sub: g.sub,
                normal: unit_normal(pose_a.rotation * g.normal_a),
                points: [CachedPoint::default(); MAX_CONTACT_POINTS],
                count: keep.len() as u8,
            };
            for (j, &k) in keep.iter().enumerate() {
                let gp = g.points[k];
                let at =
                    (pose_a.transform_point(gp.local_a) + pose_b.transform_point(gp.local_b)) * 0.5;
                m.points[j] = CachedPoint {
                    local_a: gp.local_a,
                    local_b: gp.local_b,
                    arms: [at - pose_a.translation, at - pose_b.translation],
                    id: gp.id,
                };
            }
            self.wanted
                .push(frame.moved(existing, &m, self.generated.len() as u32));
            self.generated.push(m);
            self.manifolds += 1;
        }
    }
}

/// The pair's contact parameters read again from the material table when it changed; whether
/// they were (`None`: the materials are gone, nothing to do this step).
fn refresh_params(
    shared: &Shared<'_>,
    p: &mut PairState,
    flip: bool,
    (a, b): (&ColliderDef, &ColliderDef),
) -> Option<bool> {
    let revision = shared.materials.revision();
    if p.params_revision == revision {
        return Some(false);
    }
    let (m1, m2) = if flip {
        (b.material, a.material)
    } else {
        (a.material, b.material)
    };
    let pair = shared.materials.pair_contact(m1, m2).ok()?;
    p.params = pair.params;
    p.direction = pair.friction_direction;
    let max_points = pair.strategy.map_or(0, |s| s.max_points as u8);
    if max_points != p.max_points {
        // Another strategy: the kept manifolds have the old number of points.
        p.max_points = max_points;
        p.generated_at = None;
    }
    p.params_revision = revision;
    Some(true)
}

/// What every manifold of one pair shares this step.
struct Frame {
    pair: u32,
    bodies: (BodyHandle, Option<BodyHandle>),
    /// The first collider is static, so it is body 2 and the normal keeps parry's direction.
    flip: bool,
    poses: (Pose, Pose),
    refresh: bool,
}

impl Frame {
    /// Manifold `m` (index `k` of its pair, or [`Wanted::NEW`]) at the colliders' poses now.
    fn moved(&self, k: u32, m: &ManifoldCache, cache: u32) -> Wanted {
        let (pose_a, pose_b) = &self.poses;
        // Frozen while reused (module docs); the separations follow the colliders.
        let n = m.normal;
        let mut w = Wanted {
            pair: self.pair,
            existing: k,
            bodies: self.bodies,
            // Kea's normal points from body 2 to body 1; parry's from the first shape.
            normal: if self.flip { n } else { -n },
            points: [ContactPoint::default(); MAX_CONTACT_POINTS],
            count: m.count,
            cache,
            refresh: self.refresh,
        };
        for (cp, out) in m.points[..m.count as usize].iter().zip(w.points.iter_mut()) {
            let wa = pose_a.transform_point(cp.local_a);
            let wb = pose_b.transform_point(cp.local_b);
            let held_a = pose_a.translation + cp.arms[0];
            let held_b = pose_b.translation + cp.arms[1];
            // Body 1 of the contact holds the point first.
            let (first, second) = if self.flip {
                (held_b, held_a)
            } else {
                (held_a, held_b)
            };
            *out = ContactPoint::held_at(first, second, -(wb - wa).dot(n), cp.id);
        }
        w
    }
}

/// The filter: not the same body (or both static), groups and masks agree, and not joined.
pub(crate) fn should_collide(
    jointed: &[(BodyHandle, BodyHandle)],
    a: &ColliderDef,
    b: &ColliderDef,
) -> bool {
    if a.body == b.body || a.groups & b.mask == 0 || b.groups & a.mask == 0 {
        return false;
    }
    match (a.body, b.body) {
        (Some(x), Some(y)) => jointed.binary_search(&(x.min(y), x.max(y))).is_err(),
        _ => true,
    }
}

/// `n` made unit again where rounding (a compound's part rotations composed with the pose's)
/// left it off by more than Kea's contacts allow for noise; a normal already unit to within
/// 10⁻⁵ is kept bit for bit.
fn unit_normal(n: Vec3) -> Vec3 {
    if (n.length_squared() - 1.0).abs() > 1.0e-5 {
        n.normalize()
    } else {
        n
    }
}
