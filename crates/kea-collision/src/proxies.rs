//! The broad phase's step: keep each moving collider's fat box around its swept box, and look
//! up the colliders whose fat box moved for new pairs (see `broad_phase`).

use crate::broad_phase::Aabb;
use crate::collision_world::{
    collider_pose, is_multi_manifold, CollisionWorld, FAT_LOOKAHEAD, FAT_MARGIN,
};

use crate::narrow_phase::should_collide;
use kea::{Real, Vec3, World};

impl CollisionWorld {
    /// Refreshes the fat box of every collider on a body that moves this step (awake and
    /// enabled), grown by the speculative margin and swept by its motion over `dt`. A
    /// collider whose box left its fat box gets a new one and is marked moved. When
    /// `incremental`, only the changed colliders are looked at (the others are still, as
    /// they were); in slot order either way, so the broad phase's tree sees the same updates.
    pub(crate) fn update_bounds(&mut self, world: &World, dt: Real, incremental: bool) {
        // Empty slots count as still: they are in no pair.
        let occupied = |s: &[crate::collider::Slot], i: usize| s[i].collider.is_some();
        self.all_still = true;
        if incremental {
            for k in 0..self.changed.len() {
                let i = self.changed[k] as usize;
                self.still[i] = self.update_bound(i, world, dt);
                self.all_still &= self.still[i] || !occupied(&self.slots, i);
            }
            #[cfg(debug_assertions)]
            self.check_left_out(world);
            return;
        }
        self.still.clear();
        self.still.resize(self.slots.len(), false);
        for i in 0..self.slots.len() {
            self.still[i] = self.update_bound(i, world, dt);
            self.all_still &= self.still[i] || !occupied(&self.slots, i);
        }
        if !self.by_body.is_valid() {
            self.by_body.build(&self.slots);
        }
    }

    /// [`CollisionWorld::update_bounds`] for collider slot `i`: whether it is still this step
    /// (false for an empty slot).
    fn update_bound(&mut self, i: usize, world: &World, dt: Real) -> bool {
        let margin = self.margin;
        let Some(c) = self.slots[i].collider.as_mut() else {
            return false;
        };
        let Some(body) = c.def.body.and_then(|b| world.body(b).ok()) else {
            return c.still;
        };
        if body.is_sleeping() {
            c.still = true;
            return true;
        }
        // A disabled body can be placed by hand: its pose is refreshed, its box is not.
        c.pose = collider_pose(world, &c.def);
        c.still = !body.is_enabled();
        c.motion = body.linear_velocity().length() + body.angular_velocity().length() * c.reach;
        if c.still {
            return true;
        }
        let (lo, hi) = c.world_box();
        let (mut min, mut max) = (lo - Vec3::splat(margin), hi + Vec3::splat(margin));
        let sweep = body.linear_velocity() * dt;
        min += sweep.min(Vec3::ZERO);
        max += sweep.max(Vec3::ZERO);
        let turn = Vec3::splat(body.angular_velocity().length() * dt * c.reach);
        min -= turn;
        max += turn;
        let tight = Aabb { min, max };
        if !c.fat.contains(&tight) {
            let ahead = sweep * FAT_LOOKAHEAD;
            let fat = tight.grown(FAT_MARGIN);
            c.fat = Aabb {
                min: fat.min + ahead.min(Vec3::ZERO),
                max: fat.max + ahead.max(Vec3::ZERO),
            };
            self.tree.update(c.leaf, c.fat);
            self.moved.push(i as u32);
        }
        false
    }

    /// Looks up every moved collider in the tree and adds the pairs it did not have, in a
    /// deterministic order (sorted), filtered as the narrow phase filters.
    pub(crate) fn find_new_pairs(&mut self) {
        self.new_pairs.clear();
        self.moved.sort_unstable();
        self.moved.dedup();
        for k in 0..self.moved.len() {
            let i = self.moved[k];
            let Some(fat) = self.slots[i as usize].collider.as_ref().map(|c| c.fat) else {
                continue;
            };
            let (moved, new_pairs) = (&self.moved, &mut self.new_pairs);
            self.tree.query(&fat, |j| {
                // Both moved: the lower slot reports the pair.
                if j != i && (j > i || moved.binary_search(&j).is_err()) {
                    new_pairs.push((i.min(j), i.max(j)));
                }
            });
        }
        self.moved.clear();
        self.new_pairs.sort_unstable();
        self.new_pairs.dedup();
        let mut added = 0;
        self.found_pairs.clear();
        for k in 0..self.new_pairs.len() {
            let key = self.new_pairs[k];
            if self.pairs.find(key).is_some() {
                continue;
            }
            let (Some(a), Some(b)) = (
                &self.slots[key.0 as usize].collider,
                &self.slots[key.1 as usize].collider,
            ) else {
                continue;
            };
            if a.def.body.is_none() && b.def.body.is_none() {
                continue; // two static colliders never touch each other's motion
            }
            if !should_collide(&self.jointed, &a.def, &b.def) {
                continue;
            }
            let multi = is_multi_manifold(&a.def) || is_multi_manifold(&b.def);
            let slot = self.pairs.insert(key, multi);
            self.found_pairs.push(slot);
            added += 1;
        }
        self.stats.new_pairs = added;
    }
}

/// Which colliders an update must look at: those of the bodies that may have changed since the
/// last update (the awake bodies and the ones touched). A collider of a body asleep or disabled
/// and untouched since is still as it was, so a sleeping pile's colliders cost an update
/// nothing.
impl CollisionWorld {
    /// Lists in `self.changed` (ascending) the colliders this update must look at, if the
    /// world can tell which bodies changed since the last update; returns false when every
    /// collider must be looked at (the first update, colliders added or removed, a restored
    /// world, or more than one step since).
    pub(crate) fn list_changed_colliders(&mut self, world: &World) -> bool {
        if !self.by_body.is_valid() || self.still.len() != self.slots.len() {
            return false;
        }
        let Some(bodies) = self
            .bodies_seen_at
            .and_then(|since| world.bodies_changed_since(since))
        else {
            return false;
        };
        self.changed.clear();
        for b in bodies {
            self.changed.extend_from_slice(self.by_body.of(b));
        }
        self.changed.sort_unstable();
        self.changed.dedup();
        true
    }

    /// Checks (debug builds) that every collider left out of this update is still: static, or
    /// on a body asleep or disabled, and marked still.
    #[cfg(debug_assertions)]
    pub(crate) fn check_left_out(&self, world: &World) {
        for (i, s) in self.slots.iter().enumerate() {
            let Some(c) = &s.collider else { continue };
            if self.changed.binary_search(&(i as u32)).is_ok() {
                continue;
            }
            let Some(b) = c.def.body else { continue };
            let body = world.body(b).expect("a destroyed body is a changed one");
            assert!(
                (body.is_sleeping() || !body.is_enabled()) && self.still[i],
                "collider {i} left out of the update, but its body moves"
            );
        }
    }
}
