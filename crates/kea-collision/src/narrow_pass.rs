//! The narrow phase over every pair: the pairs cut into chunks, each chunk run by its worker
//! (`narrow_phase.rs`; on all cores with the `parallel` feature), what they found summed.

use crate::collider::handle_of;
use crate::collision_world::CollisionWorld;
#[cfg(feature = "parallel")]
use crate::narrow_phase::PARALLEL_MIN_CHUNKS;
use crate::narrow_phase::{cos_half_cache_angle, NarrowWorker, Shared, PAIR_CHUNK};
use crate::pairs::PairState;
use kea::{Real, MAX_CONTACT_POINTS};

impl CollisionWorld {
    /// Fills the workers with the manifolds of every pair that can move this step and with
    /// the pairs to forget, chunk by chunk (on all cores with the `parallel` feature).
    /// Returns whether the update is quiet: nothing to do, and nothing done.
    pub(crate) fn narrow_phase(&mut self, dt: Real) -> bool {
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
            return true;
        }
        let chunks = self.pairs.slots.len().div_ceil(PAIR_CHUNK);
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
        if parallel {
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
        self.unrest = Some(workers.iter().map(|w| w.unrest).sum());
        self.failed_pairs.clear();
        for &slot in workers.iter().flat_map(|w| &w.failed) {
            let (a, b) = self.pairs.slots[slot as usize].colliders;
            let pair = (handle_of(&self.slots, a), handle_of(&self.slots, b));
            log::warn!("collision pair {pair:?} failed in parry this step: it has no contacts");
            self.failed_pairs.push(pair);
        }
        self.stats.failed_pairs = self.failed_pairs.len() as u32;
        false
    }
}
