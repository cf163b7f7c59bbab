//! Stage 2 of the `smooth` corner mode (smooth.rs): the transition at a junction of two pieces
//! that do not meet with equal first and second derivatives — a quintic Hermite (hermite.rs;
//! eq. 45–52 between two lines) from a cut d on each side, d from eq. 52's apex at the tolerance,
//! shrunk until the transition keeps the tolerance, then halved while that costs less time at the
//! corner (`local_cost`), or None (a stop at the corner). The tolerance only admits cuts; the time
//! picks among them, so a larger tolerance does not pick a slower one.

use super::chain::{piece_limits, piece_speed, Curve, CurveLimits};
use super::hermite::{Hermite, BOUND_PIECES};
use super::smooth::{jet_at, joined_loss, Span};
use super::tolerance::{MIN_LENGTH, REVERSAL_COS};
use super::{constant_speed_limit, line_limits, slowest_axis};
use crate::config::Machine;
use crate::feed::bands::{Banded, Bands};
use crate::feed::{scurve7, scurve7_banded, BlockRequest, FeedLaw, Limits, ProfileKind};
use crate::geometry::Source;
use crate::geometry::{dot, norm, sub, unit};

/// Shrinks of a transition's cut (by `SHRINK` each) before the junction stops instead.
const MAX_SHRINKS: usize = 60;
const SHRINK: f64 = 0.85;
/// Samples of a transition checked against the programmed geometry.
const DEVIATION_SAMPLES: usize = 64;

/// The limits of transition `h` at `feed` if running through it beats stopping at the corner:
/// its time at its speed limit is at most the rest-to-rest time over its length within the feed
/// and the axes' acceleration and jerk (a stop costs at least that; the neighbours' ramps come on
/// top). A tiny sharp transition allows so little speed that stopping is quicker; a long gentle
/// one (lines meeting at a rounding kink) runs at the feed.
fn faster_than_a_stop(h: &Hermite, feed: f64, m: &Machine) -> Option<f64> {
    let v_max = own_speed(h, feed, m);
    let t_stop = scurve7::plan(&BlockRequest {
        length: h.length(),
        v_in: 0.0,
        v_out: 0.0,
        v_feed: feed,
        limits: slowest_axis(m, feed),
    })
    .duration();
    (h.length() <= v_max * t_stop).then_some(v_max)
}

/// The limits of transition `h` at `feed` (`piece_limits`).
fn own_limits(h: &Hermite, feed: f64, m: &Machine) -> CurveLimits {
    let mut cells = Vec::with_capacity(BOUND_PIECES);
    h.cells(|c| cells.push(c));
    piece_limits(&cells, feed / h.speed_bound().max(1.0), m)
}

/// The top speed of `own_limits` alone (the cuts are compared by it; only the chosen one's
/// bands are computed).
fn own_speed(h: &Hermite, feed: f64, m: &Machine) -> f64 {
    let mut cells = Vec::with_capacity(BOUND_PIECES);
    h.cells(|c| cells.push(c));
    piece_speed(&cells, feed / h.speed_bound().max(1.0), m)
}

/// The transition between `held` and `next`: the cuts on both sides and the curve, or None
/// (stop) at a reversal or when no cut keeps the tolerance.
pub(super) fn transition(
    held: &mut Span,
    next: &mut Span,
    m: &Machine,
) -> Option<(f64, f64, Hermite, CurveLimits)> {
    let end = jet_at(&held.piece, held.piece.length());
    let start = jet_at(&next.piece, 0.0);
    let (t_in, t_out) = (unit(end.d1), unit(start.d1));
    if dot(t_in, t_out) < REVERSAL_COS {
        return None;
    }
    let tol = held.last.tolerance;
    // Eq. 52: the apex of the line-line transition lies (3/16)·L·|t_out − t_in| from the corner.
    let w = norm(sub(t_out, t_in));
    let apex_cut = if w > 0.0 {
        16.0 * tol / (3.0 * w)
    } else {
        f64::INFINITY
    };
    let mut d = apex_cut
        .min(0.5 * held.last.source.length())
        .min(0.5 * next.first.source.length())
        .min(held.piece.length())
        .min(next.piece.length());
    // Two lines: eq. 52 puts the largest deviation, |OQ| = tol, at the apex (blend.rs tests).
    let lines = matches!(
        (
            held.piece.curve,
            next.piece.curve,
            held.last.source,
            next.first.source
        ),
        (Curve::Line(_), Curve::Line(_), Source::Line(_), Source::Line(_))
    );
    let feed = held.last.feed.min(next.first.feed);
    let mut sides = [side(held, held.last.feed, m), side(next, next.first.feed, m)];
    joined_sides(&mut sides);
    // The longest cut within the tolerance first, then halves of it while they cost less (a
    // longer transition is faster through the corner but replaces more of a faster neighbour):
    // so a larger tolerance, which admits every cut a smaller one did, does not keep a costlier
    // one among those it compares.
    let cost = |d: f64, h: &Hermite, v_max: f64| {
        // Faster than the slower neighbour, it runs at that one's speed (in its chain, or with
        // no room to ramp between): its time at the slowest of the three.
        let v = v_max.min(sides[0].v).min(sides[1].v);
        local_cost(d, h.length(), v, &sides)
    };
    let mut best: Option<(f64, f64, Hermite)> = None;
    for _ in 0..MAX_SHRINKS {
        if d.is_nan() || d <= MIN_LENGTH {
            break;
        }
        let a = jet_at(&held.piece, held.piece.length() - d);
        let b = jet_at(&next.piece, d);
        // Parameter speed 1 at both ends: λ is the cut length on both sides.
        let h = Hermite::new(a, b, 2.0 * d);
        let within = || lines || within_tolerance(&h, &held.last.source, &next.first.source, tol);
        match &best {
            None => {
                if within() {
                    let Some(v_max) = faster_than_a_stop(&h, feed, m) else {
                        break;
                    };
                    best = Some((cost(d, &h, v_max), d, h));
                }
                d *= SHRINK;
            }
            Some(b) => {
                let c = cost(d, &h, own_speed(&h, feed, m));
                if c >= b.0 - SAVING || !within() {
                    break;
                }
                best = Some((c, d, h));
                d *= COMPARE_SHRINK;
            }
        }
    }
    best.map(|(_, d, h)| (d, d, h, own_limits(&h, feed, m)))
}

/// Least saving (s) for which a shorter cut is taken: far below a tick, far above rounding (equal
/// costs keep the longer cut).
const SAVING: f64 = 1e-6;
/// Step between the cuts compared once one keeps the tolerance.
const COMPARE_SHRINK: f64 = 0.5;

/// A neighbour's own speed (its class: `piece_limits` on curves, the feed and eq. 11 on lines),
/// the limits and bands it ramps within, and its length.
struct Side {
    v: f64,
    top: Limits,
    bands: Bands,
    length: f64,
    curved: bool,
    feed: f64,
}

/// The side of a junction that `span` is (its limits computed once, kept on the span).
fn side(span: &mut Span, feed: f64, m: &Machine) -> Side {
    let piece = span.piece;
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
    }
}

/// Where the faster neighbour would join one chain with the slower (smooth.rs, `joined_loss`:
/// two curves of one feed), it runs at the slower one's speed: what a cut replaces of it then
/// runs no faster than the transition.
fn joined_sides(sides: &mut [Side; 2]) {
    let (slow, fast) = if sides[0].v <= sides[1].v { (0, 1) } else { (1, 0) };
    let (s, f) = (&sides[slow], &sides[fast]);
    if s.curved && f.curved && s.feed == f.feed && f.v > s.v {
        let ramps = (f.top, f.bands.clone());
        if joined_loss(0.0, (s.length, s.v), (f.length, f.v), &ramps).is_some() {
            sides[fast].v = sides[slow].v;
        }
    }
}

/// Time a transition of cut `d` (on both sides) and `length` at speed `v` adds to the corner: its
/// own run, less the stretches of the neighbours it replaces at their own speeds, plus what each
/// neighbour loses to the ramp between `v` and its own speed (the fastest within its limits and
/// bands, `scurve7_banded`, as far as its length reaches): T − D/v_side over the ramp.
fn local_cost(d: f64, length: f64, v: f64, sides: &[Side; 2]) -> f64 {
    let mut cost = length / v.max(f64::MIN_POSITIVE);
    for s in sides {
        let v_side = s.v.max(f64::MIN_POSITIVE);
        cost -= d / v_side;
        if v < v_side {
            let banded = Banded {
                kind: ProfileKind::Scurve7,
                top: &s.top,
                bands: &s.bands,
            };
            // Every ramp here rises from v (one forward envelope).
            let rise = scurve7_banded::Rise::from(&banded, v.max(0.0));
            let (mut t, mut x) = rise.time_distance(v_side);
            if x > s.length {
                (t, x) = rise.time_distance(rise.max_speed(s.length));
            }
            cost += t - x / v_side;
        }
    }
    cost
}

/// Every point of `h` within `tol` of one of the two programmed pieces: samples every λ/N,
/// each at most tol − σ_max·λ/(2N) away, where σ_max bounds |p'| — no point of the curve is
/// farther than σ_max·λ/(2N) from a sample.
fn within_tolerance(h: &Hermite, a: &Source, b: &Source, tol: f64) -> bool {
    let guard = h.speed_bound() * h.length() / (2.0 * DEVIATION_SAMPLES as f64);
    let bound = tol - guard;
    (0..=DEVIATION_SAMPLES).all(|k| {
        let p = h.point(h.length() * k as f64 / DEVIATION_SAMPLES as f64);
        // min(|pa|, |pb|) ≤ bound: the piece the sample starts nearer first (the other often
        // needs no distance).
        let (near, far) = if 2 * k <= DEVIATION_SAMPLES {
            (a, b)
        } else {
            (b, a)
        };
        near.distance(p) <= bound || far.distance(p) <= bound
    })
}
