//! Stage timing for the step statistics, read from the clock only when asked for.
//!
//! A clock read costs tens of nanoseconds; a step reads it about a dozen times. That is
//! nothing for a pile of boxes, but a tenth of the step of a two-body world stepped a
//! thousand times in a batch, which reads no statistics. Worlds time their steps by default
//! ([`crate::WorldSettings::step_timing`] turns it off); stage times are then zero.

use std::time::{Duration, Instant};

/// A moment read from the clock when timing is on, or nothing when it is off.
#[derive(Debug, Clone, Copy)]
pub struct Stamp(Option<Instant>);

impl Stamp {
    /// Now, if `timing`; otherwise a stamp that measures every span as zero.
    #[must_use]
    pub fn now(timing: bool) -> Self {
        Self(timing.then(Instant::now))
    }

    /// Time from this stamp to `later` (zero if either was not read).
    #[must_use]
    pub fn until(self, later: Stamp) -> Duration {
        match (self.0, later.0) {
            (Some(a), Some(b)) => b.saturating_duration_since(a),
            _ => Duration::ZERO,
        }
    }

    /// Time since this stamp (zero if it was not read).
    #[must_use]
    pub fn elapsed(self) -> Duration {
        self.0.map_or(Duration::ZERO, |a| a.elapsed())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unread_stamp_measures_zero_and_a_read_one_does_not_go_back() {
        let off = Stamp::now(false);
        let on = Stamp::now(true);
        assert_eq!(off.until(on), Duration::ZERO);
        assert_eq!(on.until(off), Duration::ZERO);
        assert_eq!(off.elapsed(), Duration::ZERO);
        let later = Stamp::now(true);
        assert!(on.until(later) <= on.elapsed());
    }
}
