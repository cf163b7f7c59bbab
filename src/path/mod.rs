//! Path geometry: blocks → segments (lines, arcs and helices, corner transitions), each with its
//! length, its derivatives with respect to the path parameter s, and its path-level limits
//! projected from the axis limits. Corners are decided here (exact stop, seed-003 corner feed,
//! circular blend, quintic transition), so the planner sees only segments and junction speeds.

use crate::config::{CornerMode, Machine};
use crate::feed::Limits;
use crate::gcode::{Block, Motion, PathMode};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// A point of a segment and its derivatives with respect to the path parameter s:
/// axis velocity = d1·v, acceleration = d2·v² + d1·a, jerk = d3·v³ + 3·d2·v·a + d1·j.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Geo {
    pub p: Vec3,
    pub d1: Vec3,
    pub d2: Vec3,
    pub d3: Vec3,
}

/// Straight line from `start` to `end`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Line {
    pub start: Vec3,
    pub end: Vec3,
}

impl Line {
    pub fn length(&self) -> f64 {
        norm(sub(self.end, self.start))
    }
    /// Unit direction (zero for a zero-length line).
    pub fn direction(&self) -> Vec3 {
        let l = self.length();
        if l > 0.0 {
            scale(sub(self.end, self.start), 1.0 / l)
        } else {
            [0.0; 3]
        }
    }
    pub fn eval(&self, s: f64) -> Geo {
        let u = self.direction();
        Geo {
            p: add(self.start, scale(u, s)),
            d1: u,
            ..Geo::default()
        }
    }
}

/// PLACEHOLDER arc record until the geometry module lands.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Arc {
    pub chord: Line,
}

/// PLACEHOLDER corner-transition record until the geometry module lands.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Blend {
    pub chord: Line,
}

/// One piece of the path, parameterised by s ∈ [0, length()].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Segment {
    Line(Line),
    Arc(Arc),
    /// Corner transition, traversed at one speed (see `PathBlock::constant_speed`).
    Blend(Blend),
    /// G4: stand still at `at` for `seconds`.
    Dwell {
        at: Vec3,
        seconds: f64,
    },
}

impl Segment {
    pub fn length(&self) -> f64 {
        match self {
            Segment::Line(l) => l.length(),
            Segment::Arc(a) => a.chord.length(),
            Segment::Blend(b) => b.chord.length(),
            Segment::Dwell { .. } => 0.0,
        }
    }
    pub fn eval(&self, s: f64) -> Geo {
        match self {
            Segment::Line(l) => l.eval(s),
            Segment::Arc(a) => a.chord.eval(s),
            Segment::Blend(b) => b.chord.eval(s),
            Segment::Dwell { at, .. } => Geo {
                p: *at,
                ..Geo::default()
            },
        }
    }
    pub fn start(&self) -> Vec3 {
        self.eval(0.0).p
    }
    pub fn end(&self) -> Vec3 {
        match self {
            Segment::Line(l) => l.end,
            Segment::Arc(a) => a.chord.end,
            Segment::Blend(b) => b.chord.end,
            Segment::Dwell { at, .. } => *at,
        }
    }
}

/// A segment ready for planning: what the look-ahead needs to know about it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
}

/// Seed 004 eq. 11: on a line of unit direction u, axis i moves at u_i·v, so the path limits
/// are the smallest axis limit divided by |u_i| — the slowest axis sets the pace, all in phase.
pub fn line_limits(u: Vec3, machine: &Machine) -> Limits {
    let mut lim = Limits {
        v_max: machine.max_feed,
        a_max: f64::INFINITY,
        j_max: f64::INFINITY,
        snap_max: machine.max_snap,
    };
    for (ui, ax) in u.iter().zip(&machine.axes) {
        let k = ui.abs();
        if k > 1e-12 {
            lim.v_max = lim.v_max.min(ax.max_velocity / k);
            lim.a_max = lim.a_max.min(ax.max_acceleration / k);
            lim.j_max = lim.j_max.min(ax.max_jerk / k);
        }
    }
    if let Some(a) = machine.max_path_acceleration {
        lim.a_max = lim.a_max.min(a);
    }
    if let Some(j) = machine.max_path_jerk {
        lim.j_max = lim.j_max.min(j);
    }
    lim
}

/// Turns blocks into planned-ready segments. Holds back one segment so that the corner after it
/// can be decided (and a transition inserted) when the next block arrives.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathBuilder {
    machine: Machine,
    held: Option<PathBlock>,
}

impl PathBuilder {
    pub fn new(machine: &Machine) -> PathBuilder {
        PathBuilder {
            machine: machine.clone(),
            held: None,
        }
    }

    /// Take one block; push the segments that are now final onto `out`.
    // PLACEHOLDER: lines only, exact stop at every direction change.
    pub fn push(&mut self, block: &Block, out: &mut Vec<PathBlock>) {
        let (to, feed) = match block.motion {
            Motion::Rapid { to } => (to, self.machine.max_feed),
            Motion::Linear { to } => (to, block.feed),
            _ => return,
        };
        let line = Line {
            start: block.from,
            end: to,
        };
        if line.length() <= 0.0 {
            return;
        }
        let limits = line_limits(line.direction(), &self.machine);
        let next = PathBlock {
            line: block.line,
            segment: Segment::Line(line),
            v_feed: feed.min(limits.v_max),
            limits,
            v_end_max: 0.0,
            constant_speed: false,
        };
        if let Some(mut held) = self.held.take() {
            let collinear = match held.segment {
                Segment::Line(h) => dot(h.direction(), line.direction()) > 1.0 - 1e-12,
                _ => false,
            };
            let exact = matches!(block.path_mode, PathMode::ExactStop)
                || self.machine.corner == CornerMode::ExactStop;
            held.v_end_max = if collinear && !exact {
                held.v_feed.min(next.v_feed)
            } else {
                0.0
            };
            out.push(held);
        }
        self.held = Some(next);
    }

    /// End of program: release the held segment, stopping at its end.
    pub fn finish(&mut self, out: &mut Vec<PathBlock>) {
        if let Some(mut held) = self.held.take() {
            held.v_end_max = 0.0;
            out.push(held);
        }
    }
}

pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn scale(a: Vec3, k: f64) -> Vec3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}
