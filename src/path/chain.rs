//! A chain: pieces of lines, arcs and quintic Hermite curves joined with continuous first and
//! second derivative (C2 in the common parameter u), run by one feed profile. Inside a chain the
//! path acceleration need not be zero at piece ends, so a run of micro-segments accelerates as
//! one curve; the axis acceleration p''·u̇² + p'·ü stays continuous across every joint.

use super::arc::{curve_bands, curve_top_speed, Frame, TopSpeeds};
use super::hermite::{Hermite, Unbounded, BOUND_PIECES};
use super::max_bounds;
use crate::config::Machine;
use crate::feed::bands::{Banded, Bands};
use crate::feed::{Limits, ProfileKind};
use crate::geometry::{norm, Arc, Geo, Line};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// The curve a piece is cut from, each evaluated in its own parameter (arc length for lines and
/// arcs, u ≈ arc length for Hermite curves).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Curve {
    Line(Line),
    Arc(Arc),
    Hermite(Hermite),
}

impl Curve {
    pub fn length(&self) -> f64 {
        match self {
            Curve::Line(l) => l.length(),
            Curve::Arc(a) => a.length(),
            Curve::Hermite(h) => h.length(),
        }
    }
    pub fn eval(&self, u: f64) -> Geo {
        match self {
            Curve::Line(l) => l.eval(u),
            Curve::Arc(a) => a.eval(u),
            Curve::Hermite(h) => h.eval(u),
        }
    }
    pub fn end(&self) -> Vec3 {
        match self {
            Curve::Line(l) => l.end,
            Curve::Arc(a) => a.end,
            Curve::Hermite(h) => h.end,
        }
    }
    /// Guaranteed bound of |p'| (1 on lines and arcs: they are run in arc length).
    pub fn speed_bound(&self) -> f64 {
        match self {
            Curve::Hermite(h) => h.speed_bound(),
            _ => 1.0,
        }
    }
    /// The same bounds on stretches of the curve (cells), each holding at the same points.
    pub fn cells(&self, mut take: impl FnMut([Vec3; 3])) {
        match self {
            Curve::Line(_) => take(self.derivative_bounds()),
            Curve::Arc(a) => a.cells(take),
            Curve::Hermite(h) => h.cells(take),
        }
    }
    /// Guaranteed per-axis bounds of |p'|, |p''|, |p'''| over the whole curve.
    pub fn derivative_bounds(&self) -> [Vec3; 3] {
        match self {
            Curve::Line(l) => {
                let d = l.direction();
                [[d[0].abs(), d[1].abs(), d[2].abs()], [0.0; 3], [0.0; 3]]
            }
            Curve::Arc(a) => a.derivative_bounds(),
            Curve::Hermite(h) => h.derivative_bounds(),
        }
    }
}

/// The range [u0, u1] of a curve, from program line `line`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Piece {
    pub curve: Curve,
    pub u0: f64,
    pub u1: f64,
    pub line: u32,
}

impl Piece {
    pub fn whole(curve: Curve, line: u32) -> Piece {
        Piece {
            curve,
            u0: 0.0,
            u1: curve.length(),
            line,
        }
    }
    pub fn length(&self) -> f64 {
        self.u1 - self.u0
    }
    /// Point and derivatives at u ∈ [0, length]; the end of an uncut curve is exact.
    pub fn eval(&self, u: f64) -> Geo {
        let u = (self.u0 + u).min(self.u1);
        self.curve.eval(u)
    }
    pub fn start(&self) -> Vec3 {
        self.eval(0.0).p
    }
    pub fn end(&self) -> Vec3 {
        if self.u1 >= self.curve.length() {
            self.curve.end()
        } else {
            self.curve.eval(self.u1).p
        }
    }
}

/// Pieces back to back; `starts[k]` is the chain parameter where piece k begins. `marks` maps
/// the chain parameter back to the program: (s, line) where the tool comes onto the geometry of
/// source line `line` (a piece's own line at its start, and inside pieces that stand for several
/// programmed moves, where each begins), in increasing s.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Chain {
    pub pieces: Vec<Piece>,
    starts: Vec<f64>,
    length: f64,
    marks: Vec<(f64, u32)>,
}

impl Chain {
    /// A restored chain as `push` builds it: pieces, their starts and the length in step.
    pub fn check_state(&self) -> Result<(), String> {
        let mut rebuilt = Chain::default();
        for p in &self.pieces {
            rebuilt.push(*p);
        }
        if self.is_empty() || rebuilt.starts != self.starts || rebuilt.length != self.length {
            return Err("a chain's pieces, starts and length disagree".into());
        }
        // Source marks: one at least at each piece's start, in increasing s within the chain.
        let in_chain = |m: &(f64, u32)| (0.0..=self.length).contains(&m.0);
        if self.marks.len() < self.pieces.len()
            || !self.marks.iter().all(in_chain)
            || self.marks.windows(2).any(|w| w[1].0 < w[0].0)
        {
            return Err("a chain's source marks are not increasing within it".into());
        }
        Ok(())
    }

    pub fn push(&mut self, piece: Piece) {
        self.push_marked(piece, &[]);
    }
    /// Add a piece whose curve parameter u comes onto source line `line` at each (u, line) of
    /// `marks` (increasing u; those outside the piece's range are dropped, the last before it
    /// naming the line at its start).
    pub fn push_marked(&mut self, piece: Piece, marks: &[(f64, u32)]) {
        let start = self.length;
        let line = marks
            .iter()
            .take_while(|&&(u, _)| u <= piece.u0)
            .last()
            .map_or(piece.line, |m| m.1);
        self.marks.push((start, line));
        for &(u, line) in marks {
            if u > piece.u0 && u < piece.u1 {
                self.marks.push((start + (u - piece.u0), line));
            }
        }
        self.starts.push(start);
        self.length += piece.length();
        self.pieces.push(piece);
    }
    pub fn length(&self) -> f64 {
        self.length
    }
    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }
    fn index(&self, s: f64) -> usize {
        self.starts.partition_point(|&x| x <= s).saturating_sub(1)
    }
    pub fn eval(&self, s: f64) -> Geo {
        if s >= self.length {
            let last = self.pieces.last().expect("chains are never empty");
            let mut g = last.eval(last.length());
            g.p = last.end();
            return g;
        }
        let k = self.index(s);
        self.pieces[k].eval(s - self.starts[k])
    }
    pub fn start(&self) -> Vec3 {
        self.pieces[0].start()
    }
    pub fn end(&self) -> Vec3 {
        self.pieces.last().expect("chains are never empty").end()
    }
    /// Every point reports the same program line.
    pub fn one_source(&self) -> bool {
        self.marks.iter().all(|m| m.1 == self.marks[0].1)
    }
    /// Its pieces' bound cells in order: `cells` where it holds them, else filled with them (a
    /// builder adds a piece's cells where it computes them anyway, and drops the chain's where it
    /// does not: most chains are one piece whose limits are known).
    pub(super) fn cells<'a>(&self, cells: &'a mut Vec<[Vec3; 3]>) -> &'a [[Vec3; 3]] {
        if cells.is_empty() {
            self.pieces.iter().for_each(|p| p.curve.cells(|c| cells.push(c)));
        }
        cells
    }
    /// Program line of the geometry at s (see `marks`).
    pub fn line_at(&self, s: f64) -> u32 {
        let k = self.marks.partition_point(|&(x, _)| x <= s).saturating_sub(1);
        self.marks.get(k).map_or(self.pieces[0].line, |m| m.1)
    }
}

/// What the planner needs of a piece or chain: its limits (at every speed up to v_max), the wider
/// ones at lower speeds, and the speed class by which pieces are grouped into chains.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveLimits {
    pub limits: Limits,
    pub bands: Bands,
    pub class: f64,
}

impl CurveLimits {
    /// Its limits and bands as the banded S-curve plans a block within them.
    pub(super) fn banded(&self) -> Banded<'_> {
        Banded {
            kind: ProfileKind::Scurve7,
            top: &self.limits,
            bands: &self.bands,
        }
    }
}

/// The limits and speed bands of a piece (or chain) with derivative bound cells `cells`, capped
/// at `v_cap` (`curve_bands`); its class is its top speed.
pub(super) fn piece_limits(cells: &[[Vec3; 3]], v_cap: f64, m: &Machine) -> CurveLimits {
    limits_in(cells, &piece_frame(cells, v_cap, m), m, None)
}

/// The frame of a piece's limits (`arc::Frame`): what its limits, its top speed and the ceiling
/// of that speed all start from.
fn piece_frame(cells: &[[Vec3; 3]], v_cap: f64, m: &Machine) -> Frame {
    let b = max_bounds(cells);
    Frame::uncapped(&b, smallest_radius(&b), m).capped(v_cap)
}

/// `piece_limits` in its `frame`, given what `curve_top_speed` solved for the same cells and
/// frame (or None).
fn limits_in(cells: &[[Vec3; 3]], frame: &Frame, m: &Machine, known: Option<TopSpeeds>) -> CurveLimits {
    let (limits, bands) = curve_bands(frame, cells, m, known);
    CurveLimits {
        limits,
        bands,
        class: limits.v_max,
    }
}

/// A Hermite curve's own limits (a fitted span's or a corner transition's), worked out as far
/// as asked: its derivative bound cells, the frame of its limits at the speed its feed caps it
/// at (`feed/σ`), and what solving its top speed found (its limits then start from there).
pub(super) struct Own {
    cells: [[Vec3; 3]; BOUND_PIECES],
    frame: Frame,
    top: Option<TopSpeeds>,
    /// The curve's speed bound where its frame took it (`of_shape`).
    sigma: Option<f64>,
}

impl Own {
    pub(super) fn of(h: &Hermite, feed: f64, m: &Machine) -> Own {
        let mut cells = [[[0.0; 3]; 3]; BOUND_PIECES];
        h.cells_into(&mut cells);
        let frame = piece_frame(&cells, feed / h.speed_bound().max(1.0), m);
        Own {
            cells,
            frame,
            top: None,
            sigma: Some(h.speed_bound()),
        }
    }

    /// `of` for the curve before its speed bound σ, which only caps the frame's speed: worked out
    /// where that cap may bind (`capped_frame`), and then kept (`sigma`).
    pub(super) fn of_shape(shape: &Unbounded, feed: f64, m: &Machine) -> Own {
        let mut cells = [[[0.0; 3]; 3]; BOUND_PIECES];
        shape.cells_into(&mut cells);
        let (frame, sigma) = capped_frame(&max_bounds(&cells), feed, shape, m);
        Own {
            cells,
            frame,
            top: None,
            sigma,
        }
    }

    /// The curve's speed bound where its frame took it (None where `of_shape` left it out).
    pub(super) fn sigma(&self) -> Option<f64> {
        self.sigma
    }

    /// `Own::of_shape(shape, feed, m).ceiling()` without the cells kept: the frame takes only
    /// their largest bounds (`derivative_bounds`, the same maxima in the same order).
    pub(super) fn ceiling_of(shape: &Unbounded, feed: f64, m: &Machine) -> f64 {
        capped_frame(&shape.derivative_bounds(), feed, shape, m)
            .0
            .ceiling()
    }

    /// Its limits and bands (`piece_limits`), from its top speed where `speed` solved it.
    pub(super) fn limits(&self, m: &Machine) -> CurveLimits {
        limits_in(&self.cells, &self.frame, m, self.top)
    }

    /// The top speed of its limits alone (`curve_top_speed`; curves are compared by it, and the
    /// bands of the ones kept are computed from there).
    pub(super) fn speed(&mut self, m: &Machine) -> f64 {
        let (v, top) = curve_top_speed(&self.frame, &self.cells, m);
        self.top = Some(top);
        v
    }

    /// A bound of `speed` from above without the budget's solves: where even that decides a
    /// comparison, the speed is not solved.
    pub(super) fn ceiling(&self) -> f64 {
        self.frame.ceiling()
    }
}

/// The frame of a curve's limits (`piece_frame`) from its largest bounds `b`, capped at feed/σ
/// (σ its speed bound, at least 1), and σ where it was worked out: where even the cap from σ's
/// ceiling (`Unbounded::speed_ceiling`, no smaller) is above the speed without a cap, σ's own cap
/// is too, and the frame is the same without it (most cuts the search prunes).
fn capped_frame(b: &[Vec3; 3], feed: f64, shape: &Unbounded, m: &Machine) -> (Frame, Option<f64>) {
    let free = Frame::uncapped(b, smallest_radius(b), m);
    if feed / shape.speed_ceiling().max(1.0) > free.ceiling() {
        return (free, None);
    }
    let sigma = shape.speed_bound();
    (free.capped(feed / sigma.max(1.0)), Some(sigma))
}

/// The smallest radius of curvature the cells allow, from their largest bounds (`max_bounds`):
/// 1/|p''| for the largest |p''|.
fn smallest_radius(bounds: &[Vec3; 3]) -> f64 {
    let k = norm(bounds[1]);
    if k > 0.0 {
        1.0 / k
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{add, scale};
    use crate::path::hermite::Jet;
    use crate::path::testing;
    use crate::test_rng::unit;

    /// A curve's limits from its shape, before its speed bound (`Own::of_shape`, `ceiling_of`),
    /// are those from the bounded curve bit for bit, and the speed bound's ceiling is never below
    /// it: random transitions from nearly straight to reversing, at random feeds and limits.
    #[test]
    fn limits_before_the_speed_bound_are_the_same() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut skipped = 0;
        for _ in 0..2000 {
            let mut v = |scale: f64| -> Vec3 { std::array::from_fn(|_| scale * (2.0 * unit(&mut s) - 1.0)) };
            let (d_in, d_out, turn) = (unit_vec(v(1.0)), v(1.0), v(1.0)[0].abs());
            let d_out = unit_vec(add(d_in, scale(unit_vec(d_out), 2.0 * turn)));
            let lambda = 1e-4 * (1.0 + 100.0 * turn);
            let (a, b) = (
                Jet {
                    p: [0.0; 3],
                    d1: d_in,
                    d2: v(300.0),
                },
                Jet {
                    p: add(scale(d_in, 0.5 * lambda), scale(d_out, 0.5 * lambda)),
                    d1: d_out,
                    d2: v(300.0),
                },
            );
            let m = testing::machine(&mut s);
            let feed = 10f64.powf(-2.0 + 3.0 * unit(&mut s));
            let shape = Hermite::unbounded(a, b, lambda);
            let h = shape.bounded();
            assert!(shape.speed_ceiling() >= h.speed_bound());
            let mut own = Own::of_shape(&shape, feed, &m);
            skipped += usize::from(own.sigma().is_none());
            assert_eq!(shape.bounded_with(own.sigma()), h);
            let mut bits = Own::of(&h, feed, &m);
            assert_eq!(own.ceiling().to_bits(), bits.ceiling().to_bits());
            assert_eq!(own.speed(&m).to_bits(), bits.speed(&m).to_bits());
            assert_eq!(own.limits(&m), bits.limits(&m));
            let ceiling = Own::ceiling_of(&shape, feed, &m);
            assert_eq!(ceiling.to_bits(), bits.ceiling().to_bits());
        }
        assert!(
            skipped > 200 && skipped < 1800,
            "{skipped} of 2000 without the bound"
        );
    }

    fn unit_vec(x: Vec3) -> Vec3 {
        scale(x, 1.0 / norm(x))
    }
}
