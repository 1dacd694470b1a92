//! Keeping the world's contacts in step with the manifolds: refresh the persisting ones (same
//! handle; points matched by feature id, so the solvers warm-start them), create the new ones,
//! destroy the vanished ones, forget pairs whose boxes parted, and record began / persisted /
//! ended events per collider pair.

use crate::collision_world::{handle_of, CollisionWorld};
use crate::error::CollisionResult;
use crate::events::{ContactEvent, ContactEventKind};
use crate::narrow_phase::{NarrowWorker, Wanted};
use crate::pairs::{ManifoldCache, PairManifold, PairState};
use kea::{Contact, ContactParams, ContactPoint, Vec3, World};

impl CollisionWorld {
    /// Writes the wanted manifolds into the world. A new manifold that finds the world's
    /// constraint capacity full is left out (counted in the statistics, and tried again next
    /// step) rather than stopping the world.
    /// `quiet`: the narrow phase had nothing to do (see `narrow_pass.rs`).
    /// `listed`: the narrow phase listed the pairs it may have changed (`visited_pairs`).
    pub(crate) fn apply(
        &mut self,
        world: &mut World,
        quiet: bool,
        listed: bool,
    ) -> CollisionResult<()> {
        self.stats.dropped_manifolds = 0;
        // The workers stay out of `self` while their findings are applied.
        let workers = std::mem::take(&mut self.workers);
        let applied = self.apply_found(world, &workers[..self.active_workers]);
        self.workers = workers;
        applied?;
        self.record_events(world, quiet, listed);
        if self.stats.dropped_manifolds > 0 {
            log::warn!(
                "{} contact manifolds left out: the world holds at most {} constraints",
                self.stats.dropped_manifolds,
                world.max_constraints()
            );
        }
        Ok(())
    }

    /// Forgets the dropped pairs and writes the wanted manifolds, chunk after chunk.
    fn apply_found(&mut self, world: &mut World, workers: &[NarrowWorker]) -> CollisionResult<()> {
        for &slot in workers.iter().flat_map(|w| &w.dropped) {
            self.drop_pair(world, slot);
        }
        for w in workers {
            for wanted in &w.wanted {
                self.apply_one(world, wanted, &w.generated)?;
            }
        }
        Ok(())
    }

    fn apply_one(
        &mut self,
        world: &mut World,
        w: &Wanted,
        generated: &[ManifoldCache],
    ) -> CollisionResult<()> {
        let touch = self.touch_distance;
        let (ia, ib) = self.pairs.slots[w.pair as usize].colliders;
        let (Some(a), Some(b)) = (
            &self.slots[ia as usize].collider,
            &self.slots[ib as usize].collider,
        ) else {
            return Ok(());
        };
        let _ = (a, b);
        let p = &mut self.pairs.slots[w.pair as usize];
        let params = p.params;
        // A fixed friction direction (conveyor pairs): its projection on the tangent plane,
        // none when it is (nearly) the normal.
        let direction = p.direction.and_then(|d| {
            let t = d - w.normal * d.dot(w.normal);
            (t.length() > 1.0e-2).then(|| t.normalize())
        });
        let points = &w.points[..w.count as usize];
        if points
            .iter()
            .any(|q| q.position.abs().max_element() > kea::error::MAX_COORDINATE)
        {
            // Beyond where Kea takes contacts (a body at the edge of the world): none for
            // this pair this step.
            p.generated_at = None;
            return Ok(());
        }
        p.touching_now |= points.iter().any(|q| q.penetration > -touch);
        let found = ContactFound {
            points,
            params,
            direction,
            cache: generated.get(w.cache as usize).copied(),
        };
        match p.manifolds.get_mut(w.existing as usize) {
            Some(m) if w.existing != Wanted::NEW && world.contact(m.handle).is_ok() => {
                let c = world.contact_mut(m.handle)?;
                found.update(c, w)?;
                if let Some(g) = found.cache {
                    m.cache = g;
                }
                m.seen = true;
            }
            // A full world grows; only at its hard limit are manifolds left out.
            _ if world.constraint_count() >= kea::MAX_CAPACITY => {
                self.stats.dropped_manifolds += 1;
                p.generated_at = None; // generated again next step, when room may be free
            }
            _ => found.create(world, w, p)?,
        }
        Ok(())
    }

    /// Forgets pair `slot`: destroys its contacts and ends its touching.
    fn drop_pair(&mut self, world: &mut World, slot: u32) {
        let p = &self.pairs.slots[slot as usize];
        if !p.alive {
            return;
        }
        for m in &p.manifolds {
            let _ = world.destroy_constraint(m.handle); // may be gone with its body
        }
        if p.touching {
            let (a, b) = p.colliders;
            let colliders = [handle_of(&self.slots, a), handle_of(&self.slots, b)];
            self.pending_events.push(ContactEvent {
                kind: ContactEventKind::Ended,
                colliders,
            });
        }
        self.pairs.remove(slot);
    }
}

/// A manifold the narrow phase wants as a contact this step.
struct ContactFound<'a> {
    points: &'a [ContactPoint],
    params: ContactParams,
    direction: Option<Vec3>,
    cache: Option<ManifoldCache>,
}

impl ContactFound<'_> {
    /// Updates the pair's existing contact, writing only what changed.
    fn update(&self, c: &mut Contact, w: &Wanted) -> CollisionResult<()> {
        if w.cache != Wanted::KEPT || c.normal() != w.normal {
            c.set_normal(w.normal)?;
        }
        c.set_points(self.points)?;
        if w.refresh {
            c.set_params(self.params)?;
        }
        if self.direction.is_some() || c.direction().is_some() {
            c.set_direction(self.direction)?;
        }
        Ok(())
    }

    /// Makes a new contact for the pair: in the place of one that went away with a body, or
    /// as a new manifold.
    fn create(&self, world: &mut World, w: &Wanted, p: &mut PairState) -> CollisionResult<()> {
        let mut c = Contact::with_points(w.normal, self.points)?;
        c.set_params(self.params)?;
        c.set_direction(self.direction)?;
        let handle = world.create_contact(w.bodies.0, w.bodies.1, c)?;
        if let Some(m) = p.manifolds.get_mut(w.existing as usize) {
            m.handle = handle;
            if let Some(g) = self.cache {
                m.cache = g;
            }
            m.seen = true;
        } else {
            p.push_manifold(PairManifold {
                cache: self.cache.unwrap_or_default(),
                handle,
                seen: true,
            });
        }
        Ok(())
    }
}
