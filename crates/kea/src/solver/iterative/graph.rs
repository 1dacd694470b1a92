//! Graph colouring of the contact constraints, so that no body appears twice in a colour: the
//! constraints of one colour can then be solved side by side, in SIMD lanes and on several
//! threads, with the same answer as one after the other.
//!
//! Each body carries a bit mask of the colours it is already in; a constraint takes the first
//! colour free in both its bodies' masks (one `trailing_zeros`), in constraint order, so the
//! colouring is deterministic. Bodies that cannot be pushed (the static world, fixed and
//! kinematic bodies) are only read by the solve, never written, so they block no colour.
//!
//! As in Box2D v3, constraints between two dynamic bodies fill colours from the bottom and those
//! against a non-dynamic body from the top: colours are solved in ascending order, so the
//! contacts with the ground are solved last in every sweep and have the final say, which keeps
//! piles from being pushed into it. A constraint that finds no free colour goes to the overflow,
//! solved one lane at a time before the colours.

use super::super::reserve;

/// Colours available to constraints (the overflow is apart).
pub(crate) const COLOURS: usize = 24;
/// The colour of a constraint that found none free.
pub(crate) const OVERFLOW: u8 = u8::MAX;
/// Colours that constraints between two dynamic bodies may use (the top ones stay for
/// constraints against static bodies, so those are always solved after them).
const DYNAMIC_COLOURS: usize = COLOURS - 4;

/// Per-body colour masks, reused from step to step.
#[derive(Debug, Default, Clone)]
pub(crate) struct Colouring {
    masks: Vec<u32>,
}

impl Colouring {
    pub(crate) fn reserve(&mut self, bodies: usize) {
        reserve(&mut self.masks, bodies + 1);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.masks.capacity() * 4
    }

    /// Clears every mask, for `bodies` local bodies.
    pub(crate) fn begin(&mut self, bodies: usize) {
        self.masks.clear();
        self.masks.resize(bodies, 0);
    }

    /// The colour of a constraint on local bodies `a` and `b`, each with whether it can be
    /// pushed; marks it taken in their masks. [`OVERFLOW`] when none is free.
    pub(crate) fn assign(&mut self, a: u32, wa: bool, b: u32, wb: bool) -> u8 {
        let (a, b) = (a as usize, b as usize);
        match (wa, wb) {
            (true, true) => {
                let used = self.masks[a] | self.masks[b];
                let free = !used & ((1u32 << DYNAMIC_COLOURS) - 1);
                if free == 0 {
                    return OVERFLOW;
                }
                let c = free.trailing_zeros();
                self.masks[a] |= 1 << c;
                self.masks[b] |= 1 << c;
                c as u8
            }
            (true, false) | (false, true) => {
                let d = if wa { a } else { b };
                let free = !self.masks[d] & ((1u32 << COLOURS) - 1);
                if free == 0 {
                    return OVERFLOW;
                }
                // The highest free colour.
                let c = 31 - free.leading_zeros();
                self.masks[d] |= 1 << c;
                c as u8
            }
            // Nothing to push: any colour will do; the solve changes no velocity.
            (false, false) => (COLOURS - 1) as u8,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_body_twice_in_a_colour_and_ground_contacts_last() {
        // A chain of 30 bodies on the ground: contacts (i, i+1) and (i, ground).
        let mut g = Colouring::default();
        g.begin(31);
        let mut seen = vec![Vec::<u32>::new(); COLOURS];
        for i in 1..30u32 {
            let c = g.assign(i, true, i + 1, true);
            assert!((c as usize) < DYNAMIC_COLOURS);
            for b in [i, i + 1] {
                assert!(!seen[c as usize].contains(&b));
                seen[c as usize].push(b);
            }
        }
        for i in 1..=30u32 {
            let c = g.assign(i, true, 0, false);
            assert!(
                c as usize >= DYNAMIC_COLOURS,
                "ground contact in colour {c}"
            );
            assert!(!seen[c as usize].contains(&i));
            seen[c as usize].push(i);
        }
    }

    #[test]
    fn a_body_in_every_colour_overflows() {
        let mut g = Colouring::default();
        g.begin(2 + COLOURS);
        let mut overflowed = 0;
        for i in 0..COLOURS + 3 {
            if g.assign(1, true, 2 + (i % COLOURS) as u32, true) == OVERFLOW {
                overflowed += 1;
            }
        }
        assert_eq!(overflowed, COLOURS + 3 - DYNAMIC_COLOURS);
    }
}
