//! Path geometry: blocks → segments (lines, arcs and helices, corner transitions), each with its
//! length, its derivatives with respect to the path parameter s, and its path-level limits
//! projected from the axis limits. Corners are decided here (exact stop, seed-003 corner feed,
//! circular blend, quintic transition), so the planner sees only segments and junction speeds.
//!
//! Corner rules (`PathBuilder`): G61 (on either block) or `corner = exact_stop` stops; collinear
//! lines pass at full speed; between two lines `acceleration_period` caps the junction at the
//! seed-003 F_c, `circular` inserts the eq. 8 arc and `polynomial` the eq. 25–52 quintic, both
//! traversed at one speed. Junctions involving an arc: tangent-continuous → eq. 10 curvature-change
//! speed; otherwise the seed-003 corner feed (an arc cannot be trimmed, so no transition is
//! inserted). Dwell and stop blocks stop the path.

use crate::config::{AxisLimits, CornerMode, Machine};
use crate::feed::bands::Bands;
use crate::feed::Limits;
use crate::gcode::{Block, Motion, PathMode};
use crate::geometry::{dot, sub, unit, Arc, Geo, Line, Source, Vec3};
use serde::{Deserialize, Serialize};
use tolerance::{COLLINEAR_EPS, END_SHARE, MIN_LENGTH, REVERSAL_COS, TANGENT_EPS};

mod arc;
mod blend;
mod budget;
mod chain;
mod check;
mod corner;
mod cover;
mod fit;
mod hermite;
mod junction;
mod line;
mod merge;
mod micro;
mod smooth;
mod source_map;
#[cfg(test)]
mod testing;
pub mod tolerance;

pub use arc::{arc_limits, chord_error_speed, constant_speed_limit, curve_limits, Shares};
pub use blend::Blend;
pub use budget::max_bounds;
pub use chain::{Chain, Curve, Piece};
pub use corner::{circular_blend, circular_blend_speed, corner_feed, curvature_change_speed, step_jerk};
pub use hermite::{Hermite, Jet};
pub use line::line_limits;
pub use smooth::{Move, SmoothBuilder};

/// One piece of the path, parameterised by s ∈ [0, length()].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Segment {
    /// Lines, arcs and transitions joined C2, run by one profile (`smooth` corner mode).
    Chain(Chain),
    Line(Line),
    /// Arc or helix (G2/G3, or a circular corner blend).
    Arc(Arc),
    /// Corner transition, traversed at one speed (see `PathBlock::constant_speed`).
    Blend(Blend),
    /// G4: stand still at `at` for `seconds`.
    Dwell {
        at: Vec3,
        seconds: f64,
    },
    /// The piece [s0, s0 + len] of a line, arc or transition: what is left of a block when a
    /// feed hold or an override change re-plans from the middle of it.
    Part {
        whole: Whole,
        s0: f64,
        len: f64,
        /// The part runs to the end of the whole segment (its end point is then exact).
        to_end: bool,
    },
}

/// A segment that can be cut into parts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Whole {
    Line(Line),
    Arc(Arc),
    Blend(Blend),
    Chain(Chain),
}

impl Whole {
    fn length(&self) -> f64 {
        match self {
            Whole::Line(l) => l.length(),
            Whole::Arc(a) => a.length(),
            Whole::Blend(b) => b.length,
            Whole::Chain(c) => c.length(),
        }
    }
    fn eval(&self, s: f64) -> Geo {
        match self {
            Whole::Line(l) => l.eval(s),
            Whole::Arc(a) => a.eval(s),
            Whole::Blend(b) => b.eval(s),
            Whole::Chain(c) => c.eval(s),
        }
    }
    fn end(&self) -> Vec3 {
        match self {
            Whole::Line(l) => l.end,
            Whole::Arc(a) => a.end,
            Whole::Blend(b) => b.end(),
            Whole::Chain(c) => c.end(),
        }
    }
}

impl Segment {
    /// The piece [from, from + len] of this segment (None for a dwell).
    pub fn part(&self, from: f64, len: f64) -> Option<Segment> {
        let (whole, s0, to_end_of_whole) = match self {
            Segment::Line(l) => (Whole::Line(*l), 0.0, self.length()),
            Segment::Arc(a) => (Whole::Arc(*a), 0.0, self.length()),
            Segment::Blend(b) => (Whole::Blend(*b), 0.0, self.length()),
            Segment::Chain(c) => (Whole::Chain(c.clone()), 0.0, self.length()),
            Segment::Part { whole, s0, .. } => (whole.clone(), *s0, whole.length() - s0),
            Segment::Dwell { .. } => return None,
        };
        let to_end = from + len >= to_end_of_whole * (1.0 - END_SHARE) && self.ends_whole();
        Some(Segment::Part {
            whole,
            s0: s0 + from,
            len,
            to_end,
        })
    }

    fn ends_whole(&self) -> bool {
        match self {
            Segment::Part { to_end, .. } => *to_end,
            _ => true,
        }
    }
}

impl Segment {
    pub fn length(&self) -> f64 {
        match self {
            Segment::Line(l) => l.length(),
            Segment::Arc(a) => a.length(),
            Segment::Blend(b) => b.length,
            Segment::Chain(c) => c.length(),
            Segment::Dwell { .. } => 0.0,
            Segment::Part { len, .. } => *len,
        }
    }
    /// Point and derivatives at arc length s (clamped to the segment).
    pub fn eval(&self, s: f64) -> Geo {
        match self {
            Segment::Line(l) => l.eval(s),
            Segment::Arc(a) => a.eval(s),
            Segment::Blend(b) => b.eval(s),
            Segment::Chain(c) => c.eval(s),
            Segment::Dwell { at, .. } => Geo {
                p: *at,
                ..Geo::default()
            },
            Segment::Part {
                whole,
                s0,
                len,
                to_end,
            } => {
                if *to_end && s >= *len {
                    let mut g = whole.eval(whole.length());
                    g.p = whole.end();
                    g
                } else {
                    whole.eval(s0 + s.clamp(0.0, *len))
                }
            }
        }
    }
    /// s clamped to [0, length()] and the point there (the interpolator's tick): each kind's
    /// length beside its own evaluation, where the compiler shares their square root or `hypot`.
    #[inline]
    pub fn eval_clamped(&self, s: f64) -> (f64, Geo) {
        match self {
            Segment::Line(l) => {
                let s = s.clamp(0.0, l.length());
                (s, l.eval(s))
            }
            Segment::Arc(a) => a.eval_clamped(s),
            Segment::Chain(c) => {
                let s = s.clamp(0.0, c.length());
                (s, c.eval(s))
            }
            _ => {
                let s = s.clamp(0.0, self.length());
                (s, self.eval(s))
            }
        }
    }
    pub fn start(&self) -> Vec3 {
        match self {
            Segment::Line(l) => l.start,
            Segment::Blend(b) => b.start(),
            Segment::Chain(c) => c.start(),
            _ => self.eval(0.0).p,
        }
    }
    /// The exact end point (the programmed one for lines and arcs).
    pub fn end(&self) -> Vec3 {
        match self {
            Segment::Line(l) => l.end,
            Segment::Arc(a) => a.end,
            Segment::Blend(b) => b.end(),
            Segment::Chain(c) => c.end(),
            Segment::Dwell { at, .. } => *at,
            Segment::Part {
                whole,
                s0,
                len,
                to_end,
            } => {
                if *to_end {
                    whole.end()
                } else {
                    whole.eval(s0 + len).p
                }
            }
        }
    }

    /// Program line of the point at s, for segments that span several lines (chains).
    #[inline]
    pub fn line_at(&self, s: f64) -> Option<u32> {
        match self {
            Segment::Chain(c) => Some(c.line_at(s)),
            Segment::Part {
                whole: Whole::Chain(c),
                s0,
                ..
            } => Some(c.line_at(s0 + s)),
            _ => None,
        }
    }
}

/// A segment ready for planning: what the look-ahead needs to know about it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathBlock {
    /// Source line of the block this segment comes from.
    pub line: u32,
    pub segment: Segment,
    /// Programmed feed for this segment (m/s), already capped by `limits.v_max`.
    pub v_feed: f64,
    /// Path-level limits on this segment (eq. 11 on lines, eq. 17–24 and chord error on arcs).
    pub limits: Limits,
    /// Largest speed at the junction after this segment (m/s); 0 stops there.
    pub v_end_max: f64,
    /// Traversed at one speed: v_in = v_out (corner transitions).
    pub constant_speed: bool,
    /// A constant-speed transition follows, entered at exactly `v_end_max` (which the block
    /// after that transition can always leave: see `PathBuilder::corner`).
    pub before_transition: bool,
    /// Wider limits at lower speeds (curves: feed/bands.rs); `limits` hold at every speed.
    pub bands: Bands,
}

/// Largest share of a programmed line a constant-speed transition may replace at one end.
const TRANSITION_SHARE: f64 = 0.4;

/// The segment held back, with what the next corner needs to know.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Held {
    block: PathBlock,
    /// Length as programmed, before any trimming (a transition takes at most half of it).
    programmed: f64,
    mode: PathMode,
}

/// Turns blocks into planned-ready segments. Holds back one segment so that the corner after it
/// can be decided (and a transition inserted) when the next block arrives.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathBuilder {
    machine: Machine,
    /// The machine with the transition jerk on every axis (seed 004 Table 1: the jerk on passage
    /// of a discontinuity in curvature), where one is set: the circular mode's corner arcs, whose
    /// ends are such discontinuities (the polynomial mode's quintic is curvature-continuous and
    /// keeps the axis jerk, as in the paper's eq. 54).
    transition_machine: Option<Machine>,
    held: Option<Held>,
    smooth: SmoothBuilder,
    merger: merge::Merger,
    micro: micro::MicroMoves,
}

impl PathBuilder {
    pub fn new(machine: &Machine) -> PathBuilder {
        let transition_machine = machine.max_transition_jerk.map(|j| {
            let mut m = machine.clone();
            for a in &mut m.axes {
                a.max_jerk = j;
            }
            m
        });
        PathBuilder {
            machine: machine.clone(),
            transition_machine,
            held: None,
            smooth: SmoothBuilder::new(),
            merger: merge::Merger::new(),
            micro: micro::MicroMoves::default(),
        }
    }

    /// Take one block; push the segments that are now final onto `out`. Under G64 Q, nearly
    /// collinear G1 moves are merged first (merge.rs).
    pub fn push(&mut self, block: &Block, out: &mut Vec<PathBlock>) {
        let mut merger = std::mem::take(&mut self.merger);
        let split = self.machine.corner == CornerMode::Smooth;
        merger.push(block, split, |b| self.push_merged(b, out));
        self.merger = merger;
    }

    fn push_merged(&mut self, block: &Block, out: &mut Vec<PathBlock>) {
        let (segment, feed) = match (block.geometry(), block.motion) {
            (_, Motion::Dwell { seconds }) => return self.stop(block, Some(seconds), out),
            (_, Motion::Stop(_)) => return self.stop(block, None, out),
            (None, _) => return,
            (Some(Source::Line(l)), Motion::Rapid { .. }) => (Segment::Line(l), self.machine.max_feed),
            (Some(Source::Line(l)), _) => (Segment::Line(l), block.feed),
            (Some(Source::Arc(a)), _) => (Segment::Arc(a), block.feed),
        };
        let length = segment.length();
        if length.is_nan() || length <= MIN_LENGTH {
            return;
        }
        let feed = feed.max(0.0);
        if self.machine.corner == CornerMode::Smooth {
            let source = match segment {
                Segment::Arc(a) => Source::Arc(a),
                Segment::Line(l) => Source::Line(l),
                _ => return,
            };
            let exact = matches!(block.path_mode, PathMode::ExactStop);
            let tolerance = tolerance_of(block.path_mode, self.machine.path_tolerance);
            let mv = Move {
                source,
                line: block.line,
                feed,
                tolerance,
                exact,
                absorbed: 0.0,
            };
            if self.micro.held_before(&mv) {
                self.run_tiny(out);
            }
            if let Some(mv) = self.micro.take(mv) {
                self.smooth.push(mv, &self.machine, out);
            }
            return;
        }
        let limits = match &segment {
            Segment::Line(l) => line_limits(l.direction(), &self.machine),
            Segment::Arc(a) => arc_limits(a, &self.machine),
            _ => self.rest_limits(),
        };
        let next = Held {
            block: PathBlock {
                line: block.line,
                segment,
                v_feed: feed.min(limits.v_max),
                limits,
                v_end_max: 0.0,
                constant_speed: false,
                before_transition: false,
                bands: Bands::default(),
            },
            programmed: length,
            mode: block.path_mode,
        };
        match self.held.take() {
            Some(held) => self.corner(held, next, out),
            None => self.held = Some(next),
        }
    }

    /// A stop on the path (M0, M1, M2, …), with a dwell of `seconds` where given.
    fn stop(&mut self, block: &Block, seconds: Option<f64>, out: &mut Vec<PathBlock>) {
        self.release(0.0, out);
        self.stop_smooth(out);
        if let Some(seconds) = seconds {
            out.push(PathBlock {
                line: block.line,
                segment: Segment::Dwell {
                    at: block.from,
                    seconds: seconds.max(0.0),
                },
                v_feed: 0.0,
                limits: self.rest_limits(),
                v_end_max: 0.0,
                constant_speed: false,
                before_transition: false,
                bands: Bands::default(),
            });
        }
    }

    /// End of program: release the held segment, stopping at its end.
    pub fn finish(&mut self, out: &mut Vec<PathBlock>) {
        let mut merger = std::mem::take(&mut self.merger);
        let split = self.machine.corner == CornerMode::Smooth;
        merger.flush(split, &mut |b: &Block| self.push_merged(b, out));
        self.release(0.0, out);
        self.stop_smooth(out);
    }

    /// The smooth mode's stop: held tiny moves run first, so the programmed point is reached.
    fn stop_smooth(&mut self, out: &mut Vec<PathBlock>) {
        self.run_tiny(out);
        self.smooth.stop(&self.machine, out);
    }

    /// The held tiny moves where no line after takes them: the line before ends where they end,
    /// or they run as one line.
    fn run_tiny(&mut self, out: &mut Vec<PathBlock>) {
        if let Some(tiny) = self.micro.flush() {
            if !self.smooth.end_last_at(&tiny) {
                self.smooth.push(tiny.line(), &self.machine, out);
            }
        }
    }

    fn release(&mut self, v_end_max: f64, out: &mut Vec<PathBlock>) {
        if let Some(mut held) = self.held.take() {
            held.block.v_end_max = v_end_max;
            out.push(held.block);
        }
    }

    /// Limits for blocks that do not move (dwell): the slowest axis.
    fn rest_limits(&self) -> Limits {
        slowest_axis(&self.machine, self.machine.max_feed)
    }

    /// Decide the junction between `held` and `next`; emit `held` (and a transition if any).
    fn corner(&mut self, mut held: Held, mut next: Held, out: &mut Vec<PathBlock>) {
        let m = &self.machine;
        let exact = m.corner == CornerMode::ExactStop
            || matches!(held.mode, PathMode::ExactStop)
            || matches!(next.mode, PathMode::ExactStop);
        let g_in = held.block.segment.eval(held.block.segment.length());
        let g_out = next.block.segment.eval(0.0);
        let (t_in, t_out) = (unit(g_in.d1), unit(g_out.d1));
        let cos = dot(t_in, t_out);
        let feeds = held.block.v_feed.min(next.block.v_feed);
        let lines = matches!(
            (&held.block.segment, &next.block.segment),
            (Segment::Line(_), Segment::Line(_))
        );
        let v_end_max = if exact {
            0.0
        } else if lines && 1.0 - cos <= COLLINEAR_EPS {
            feeds
        } else if lines && m.corner == CornerMode::AccelerationPeriod {
            corner_feed(t_in, t_out, m).min(feeds)
        } else if lines {
            if let Some(transition) = self.blend_lines(&mut held, &mut next, t_in, t_out, feeds) {
                if held.block.segment.length() > MIN_LENGTH {
                    out.push(held.block);
                }
                out.push(transition);
                self.held = Some(next);
                return;
            }
            0.0
        } else if 1.0 - cos <= TANGENT_EPS {
            corner::tangent_junction(sub(g_out.d2, g_in.d2), &mut held.block, &mut next.block, m).min(feeds)
        } else if m.corner == CornerMode::AccelerationPeriod {
            // Seed 003's rule allows the velocity step of one period at the corner.
            corner_feed(t_in, t_out, m).min(feeds)
        } else {
            // No transition is inserted at a sharp corner with an arc: stop there, so that the
            // axis acceleration and jerk limits hold (a speed through the corner would step them).
            0.0
        };
        held.block.v_end_max = v_end_max;
        out.push(held.block);
        self.held = Some(next);
    }

    /// The constant-speed transition (circular or polynomial mode) between two lines: both lines
    /// are cut back to it. None: no transition fits, stop at the corner.
    fn blend_lines(
        &self,
        held: &mut Held,
        next: &mut Held,
        t_in: Vec3,
        t_out: Vec3,
        feeds: f64,
    ) -> Option<PathBlock> {
        let (&Segment::Line(h), &Segment::Line(n)) = (&held.block.segment, &next.block.segment) else {
            return None;
        };
        let m = &self.machine;
        let tol = tolerance_of(held.mode, m.path_tolerance);
        // A share below one half leaves a piece of every line between two transitions: a
        // constant-speed transition needs a block after it that can stop.
        let max_cut = (TRANSITION_SHARE * held.programmed.min(next.programmed)).min(h.length());
        // The line after keeps at least (1 − 2·share) of its length; the transition's speed is one
        // that line can always stop from, so the look-ahead's window-end stop never has to lower it
        // later. Slowing from v to any x < v takes (v + x)/2·T(v − x) ≤ v·T(v) = 2·D(v, 0): a speed
        // that stops in half the rest reaches every lower one.
        let rest = (1.0 - 2.0 * TRANSITION_SHARE) * next.programmed;
        let v_stop = crate::feed::max_entry(m.profile, 0.5 * rest, 0.0, &corner::stop_limits(&next.block, m));
        let (segment, v) = self.transition(h.end, t_in, t_out, tol, max_cut, feeds.min(v_stop))?;
        held.block.segment = Segment::Line(Line {
            start: h.start,
            end: segment.start(),
        });
        next.block.segment = Segment::Line(Line {
            start: segment.end(),
            end: n.end,
        });
        held.block.v_end_max = v;
        held.block.before_transition = true;
        let limits = Limits {
            v_max: v,
            a_max: held.block.limits.a_max.min(next.block.limits.a_max),
            j_max: held.block.limits.j_max.min(next.block.limits.j_max),
            snap_max: m.max_snap,
        };
        Some(PathBlock {
            line: held.block.line,
            segment,
            v_feed: v,
            limits,
            v_end_max: v,
            constant_speed: true,
            before_transition: false,
            bands: Bands::default(),
        })
    }

    /// The corner transition of the machine's mode and its constant speed, or None (stop).
    fn transition(
        &self,
        corner: Vec3,
        t_in: Vec3,
        t_out: Vec3,
        tol: f64,
        max_cut: f64,
        feeds: f64,
    ) -> Option<(Segment, f64)> {
        let m = &self.machine;
        if dot(t_in, t_out) < REVERSAL_COS || max_cut.is_nan() || max_cut <= MIN_LENGTH {
            return None;
        }
        let (segment, v) = if m.corner == CornerMode::Circular {
            // Passing the arc, whose ends are curvature discontinuities, the axes may use J_c.
            let arc = circular_blend(corner, t_in, t_out, tol, max_cut)?;
            let jc = self.transition_machine.as_ref().unwrap_or(m);
            (Segment::Arc(arc), circular_blend_speed(&arc, jc))
        } else {
            // Eq. 52 with the half-length rule of §3.5: L ≤ half of either line; V_In from the
            // exact bounds is eq. 54–57.
            let half = Blend::half_for_tolerance(t_in, t_out, tol).min(max_cut);
            let b = Blend::new(corner, t_in, t_out, half);
            (Segment::Blend(b), constant_speed_limit(&b.derivative_bounds(), m))
        };
        let v = v.min(feeds);
        (v > 0.0 && v.is_finite()).then_some((segment, v))
    }
}

/// Limits at `v_max` with the acceleration and jerk of the slowest axis (what holds whichever
/// way the path points).
fn slowest_axis(m: &Machine, v_max: f64) -> Limits {
    let slowest = |f: fn(&AxisLimits) -> f64| m.axes.iter().map(f).fold(f64::INFINITY, f64::min);
    Limits {
        v_max,
        a_max: slowest(|a| a.max_acceleration),
        j_max: slowest(|a| a.max_jerk),
        snap_max: m.max_snap,
    }
}

/// The path tolerance of a block: its G64 P where given and positive, else the machine's.
fn tolerance_of(mode: PathMode, machine_tolerance: f64) -> f64 {
    match mode {
        PathMode::Blend {
            tolerance: Some(t), ..
        } if t > 0.0 => t,
        _ => machine_tolerance,
    }
}

#[cfg(test)]
mod tests;
