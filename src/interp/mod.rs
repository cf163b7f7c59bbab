//! Fixed-period interpolator: walks the planned segments in path time, one tick per interpolation
//! period, and turns the feed profile s(t) and the segment geometry into axis motion by the chain
//! rule. The time left over at a block end is carried into the next block (several short blocks
//! may pass in one tick), and a block's end point is emitted exactly as programmed.

mod differences;
pub use differences::Differences;

use crate::feed::{FeedLaw, Kin};
use crate::geometry::Geo;
use crate::path::Segment;
use crate::plan::{Here, Planned};
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// What the interpolator emits every period.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Tick {
    /// Time of this tick (s).
    pub t: f64,
    /// Source line of the block being executed (0 before the first).
    pub line: u32,
    pub p: Vec3,
    pub v: Vec3,
    pub a: Vec3,
    pub j: Vec3,
    /// Path speed, acceleration and jerk (m/s, m/s², m/s³).
    pub feed: f64,
    pub path_acceleration: f64,
    pub path_jerk: f64,
    /// Path distance travelled since the start (m).
    pub distance: f64,
    /// Unit tangent of the path at this point (zero at rest between blocks of unknown direction).
    pub tangent: Vec3,
    /// All motion done.
    pub finished: bool,
}

/// Axis derivatives from the path derivatives (chain rule of x(s(t))):
/// v = x'·ṡ, a = x''·ṡ² + x'·s̈, j = x'''·ṡ³ + 3·x''·ṡ·s̈ + x'·s⃛.
pub fn axis_motion(g: &Geo, k: &Kin) -> (Vec3, Vec3, Vec3) {
    let mut v = [0.0; 3];
    let mut a = [0.0; 3];
    let mut j = [0.0; 3];
    for i in 0..3 {
        v[i] = g.d1[i] * k.v;
        a[i] = g.d2[i] * k.v * k.v + g.d1[i] * k.a;
        j[i] = g.d3[i] * k.v * k.v * k.v + 3.0 * g.d2[i] * k.v * k.a + g.d1[i] * k.j;
    }
    (v, a, j)
}

/// The block being executed and the time spent in it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Current {
    planned: Planned,
    /// Path time inside the block (s).
    tau: f64,
    /// Total time of the block: the profile's duration, or the dwell time.
    duration: f64,
}

fn block_duration(p: &Planned) -> f64 {
    match p.block.segment {
        Segment::Dwell { seconds, .. } => seconds.max(0.0),
        _ => p.profile.duration(),
    }
}

/// Walks planned segments in path time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Interpolator {
    current: Option<Current>,
    /// Distance of all completed blocks (m).
    distance_done: f64,
    /// Path time of all completed blocks (s): the exact motion time once finished.
    time_done: f64,
    /// Position at rest (start, or the end of the last block).
    rest: Vec3,
    last_line: u32,
    last_tangent: Vec3,
}

impl Interpolator {
    pub fn new(start: Vec3) -> Interpolator {
        Interpolator {
            current: None,
            distance_done: 0.0,
            time_done: 0.0,
            rest: start,
            last_line: 0,
            last_tangent: [0.0; 3],
        }
    }

    /// A restored interpolator: the block in progress checked, its time within its duration,
    /// the rest point in range.
    pub fn check_state(&self, kind: crate::feed::ProfileKind) -> Result<(), String> {
        use crate::valid::{point, within, MAX_POSITION_M};
        if let Some(c) = &self.current {
            c.planned.check_state(kind)?;
            if c.duration != block_duration(&c.planned) {
                return Err("interpolator: the block's duration is not its profile's".into());
            }
            within("time in block", c.tau, 0.0, c.duration)?;
        }
        within("path time", self.time_done, 0.0, crate::valid::MAX_TIME_S)?;
        within(
            "path distance",
            self.distance_done,
            0.0,
            crate::valid::MAX_MAGNITUDE,
        )?;
        point("rest point", self.rest, MAX_POSITION_M)?;
        point("tangent", self.last_tangent, 2.0)
    }

    /// Path time of all completed blocks plus the time inside the current one (s).
    pub fn path_time(&self) -> f64 {
        self.time_done + self.current.as_ref().map_or(0.0, |c| c.tau)
    }

    /// Path distance travelled (m).
    pub fn distance(&self) -> f64 {
        self.distance_done
            + self
                .current
                .as_ref()
                .map_or(0.0, |c| c.planned.profile.at(c.tau).s)
    }

    /// The block in progress and the path time left in it (s).
    pub fn current(&self) -> Option<(&Planned, f64)> {
        self.current
            .as_ref()
            .map(|c| (&c.planned, (c.duration - c.tau).max(0.0)))
    }

    /// True when no block is in progress (the caller knows whether more will come).
    pub fn idle(&self) -> bool {
        self.current.is_none()
    }

    /// Advance the path time by `dt` (s), taking blocks from `queue` as the previous ones end.
    /// Returns the time not used because the queue ran dry (0 when all of `dt` was used): the
    /// caller refills the queue and calls again with it.
    #[inline]
    pub fn advance(&mut self, dt: f64, queue: &mut VecDeque<Planned>) -> f64 {
        // Most ticks stay inside the block in progress: that step is kept apart from the block
        // changes (its first turn, the same test).
        if let Some(c) = self.current.as_mut() {
            if dt < c.duration - c.tau {
                c.tau += dt;
                return 0.0;
            }
        }
        self.advance_across(dt, queue)
    }

    /// [`Interpolator::advance`] where a block may end within `dt`.
    #[inline(never)]
    fn advance_across(&mut self, mut dt: f64, queue: &mut VecDeque<Planned>) -> f64 {
        loop {
            if self.current.is_none() {
                let Some(planned) = queue.pop_front() else {
                    return dt;
                };
                let duration = block_duration(&planned);
                self.current = Some(Current {
                    planned,
                    tau: 0.0,
                    duration,
                });
            }
            let c = self.current.as_mut().expect("current block set above");
            let left = c.duration - c.tau;
            if dt < left {
                c.tau += dt;
                return 0.0;
            }
            // Block ends inside this step: carry the remaining time into the next block.
            dt -= left.max(0.0);
            let c = self.current.take().expect("current block set above");
            self.finish_block(&c);
            if dt <= 0.0 && queue.is_empty() {
                return 0.0;
            }
        }
    }

    /// Where the path is, for a feed override or hold (plain data for the plan stage).
    pub fn here(&self) -> Here<'_> {
        match &self.current {
            Some(c) => Here::Inside {
                block: &c.planned.block,
                kin: c.planned.profile.at(c.tau),
            },
            None => Here::Between,
        }
    }

    /// End the block in progress where it is (its rest has been planned again): the part done
    /// is booked, the path rests at the current point until the next block starts.
    pub fn end_here(&mut self) {
        let Some(c) = self.current.take() else { return };
        let block = &c.planned.block;
        let s = c.planned.profile.at(c.tau).s.clamp(0.0, block.segment.length());
        let g = block.segment.eval(s);
        self.time_done += c.tau;
        self.distance_done += s;
        self.last_line = block.segment.line_at(s).unwrap_or(block.line);
        self.rest = g.p;
        self.last_tangent = g.d1;
    }

    fn finish_block(&mut self, c: &Current) {
        self.time_done += c.duration;
        self.distance_done += c.planned.profile.length();
        let seg = &c.planned.block.segment;
        self.rest = seg.end();
        // The line of the geometry at the block's end (a chain stands for several).
        self.last_line = seg.line_at(seg.length()).unwrap_or(c.planned.block.line);
        let g = seg.eval(seg.length());
        if g.d1 != [0.0; 3] {
            self.last_tangent = g.d1;
        }
    }

    /// The motion at the current path time.
    pub fn sample(&self, t: f64, finished: bool) -> Tick {
        let mut tick = Tick::default();
        self.sample_into(t, finished, &mut tick);
        tick
    }

    /// [`Interpolator::sample`] written in place (the engine's tick, every period: no copy of
    /// the record).
    pub fn sample_into(&self, t: f64, finished: bool, out: &mut Tick) {
        let Some(c) = &self.current else {
            *out = Tick {
                t,
                line: self.last_line,
                p: self.rest,
                distance: self.distance_done,
                tangent: self.last_tangent,
                finished,
                ..Tick::default()
            };
            return;
        };
        let seg = &c.planned.block.segment;
        if let Segment::Dwell { at, .. } = seg {
            *out = Tick {
                t,
                line: c.planned.block.line,
                p: *at,
                distance: self.distance_done,
                tangent: self.last_tangent,
                finished: false,
                ..Tick::default()
            };
            return;
        }
        let k = c.planned.profile.at(c.tau);
        let (s, g) = seg.eval_clamped(k.s);
        let (v, a, j) = axis_motion(&g, &k);
        *out = Tick {
            t,
            line: seg.line_at(s).unwrap_or(c.planned.block.line),
            p: g.p,
            v,
            a,
            j,
            // Chains run in a parameter with |p'| ≈ 1; the feed is the speed along the path.
            feed: crate::geometry::norm(v),
            path_acceleration: k.a,
            path_jerk: k.j,
            distance: self.distance_done + s,
            tangent: g.d1,
            finished: false,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::{BlockRequest, Limits, Profile, ProfileKind};
    use crate::geometry::Line;
    use crate::path::PathBlock;

    fn planned(from: f64, to: f64, v_in: f64, v_out: f64) -> Planned {
        let limits = Limits {
            v_max: 0.1,
            a_max: 2.0,
            j_max: 60.0,
            snap_max: 6e3,
        };
        let line = Line {
            start: [from, 0.0, 0.0],
            end: [to, 0.0, 0.0],
        };
        let req = BlockRequest {
            length: to - from,
            v_in,
            v_out,
            v_feed: 0.1,
            limits,
        };
        Planned {
            block: PathBlock {
                line: 1,
                segment: Segment::Line(line),
                v_feed: 0.1,
                limits,
                v_end_max: v_out,
                constant_speed: false,
                before_transition: false,
                bands: Default::default(),
            },
            v_in,
            v_out,
            profile: Profile::plan(ProfileKind::Trapezoid, &req),
        }
    }

    #[test]
    fn carries_time_across_blocks_and_ends_exactly() {
        let mut q: VecDeque<Planned> = VecDeque::new();
        q.push_back(planned(0.0, 0.01, 0.0, 0.05));
        q.push_back(planned(0.01, 0.0123, 0.05, 0.0));
        let total: f64 = q.iter().map(block_duration).sum();
        let mut it = Interpolator::new([0.0; 3]);
        let mut ticks = 0;
        while it.advance(1e-3, &mut q) == 0.0 {
            ticks += 1;
            assert!(ticks < 100_000);
        }
        assert!(it.idle());
        // Every tick but the last used a full period; the path time is the exact sum.
        assert!((it.path_time() - total).abs() < 1e-12);
        let end = it.sample(0.0, true);
        assert_eq!(end.p, [0.0123, 0.0, 0.0]);
        assert!((end.distance - 0.0123).abs() < 1e-15);
    }
}
