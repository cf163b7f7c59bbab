//! The times a fitted curve is compared with (fit.rs): its moves from rest to rest, through
//! their corners, or between the transitions at a line's corners, and with the corner after the
//! run.

use super::{line_of, Fit};
use crate::config::Machine;
use crate::feed::{scurve7, scurve7_banded, BlockRequest, FeedLaw, Limits};
use crate::geometry::{add, scale, Line, Source};
use crate::path::chain::{Curve, CurveLimits, Piece};
use crate::path::hermite::Hermite;
use crate::path::junction::corner_ceiling;
use crate::path::smooth::{Move, Span, TIGHTER_RAMP};
use crate::path::{constant_speed_limit, line_limits};

/// How much slower than the lines through their corners (`slower_between`) a curve may be: short
/// lines between transitions run below the ceilings their corners promise. At 1.05, of 12 000
/// random programs a larger tolerance lengthened a new one by 0.6 %, where a curve estimated 6.7 %
/// slower than its lines had run faster; at 1.1 the found case was kept (its curve 8.1 % slower).
const BETWEEN_SLACK: f64 = 1.075;

/// Whether a curve of `length` and top speed `class` over one programmed line is slower than
/// that line run between the transitions at its corners, whose time is `line`
/// (`its_line_time`): the curve's time at its top speed is above the line's.
pub(super) fn slower_than_its_line(length: f64, class: f64, line: f64) -> bool {
    length > class * line
}

/// Over one programmed line, the time of its block from one corner's speed to the other's,
/// within its feed and limits: the speeds of the transitions at its corners where they lie
/// within the run, else the curve's top speed `class` (`None` where that is not solved yet).
/// `None` over several moves.
pub(super) fn its_line_time(span: Fit, class: Option<f64>, m: &Machine) -> Option<f64> {
    if span.to - span.from != 1 {
        return None;
    }
    let corner = |k: usize| {
        if k >= 1 && k < span.run.len() {
            Some(span.vertices.corner_speed(span.run, k, m))
        } else {
            class
        }
    };
    Some(line_time(
        &span.run[span.from],
        corner(span.from)?,
        corner(span.to)?,
        m,
    ))
}

/// Time of `moves` each run from rest to rest at its feed within its line's limits (the last to
/// `v_end`): a bound on the lines' time, corners and all. The tiny moves a line took (micro.rs)
/// count as they were programmed, so that a larger tolerance, which lets a line take more, does not
/// lower it: a 3 µm move before an arc, taken at 3.5 times the tolerance, left the baseline of the
/// curve over the moves before it without its stop: the curve was not kept, and the program ran
/// 2.3 % longer through the moves' sharp corner into the arc (tests/monotone_found.rs).
pub(super) fn stops_time(moves: &[Move], v_end: f64, m: &Machine) -> f64 {
    let n = moves.len();
    let end = |i: usize| if i + 1 == n { v_end } else { 0.0 };
    moves
        .iter()
        .enumerate()
        .map(|(i, mv)| line_time(mv, 0.0, end(i), m) + absorbed_time(mv, m))
        .sum()
}

/// The tiny moves `mv` took, from rest to rest along it as one line: what they add to the
/// moves' stops as programmed.
fn absorbed_time(mv: &Move, m: &Machine) -> f64 {
    if mv.absorbed <= 0.0 {
        return 0.0;
    }
    let l = line_of(mv);
    let end = add(l.start, scale(l.direction(), mv.absorbed));
    let tiny = Move {
        source: Source::Line(Line { start: l.start, end }),
        ..*mv
    };
    line_time(&tiny, 0.0, 0.0, m)
}

/// Time of the span's moves from rest through their corners to `v_end`: each corner at its
/// transition's ceiling (`corner_speed`) where that is at least `pass`, else a stop (a slower
/// transition's own ramps are not counted); each line within what it reaches from the speed
/// before it and to the speed after (a pass forward and one back).
pub(super) fn corners_time(span: Fit, pass: f64, v_end: f64, m: &Machine) -> f64 {
    corners_time_from(span, pass, [0.0, v_end], m)
}

/// `corners_time` from `v_in` (the first line's corner before) instead of rest.
fn corners_time_from(span: Fit, pass: f64, [v_in, v_end]: [f64; 2], m: &Machine) -> f64 {
    let moves = &span.run[span.from..span.to];
    let lines: Vec<Line> = moves.iter().map(line_of).collect();
    let limits: Vec<Limits> = lines.iter().map(|l| line_limits(l.direction(), m)).collect();
    let n = moves.len();
    let mut v = vec![0.0; n + 1];
    v[0] = v_in.min(line_speed(&moves[0], m));
    v[n] = v_end;
    for i in 1..n {
        let c = span.vertices.corner_speed(span.run, span.from + i, m);
        let reach = scurve7::max_exit(lines[i - 1].length(), v[i - 1], &limits[i - 1]);
        v[i] = if c >= pass {
            c.min(line_speed(&moves[i - 1], m))
                .min(line_speed(&moves[i], m))
                .min(reach)
        } else {
            0.0
        };
    }
    v[n] = v[n].min(scurve7::max_exit(lines[n - 1].length(), v[n - 1], &limits[n - 1]));
    for i in (0..n).rev() {
        v[i] = v[i].min(scurve7::max_entry(lines[i].length(), v[i + 1], &limits[i]));
    }
    (0..n).map(|i| line_time(&moves[i], v[i], v[i + 1], m)).sum()
}

/// The corner after the run where the curve, its last span, meets the line after it slower than
/// its last line would (each corner's ceiling as the junction's search starts,
/// `corner_ceiling`): the curve's speed there and the line's, and what the line after loses from
/// the curve's (its time from there to rest less its time from the line's). A curve's end
/// continues the circle through its last knots: beside a hook, its end tangent turns away from
/// its line, and the long line after it ran from 17.4 mm/s instead of 23.0 on a low-jerk axis
/// (+2.75 %, tests/monotone_found.rs). None where no line follows or the curve's corner is not
/// slower.
fn slower_exit(span: Fit, h: &Hermite, m: &Machine) -> Option<Exit> {
    let next = span.after.filter(|_| span.to == span.run.len())?;
    let Source::Line(line) = next.source else {
        return None;
    };
    let moves = &span.run[span.from..span.to];
    let last = moves[moves.len() - 1];
    let after = Span::single(Curve::Line(line), *next);
    let curve = Span::fitted(Piece::whole(Curve::Hermite(*h), moves[0].line), moves);
    let straight = Span::single(Curve::Line(line_of(&last)), last);
    let v_curve = corner_ceiling(&curve, &after, true, m);
    let v_line = corner_ceiling(&straight, &after, true, m);
    (v_curve < v_line).then(|| Exit {
        curve: v_curve,
        line: v_line,
        loss: line_time(next, v_curve, 0.0, m) - line_time(next, v_line, 0.0, m),
    })
}

/// Whether the curve, from rest to its corner with the line after the run (`slower_exit`) and
/// that line on to rest, is slower than its moves (`stops_time`, and where the run stands alone
/// `corners_time` through every corner that does not reverse) to the last line's corner and the
/// line after from there: as `slower_from_rest`, which it follows, with the corner after. Over
/// one line amid a run, against `TIGHTER_RAMP` times the moves' time.
pub(super) fn slower_to_exit(
    span: Fit,
    h: &Hermite,
    own: &CurveLimits,
    [rest_to_rest, alone]: [bool; 2],
    m: &Machine,
) -> bool {
    let Some(e) = slower_exit(span, h, m) else {
        return false;
    };
    let moves = &span.run[span.from..span.to];
    let mut lines = stops_time(moves, e.line, m);
    if alone {
        lines = lines.min(corners_time(span, 0.0, e.line, m));
    }
    if !rest_to_rest {
        lines *= TIGHTER_RAMP;
    }
    slower_from_rest(h.length(), own, e.curve, lines - e.loss)
}

/// A slower corner after a curve than after its last line (`slower_exit`).
#[derive(Clone, Copy)]
struct Exit {
    curve: f64,
    line: f64,
    loss: f64,
}

/// Whether a curve of `length` within its limits `own`, over several moves that start its run
/// and end it before a stop, is slower from its corner with the span before, `v_curve`, to rest
/// than its moves from theirs, `v_line`, through their corners (`corners_time`): as
/// `slower_to_exit` at the run's end. A 0.64 mm line and a 17 µm one (which took a 16 µm move at
/// 2.8 times the tolerance) ending a program, fitted as one curve, met the line before at
/// 9.4 mm/s where the line meets it at 11.4, and ran 0.66 mm at that speed (+0.64 %,
/// tests/monotone_found/fit.rs).
pub(super) fn slower_from_entry(
    span: Fit,
    length: f64,
    own: &CurveLimits,
    [v_curve, v_line]: [f64; 2],
    m: &Machine,
) -> bool {
    let b = own.banded();
    let curve = scurve7_banded::plan_time(&b, length, v_curve.min(own.class), 0.0, own.class).0;
    curve > corners_time_from(span, 0.0, [v_line, 0.0], m)
}

/// Whether a curve of `length` and top speed `class` is surely slower than its moves, whose
/// `stops_time` is `stops`: its time at that speed above theirs. A curve over a long move and a
/// short hook runs the whole move at the hook's speed (2.46 mm at 11 mm/s, where the line alone
/// runs at 109).
pub(super) fn slower_than_stops(length: f64, class: f64, stops: f64) -> bool {
    length > class * stops
}

/// Whether a curve of `length` within its limits `own` is slower from rest to rest (to `v_out`)
/// than its moves, whose `stops_time` is `stops` (as `slower_than_stops`, with the curve's ramps: a
/// curve over a bend in a low-jerk axis may not reach its top speed in its length). Asked of every
/// curve over several moves since a span may use the whole tolerance: a 2.46 mm line and the 0.26
/// mm hook before it, fitted as one curve at 33 mm/s whose top band leaves 0.4 mm/s², ran 0.36 s
/// from rest to rest against its moves' 0.27 s (tests/monotone_found.rs). Over one line, against
/// `TIGHTER_RAMP` times its line's: that 2.46 mm line, fitted alone once the hook after it was
/// taken into it (micro.rs), had a top speed of 32 mm/s but ran at 12 where the line reaches 35.
pub(super) fn slower_from_rest(length: f64, own: &CurveLimits, v_out: f64, stops: f64) -> bool {
    let v_out = v_out.min(own.class);
    // Planned within its tightest pair throughout, to the same end speed, the curve takes at
    // least as long as within its bands (each allows that pair): where even that is not slower,
    // they need not be planned.
    let tightest = scurve7::plan(&BlockRequest {
        length,
        v_in: 0.0,
        v_out,
        v_feed: own.class,
        limits: own.bands.pair_range(&own.limits).0,
    });
    if tightest.duration() <= stops {
        return false;
    }
    let b = own.banded();
    let curve = scurve7_banded::plan_time(&b, length, 0.0, v_out, own.class).0;
    curve > stops
}

/// Time of the line of `mv` as one block from `v_in` to `v_out`, each at most its own speed
/// (its feed and eq. 11), within its axis limits.
fn line_time(mv: &Move, v_in: f64, v_out: f64, m: &Machine) -> f64 {
    let l = line_of(mv);
    let v_feed = line_speed(mv, m);
    scurve7::plan(&BlockRequest {
        length: l.length(),
        v_in: v_in.min(v_feed),
        v_out: v_out.min(v_feed),
        v_feed,
        limits: line_limits(l.direction(), m),
    })
    .duration()
}

/// The own speed of the line of `mv`: its feed, within eq. 11.
fn line_speed(mv: &Move, m: &Machine) -> f64 {
    constant_speed_limit(&Curve::Line(line_of(mv)).derivative_bounds(), m).min(mv.feed)
}

/// Whether a curve over several moves, from the speed at its start to the speed at its end
/// (`[v_in, v_out]`, each the curve's and its end line's), is more than `BETWEEN_SLACK` times
/// slower than its lines through their corners between the same ends' speeds (`corners_time`
/// from `v_in`). From rest to rest, the lines' stops counted where they pass their corners at
/// speed: three lines of 2.06 mm between two tiny arcs, fitted as one curve whose top band
/// leaves 6 mm/s² on Y's 369, ran 4.4 ms slower than the lines through their corners at 22 and
/// 25 mm/s (+2.6 %, tests/monotone_found.rs).
pub(super) fn slower_between(
    span: Fit,
    h: &Hermite,
    own: &CurveLimits,
    [[curve_in, line_in], [curve_out, line_out]]: [[f64; 2]; 2],
    m: &Machine,
) -> bool {
    let (length, class) = (h.length(), own.class);
    let (v_in, v_out) = (curve_in.min(class), curve_out.min(class));
    // Within its tightest pair throughout, from no faster ends, the curve takes at least as long
    // as within its bands: where even that is not slower, the bands need not be planned.
    let tight = own.bands.pair_range(&own.limits).0;
    let t_out = v_out.min(scurve7::max_exit(length, v_in, &tight));
    let t_in = v_in.min(scurve7::max_entry(length, t_out, &tight));
    let tightest = BlockRequest {
        length,
        v_in: t_in,
        v_out: t_out,
        v_feed: class,
        limits: tight,
    };
    let tightest = scurve7::plan(&tightest).duration();
    // The lines take at least their lengths at their own speeds.
    let moves = &span.run[span.from..span.to];
    let cruise: f64 = moves
        .iter()
        .map(|mv| mv.source.length() / line_speed(mv, m))
        .sum();
    if tightest <= BETWEEN_SLACK * cruise {
        return false;
    }
    let lines = BETWEEN_SLACK * corners_time_from(span, 0.0, [line_in, line_out], m);
    if tightest <= lines {
        return false;
    }
    let b = own.banded();
    let v_out = v_out.min(b.max_exit(length, v_in));
    let v_in = v_in.min(b.max_entry(length, v_out));
    scurve7_banded::plan_time(&b, length, v_in, v_out, class).0 > lines
}
