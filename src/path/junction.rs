//! Stage 2 of the `smooth` corner mode (smooth.rs): the transition at a junction of two pieces
//! that do not meet with equal first and second derivatives — a quintic Hermite (hermite.rs;
//! eq. 45–52 between two lines) from a cut d on each side, d from eq. 52's apex at the tolerance,
//! shrunk until the transition keeps the tolerance, or None (a stop at the corner).

use super::chain::Curve;
use super::chain::{piece_limits, CurveLimits};
use super::hermite::Hermite;
use super::slowest_axis;
use super::smooth::{jet_at, Span};
use super::tolerance::{MIN_LENGTH, REVERSAL_COS};
use crate::config::Machine;
use crate::feed::{scurve7, BlockRequest, FeedLaw};
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
fn faster_than_a_stop(h: &Hermite, feed: f64, m: &Machine) -> Option<CurveLimits> {
    let mut cells = Vec::new();
    h.cells(|c| cells.push(c));
    let limits = piece_limits(&cells, feed / h.speed_bound().max(1.0), m);
    let t_stop = scurve7::plan(&BlockRequest {
        length: h.length(),
        v_in: 0.0,
        v_out: 0.0,
        v_feed: feed,
        limits: slowest_axis(m, feed),
    })
    .duration();
    (h.length() <= limits.limits.v_max * t_stop).then_some(limits)
}

/// The transition between `held` and `next`: the cuts on both sides and the curve, or None
/// (stop) at a reversal or when no cut keeps the tolerance.
pub(super) fn transition(held: &Span, next: &Span, m: &Machine) -> Option<(f64, f64, Hermite, CurveLimits)> {
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
    for _ in 0..MAX_SHRINKS {
        if d.is_nan() || d <= MIN_LENGTH {
            return None;
        }
        let a = jet_at(&held.piece, held.piece.length() - d);
        let b = jet_at(&next.piece, d);
        // Parameter speed 1 at both ends: λ is the cut length on both sides.
        let h = Hermite::new(a, b, 2.0 * d);
        if lines || within_tolerance(&h, &held.last.source, &next.first.source, tol) {
            let feed = held.last.feed.min(next.first.feed);
            return faster_than_a_stop(&h, feed, m).map(|limits| (d, d, h, limits));
        }
        d *= SHRINK;
    }
    None
}

/// Every point of `h` within `tol` of one of the two programmed pieces: samples every λ/N,
/// each at most tol − σ_max·λ/(2N) away, where σ_max bounds |p'| — no point of the curve is
/// farther than σ_max·λ/(2N) from a sample.
fn within_tolerance(h: &Hermite, a: &Source, b: &Source, tol: f64) -> bool {
    let guard = h.speed_bound() * h.length() / (2.0 * DEVIATION_SAMPLES as f64);
    (0..=DEVIATION_SAMPLES).all(|k| {
        let p = h.eval(h.length() * k as f64 / DEVIATION_SAMPLES as f64).p;
        a.distance(p).min(b.distance(p)) <= tol - guard
    })
}
