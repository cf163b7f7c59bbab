//! Cuts that cost the same at a junction (junction.rs, `Search::cuts`): where both sides run at
//! one speed and hold the transition to it, every cut is costed at that speed, but a transition
//! in a chain of its own runs above it within its length; of two such cuts the one with more to
//! gain there is taken.

use super::{Found, Search, SAVING};
use crate::path::smooth::joined_loss;

impl Found {
    /// Whether it costs what `best` costs, to `SAVING`, where `best` is held below its own top
    /// speed (by a neighbour, which the cost charges both at), and may gain more by `SAVING` on
    /// its own above that speed (`headroom`).
    pub(super) fn ties_faster(&self, best: &Found) -> bool {
        best.at < best.v && self.cost < best.cost + SAVING && self.headroom() > best.headroom() + SAVING
    }

    /// The most its run gains above the speed it is costed at: its length at its own top speed.
    fn headroom(&self) -> f64 {
        let length = self.h.length();
        if self.at > 0.0 && self.v > self.at {
            length / self.at - length / self.v
        } else {
            0.0
        }
    }
}

impl Search<'_> {
    /// Whether both sides run at one speed of their own: no ramp between them passes through the
    /// transition (in a spiral of arcs it does, and a faster but sharper one slows it).
    pub(super) fn even(&self) -> bool {
        self.sides[0].apart == self.sides[1].apart
    }

    /// How much dearer than `best` a cut may cost and still be taken (`Found::ties_faster`).
    pub(super) fn tie(&self, best: &Found) -> f64 {
        if best.at < best.v && self.even() {
            SAVING
        } else {
            -SAVING
        }
    }

    /// Whether the transition `found` joins neither curved neighbour's chain (smooth.rs,
    /// `joined_loss`) while both run at one speed: then it runs above that speed within its
    /// own length, where a cut that costs the same gains what it runs faster (an S-bend between
    /// arcs both held to Y's velocity: 5.7 mm up to 31.47 mm/s, 2.6 ms quicker than at 30.91,
    /// against 6.8 mm up to 31.03, 0.8 ms). Joined, its tighter bands would only slow the chain.
    pub(super) fn apart(&self, found: &Found) -> bool {
        if !self.even() {
            return false;
        }
        let own = found.own.limits(self.m);
        let cut = (found.h.length(), found.v);
        self.sides.iter().enumerate().all(|(k, s)| {
            if !s.curved || s.feed != self.feed {
                return true;
            }
            let side = (s.length, s.apart);
            let (chain, piece) = if k == 0 { (side, cut) } else { (cut, side) };
            let (theirs, ours) = ((&s.top, &s.bands), (&own.limits, &own.bands));
            let (fast, slow) = if s.apart >= found.v {
                (theirs, ours)
            } else {
                (ours, theirs)
            };
            joined_loss(0.0, chain, piece, fast, slow, (false, false)).is_none()
        })
    }
}
