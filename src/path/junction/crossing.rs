//! The kink of a junction's cost where the rise of the span before from its entry, over what
//! a cut leaves of it, meets the transition's speed (junction.rs, `Search::cuts`): shorter cuts
//! run at their own speed, longer ones at the rise's, which falls fast as they grow.

use super::{cut_shape, Own, Search};

impl Search<'_> {
    /// Whether cut d's speed (its ceiling, within the sides' speeds) is capped by the rise of the
    /// span before from its entry over what the cut leaves of it (as `speed` caps it).
    pub(super) fn rise_capped(&self, d: f64, share: f64) -> bool {
        let Some((rise, to_slower)) = self.ends[0] else {
            return false;
        };
        let rest = (self.held.piece.length() - d).max(0.0);
        if rest >= to_slower {
            return false;
        }
        let v = Own::ceiling_of(&cut_shape(self.held, self.next, d, share), self.feed, self.m)
            .min(self.sides[0].v)
            .min(self.sides[1].v);
        // It needs more than `rest` to reach v: what it reaches over `rest` is below v.
        rise.time_distance(v).1 > rest
    }

    /// The cut between `free` (not capped by the rise, `rise_capped`) and the longer `capped`
    /// where the rise meets the curve's speed (`CROSSING_STEPS` bisections; the uncapped end),
    /// or None where they are not on both sides of it.
    pub(super) fn rise_crossing(&self, mut free: f64, mut capped: f64, share: f64) -> Option<f64> {
        if self.rise_capped(free, share) || !self.rise_capped(capped, share) {
            return None;
        }
        let start = free;
        for _ in 0..CROSSING_STEPS {
            let mid = 0.5 * (free + capped);
            if self.rise_capped(mid, share) {
                capped = mid;
            } else {
                free = mid;
            }
        }
        (free != start).then_some(free)
    }
}

/// Bisections of the cut between two grid neighbours across the kink of a rise's cap
/// (`rise_crossing`): to 2^-10 of their distance.
const CROSSING_STEPS: u32 = 10;
