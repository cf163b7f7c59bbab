//! The kink of a junction's cost where the rise of the span before from its entry, over what
//! a cut leaves of it, meets the transition's speed (junction.rs, `Search::cuts`): shorter cuts
//! run at their own speed, longer ones at the rise's, which falls fast as they grow.

use super::{cut_shape, Own, Search, Unbounded};

impl Search<'_> {
    /// Whether cut d's speed (its ceiling, within the sides' speeds) is capped by the rise of the
    /// span before from its entry over what the cut leaves of it (as `speed` caps it). The
    /// ceiling (`Own::ceiling_of` of the cut's shape) is asked only where the rise may cap it.
    pub(super) fn rise_capped(&self, d: f64, ceiling: impl FnOnce() -> f64) -> bool {
        let Some((rise, to_slower)) = self.ends[0] else {
            return false;
        };
        let rest = (self.held.piece.length() - d).max(0.0);
        if rest >= to_slower {
            return false;
        }
        let slower = self.slower();
        let v = ceiling().min(slower);
        // It needs more than `rest` to reach v: what it reaches over `rest` is below v (at the
        // slower side's speed it needs `to_slower`).
        v == slower || rise.time_distance(v).1 > rest
    }

    /// The cut between `free` (not capped by the rise, `rise_capped`; with its ceiling) and the
    /// longer `capped` (with its shape) where the rise meets the curve's speed (`CROSSING_STEPS`
    /// bisections; the uncapped end) and its shape, or None where they are not on both sides of
    /// it.
    pub(super) fn rise_crossing(
        &self,
        (mut free, free_ceiling): (f64, f64),
        (mut capped, capped_shape): (f64, Unbounded),
        share: f64,
    ) -> Option<(f64, Unbounded)> {
        let ceiling_of = |shape: &Unbounded| Own::ceiling_of(shape, self.feed, self.m);
        if self.rise_capped(free, || free_ceiling) || !self.rise_capped(capped, || ceiling_of(&capped_shape))
        {
            return None;
        }
        let start = free;
        // The shape of the last free cut, where its ceiling was asked.
        let mut free_shape = None;
        for _ in 0..CROSSING_STEPS {
            let mid = 0.5 * (free + capped);
            let mut shape = None;
            let at_mid = |shape: &mut Option<Unbounded>| {
                ceiling_of(shape.insert(cut_shape(self.held, self.next, mid, share)))
            };
            if self.rise_capped(mid, || at_mid(&mut shape)) {
                capped = mid;
            } else {
                free = mid;
                free_shape = shape;
            }
        }
        (free != start).then(|| {
            let shape = free_shape.unwrap_or_else(|| cut_shape(self.held, self.next, free, share));
            (free, shape)
        })
    }
}

/// Bisections of the cut between two grid neighbours across the kink of a rise's cap
/// (`rise_crossing`): to 2^-10 of their distance.
const CROSSING_STEPS: u32 = 10;
