//! The cost of a junction's choices (junction.rs): each neighbour of the corner as a side — its
//! own speed, the limits and bands it ramps within, its length and, where known, the speed at
//! its far end — and the time a transition (or a stop) adds at the corner against the sides
//! running at their own speeds.

use crate::config::Machine;
use crate::feed::bands::{Banded, Bands};
use crate::feed::{scurve7, scurve7_banded, Limits, ProfileKind};
use crate::path::chain::{piece_limits, Curve};
use crate::path::hermite::BOUND_PIECES;
use crate::path::smooth::{joined_loss, Span};
use crate::path::tolerance::{RAMP_FIT, RAMP_STEPS};
use crate::path::{constant_speed_limit, line_limits};

/// A neighbour's own speed (its class: `piece_limits` on curves, the feed and eq. 11 on lines),
/// the limits and bands it ramps within, and its length.
pub(super) struct Side {
    pub(super) v: f64,
    pub(super) top: Limits,
    pub(super) bands: Bands,
    pub(super) length: f64,
    pub(super) curved: bool,
    pub(super) feed: f64,
    /// The speed at its span's far end from the corner, where known: its block between the
    /// corner and there is costed (`local_cost`).
    pub(super) far: Option<Far>,
    /// Its speed before `joined_sides` lowers it to the slower side's.
    pub(super) apart: f64,
}

impl Side {
    /// Its limits and bands, as its ramps are planned.
    pub(super) fn banded(&self) -> Banded<'_> {
        Banded {
            kind: ProfileKind::Scurve7,
            top: &self.top,
            bands: &self.bands,
        }
    }

    /// The speed it runs at beside a far end at `far`: its own (`apart`) where that is rest, its
    /// block from or to there planned apart from the slower side (beside a seed-4 stop, a
    /// 0.96 mm arc costed at its 0.21 mm neighbour's 7.9 mm/s gained 25 ms from a 3.8 mm/s
    /// transition where its block, at up to 16.6 mm/s, gains 16), else `v`.
    pub(super) fn beside(&self, far: f64) -> f64 {
        if far == 0.0 {
            self.apart
        } else {
            self.v
        }
    }
}

/// A side's far end: the speed its span starts at (the span before, after a stop) or ends at
/// (the span after: a stop, or the estimate at its own far corner), and the time and distance
/// of its ramp between that speed and the side's own ((0, 0) where that is not below).
#[derive(Clone, Copy)]
pub(super) struct Far {
    pub(super) v: f64,
    pub(super) at_start: bool,
    pub(super) ramp: (f64, f64),
}

/// A side's speed where its span begins (the span before) or ends (the span after), where
/// known, and a copy of the limits it ramps within.
pub(super) struct End {
    pub(super) v: f64,
    pub(super) top: Limits,
    pub(super) bands: Bands,
}

impl End {
    pub(super) fn banded(&self) -> Banded<'_> {
        Banded {
            kind: ProfileKind::Scurve7,
            top: &self.top,
            bands: &self.bands,
        }
    }
}

/// The side of a junction that `span` is (its limits computed once, kept on the span).
pub(super) fn side(span: &mut Span, feed: f64, m: &Machine) -> Side {
    let piece = &span.piece;
    let sigma = piece.curve.speed_bound().max(1.0);
    let (v, top, bands) = match piece.curve {
        Curve::Line(line) => {
            let v = constant_speed_limit(&piece.curve.derivative_bounds(), m).min(feed / sigma);
            (v, line_limits(line.direction(), m), Bands::default())
        }
        _ => {
            let l = span.own.get_or_insert_with(|| {
                let mut cells = Vec::with_capacity(BOUND_PIECES);
                piece.curve.cells(|c| cells.push(c));
                piece_limits(&cells, feed / sigma, m)
            });
            (l.class, l.limits, l.bands.clone())
        }
    };
    Side {
        v,
        top,
        bands,
        length: piece.length(),
        curved: !matches!(piece.curve, Curve::Line(_)),
        feed,
        far: None,
        apart: v,
    }
}

/// Where the faster neighbour would join one chain with the slower (smooth.rs, `joined_loss`:
/// two curves of one feed), it runs at the slower one's speed: what a cut replaces of it then
/// runs no faster than the transition.
pub(super) fn joined_sides(sides: &mut [Side; 2]) {
    for s in sides.iter_mut() {
        s.apart = s.v;
    }
    let (slow, fast) = if sides[0].v <= sides[1].v { (0, 1) } else { (1, 0) };
    let (s, f) = (&sides[slow], &sides[fast]);
    if s.curved && f.curved && s.feed == f.feed && f.v > s.v {
        let (ramps, rest) = (((&f.top, &f.bands), (&s.top, &s.bands)), (false, false));
        if joined_loss(0.0, (s.length, s.v), (f.length, f.v), ramps.0, ramps.1, rest).is_some() {
            sides[fast].v = sides[slow].v;
        }
    }
}

/// Time a transition of cut `d` (on both sides) and `length` at speed `v` adds to the corner: its
/// own run, less the stretches of the neighbours it replaces at their own speeds, plus what each
/// neighbour loses to the ramp between `v` and its own speed (the fastest within its limits and
/// bands, `scurve7_banded`, as far as its length reaches): T − D/v_side over the ramp. A
/// neighbour whose far end is known (`Far`) counts its block between `v` and that end over what
/// the cut leaves of it instead (less its whole length at its speed, as the others): it does
/// not run on at its own speed, and its two ramps share what is left of it. Where both fit,
/// that is the ramp from `v` and the far ramp, each against running at its own speed (its
/// speed apart where that end is rest: `Side::beside`).
pub(super) fn local_cost(d: f64, length: f64, v: f64, sides: &[Side; 2]) -> f64 {
    let mut cost = length / v.max(f64::MIN_POSITIVE);
    for s in sides {
        cost = with_side(cost, d, v, s);
    }
    cost
}

/// Whether a stop at the corner costs less than `bound`: `local_cost(0.0, 0.0, 0.0, sides) <
/// bound`, by the same sums. At a stop each side adds the time of its ramp (or block) from rest
/// less its distance at the side's own speed, never below 0: the ramp runs below that speed
/// throughout (an S-curve from rest covers half its time at its end speed). Once the sum
/// reaches `bound` the other side cannot bring it back below and is not costed (after the
/// first side at 87 % of the corners of the CAM-like program).
pub(super) fn stop_below(sides: &[Side; 2], bound: f64) -> bool {
    let mut cost = 0.0;
    for s in sides {
        cost = with_side(cost, 0.0, 0.0, s);
        if cost >= bound {
            return false;
        }
    }
    cost < bound
}

/// `cost` with side `s`'s part of `local_cost` at cut `d` and speed `v`.
fn with_side(mut cost: f64, d: f64, v: f64, s: &Side) -> f64 {
    let v_side = s.v.max(f64::MIN_POSITIVE);
    let banded = s.banded();
    let rest = (s.length - d).max(0.0);
    if let Some(far) = s.far {
        // At `beside`'s speed, its time against the same constant (its length at `s.v`).
        let own = s.beside(far.v).max(f64::MIN_POSITIVE);
        cost += s.length / own - s.length / v_side;
        let v_side = own;
        let v0 = v.clamp(0.0, v_side);
        let (t, x) = rise(&banded, v0, v_side, f64::INFINITY);
        let (t_far, x_far) = far.ramp;
        if x + x_far <= rest {
            cost += t - x / v_side + t_far - x_far / v_side - d / v_side;
        } else {
            // Its block over what is left of it, less the same constant.
            let (v_in, v_out) = if far.at_start { (far.v, v0) } else { (v0, far.v) };
            let (t, _) = scurve7_banded::plan_time(&banded, rest, v_in, v_out, v_side);
            cost += t - s.length / v_side;
        }
        return cost;
    }
    cost -= d / v_side;
    if v < v_side {
        let (t, x) = rise(&banded, v.max(0.0), v_side, rest);
        cost += t - x / v_side;
    }
    cost
}

/// What the corner before loses where the span before (`held`, side `s`) cannot drop from its
/// entry (the top speed of the transition before it) to `v` over what cut `d` leaves of it:
/// that transition then runs no faster than the span drops from, and the span's length is run
/// at the mean of both speeds, not at the entry (a proxy for that transition's own length).
pub(super) fn entry_drop(held: &Span, s: &Side, d: f64, v: f64) -> f64 {
    let Some(e) = held.entry.filter(|&e| e > v) else {
        return 0.0;
    };
    let length = held.piece.length();
    let rest = (length - d).max(0.0);
    // Most drops fit within the side's tightest pair already: no banded solve.
    let (tightest, _) = s.bands.pair_range(&s.top);
    if scurve7::ramp_distance(v.max(0.0), e, &tightest) <= rest {
        return 0.0;
    }
    let banded = s.banded();
    let r = banded.max_entry(rest, v.max(0.0));
    if r >= e {
        return 0.0;
    }
    length * (2.0 / (r + e) - 1.0 / e)
}

/// A bound from below of `local_cost` at the same cut and speed, without the banded ramps'
/// solves: each side's ramp within the widest of its pairs (its bands only widen its limits
/// below its top, so no ramp within them is faster: T − D/v_side is no smaller), in closed
/// form, less the most that `local_cost`'s ramp over what is left of the side (`ramp_within`,
/// to `RAMP_FIT` of that length) can fall short of the exact one: RAMP_FIT of that length at
/// the ramp's start speed. That holds where its regula falsi converges; where it stops at
/// `RAMP_STEPS` (4 % of its solves on the CAM-like program) its cost is an iterate's, which
/// may lie below (no decision changed on the 490 digest runs nor on 12 000 random programs).
/// None where a side's far end is known (its block is planned there).
pub(super) fn cost_floor(d: f64, length: f64, v: f64, sides: &[Side; 2]) -> Option<f64> {
    let mut cost = length / v.max(f64::MIN_POSITIVE);
    for s in sides {
        if s.far.is_some() {
            return None;
        }
        let v_side = s.v.max(f64::MIN_POSITIVE);
        cost -= d / v_side;
        if v < v_side {
            let rest = (s.length - d).max(0.0);
            let (_, widest) = s.bands.pair_range(&s.top);
            let (t, x) = scurve7::rise_within(v.max(0.0), v_side, rest, &widest);
            cost += t - x / v_side - RAMP_FIT * rest / v.max(f64::MIN_POSITIVE);
        }
    }
    Some(cost)
}

/// Time and distance of the side's rise from v0 up to `v_side`, or over `rest` where it ends
/// before.
fn rise(banded: &Banded, v0: f64, v_side: f64, rest: f64) -> (f64, f64) {
    if v0 >= v_side {
        (0.0, 0.0)
    } else if banded.bands.levels().is_empty() {
        // One band: scurve7's closed forms.
        scurve7::rise_within(v0, v_side, rest, banded.top)
    } else {
        // Every ramp here rises from v (one forward envelope).
        let mut rise = None;
        ramp_within(
            scurve7_banded::Rise::build_in(&mut rise, banded, v0),
            v_side,
            rest,
        )
    }
}

/// Time and distance of `rise` up to `v_side`, or over `rest` where it ends before (the side is
/// shorter than the ramp): the exit speed whose distance is `rest` to `RAMP_FIT` of it, by the
/// Illinois regula falsi between the rise's start and `v_side` (a cost to compare cuts by, not a
/// speed to plan with).
fn ramp_within(rise: &scurve7_banded::Rise, v_side: f64, rest: f64) -> (f64, f64) {
    let (t_top, x_top) = rise.time_distance(v_side);
    if x_top <= rest {
        return (t_top, x_top);
    }
    let (mut lo, mut g_lo) = (rise.lo(), -rest);
    let (mut hi, mut g_hi) = (v_side, x_top - rest);
    let mut at = (0.0, 0.0);
    let mut last_lo = None;
    for _ in 0..RAMP_STEPS {
        let mut w = lo - g_lo * (hi - lo) / (g_hi - g_lo);
        if !(w > lo && w < hi) {
            w = 0.5 * (lo + hi);
        }
        at = rise.time_distance(w);
        let g = at.1 - rest;
        if g.abs() <= RAMP_FIT * rest {
            break;
        }
        // Illinois: the end that stays twice has its value halved.
        if g < 0.0 {
            (lo, g_lo) = (w, g);
            if last_lo == Some(true) {
                g_hi *= 0.5;
            }
            last_lo = Some(true);
        } else {
            (hi, g_hi) = (w, g);
            if last_lo == Some(false) {
                g_lo *= 0.5;
            }
            last_lo = Some(false);
        }
    }
    at
}
