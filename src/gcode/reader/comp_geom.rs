//! Plane geometry of cutter compensation: offset elements (lines and arcs in the active plane)
//! and their intersections. Points are (a, b) in the plane's axes (`Plane::axes`). The stage's
//! tolerances are named here (JOIN, PARALLEL, CONCENTRIC). Every one that decides a join is a
//! length, JOIN: two offset points nearer than it are one point, an element may start that far
//! from its ideal start and run that far past its end. An angle tolerance would be a length
//! that shrinks with the radius (1e-9 rad is 3e-12 m on a 3 mm arc, smaller than the joins it
//! has to accept: a 1 µm tool refused paths that 0 and 0.1 mm tools run).

use crate::gcode::{Block, Motion};
use crate::geometry::vec2::{along, angle, cross, dist, dot, left, norm, sub, P2};

/// A programmed element in the plane: a line or an arc (centre, radius, clockwise).
#[derive(Clone, Copy, Debug)]
pub enum Elem {
    Line {
        start: P2,
        end: P2,
    },
    Arc {
        start: P2,
        end: P2,
        center: P2,
        radius: f64,
        cw: bool,
    },
}

impl Elem {
    /// The element of a motion block in the plane of axes (a, b); None if it does not move there.
    pub fn of(block: &Block, a: usize, b: usize) -> Option<Elem> {
        let s = [block.from[a], block.from[b]];
        match block.motion {
            Motion::Rapid { to } | Motion::Linear { to } => {
                let e = [to[a], to[b]];
                (dist(s, e) > JOIN).then_some(Elem::Line { start: s, end: e })
            }
            Motion::Arc {
                to,
                center,
                clockwise,
                ..
            } => {
                let c = [center[a], center[b]];
                Some(Elem::Arc {
                    start: s,
                    end: [to[a], to[b]],
                    center: c,
                    radius: dist(s, c),
                    cw: clockwise,
                })
            }
            _ => None,
        }
    }

    pub fn start(&self) -> P2 {
        match *self {
            Elem::Line { start, .. } | Elem::Arc { start, .. } => start,
        }
    }

    pub fn end(&self) -> P2 {
        match *self {
            Elem::Line { end, .. } | Elem::Arc { end, .. } => end,
        }
    }

    /// Unit tangent at point `p` of the element (direction of travel).
    pub fn tangent(&self, p: P2) -> P2 {
        match *self {
            Elem::Line { start, end } => {
                let d = sub(end, start);
                let l = norm(d);
                [d[0] / l, d[1] / l]
            }
            Elem::Arc { center, cw, .. } => {
                let r = sub(p, center);
                let l = norm(r);
                let t = [-r[1] / l, r[0] / l];
                if cw {
                    [-t[0], -t[1]]
                } else {
                    t
                }
            }
        }
    }

    /// Radius of the offset arc, `side` +1 (G41, tool left) or −1 (G42); None for a line.
    pub fn offset_radius(&self, side: f64, r: f64) -> Option<f64> {
        match *self {
            Elem::Line { .. } => None,
            Elem::Arc { radius, cw, .. } => Some(radius + side * r * if cw { 1.0 } else { -1.0 }),
        }
    }

    /// The offset of point `p` (start or end) of the element.
    pub fn offset_point(&self, p: P2, side: f64, r: f64) -> P2 {
        along(p, left(self.tangent(p)), side * r)
    }
}

impl Elem {
    /// Whether the offset element from `p` to `q` runs the programmed way and no longer than
    /// the programmed element, within JOIN: a line not reversed, an arc not swept beyond its own
    /// angle (a concave corner eating the whole element is a gouge).
    pub fn runs_forward(&self, p: P2, q: P2) -> bool {
        if dist(p, q) <= JOIN {
            return true;
        }
        match *self {
            Elem::Line { .. } => dot(sub(q, p), self.tangent(p)) > -JOIN,
            Elem::Arc {
                start,
                end,
                center,
                cw,
                ..
            } => {
                let full = sweep(center, start, end, cw);
                // Compared as arc lengths on the offset circle.
                let r = dist(p, center).max(dist(q, center));
                full * r <= JOIN || sweep(center, p, q, cw) * r <= full * r + JOIN
            }
        }
    }
}

/// The tool path of a G41/G42 entry arc (LinuxCNC `convert_arc_comp1`): from the tool at `s`,
/// the programmed arc turning as programmed, to `a`, the perpendicular offset of the programmed
/// end, with its centre on the radial line from `a` towards the programmed centre `c` (so the
/// tool arrives along the offset contour) and equidistant from `s` and `a`. Its centre, or why
/// there is none: `Backwards` where `s` lies on the far side of the tangent at `a` (the centre
/// would be beyond `a`: LinuxCNC runs that arc, a loop that arrives against the contour's
/// direction), `Flat` where the radius would exceed 5000 chords (LinuxCNC's TOLERANCE_EQUAL
/// bound on the cosine, its "tool radius not less than arc radius with comp").
pub fn entry_arc_center(s: P2, a: P2, c: P2) -> Result<P2, EntryArc> {
    let toward = sub(c, a);
    let d = [toward[0] / norm(toward), toward[1] / norm(toward)];
    let sa = sub(s, a);
    let proj = dot(sa, d);
    if proj <= 0.0 {
        return Err(EntryArc::Backwards);
    }
    if proj < ENTRY_COS * norm(sa) {
        return Err(EntryArc::Flat);
    }
    Ok(along(a, d, dot(sa, sa) / (2.0 * proj)))
}

/// Why a G41/G42 entry arc has no tool path (`entry_arc_center`).
#[derive(Debug, PartialEq)]
pub enum EntryArc {
    Backwards,
    Flat,
}

/// LinuxCNC's TOLERANCE_EQUAL, on the cosine between the entry arc's chord and its radius.
const ENTRY_COS: f64 = 1e-4;

/// The length tolerance of cutter compensation (m): 1 nm.
pub const JOIN: f64 = 1e-9;
/// Offset lines whose unit tangents cross by less than this (sin θ) are parallel: they have no
/// intersection (collinear elements meet by JOIN instead).
const PARALLEL: f64 = 1e-12;
/// Offset circles whose centres are nearer than this (m) are concentric: no intersection.
const CONCENTRIC: f64 = 1e-12;

/// Angle swept from `p` to `q` about `c` (0 … 2π), clockwise or not.
fn sweep(c: P2, p: P2, q: P2, cw: bool) -> f64 {
    let (a, b) = (angle(c, p), angle(c, q));
    let s = if cw { a - b } else { b - a };
    s.rem_euclid(std::f64::consts::TAU)
}

/// Intersections of two offset elements (line through `p` along `t`, or circle `c`, `radius`).
pub enum Curve {
    Line(P2, P2),
    Circle(P2, f64),
}

/// The intersection of two offset curves nearest to `near`, if any.
pub fn intersect(c1: &Curve, c2: &Curve, near: P2) -> Option<P2> {
    let points: Vec<P2> = match (c1, c2) {
        (Curve::Line(p, t), Curve::Line(q, u)) => {
            let den = cross(*t, *u);
            if den.abs() < PARALLEL {
                return None;
            }
            let s = cross(sub(*q, *p), *u) / den;
            vec![along(*p, *t, s)]
        }
        (Curve::Line(p, t), Curve::Circle(c, r)) | (Curve::Circle(c, r), Curve::Line(p, t)) => {
            let f = sub(*p, *c);
            let b = dot(f, *t);
            let disc = b * b - (dot(f, f) - r * r);
            // The line misses the circle by δ when disc ≈ −2·r·δ: a miss within JOIN touches.
            if disc < -2.0 * r * JOIN {
                return None;
            }
            let h = disc.max(0.0).sqrt();
            vec![along(*p, *t, -b - h), along(*p, *t, -b + h)]
        }
        (Curve::Circle(c1, r1), Curve::Circle(c2, r2)) => {
            let d = dist(*c1, *c2);
            if d < CONCENTRIC || d > r1 + r2 + JOIN || d < (r1 - r2).abs() - JOIN {
                return None;
            }
            let x = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);
            let h = (r1 * r1 - x * x).max(0.0).sqrt();
            let u = [(c2[0] - c1[0]) / d, (c2[1] - c1[1]) / d];
            let m = along(*c1, u, x);
            vec![along(m, left(u), h), along(m, left(u), -h)]
        }
    };
    points
        .into_iter()
        .min_by(|p, q| dist(*p, near).total_cmp(&dist(*q, near)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entry_arc_centres() {
        // LinuxCNC's comp311_2.ngc: G41, tool radius 0.125, G3 from (1, 4) to (2, 3) about
        // (2, 4): the tool ends at (2, 3.125); the centre (2, y) with 1 + (4 − y)² = (y − 3.125)²,
        // y = 7.234375 / 1.75 (rs274 prints ARC_FEED(2.0000, 3.1250, 2.0000, 4.1339, 1)).
        let b = entry_arc_center([1.0, 4.0], [2.0, 3.125], [2.0, 4.0]).unwrap();
        assert!(dist(b, [2.0, 7.234375 / 1.75]) < 1e-15, "{b:?}");
        // A start near the end, behind the tangent at the tool's end point.
        let e = entry_arc_center([1.0, 0.0], [0.8617, 0.1519], [0.0, 0.0]);
        assert_eq!(e, Err(EntryArc::Backwards));
    }

    #[test]
    fn offset_elements_run_forward_only_within_their_element() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let arc = Elem::Arc {
            start: [1.0, 0.0],
            end: [0.0, 1.0],
            center: [0.0, 0.0],
            radius: 1.0,
            cw: false,
        };
        assert!(arc.runs_forward([2.0, 0.0], [2.0 * h, 2.0 * h]));
        // Starting before the arc's start: the offset would sweep more than the quarter.
        assert!(!arc.runs_forward([h, -h], [0.0, 1.0]));
        let line = Elem::Line {
            start: [0.0, 0.0],
            end: [1.0, 0.0],
        };
        assert!(line.runs_forward([0.0, 1.0], [0.5, 1.0]) && !line.runs_forward([0.5, 1.0], [0.2, 1.0]));
        // G41 on a counter-clockwise arc: the tool inside, radius R − r; a line's offset is beside it.
        assert_eq!(arc.offset_radius(1.0, 0.25), Some(0.75));
        assert_eq!(line.offset_point([1.0, 0.0], -1.0, 0.5), [1.0, -0.5]);
    }
}
