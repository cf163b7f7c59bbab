//! Programmed geometry: the line or arc of a G-code block (`Block::geometry`), as the path stage
//! runs it and as ticks are measured against it.

use super::{add, dot, norm, scale, sub, Arc, Line, Vec3};
use serde::{Deserialize, Serialize};

/// Programmed geometry: what ticks are measured against.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Source {
    Line(Line),
    Arc(Arc),
}

impl Source {
    pub fn length(&self) -> f64 {
        match self {
            Source::Line(l) => l.length(),
            Source::Arc(a) => a.length(),
        }
    }
    /// Distance from p to this line segment or arc.
    pub fn distance(&self, p: Vec3) -> f64 {
        match self {
            Source::Line(l) => distance_to_segment(p, l.start, l.end),
            Source::Arc(a) => distance_to_arc(p, a),
        }
    }
}

pub fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(p, add(a, scale(ab, t))))
}

fn distance_to_arc(p: Vec3, a: &Arc) -> f64 {
    let ends = norm(sub(p, a.start)).min(norm(sub(p, a.end)));
    a.distance_at_angle(p).map_or(ends, |d| ends.min(d))
}
