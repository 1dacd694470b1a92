//! Broad phase: sweep and prune along x. Boxes are sorted by their lower x bound (insertion
//! sort, which is near linear when the order barely changes from step to step, as in a
//! simulation), then each box is tested against the following boxes until one starts past its
//! upper bound. Pairs come out in a deterministic order: by collider slot, smaller first.

use kea::Vec3;

/// An axis-aligned box of one collider.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Entry {
    pub slot: u32,
    pub min: Vec3,
    pub max: Vec3,
}

/// Scratch kept between steps, so the sort starts from last step's order and nothing is
/// allocated once the buffers have grown.
#[derive(Debug, Default)]
pub(crate) struct SweepAndPrune {
    entries: Vec<Entry>,
    previous: Vec<Entry>,
    fresh: Vec<Entry>,
    taken: Vec<bool>,
}

impl SweepAndPrune {
    /// Finds every overlapping pair among `boxes` and writes `(slot a, slot b)` with a < b
    /// into `pairs`, sorted.
    pub fn pairs(&mut self, boxes: impl Iterator<Item = Entry>, pairs: &mut Vec<(u32, u32)>) {
        self.fresh.clear();
        self.fresh.extend(boxes);
        self.fresh.sort_unstable_by_key(|e| e.slot);
        // Keep last step's order for the boxes that remain, so the sort has little to do.
        std::mem::swap(&mut self.entries, &mut self.previous);
        self.entries.clear();
        self.taken.clear();
        self.taken.resize(self.fresh.len(), false);
        for e in &self.previous {
            if let Ok(i) = self.fresh.binary_search_by_key(&e.slot, |f| f.slot) {
                self.entries.push(self.fresh[i]);
                self.taken[i] = true;
            }
        }
        let taken = &self.taken;
        self.entries.extend(
            self.fresh
                .iter()
                .enumerate()
                .filter(|(i, _)| !taken[*i])
                .map(|(_, f)| *f),
        );
        insertion_sort_by_min_x(&mut self.entries);

        pairs.clear();
        for (i, a) in self.entries.iter().enumerate() {
            for b in &self.entries[i + 1..] {
                if b.min.x > a.max.x {
                    break;
                }
                if a.min.y <= b.max.y
                    && b.min.y <= a.max.y
                    && a.min.z <= b.max.z
                    && b.min.z <= a.max.z
                {
                    pairs.push((a.slot.min(b.slot), a.slot.max(b.slot)));
                }
            }
        }
        pairs.sort_unstable();
    }
}

fn insertion_sort_by_min_x(v: &mut [Entry]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].min.x > v[j].min.x {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(slot: u32, x: f32) -> Entry {
        Entry {
            slot,
            min: Vec3::new(x as kea::Real, 0.0, 0.0),
            max: Vec3::new(x as kea::Real + 1.0, 1.0, 1.0),
        }
    }

    #[test]
    fn finds_exactly_the_overlapping_pairs_in_order() {
        let mut sap = SweepAndPrune::default();
        let mut pairs = Vec::new();
        let boxes = [entry(3, 0.0), entry(1, 0.5), entry(2, 5.0), entry(0, 1.4)];
        sap.pairs(boxes.iter().copied(), &mut pairs);
        assert_eq!(pairs, vec![(0, 1), (1, 3)]);
        // Moving a box re-sorts and finds its new neighbours.
        let boxes = [entry(3, 0.0), entry(1, 0.5), entry(2, 1.2), entry(0, 9.0)];
        sap.pairs(boxes.iter().copied(), &mut pairs);
        assert_eq!(pairs, vec![(1, 2), (1, 3)]);
    }
}
