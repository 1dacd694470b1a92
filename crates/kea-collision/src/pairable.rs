//! Whether any two colliders may ever pair under the filter (bodies, groups and masks, joints
//! and excluded pairs). A world whose colliders cannot — a cart-pole whose two shapes are
//! jointed, a robot whose geoms its MJCF file keeps out of collision — skips the broad and
//! narrow phases: nothing there could find a pair. Queries do not need them: they read each
//! collider's pose from its body when asked.

use crate::broad_phase::Aabb;
use crate::collision_world::{collider_pose, CollisionWorld, FAT_MARGIN};
use crate::narrow_phase::should_collide;
use kea::{Vec3, World};

/// Pair tests the search makes before it answers "may pair" unsearched: the answer that
/// only costs the shortcut, never a contact, in a world of many colliders none of which
/// can meet (a long chain with no ground) where a full search would stall an update.
const SEARCH_BUDGET: usize = 1 << 16;

impl CollisionWorld {
    /// Whether two colliders may pair, from the cache or searched again after colliders or
    /// the jointed pairs changed.
    pub(crate) fn may_pair(&mut self) -> bool {
        if let Some(known) = self.pairable {
            return known;
        }
        let known = self.search_pairable();
        self.pairable = Some(known);
        known
    }

    /// The search: every collider on a body against every other collider (two static ones
    /// never pair), each pair of bodied colliders once.
    fn search_pairable(&self) -> bool {
        let live = |i: usize| {
            self.slots[i]
                .collider
                .as_ref()
                .map(|c| &c.def)
                .filter(|d| d.groups != 0 && d.mask != 0)
        };
        let mut tests = 0;
        for i in 0..self.slots.len() {
            let Some(a) = live(i).filter(|a| a.body.is_some()) else {
                continue;
            };
            for j in 0..self.slots.len() {
                let Some(b) = live(j) else { continue };
                if j == i || (b.body.is_some() && j < i) {
                    continue;
                }
                tests += 1;
                if tests > SEARCH_BUDGET || should_collide(&self.jointed, a, b) {
                    return true;
                }
            }
        }
        false
    }

    /// The update when no two colliders may pair and none do: the bounds are left as they
    /// are (the next update that may pair looks at every collider again), and the update's
    /// events and read-outs are those of an update that found nothing.
    pub(crate) fn pass_unpairable(&mut self) {
        self.bodies_seen_at = None;
        self.bounds_stale = true;
        self.moved.clear();
        self.events.clear();
        self.event_record.forget();
        self.events_quiet = false;
        self.failed_pairs.clear();
        self.unrest = Some(0);
        self.unrested.clear();
        self.active_workers = 0;
        self.stats = kea::CollisionStats::default();
    }

    /// After updates that passed the broad phase by: every collider on a body gets its pose
    /// and a fat box about it again, and looks for pairs. An update skips a sleeping body's
    /// colliders and keeps a disabled one's box, which would otherwise stay where they were
    /// when the passing began.
    pub(crate) fn refit_stale_bounds(&mut self, world: &World) {
        let margin = self.margin;
        for i in 0..self.slots.len() {
            let Some(c) = self.slots[i].collider.as_mut() else {
                continue;
            };
            if c.def.body.is_none_or(|b| world.body(b).is_err()) {
                continue; // static geometry does not move; a destroyed body's is forgotten
            }
            c.pose = collider_pose(world, &c.def);
            let (lo, hi) = c.world_box();
            let tight = Aabb {
                min: lo - Vec3::splat(margin),
                max: hi + Vec3::splat(margin),
            };
            c.fat = tight.grown(FAT_MARGIN);
            self.tree.update(c.leaf, c.fat);
            self.moved.push(i as u32);
        }
        self.bounds_stale = false;
    }

    /// Whether this update may pass the broad and narrow phases by: no two colliders may
    /// pair, no pair is left from before, and no event waits to be reported.
    pub(crate) fn nothing_to_pair(&mut self) -> bool {
        self.pairs.len() == 0 && self.pending_events.is_empty() && !self.may_pair()
    }
}
