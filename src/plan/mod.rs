//! Look-ahead planner: decides each segment's entry and exit speeds over a bounded window of
//! `lookahead_blocks` segments, so that every planned V_out is reachable by the feed law.
//!
//! - Backward pass: from the window's end (where a stop is assumed, as a real NC does when its
//!   look-ahead is full), each segment's entry limit is the largest speed from which the law can
//!   still slow to what the next segment accepts. With acceleration zero at block ends the jerk-
//!   limited ramp distance D(v1, v2) = (v1 + v2)/2 · T(|v2 − v1|) is *not* monotone in the exit
//!   speed (slowing from v to v/3 can take longer than stopping), so the entry limit is the larger
//!   of "slow to the next limit" and "stop at the block end" (D is unimodal in the exit speed on
//!   [0, v], so the best exit below the limit is one of the two interval ends). The same pass
//!   without the stop gives each segment a pass-through limit, which the segment before aims at
//!   wherever it is entered within its own: entering faster only to stop at the block end then
//!   starting from rest costs more than it gains (CAM-like programs: 3.4 % of their time).
//! - Forward pass: from the actual entry speed, the exit is the next limit if reachable, the best
//!   reachable speed otherwise (accelerating: `max_exit`; slowing: `lowest_exit`, the largest exit
//!   on the rising branch of D, in closed form where the law has one — only when a stop was planned).
//!
//! Work is per block: the window is refilled, swept backwards until the limits stop changing, and
//! its first half emitted, so each block costs O(1) profile solves amortised.

mod feed_control;
pub use feed_control::{FeedControl, Here, Replan};

use crate::feed::bands::Banded;
use crate::feed::scurve7_banded::{self, Rise};
use crate::feed::{scurve7, BlockRequest, FeedLaw, Profile, ProfileKind};
use crate::path::{PathBlock, Segment};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// A segment with its speeds decided and its feed profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Planned {
    pub block: PathBlock,
    pub v_in: f64,
    pub v_out: f64,
    pub profile: Profile,
}

impl Planned {
    /// A restored planned segment: its block, and a profile of the law whose exit speed is the
    /// planned one.
    pub fn check_state(&self, kind: ProfileKind) -> Result<(), String> {
        use crate::valid::{within, MAX_SPEED_M_S};
        self.block.check_state()?;
        self.profile.check_state(kind)?;
        within("entry speed", self.v_in, 0.0, MAX_SPEED_M_S)?;
        if self.v_out != self.profile.v_end() {
            return Err("a planned exit speed is not its profile's".into());
        }
        Ok(())
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct Entry {
    block: PathBlock,
    /// Largest entry speed the segment and its junction with the previous one allow.
    v_in_cap: f64,
    /// Entry limit from the backward pass (NaN until computed).
    v_in_lim: f64,
    /// Entry limit of the backward pass that plans no stop at a block end short of the window's
    /// (NaN until computed): what the segment before aims at where it can pass through.
    v_in_pass: f64,
    /// Largest entry speed from which the segment can stop within its length (fixed; NaN until
    /// a backward pass needs it: on a program that cruises it rarely does, and it costs a root
    /// solve).
    v_in_stop: f64,
    /// Feed for this segment with the override applied (the block keeps the programmed one).
    v_feed: f64,
}

/// The bounded look-ahead window.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Planner {
    kind: ProfileKind,
    capacity: usize,
    window: VecDeque<Entry>,
    /// Actual exit speed of the last emitted segment (entry of the next one).
    v_prev: f64,
    /// Junction limit after the last segment pushed (0 before the first).
    junction_prev: f64,
    /// Feed multiplier for segments pushed from now on (feed override).
    feed_scale: f64,
    /// After a restart from the middle of the path: the entry speed of the next segment pushed.
    forced_entry: Option<f64>,
}

/// Segments released per backward pass when the window is full.
const EMIT_BATCH: usize = 16;

impl Planner {
    pub fn new(kind: ProfileKind, lookahead_blocks: usize) -> Planner {
        Planner {
            kind,
            capacity: lookahead_blocks.max(2),
            window: VecDeque::with_capacity(lookahead_blocks.max(2)),
            v_prev: 0.0,
            junction_prev: 0.0,
            feed_scale: 1.0,
            forced_entry: None,
        }
    }

    /// A restored planner: the machine's law and window size (the window releases segments
    /// when it holds that many: a larger one would read the whole program at once), speeds and
    /// scale in range, its segments checked.
    pub fn check_state(&self, machine: &crate::config::Machine) -> Result<(), String> {
        use crate::valid::{within, MAX_SPEED_M_S};
        let fresh = Planner::new(machine.profile, machine.lookahead_blocks);
        if (self.kind, self.capacity) != (fresh.kind, fresh.capacity) {
            return Err("planner: saved for another law or look-ahead".into());
        }
        if self.window.len() > self.capacity + 1 {
            return Err(format!(
                "planner: {} segments in a window of {}",
                self.window.len(),
                self.capacity
            ));
        }
        within("feed scale", self.feed_scale, 1e-3, 2.0)?;
        within("planner speed", self.v_prev, 0.0, MAX_SPEED_M_S)?;
        within("junction speed", self.junction_prev, 0.0, f64::INFINITY)?;
        within(
            "forced entry",
            self.forced_entry.unwrap_or(0.0),
            0.0,
            MAX_SPEED_M_S,
        )?;
        for e in &self.window {
            e.block.check_state()?;
            within("entry cap", e.v_in_cap, 0.0, MAX_SPEED_M_S)?;
            if !e.v_in_stop.is_nan() {
                within("stop entry", e.v_in_stop, 0.0, MAX_SPEED_M_S)?;
            }
            within("window feed", e.v_feed, 0.0, MAX_SPEED_M_S)?;
            if !e.v_in_lim.is_nan() {
                within("entry limit", e.v_in_lim, 0.0, MAX_SPEED_M_S)?;
            }
            if !e.v_in_pass.is_nan() {
                within("pass-through entry limit", e.v_in_pass, 0.0, MAX_SPEED_M_S)?;
            }
        }
        Ok(())
    }

    /// Start again from a point of the path reached at speed `v_start` (acceleration zero): the
    /// segments waiting in the window come back to the caller, to be pushed again after what is
    /// left of the current one; the next segment pushed enters at `v_start` (override and hold).
    fn restart(&mut self, v_start: f64) -> Vec<PathBlock> {
        let blocks = self.window.drain(..).map(|e| e.block).collect();
        self.v_prev = v_start;
        self.junction_prev = f64::INFINITY;
        self.forced_entry = Some(v_start);
        blocks
    }

    /// Scale the feed of segments pushed from now on (0 < scale ≤ 2; capped by each segment's
    /// limits).
    pub fn set_feed_scale(&mut self, scale: f64) {
        self.feed_scale = scale.clamp(1e-3, 2.0);
    }

    pub fn feed_scale(&self) -> f64 {
        self.feed_scale
    }

    /// Take one segment; emit planned segments to `out` when the window is full.
    pub fn push(&mut self, block: PathBlock, out: &mut VecDeque<Planned>) {
        self.admit(block);
        self.release(out);
    }

    /// Plan and emit a batch when the window is full.
    fn release(&mut self, out: &mut VecDeque<Planned>) {
        // A full window releases a small batch: one backward pass serves EMIT_BATCH segments
        // (the pass re-plans the deceleration zone at the window's end, tens of segments on
        // micro-segment programs), and no tick pays for a large burst.
        // A constant-speed transition at the window's end would be planned to stop there, at
        // zero speed for ever: the window waits for the block after it, which can stop.
        let last_can_stop = !self.window.back().is_some_and(|e| e.block.constant_speed);
        if self.window.len() >= self.capacity && last_can_stop {
            self.backward();
            for _ in 0..EMIT_BATCH.min(self.capacity / 2) {
                self.emit_front(out);
            }
        }
    }

    /// Largest speed at which `blocks`, the path from a point on, may be entered whatever the
    /// feed there (a forced entry), at the feed scale `scale`: the backward pass over them from a
    /// stop after the last one (or after a full window). Entries at or below it are planned
    /// within the limits.
    fn entry_limit_of<'a>(&self, blocks: impl Iterator<Item = &'a PathBlock>, scale: f64) -> f64 {
        let mut scratch = Planner::new(self.kind, self.capacity);
        scratch.set_feed_scale(scale);
        scratch.junction_prev = f64::INFINITY;
        scratch.forced_entry = Some(f64::INFINITY);
        for b in blocks.take(self.capacity) {
            scratch.admit(b.clone());
        }
        scratch.backward();
        // No segment known after the point: the path stops there.
        scratch.window.front().map_or(0.0, |e| e.v_in_lim)
    }

    /// Add a segment to the window's end with its entry cap and stop limit.
    fn admit(&mut self, block: PathBlock) {
        let v_feed = if self.feed_scale != 1.0 {
            (block.v_feed * self.feed_scale).min(block.limits.v_max)
        } else {
            block.v_feed
        };
        let dwell = matches!(block.segment, Segment::Dwell { .. });
        let mut v_in_cap = v_feed.min(self.junction_prev);
        if dwell {
            v_in_cap = 0.0;
        }
        if let Some(v) = self.forced_entry.take() {
            v_in_cap = if dwell { 0.0 } else { v };
        }
        self.junction_prev = if dwell { 0.0 } else { block.v_end_max.min(v_feed) };
        let v_in_stop = if dwell || block.constant_speed {
            0.0
        } else {
            f64::NAN
        };
        self.window.push_back(Entry {
            block,
            v_in_cap,
            v_in_lim: f64::NAN,
            v_in_pass: f64::NAN,
            v_in_stop,
            v_feed,
        });
    }

    /// After the program's last segment: plan and emit the front segment of the window (a stop
    /// at the window's end is then the real program end). Returns false when the window is empty.
    pub fn emit_one(&mut self, out: &mut VecDeque<Planned>) -> bool {
        if self.window.is_empty() {
            return false;
        }
        self.backward();
        self.emit_front(out);
        true
    }

    /// End of program: plan everything left, stopping at the end.
    pub fn finish(&mut self, out: &mut VecDeque<Planned>) {
        self.backward();
        while !self.window.is_empty() {
            self.emit_front(out);
        }
        self.junction_prev = 0.0;
    }

    /// The segments waiting in the window, in order.
    fn window(&self) -> impl Iterator<Item = &PathBlock> {
        self.window.iter().map(|e| &e.block)
    }

    /// Number of segments waiting in the window.
    pub fn pending(&self) -> usize {
        self.window.len()
    }

    /// Backward pass from the window's end (a stop there), until the limits stop changing.
    fn backward(&mut self) {
        let (mut v_next, mut v_next_pass): (f64, f64) = (0.0, 0.0);
        // A stop at a block end is only a way out when the next block can start from rest: a
        // constant-speed transition cannot (it would be traversed at zero speed, forever).
        let mut next_can_start_at_rest = true;
        let last = self.window.len().saturating_sub(1);
        for i in (0..self.window.len()).rev() {
            let e = &self.window[i];
            // Before a transition the exit is its speed, even at the window's end (the
            // transition will accept exactly that), so the limit never falls later.
            let (v_exit, v_exit_pass) = if i == last && e.block.before_transition {
                next_can_start_at_rest = false;
                (e.block.v_end_max, e.block.v_end_max)
            } else {
                (v_next.min(e.block.v_end_max), v_next_pass.min(e.block.v_end_max))
            };
            let constant_speed = e.block.constant_speed;
            let e = &mut self.window[i];
            let (lim, slow) = entry_limit(self.kind, e, v_exit, next_can_start_at_rest);
            let pass = if v_exit_pass == v_exit {
                slow
            } else {
                entry_limit(self.kind, e, v_exit_pass, false).0
            };
            next_can_start_at_rest = !constant_speed;
            if lim == e.v_in_lim && pass == e.v_in_pass {
                break;
            }
            (e.v_in_lim, e.v_in_pass) = (lim, pass);
            (v_next, v_next_pass) = (lim, pass);
        }
    }

    /// The block's limits and speed bands for this planner's feed law.
    fn banded<'a>(&self, block: &'a PathBlock) -> Banded<'a> {
        Banded {
            kind: self.kind,
            top: &block.limits,
            bands: &block.bands,
        }
    }

    /// Forward pass for the front segment: decide its exit, plan its profile, emit it (a block
    /// with speed bands as one part per band it crosses).
    fn emit_front(&mut self, out: &mut VecDeque<Planned>) {
        let Some(e) = self.window.pop_front() else { return };
        let v_in = self.v_prev.min(e.v_in_cap.max(0.0));
        // Where this segment is entered within its pass-through limit, it aims at the next one's
        // (reachable, and no stop at its end); else at the next one's entry limit, which may
        // mean a stop at its end (slowing to a third of a speed can take longer than stopping).
        let v_next = self.window.front().map_or(0.0, |n| {
            if v_in <= e.v_in_pass {
                n.v_in_pass
            } else {
                n.v_in_lim
            }
        });
        let target = v_next.min(e.block.v_end_max).max(0.0);
        let length = e.block.segment.length();
        let lim = e.block.limits;
        let banded = self.banded(&e.block);
        let v_out = if matches!(e.block.segment, Segment::Dwell { .. }) {
            0.0
        } else if e.block.constant_speed {
            v_in
        } else if target >= v_in {
            // The largest exit, where it is below a target above 0 (at or above, the target).
            let range = (f64::NEG_INFINITY, target);
            let reach = if target > 0.0 && banded.joined() {
                Rise::build_in(&mut None, &banded, v_in.max(0.0)).max_speed_within(length, range)
            } else {
                Some(banded.max_exit(length, v_in))
            };
            reach.map_or(target, |v| target.min(v))
        } else {
            banded.lowest_exit(length, v_in, target)
        };
        let v_feed = if e.block.constant_speed {
            v_in
        } else {
            e.v_feed.max(v_in).max(v_out)
        };
        if banded.joined() {
            let profile = Profile::Scurve7Banded(scurve7_banded::plan(&banded, length, v_in, v_out, v_feed));
            let v_out = profile.v_end();
            self.v_prev = v_out;
            out.push_back(Planned {
                block: e.block,
                v_in,
                v_out,
                profile,
            });
            return;
        }
        if !e.block.bands.is_empty() {
            return self.emit_parts(e.block, v_in, v_out, v_feed, out);
        }
        let req = BlockRequest {
            length,
            v_in,
            v_out,
            v_feed,
            limits: lim,
        };
        let profile = Profile::plan(self.kind, &req);
        let v_out = profile.v_end();
        self.v_prev = v_out;
        out.push_back(Planned {
            block: e.block,
            v_in,
            v_out,
            profile,
        });
    }

    /// A banded block as its parts: each a piece of the segment with its band's limits (and no
    /// bands of its own, so a re-plan from inside it keeps within that band).
    fn emit_parts(
        &mut self,
        block: PathBlock,
        v_in: f64,
        v_out: f64,
        v_feed: f64,
        out: &mut VecDeque<Planned>,
    ) {
        let length = block.segment.length();
        let parts = self.banded(&block).parts(length, v_in, v_out, v_feed);
        let last = parts.len().saturating_sub(1);
        for (k, part) in parts.into_iter().enumerate() {
            let Some(segment) = block.segment.part(part.s0, part.length) else {
                continue;
            };
            // The last part ends at the block's junction; the others at a band edge.
            let v_end_max = if k == last {
                block.v_end_max
            } else {
                part.limits.v_max
            };
            self.v_prev = part.v_out;
            out.push_back(Planned {
                block: PathBlock {
                    segment,
                    v_feed: part.v_feed,
                    limits: part.limits,
                    v_end_max,
                    bands: Default::default(),
                    ..block.clone()
                },
                v_in: part.v_in,
                v_out: part.v_out,
                profile: part.profile,
            });
        }
    }
}

/// Largest entry speed of a segment whose exit may be at most `v_exit`, and the largest from
/// which it passes on at `v_exit` without stopping (the slow-down limit under the cap). Its stop
/// limit is computed the first time it can change the result (the slow-down limit below the
/// cap), or taken from the slow-down limit itself when that is the stop (`v_exit` +0: the same
/// solve). Under joined bands a root search stops as soon as its answer cannot change the
/// result: a slow-down limit at or above the cap, a stop limit below the slow-down limit.
fn entry_limit(kind: ProfileKind, e: &mut Entry, v_exit: f64, may_stop: bool) -> (f64, f64) {
    let cap = e.v_in_cap;
    if cap <= v_exit || e.block.constant_speed {
        return (cap.min(v_exit), cap.min(v_exit));
    }
    let length = e.block.segment.length();
    let banded = Banded {
        kind,
        top: &e.block.limits,
        bands: &e.block.bands,
    };
    // At or above the cap the result is the cap, whatever the stop limit.
    let Some(slow_to_next) = max_entry_within(&banded, length, v_exit, (f64::NEG_INFINITY, cap)) else {
        return (cap, cap);
    };
    if v_exit.to_bits() == 0 && e.v_in_stop.is_nan() {
        e.v_in_stop = slow_to_next;
    }
    let pass = cap.min(slow_to_next);
    if !may_stop || slow_to_next > cap {
        return (pass, pass);
    }
    if e.v_in_stop.is_nan() {
        if banded.joined() && stop_is_below(&banded, length, slow_to_next) {
            return (pass, pass);
        }
        // Below the slow-down limit it is not the limit: left unsolved (NaN) then.
        match max_entry_within(&banded, length, 0.0, (slow_to_next, f64::INFINITY)) {
            Some(v) => e.v_in_stop = v,
            None => return (pass, pass),
        }
    }
    (cap.min(slow_to_next.max(e.v_in_stop)), pass)
}

/// Relative margin by which a stop ramp must overrun the length for `stop_is_below`: far above
/// the rounding of a ramp distance, so the distance as evaluated rises across it.
const STOP_MARGIN: f64 = 1e-6;
/// Relative margin by which `rest_ramp_floor` must overrun the length: far above the rounding of
/// the floor and of the ramp distance, so the distance as evaluated then overruns it by
/// `STOP_MARGIN` too.
const FLOOR_MARGIN: f64 = 1e-4;

/// Whether the stop limit (`max_entry` to 0) is below `v`, without solving it (a root search
/// from rest through every band): the stop solve returns a speed whose ramp from rest fits in
/// `length`, so where the ramp from rest to `v` overruns it clearly, that speed is below `v`
/// and the slow-down limit `v` is the entry limit. The ramp's floor answers most of them
/// without the ramp (the same answers: where the floor overruns, so does the ramp).
fn stop_is_below(banded: &Banded, length: f64, v: f64) -> bool {
    rest_ramp_floor(banded, v) > length * (1.0 + FLOOR_MARGIN)
        || scurve7_banded::ramp_distance(banded, 0.0, v) > length * (1.0 + STOP_MARGIN)
}

/// A floor of the distance of any ramp from rest to `v` within the bands: the S-curve's within
/// the widest of their pairs (the largest acceleration A and jerk J of any band), v·T/2. Along a
/// ramp with a = 0 at both ends, a² ≤ 2J·u and a² ≤ 2J·(v − u) at speed u, and a ≤ A; the
/// distance ∫ u/a du is least where a takes the least of these bounds, which is that S-curve.
/// 0 (no floor) where a limit is infinite.
fn rest_ramp_floor(banded: &Banded, v: f64) -> f64 {
    let (_, widest) = banded.bands.pair_range(banded.top);
    scurve7::ramp_distance(0.0, v, &widest)
}

/// `banded.max_entry(length, v_out)`, or None where it lies outside (below, above): under joined
/// bands its root search gives up as soon as it has found that (the same steps as the whole
/// search until then; `Rise::max_speed_within`).
fn max_entry_within(banded: &Banded, length: f64, v_out: f64, range: (f64, f64)) -> Option<f64> {
    if banded.joined() {
        Rise::build_in(&mut None, banded, v_out.max(0.0)).max_speed_within(length, range)
    } else {
        Some(banded.max_entry(length, v_out))
    }
}

#[cfg(test)]
mod tests;
