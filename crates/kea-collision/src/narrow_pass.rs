//! The narrow phase over every pair: the pairs cut into chunks, each chunk run by its worker
//! (`narrow_phase.rs`; on all cores with the `parallel` feature), what they found summed.
//!
//! A pair at rest last update whose colliders are both still stays at rest, and is passed by.
//! When the update can tell which colliders changed, the pairs that may not stay at rest are
//! listed instead of found by a pass over every pair: those the last narrow phase left not at
//! rest, those found this update, and those of the colliders that move (each collider's pairs
//! are kept in lists, `Pairs::of_collider`). A sleeping pile beside a moving body then costs
//! its pairs nothing. Both ways visit the same pairs in the same order, and find the same.

use crate::collider::handle_of;
use crate::collision_world::CollisionWorld;
#[cfg(debug_assertions)]
use crate::narrow_phase::stays_at_rest;
#[cfg(feature = "parallel")]
use crate::narrow_phase::PARALLEL_MIN_CHUNKS;
use crate::narrow_phase::{cos_half_cache_angle, NarrowWorker, Shared, PAIR_CHUNK};
use crate::pairs::PairState;
use kea::{Real, MAX_CONTACT_POINTS};

impl CollisionWorld {
    /// Fills the workers with the manifolds of every pair that can move this step and with
    /// the pairs to forget, chunk by chunk (on all cores with the `parallel` feature).
    /// Returns whether the update is quiet — every pair stayed at rest (nothing looked at,
    /// nothing done) — and whether the pairs it may have changed are listed (in
    /// `visited_pairs`; else any may have). `incremental`: the update looked only at the
    /// colliders that changed (`changed`).
    pub(crate) fn narrow_phase(&mut self, dt: Real, incremental: bool) -> (bool, bool) {
        // Nothing moves, no pair is new or unsettled, the filter is as it was: every pair
        // rests again, and a pass over them would find nothing (a sleeping pile).
        let quiet = self.all_still
            && !self.jointed_changed
            && self.stats.new_pairs == 0
            && self.unrest == Some(0);
        if quiet {
            self.active_workers = 0;
            self.stats.manifolds = 0;
            self.stats.reused_manifolds = 0;
            self.failed_pairs.clear();
            self.stats.failed_pairs = 0;
            self.visited_pairs.clear();
            return (true, true);
        }
        let listed = incremental && self.list_visited_pairs();
        let chunks = if listed {
            1
        } else {
            self.pairs.slots.len().div_ceil(PAIR_CHUNK)
        };
        if self.workers.len() < chunks {
            self.workers.resize_with(chunks, NarrowWorker::default);
        }
        self.active_workers = chunks;
        let shared = Shared {
            slots: &self.slots,
            still: &self.still,
            jointed_changed: self.jointed_changed,
            jointed: &self.jointed,
            materials: &self.materials,
            margin: self.margin,
            max_points: self.strategy.max_points.clamp(1, MAX_CONTACT_POINTS),
            dt,
            cos_half: cos_half_cache_angle(),
        };
        let work = |(k, (pairs, worker)): (usize, (&mut [PairState], &mut NarrowWorker))| {
            worker.run(&shared, (k * PAIR_CHUNK) as u32, pairs);
        };
        // A few chunks are not worth waking another thread for: handing work over costs tens
        // of microseconds, about what a chunk of resting pairs takes (with 2 chunks, a
        // sleeping 820-box pyramid stepped at 0.67 of its one-thread speed on 2 cores).
        #[cfg(feature = "parallel")]
        let parallel = chunks >= PARALLEL_MIN_CHUNKS;
        #[cfg(not(feature = "parallel"))]
        let parallel = false;
        if listed {
            #[cfg(debug_assertions)]
            for (slot, p) in self.pairs.slots.iter().enumerate() {
                let left_out = self.visited_pairs.binary_search(&(slot as u32)).is_err();
                assert!(
                    !(left_out && p.alive && !stays_at_rest(&shared, p)),
                    "pair {slot} left out of the narrow phase, but it may not stay at rest"
                );
            }
            self.workers[0].run_listed(&shared, &self.visited_pairs, &mut self.pairs.slots);
        } else if parallel {
            #[cfg(feature = "parallel")]
            {
                use rayon::prelude::*;
                self.pairs
                    .slots
                    .par_chunks_mut(PAIR_CHUNK)
                    .zip(self.workers.par_iter_mut())
                    .enumerate()
                    .for_each_init(kea::float_mode::FlushSubnormals::new, |_, item| work(item));
            }
        } else {
            self.pairs
                .slots
                .chunks_mut(PAIR_CHUNK)
                .zip(self.workers.iter_mut())
                .enumerate()
                .for_each(work);
        }
        let workers = &self.workers[..chunks];
        self.stats.manifolds = workers.iter().map(|w| w.manifolds).sum();
        self.stats.reused_manifolds = workers.iter().map(|w| w.reused).sum();
        self.unrested.clear();
        for w in workers {
            self.unrested.extend_from_slice(&w.unrested);
        }
        self.unrest = Some(self.unrested.len() as u32);
        self.failed_pairs.clear();
        for &slot in workers.iter().flat_map(|w| &w.failed) {
            let (a, b) = self.pairs.slots[slot as usize].colliders;
            let pair = (handle_of(&self.slots, a), handle_of(&self.slots, b));
            log::warn!("collision pair {pair:?} failed in parry this step: it has no contacts");
            self.failed_pairs.push(pair);
        }
        self.stats.failed_pairs = self.failed_pairs.len() as u32;
        (workers.iter().all(|w| w.visited == 0), listed)
    }
}

/// Listing the pairs to visit is worth it while they are at most this share of the live
/// pairs: past it, a pass over every pair costs about what sorting the list does.
const LIST_SHARE: usize = 4;

impl CollisionWorld {
    /// Lists in `visited_pairs` (ascending) every pair that may not stay at rest this update
    /// (module docs); false when that cannot be told (the filter changed, the last narrow
    /// phase is not known) or the list would be long.
    fn list_visited_pairs(&mut self) -> bool {
        if self.jointed_changed || self.unrest.is_none() {
            return false;
        }
        // One worker runs the list: at most a chunk, the room each worker keeps.
        let most = (self.pairs.len() / LIST_SHARE).min(PAIR_CHUNK);
        if self.unrested.len() + self.found_pairs.len() > most {
            return false;
        }
        let list = &mut self.visited_pairs;
        list.clear();
        list.extend_from_slice(&self.unrested);
        list.extend_from_slice(&self.found_pairs);
        for &i in &self.changed {
            if list.len() > most {
                return false;
            }
            if !self.still[i as usize] {
                list.extend(self.pairs.of_collider(i));
            }
        }
        if list.len() > most {
            return false;
        }
        list.sort_unstable();
        list.dedup();
        true
    }
}
