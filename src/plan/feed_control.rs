//! Feed override and feed hold: the one place that decides how a change of the feed scale, a hold
//! and its release re-plan the path. The engine hands in where the path is (plain data from the
//! interpolator) and the planned queue; what comes back is the new queue, and whether the block in
//! progress ends where it is.
//!
//! A change is applied at the next point of zero path acceleration (a cruise phase or a block
//! end), so every speed change is one of the feed law's own ramps: jerk-limited, within every
//! limit. What is left of the current block is cut off; if the speed must come down, a ramp of
//! the law brings it down over the shortest distance (the rest of the block, if that is too short,
//! and the next block continues it); then the rest of the path goes through a fresh look-ahead at
//! the new feed scale. A hold plans only the slow-down to standstill and keeps the rest of the
//! path until the release, which plans it again from where the path stopped.

use super::{Planned, Planner};
use crate::config::ranges::MAX_FEED_OVERRIDE;
use crate::config::Machine;
use crate::feed::{self, BlockRequest, FeedLaw, Kin, Profile, ProfileKind};
use crate::path::{PathBlock, Segment};
use crate::tolerance::SPEED_MARGIN;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Path acceleration counted as zero, relative to the largest axis acceleration.
const ZERO_ACCELERATION: f64 = 1e-9;
/// Relative length added to a slow-down ramp's own distance: the law then reaches its target with
/// a few ulps to cruise, where at exactly its distance rounding may call the target unreachable
/// (and the law would stop the ramp at a higher speed).
const RAMP_SLACK: f64 = 1e-9;
/// Smallest feed scale the planner runs at once a hold is released (0 itself means "hold").
const MIN_SCALE: f64 = 1e-3;

/// Where the path is when a change is to be applied (the interpolator's state, plain data).
#[derive(Clone, Copy, Debug)]
pub enum Here<'a> {
    /// Inside `block`, with the feed profile's state `kin` (s from the block start).
    Inside { block: &'a PathBlock, kin: Kin },
    /// Between blocks: the next one comes from the queue.
    Between,
}

/// The outcome of one attempt to apply a pending change.
#[derive(Clone, Debug, PartialEq)]
pub enum Replan {
    /// Not a point of zero acceleration: try again at the next tick.
    Wait,
    /// The queue was planned again; with `cut`, the block in progress ends where it is (its rest
    /// is in the new queue).
    Done { cut: bool },
}

/// Feed override and hold state between ticks.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FeedControl {
    feed_override: f64,
    feed_hold: bool,
    /// Path acceleration below which a change may be applied (m/s²).
    a_zero: f64,
    /// An override or hold change waits for a point where the path acceleration is zero.
    pending: bool,
    /// The hold has been planned: the path stops at the end of the queued deceleration.
    hold_applied: bool,
    /// The rest of the path during a hold, planned again from rest at the release.
    held: Vec<PathBlock>,
}

impl FeedControl {
    pub fn new(machine: &Machine) -> FeedControl {
        let a_max = machine
            .axes
            .iter()
            .map(|x| x.max_acceleration)
            .fold(0.0, f64::max);
        FeedControl {
            feed_override: 1.0,
            feed_hold: false,
            a_zero: ZERO_ACCELERATION * a_max,
            pending: false,
            hold_applied: false,
            held: Vec::new(),
        }
    }

    /// A restored state: for this machine, the override in range, the held blocks checked.
    pub fn check_state(&self, machine: &Machine) -> Result<(), String> {
        crate::valid::within("feed override", self.feed_override, 0.0, 2.0)?;
        if self.a_zero != FeedControl::new(machine).a_zero {
            return Err("feed control: saved for another machine".into());
        }
        self.held.iter().try_for_each(PathBlock::check_state)
    }

    /// Stop, or stay stopped: a hold, or an override of 0.
    pub fn holding(&self) -> bool {
        self.feed_hold || self.feed_override == 0.0
    }

    /// The hold's slow-down is queued: no block after it may start, nothing more is read.
    pub fn hold_applied(&self) -> bool {
        self.hold_applied
    }

    /// A change waits for a point of zero acceleration.
    pub fn pending(&self) -> bool {
        self.pending
    }

    /// Blocks kept back by a hold (they run after the release).
    pub fn held(&self) -> usize {
        self.held.len()
    }

    /// New override factor (clamped to 0…2; not finite counts as 1). Leaving an override of 0
    /// releases the hold it made; `current` is the block in progress.
    pub fn set_override(
        &mut self,
        k: f64,
        current: Option<&Planned>,
        queue: &mut VecDeque<Planned>,
        planner: &mut Planner,
    ) {
        let k = if k.is_finite() {
            k.clamp(0.0, MAX_FEED_OVERRIDE)
        } else {
            1.0
        };
        if k != self.feed_override {
            let was_holding = self.holding();
            self.feed_override = k;
            if was_holding && !self.holding() {
                self.release(current, queue, planner);
            }
            self.pending = true;
        }
    }

    /// Feed hold on or off; off releases it (`current`: the block in progress).
    pub fn set_hold(
        &mut self,
        hold: bool,
        current: Option<&Planned>,
        queue: &mut VecDeque<Planned>,
        planner: &mut Planner,
    ) {
        if hold != self.feed_hold {
            self.feed_hold = hold;
            if hold {
                self.pending = true;
            } else {
                self.release(current, queue, planner);
            }
        }
    }

    /// End of a hold: the rest of the path is planned again from where the path stops. Still
    /// slowing down when released, the ramp finishes first (queued or in progress), and the rest
    /// of the path enters at the speed it ends with (0 at rest).
    fn release(&mut self, current: Option<&Planned>, queue: &mut VecDeque<Planned>, planner: &mut Planner) {
        if self.holding() {
            return;
        }
        self.pending = false;
        if !self.hold_applied {
            return;
        }
        self.hold_applied = false;
        // Not the speed now: a ramp in progress ends at its own exit speed (its end is fixed).
        let v_entry = queue.back().or(current).map_or(0.0, |p| p.v_out);
        let mut blocks = std::mem::take(&mut self.held);
        blocks.extend(planner.restart(v_entry));
        planner.set_feed_scale(self.feed_override.max(MIN_SCALE));
        for b in blocks {
            planner.push(b, queue);
        }
    }

    /// Apply the pending change at `here`, if the path acceleration is zero there and the path
    /// after the speed change can still be planned within the limits (else nothing changes and
    /// the next point of zero acceleration is tried): `queue` is planned again (what is left of
    /// the block in progress first, when `Done { cut: true }`).
    pub fn replan(&mut self, here: Here, queue: &mut VecDeque<Planned>, planner: &mut Planner) -> Replan {
        let (rest, v_cur, cut) = match here {
            Here::Inside { block, kin } => match self.rest_of(block, &kin) {
                Some(rest) => (Some(rest), kin.v, true),
                None => return Replan::Wait,
            },
            Here::Between => match queue.front() {
                Some(p) if p.block.constant_speed => return Replan::Wait,
                // At a block boundary: the next queued block plays the part of the rest.
                Some(p) => (Some(p.block.clone()), p.v_in, false),
                None => (None, 0.0, false),
            },
        };
        let hold = self.holding();
        let scale = if hold {
            planner.feed_scale()
        } else {
            self.feed_override
        };
        let change = match rest {
            Some(rest) => {
                let target = if hold {
                    0.0
                } else {
                    (rest.v_feed * scale).min(rest.limits.v_max)
                };
                slow_down(planner.kind, rest, v_cur, target)
            }
            None => Change {
                head: None,
                rest: None,
                v_start: v_cur,
                settled: true,
            },
        };
        // A ramp to the block's end meets the junction there.
        let junction = match (&change.head, &change.rest) {
            (Some(ramp), None) => ramp.block.v_end_max,
            _ => f64::INFINITY,
        };
        // The path after the change, as it will be planned: the rest of the block, the queue
        // (without the block taken as the rest), the look-ahead window.
        let room = {
            let queued = queue.iter().skip(usize::from(!cut)).map(|p| &p.block);
            let after = change.rest.iter().chain(queued).chain(planner.window());
            planner.entry_limit_of(after, scale).min(junction)
        };
        if change.v_start > 0.0 && change.v_start > room {
            // Slowing down here would leave too little room after it (a jerk-limited change
            // v → w → 0 can take longer than v → 0), or end above the junction's speed: keep
            // the plan, try again further on.
            return Replan::Wait;
        }
        if !cut {
            queue.pop_front();
        }
        let mut head: VecDeque<Planned> = change.head.into_iter().collect();
        let mut blocks: Vec<PathBlock> = change.rest.into_iter().collect();
        blocks.extend(queue.drain(..).map(|p| p.block));
        blocks.extend(planner.restart(change.v_start));
        self.pending = !change.settled;
        if hold && change.settled {
            // Only the deceleration runs; the rest of the path waits for the release.
            self.hold_applied = true;
            self.held.extend(blocks);
        } else {
            if !hold {
                planner.set_feed_scale(scale);
            }
            for b in blocks {
                planner.push(b, &mut head);
            }
        }
        *queue = head;
        Replan::Done { cut }
    }

    /// What is left of the block in progress, if it may be cut here: a point of zero acceleration
    /// that is not inside a constant-speed transition or a dwell.
    fn rest_of(&self, block: &PathBlock, kin: &Kin) -> Option<PathBlock> {
        if block.constant_speed || matches!(block.segment, Segment::Dwell { .. }) {
            return None;
        }
        if kin.a.abs() > self.a_zero {
            return None;
        }
        let length = block.segment.length();
        let s = kin.s.clamp(0.0, length);
        let segment = block.segment.part(s, length - s)?;
        Some(PathBlock {
            segment,
            ..block.clone()
        })
    }
}

/// A speed change at a point of the path: the ramp planned from there (if the speed must come
/// down), the rest of the block after it, the speed that rest is entered at, and whether that is
/// the target speed.
struct Change {
    head: Option<Planned>,
    rest: Option<PathBlock>,
    v_start: f64,
    settled: bool,
}

/// Slow from `v_cur` to `target` at the start of `rest`, if the speed must come down, over the
/// shortest distance the law allows (the whole of `rest` if that is too short).
fn slow_down(kind: ProfileKind, rest: PathBlock, v_cur: f64, target: f64) -> Change {
    let unchanged = |rest: PathBlock| Change {
        head: None,
        rest: Some(rest),
        v_start: v_cur,
        settled: true,
    };
    if v_cur <= target * (1.0 + SPEED_MARGIN) || matches!(rest.segment, Segment::Dwell { .. }) {
        return unchanged(rest);
    }
    let length = rest.segment.length();
    let d = feed::ramp_distance(kind, v_cur, target, &rest.limits) * (1.0 + RAMP_SLACK);
    let request = |length: f64| BlockRequest {
        length,
        v_in: v_cur,
        v_out: target,
        v_feed: v_cur,
        limits: rest.limits,
    };
    if d >= length {
        // The whole rest of the block slows down as hard as the law allows.
        let profile = Profile::plan(kind, &request(length));
        let v_out = profile.v_end();
        return Change {
            head: Some(Planned {
                block: rest,
                v_in: v_cur,
                v_out,
                profile,
            }),
            rest: None,
            v_start: v_out,
            settled: v_out <= target * (1.0 + SPEED_MARGIN),
        };
    }
    // Slow down over d, then the rest of the block at the new feed.
    let (Some(a), Some(b)) = (rest.segment.part(0.0, d), rest.segment.part(d, length - d)) else {
        return unchanged(rest);
    };
    let profile = Profile::plan(kind, &request(d));
    // The speed the ramp really ends with is where the rest starts (continuity, whatever rounding).
    let v_out = profile.v_end();
    Change {
        head: Some(Planned {
            block: PathBlock {
                segment: a,
                v_end_max: target,
                ..rest.clone()
            },
            v_in: v_cur,
            v_out,
            profile,
        }),
        rest: Some(PathBlock { segment: b, ..rest }),
        v_start: v_out,
        settled: v_out <= target * (1.0 + SPEED_MARGIN),
    }
}
