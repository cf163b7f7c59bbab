//! Stage 1 of the `smooth` corner mode (smooth.rs): a run of moves whose inner vertices are
//! smooth, fitted with quintic Hermite spans between knots. A knot's tangent and curvature are
//! those of the circle through it and its neighbouring knots (a compressor in the manner of the
//! 840D's COMPCURV, but interpolating the programmed points). A span is kept only if its Bézier
//! control points — hence the whole span — lie within the tolerance of its programmed chords
//! and it is not surely slower than its moves (`slower_than_stops`) nor, over a single line,
//! slower than that line run between the transitions at its corners (`slower_than_its_line`),
//! nor, over several moves or fitted from rest, slower from rest to rest than its moves
//! (`slower_from_rest`), nor, ending the run, slower than they are to its corner with the line
//! after it and that line on (`slower_to_exit`), nor, over several moves at an end of the run,
//! slower than its lines between the corners at its ends (`slower_between`), nor, over the
//! first line of a run that was split, or its first two moves, meeting the span before at a
//! lower corner ceiling than that line, or over a whole run before a stop, meeting it lower and
//! slower from there to rest than its lines through their corners (`slower_entry`); otherwise
//! it is split at a vertex, down to the programmed line, or, where it is slower than its lines
//! between its corners, left as those lines. Those times are in fit/baseline.rs, the corners at
//! the run's ends in fit/ends.rs.
//!
//! Moves that continue one line (`continues`: a G64 Q line split at its merged vertices for the
//! blocks it reports, CAM output that splits a straight cut) are one line here: their inner
//! vertices are neither knots nor split points, and a span that does not fit over them is the
//! line itself, whose junctions the transitions then cut along its whole length.

mod baseline;
mod ends;

use super::chain::{Curve, Own, Piece};
use super::hermite::{bezier, Hermite, Jet, Unbounded};
use super::junction::corner_speed;
use super::smooth::{end_of, start_of, Move, SmoothBuilder, Span, TIGHTER_RAMP};
use super::tolerance::{COLLINEAR_EPS, COLLINEAR_SIN2, KNOT_SLACK};
use super::PathBlock;
use crate::config::Machine;
use crate::geometry::{add, cross, distance_to_segment, dot, norm, scale, sub, unit, Line, Source};
use crate::Vec3;
use baseline::{
    corners_time, its_line_time, slower_from_rest, slower_than_its_line, slower_than_stops, slower_to_exit,
    stops_time,
};
use std::cell::Cell;

/// Parts of each chord's range whose control points are checked.
const CHECK_PIECES: usize = 4;
/// Knot spacing of the fitted spans (m): long enough that rounding of the programmed points
/// does not show as jerk, short enough to follow curvature.
const KNOT_LENGTH: f64 = 2e-3;
/// Largest turning between two knots (rad): three knots on one bend of at most twice this.
const KNOT_TURN: f64 = std::f64::consts::FRAC_PI_4;
/// A knot's neighbours more unequal than this along the path make its jet one-sided (`Vertices::jet`).
const BALANCE: f64 = 3.0;
/// A vertex this close (m) to a run's end along the path is a hook (a rounding jog, a tiny
/// closing move) that the circle the run ends on does not pass through: as if a line had taken
/// the tiny move (micro.rs, which a larger tolerance lets it do), so that circle is the same
/// whether it did or not. Through a 3.8 µm hook, the end tangents of 0.3 mm of lines turned by
/// 0.15 rad more once the hook was taken (+1.4 %, tests/monotone_found.rs); at 10 µm a random
/// program in 6000 ran 3 % longer at a larger tolerance (seed 9), at 15 µm a digest run 0.4 %.
const HOOK: f64 = 5e-6;
/// Share of a run's length at either end where its middle vertex counted in moves bunches the
/// end circle's points: its circle stands for that end alone. A larger tolerance let the last
/// of four lines take a 4.8 µm move, and the middle moved from 0.45 mm into the 0.51 mm run to
/// the 10 µm first line's end (+3.4 %, tests/monotone_found.rs).
const END_SHARE: f64 = 0.1;
/// Share of the moves' turns that their net turn must reach to count as one bend.
const COHERENT: f64 = 0.5;

/// A vertex's tangent and curvature when it is smooth.
pub(super) type VertexJet = Option<(Vec3, Vec3)>;

/// Tangent and curvature vector at `b` of the circle through a, b, c (travelled a → b → c).
fn circle_jet(a: Vec3, b: Vec3, c: Vec3) -> (Vec3, Vec3) {
    let (u, w) = (sub(a, b), sub(c, b));
    let n = cross(u, w);
    let n2 = dot(n, n);
    let chord = sub(c, a);
    if n2 <= COLLINEAR_SIN2 * dot(u, u) * dot(w, w) {
        return (unit(chord), [0.0; 3]);
    }
    // Circumcentre relative to b: ((|u|²·w − |w|²·u) × n) / (2|n|²).
    let o = scale(cross(sub(scale(w, dot(u, u)), scale(u, dot(w, w))), n), 0.5 / n2);
    let k = scale(o, 1.0 / dot(o, o));
    let on = unit(o);
    let t = unit(sub(chord, scale(on, dot(chord, on))));
    (t, k)
}

/// Jet at the end point `a` of the circle through a, b, c (travelled from a towards b; with
/// `reverse`, arriving at a from b).
fn circle_jet_at_end(a: Vec3, b: Vec3, c: Vec3, reverse: bool) -> (Vec3, Vec3) {
    let (t_mid, k_mid) = circle_jet(a, b, c);
    let toward = if reverse { sub(a, b) } else { sub(b, a) };
    if dot(k_mid, k_mid) == 0.0 {
        // Collinear points: the chord's direction, pointing the way the path runs at `a`.
        let t = if dot(t_mid, toward) < 0.0 {
            scale(t_mid, -1.0)
        } else {
            t_mid
        };
        return (t, k_mid);
    }
    let o = add(b, scale(k_mid, 1.0 / dot(k_mid, k_mid)));
    let r = sub(o, a);
    let k = scale(r, 1.0 / dot(r, r));
    let rn = unit(r);
    (unit(sub(toward, scale(rn, dot(toward, rn)))), k)
}

/// The run's vertices (0 … moves), the path length to each, and the speed at each inner
/// vertex as a corner between its lines (`corner_speed`), solved when first asked: a vertex is
/// the end of one fitted line and the start of the next.
struct Vertices {
    p: Vec<Vec3>,
    s: Vec<f64>,
    corners: Vec<Cell<Option<f64>>>,
    /// Whether the vertex ends a line that took tiny moves (micro.rs).
    took: Vec<bool>,
}

impl Vertices {
    fn of(run: &[Move]) -> Vertices {
        let p = std::iter::once(start_of(&run[0]))
            .chain(run.iter().map(end_of))
            .collect();
        let mut s = vec![0.0];
        s.extend(run.iter().scan(0.0, |acc, mv| {
            *acc += mv.source.length();
            Some(*acc)
        }));
        let corners = vec![Cell::new(None); run.len() + 1];
        let took = std::iter::once(false)
            .chain(run.iter().map(|mv| mv.absorbed > 0.0))
            .collect();
        Vertices { p, s, corners, took }
    }

    /// The speed at inner vertex k of `run` (the run these vertices are of) as a corner between
    /// its lines.
    fn corner_speed(&self, run: &[Move], k: usize, m: &Machine) -> f64 {
        if let Some(v) = self.corners[k].get() {
            return v;
        }
        let (a, b) = (&run[k - 1], &run[k]);
        let v = corner_speed(&line_of(a), &line_of(b), b.tolerance, b.feed, m);
        self.corners[k].set(Some(v));
        v
    }

    /// The middle point of the circle a run between two knots ends on: its middle vertex
    /// (counted in moves), or the one nearest it that is not within `HOOK` of either end; where
    /// that lies in the run's outer `END_SHARE` of length, the vertex nearest the middle of its
    /// length (not within `HOOK`); with none, no circle (the run's chord). Nor the end of a line
    /// that took tiny moves: a larger tolerance lets it take more, which moves the middle counted
    /// in moves onto it. Lines of 9, 2.7, 19 and 25 µm with Z zig-zags of 5 µm, the third taking
    /// the two before it at 1.9 times the tolerance: the circle through its end, at the bottom of
    /// a dip, turned the curve's start down and the 15 mm arc before braked to 9.1 mm/s instead
    /// of 15.2 (+0.99 %, tests/monotone_found/fit.rs).
    fn end_circle_middle(&self, moves: usize) -> Option<usize> {
        let s = &self.s;
        let hook = |k: usize| s[k] < HOOK || s[moves] - s[k] < HOOK || self.took[k];
        let off_middle = |k: usize| (s[k] - 0.5 * s[moves]).abs();
        let mid = moves / 2;
        (0..moves)
            .flat_map(|k| [mid + k, mid.wrapping_sub(k)])
            .find(|&k| (1..moves).contains(&k) && !hook(k))
            .filter(|&k| off_middle(k) <= (0.5 - END_SHARE) * s[moves])
            .or_else(|| {
                (1..moves)
                    .filter(|&k| !hook(k))
                    .min_by(|&a, &b| off_middle(a).total_cmp(&off_middle(b)))
            })
    }

    /// The jet at vertex `i` from the circle through it and the vertices `lo` before and `hi`
    /// after it. Where one of those is more than `BALANCE` times as far along the path as the
    /// other, the circle through three points on one side instead, on the nearer side whose two
    /// steps are about even (beside a long move the circle through both sides stands for
    /// neither: at a bend's end next to a straight row its tangent is off by degrees, its
    /// curvature a tenth).
    fn jet(&self, i: usize, lo: usize, hi: usize) -> (Vec3, Vec3) {
        let s = &self.s;
        let uneven = |a: f64, b: f64| a.max(b) / a.min(b);
        let both = uneven(s[i] - s[lo], s[hi] - s[i]);
        let across = circle_jet(self.p[lo], self.p[i], self.p[hi]);
        if both <= BALANCE {
            return across;
        }
        // A second step on each side: beyond `lo` (or `hi`) at least as long as the first, or
        // the vertex between.
        let last = self.p.len() - 1;
        let before = (0..lo)
            .rev()
            .find(|&k| s[lo] - s[k] >= s[i] - s[lo])
            .map(|k| (k, lo))
            .or_else(|| (lo + 1 < i).then_some((lo, (lo + i) / 2)));
        let after = (hi + 1..=last)
            .find(|&k| s[k] - s[hi] >= s[hi] - s[i])
            .map(|k| (hi, k))
            .or_else(|| (i + 1 < hi).then_some(((i + hi) / 2, hi)));
        // Of the sides whose two steps are even, the nearer.
        let left = before
            .filter(|&(far, near)| uneven(s[i] - s[near], s[near] - s[far]) <= BALANCE)
            .map(|(far, near)| (s[i] - s[near], far, near));
        let right = after
            .filter(|&(near, far)| uneven(s[near] - s[i], s[far] - s[near]) <= BALANCE)
            .map(|(near, far)| (s[near] - s[i], near, far));
        match (left, right) {
            (Some(l), r) if r.is_none_or(|r| l.0 <= r.0) => {
                circle_jet_at_end(self.p[i], self.p[l.2], self.p[l.1], true)
            }
            (_, Some(r)) => circle_jet_at_end(self.p[i], self.p[r.1], self.p[r.2], false),
            _ => across,
        }
    }
}

impl SmoothBuilder {
    /// Fit the run with Hermite spans between knots about `KNOT_LENGTH` apart; with
    /// `keep_tail`, the last span stays in the run (its first knot's jet carried) for the moves
    /// still to come. `after`: the move after the run, past a corner, where it is known.
    pub(super) fn flush_run(
        &mut self,
        keep_tail: bool,
        after: Option<&Move>,
        m: &Machine,
        out: &mut Vec<PathBlock>,
    ) {
        let run = std::mem::take(&mut self.run);
        let jet0 = self.run_jet.take();
        let Some(first) = run.first().copied() else { return };
        if run.len() == 1 && jet0.is_none() {
            self.junction(Span::programmed(first), m, out);
            return;
        }
        let vertices = Vertices::of(&run);
        let verts = &vertices.p;
        let knots = choose_knots(&run);
        let mut jets: Vec<VertexJet> = vec![None; knots.len()];
        for j in 1..knots.len() - 1 {
            jets[j] = Some(vertices.jet(knots[j], knots[j - 1], knots[j + 1]));
        }
        // The run's ends continue the circle through their three nearest knots (or vertices), so
        // curvature does not fall to zero there; the transition to the neighbour takes over.
        let n = knots.len();
        let ends = if n >= 3 {
            Some((
                [knots[0], knots[1], knots[2]],
                [knots[n - 1], knots[n - 2], knots[n - 3]],
            ))
        } else if run.len() >= 2 {
            let last = run.len();
            Some(match vertices.end_circle_middle(last) {
                Some(mid) => ([0, mid, last], [last, mid, 0]),
                // The chord: each end's circle through the other end twice.
                None => ([0, last, last], [last, 0, 0]),
            })
        } else {
            None
        };
        if let Some((s, e)) = ends {
            jets[0] = Some(circle_jet_at_end(verts[s[0]], verts[s[1]], verts[s[2]], false));
            jets[n - 1] = Some(circle_jet_at_end(verts[e[0]], verts[e[1]], verts[e[2]], true));
        }
        if jet0.is_some() {
            jets[0] = jet0;
        }
        let spans = if keep_tail && knots.len() >= 3 {
            knots.len() - 2
        } else {
            knots.len() - 1
        };
        for j in 0..spans {
            let span = Fit {
                run: &run,
                vertices: &vertices,
                from: knots[j],
                to: knots[j + 1],
                after: after.filter(|_| !keep_tail),
                stop_after: !keep_tail && after.is_none(),
            };
            self.fit(span, jets[j], jets[j + 1], m, out);
        }
        if spans < knots.len() - 1 {
            self.run = run[knots[spans]..].to_vec();
            self.run_jet = jets[spans];
        }
    }

    /// One Hermite span over `moves` from jet `a` to jet `b` if it stays within the tolerance
    /// of every programmed chord (guaranteed by the control points of the curve over
    /// each chord's parameter range); else split at the vertex nearest the middle, down to the
    /// programmed line.
    fn fit(&mut self, span: Fit, a: VertexJet, b: VertexJet, m: &Machine, out: &mut Vec<PathBlock>) {
        let moves = &span.run[span.from..span.to];
        let (first, last) = (moves[0], moves[moves.len() - 1]);
        let one_line = moves.windows(2).all(|w| continues(&w[0], &w[1]));
        if one_line && a.is_none() && b.is_none() {
            self.junction(Span::line(moves), m, out);
            return;
        }
        let jet = |p: Vec3, v: VertexJet, mv: &Move| {
            let (t, k) = v.unwrap_or((line_of(mv).direction(), [0.0; 3]));
            Jet { p, d1: t, d2: k }
        };
        let lambda: f64 = moves.iter().map(|mv| mv.source.length()).sum();
        let shape = Hermite::unbounded(
            jet(start_of(&first), a, &first),
            jet(end_of(&last), b, &last),
            lambda,
        );
        // Kept unless it is surely slower than the moves it replaces, or than one line between
        // its corners, or, over several moves or fitted from rest (nothing before it since a
        // stop), slower from rest to rest than the moves each from rest to rest; over one line
        // elsewhere, unless its ramps are clearly slower than the line's (`TIGHTER_RAMP` times
        // its time from rest to rest): its top speed then says little of what it runs.
        // So is one line that ends its run before a stop after a span left straight: it meets
        // that span at a corner and ramps to rest within its own limits, so its ramps are run.
        let rest_to_rest = moves.len() > 1
            || span.from == 0 && self.at_rest()
            || span.stop_after && span.to == span.run.len() && self.line_waits();
        // A whole run from rest stands alone (a stop before it, a corner or a stop after): its
        // lines would run through every corner at its own speed, not each from rest to rest (a
        // 16 µm line and a 0.95 mm one pass theirs at 2.7 mm/s: against a stop there, a curve
        // over both was kept that ran 1.5 % slower); so would the moves that end a run before a
        // stop where they pass all their corners at the curve's top speed (`Fit::passes_to_stop`).
        // So does a whole run that enters at a corner it nearly stops at (`stands_alone`).
        // Where such a run is split, a curve over one line after its first, left straight,
        // rises from their corner on its own ramps (`Fit::enters_below`), so is compared from
        // rest to rest.
        // Its limits: its top speed first, which the first two tests take; its bands only for
        // the third, and where it is kept (those of a curve the first two reject are not needed).
        // Over one line between two corners of the run, the line's time does not take that
        // speed: where even its ceiling is slower, the speed is not solved.
        // Set where the curve is slower than its lines through their corners: they then run
        // straight, not split into curves over parts of them, which gain nothing at corners the
        // lines pass at their ceilings.
        let straight = Cell::new(false);
        let kept = |h: &Hermite| {
            let mut own = Own::of(h, first.feed, m);
            let inner = its_line_time(span, None, m);
            if inner.is_some_and(|line| slower_than_its_line(h.length(), own.ceiling(), line)) {
                return None;
            }
            let class = own.speed(m);
            let alone = self.stands_alone(span, class, m);
            let mut stops = stops_time(moves, 0.0, m);
            if alone {
                stops = stops.min(corners_time(span, 0.0, 0.0, m));
            } else if span.passes_to_stop(class, m) {
                stops = stops.min(corners_time(span, class, 0.0, m));
            }
            let line = || inner.or_else(|| its_line_time(span, Some(class), m));
            if slower_than_stops(h.length(), class, stops)
                || line().is_some_and(|line| slower_than_its_line(h.length(), class, line))
            {
                return None;
            }
            let own = own.limits(m);
            let rest_to_rest = rest_to_rest || self.line_waits_from_rest() && span.enters_below(class, m);
            let from_rest = if rest_to_rest { stops } else { TIGHTER_RAMP * stops };
            if slower_from_rest(h.length(), &own, 0.0, from_rest) {
                return None;
            }
            if self.slower_entry(span, h, &own, m) {
                return None;
            }
            let run_end = span.from == 0 || span.to == span.run.len();
            if moves.len() > 1 && run_end && !alone && self.slower_between_corners(span, h, &own, m) {
                straight.set(true);
                return None;
            }
            (!slower_to_exit(span, h, &own, [rest_to_rest, alone], m)).then_some(own)
        };
        let fitted = within_chords(&shape, moves).then(|| shape.bounded());
        if let Some((h, own)) = fitted.and_then(|h| Some((h, kept(&h)?))) {
            let mut span = Span::fitted(Piece::whole(Curve::Hermite(h), first.line), moves);
            span.own = Some(own);
            self.junction(span, m, out);
        } else if one_line {
            self.junction(Span::line(moves), m, out);
        } else if straight.get() {
            // Each line on its own; moves that continue one line stay one.
            for line in moves.chunk_by(continues) {
                self.junction(Span::line(line), m, out);
            }
        } else {
            let mid = span.from + split_vertex(moves);
            let jm = Some(span.vertices.jet(mid, span.from, span.to));
            self.fit(Fit { to: mid, ..span }, a, jm, m, out);
            self.fit(Fit { from: mid, ..span }, jm, b, m, out);
        }
    }
}

/// The moves `from` … `to` of a run, being fitted.
#[derive(Clone, Copy)]
struct Fit<'a> {
    run: &'a [Move],
    vertices: &'a Vertices,
    from: usize,
    to: usize,
    /// The move after the run, past a corner, where it is known.
    after: Option<&'a Move>,
    /// A stop follows the run.
    stop_after: bool,
}

impl Fit<'_> {
    /// The speed of the lines' corner at the span's far end: at a vertex of its run, or with the
    /// line after the run; none (∞) before an arc or a stop.
    fn far_corner(&self, m: &Machine) -> f64 {
        if self.to < self.run.len() {
            return self.vertices.corner_speed(self.run, self.to, m);
        }
        match self.after.map(|mv| (mv, mv.source)) {
            Some((mv, Source::Line(next))) => {
                let last = line_of(&self.run[self.to - 1]);
                corner_speed(&last, &next, mv.tolerance, mv.feed, m)
            }
            _ => f64::INFINITY,
        }
    }

    /// Whether the span, one line after a vertex of its run, passes that vertex below `class`:
    /// after a line from rest left straight, it then rises from that corner on its own ramps. A
    /// 0.95 mm line after a 16 µm one from rest, fitted alone at 2.7 times the tolerance, rose
    /// from their 2.7 mm/s corner on 158 mm/s² where the line has 222 (+1.5 %,
    /// tests/monotone_found.rs). After a corner within a run elsewhere, measured and not kept:
    /// 3D_Chips +0.46 % at jerk 5e4.
    fn enters_below(&self, class: f64, m: &Machine) -> bool {
        self.to - self.from == 1
            && self.from >= 1
            && self.vertices.corner_speed(self.run, self.from, m) < class
    }

    /// Whether the moves, several, end the run before a stop and pass each corner between them
    /// at `class` or faster: a curve over them gains nothing at those corners and ramps to rest
    /// within its own limits, so it is compared with its lines through them (`corners_time`).
    /// Three nearly collinear lines ending a program, fitted as one curve at 25.65 mm/s whose
    /// top band has 117 m/s³ of jerk where the lines pass their corners at 25.70 with 139 and
    /// more, ramped to rest more slowly (+1.07 %, tests/monotone_found.rs).
    fn passes_to_stop(&self, class: f64, m: &Machine) -> bool {
        self.to - self.from > 1
            && self.to == self.run.len()
            && self.stop_after
            && self.passes_corners(class, m)
    }

    /// Whether the moves pass each corner between them at `class` or faster.
    fn passes_corners(&self, class: f64, m: &Machine) -> bool {
        (self.from + 1..self.to).all(|k| self.vertices.corner_speed(self.run, k, m) >= class)
    }
}

fn line_of(mv: &Move) -> Line {
    match mv.source {
        Source::Line(l) => l,
        Source::Arc(_) => unreachable!("runs of more than one move hold lines only"),
    }
}

/// The curve over each chord's range, in `CHECK_PIECES` parts, within the chord's tolerance:
/// each part lies in the hull of its control points, which come close to the curve as the parts
/// shrink. The whole tolerance: with 0.7 of it (a span that needed more was taken to fit badly)
/// the CAM-like 100 k lines ran 2.9 % longer.
fn within_chords(h: &Unbounded, moves: &[Move]) -> bool {
    let lambda = h.length();
    let mut u = 0.0;
    let mut jet_u = h.jet(0.0);
    for mv in moves {
        let l = line_of(mv);
        let ub = (u + l.length()).min(lambda);
        let step = (ub - u) / CHECK_PIECES as f64;
        for k in 1..=CHECK_PIECES {
            let u1 = if k == CHECK_PIECES {
                ub
            } else {
                u + step * k as f64
            };
            let jet_next = h.jet(u1);
            let inside = bezier(&jet_u, &jet_next, step)
                .iter()
                .all(|&c| distance_to_segment(c, l.start, l.end) <= mv.tolerance);
            if !inside {
                return false;
            }
            jet_u = jet_next;
        }
        u = ub;
    }
    true
}

/// Two consecutive line moves that continue one line: the second starts where the first ends,
/// in its direction (to rounding), at the same feed and tolerance.
pub(super) fn continues(a: &Move, b: &Move) -> bool {
    let (Source::Line(la), Source::Line(lb)) = (a.source, b.source) else {
        return false;
    };
    !a.exact
        && !b.exact
        && a.feed == b.feed
        && a.tolerance == b.tolerance
        && la.end == lb.start
        && 1.0 - dot(la.direction(), lb.direction()) <= COLLINEAR_EPS
}

/// The vertex (1 … moves − 1) to split a span at: of those that are not inside one line, the
/// nearest the middle (one exists: the caller checked the moves are not one line).
fn split_vertex(moves: &[Move]) -> usize {
    let mid = moves.len() / 2;
    let corner = |i: usize| (1..moves.len()).contains(&i) && !continues(&moves[i - 1], &moves[i]);
    (0..moves.len())
        .flat_map(|k| [mid + k, mid.wrapping_sub(k)])
        .find(|&i| corner(i))
        .unwrap_or(mid)
}

/// Knot indices into the run's vertices (0 … moves): about `KNOT_LENGTH` apart in length, and
/// closer where the direction turns by more than `KNOT_TURN` from a knot's (the net turn, so
/// rounding steps that turn back and forth do not count) over a stretch that bows out by more
/// than the tolerance a span may use; none inside one line (`continues`).
/// A knot's jet is the circle through it and its neighbouring knots, which stands for the curve
/// there only while they lie on one bend of it: on a tight radius, 2 mm of chords turn through
/// half a circle or more (the knots a turn apart coincide), and the spans between such knots
/// have neither the curve's tangent nor its curvature.
fn choose_knots(run: &[Move]) -> Vec<usize> {
    let total: f64 = run.iter().map(|mv| mv.source.length()).sum();
    let spans = ((total / KNOT_LENGTH).round() as usize).clamp(1, run.len());
    let target = |k: usize| total * k as f64 / spans as f64 * (1.0 - KNOT_SLACK);
    let mut knots = vec![0];
    let (mut acc, mut grid) = (0.0, 1);
    let (mut since, mut from, mut turns) = (0.0, line_of(&run[0]).direction(), 0.0);
    for (i, pair) in run.windows(2).enumerate() {
        acc += pair[0].source.length();
        if continues(&pair[0], &pair[1]) {
            continue;
        }
        let next = line_of(&pair[1]).direction();
        turns += angle(line_of(&pair[0]).direction(), next);
        let turn = angle(from, next);
        // A bend: the moves turn one way (the net turn most of their turns: not a path that
        // wanders) and bow out farther than the tolerance would absorb.
        let bow = (acc - since) / turn * (1.0 - (0.5 * turn).cos());
        let bend = turn > KNOT_TURN && turn > COHERENT * turns && bow > pair[0].tolerance;
        if acc >= target(grid) || bend {
            knots.push(i + 1);
            (since, from, turns) = (acc, next, 0.0);
            while acc >= target(grid) {
                grid += 1;
            }
        }
    }
    knots.push(run.len());
    knots
}

/// The angle between two unit vectors (rad).
fn angle(u: Vec3, w: Vec3) -> f64 {
    norm(cross(u, w)).atan2(dot(u, w))
}
