//! A corner's speed estimated without its cut search: the transition at the apex cut, for the
//! fit's baselines (`corner_speed`) and for the corner before it (`corner_ceiling`); and the
//! speed a span reaches at its end (`end_reach`).

use super::cost::side;
use super::{apex_cut, corner, cut_shape};
use crate::config::Machine;
use crate::feed::scurve7_banded::Rise;
use crate::geometry::{add, dot, norm, scale, sub, Line};
use crate::path::chain::Own;
use crate::path::hermite::{Hermite, Jet};
use crate::path::smooth::Span;
use crate::path::tolerance::{MIN_LENGTH, REVERSAL_COS};

/// The top speed of the transition the junction search starts from at a corner between two
/// programmed lines `before` and `after` (cut at the apex at `tol`, at most half the shorter
/// line, λ = 2d), 0 at a reversal or a corner too tight to cut: the speed at the corners of a
/// line that a fit replacing it is compared with (fit.rs).
pub(in crate::path) fn corner_speed(before: &Line, after: &Line, tol: f64, feed: f64, m: &Machine) -> f64 {
    let (t_in, t_out) = (before.direction(), after.direction());
    let w = norm(sub(t_out, t_in));
    if dot(t_in, t_out) < REVERSAL_COS {
        return 0.0;
    }
    let reach = 0.5 * before.length().min(after.length());
    let d = apex_cut(tol, w, 1.0).min(reach);
    if d <= MIN_LENGTH {
        return 0.0;
    }
    let corner = before.end;
    let jet = |p, t| Jet {
        p,
        d1: t,
        d2: [0.0; 3],
    };
    let shape = Hermite::unbounded(
        jet(sub(corner, scale(t_in, d)), t_in),
        jet(add(corner, scale(t_out, d)), t_out),
        2.0 * d,
    );
    Own::of_shape(&shape, feed, m).speed(m)
}

/// The ceiling of the speed of the transition between `held` and `next` as the search starts
/// (the apex cut at the tolerance within the reach, `Own::ceiling`; no tolerance check, no
/// budget solves): the speed `held` is taken to leave at when the corner before it is chosen.
/// An estimate: the search may take a shorter cut, or a stop. With `shared` (a corner at the
/// start of `held` too, not yet chosen), within the half of `held` that corner leaves it at
/// least: over its whole length the estimate grew with the tolerance while the corner before,
/// chosen against it, took more of the span (of 6000 random programs, a larger tolerance
/// lengthened 55 before, 48 since; tests/monotone_found.rs).
/// 0 at a reversal or a corner too tight to cut.
pub(in crate::path) fn corner_ceiling(held: &Span, next: &Span, shared: bool, m: &Machine) -> f64 {
    let Some((w, mut reach)) = corner(held, next) else {
        return 0.0;
    };
    if shared {
        reach = reach.min(0.5 * held.piece.length());
    }
    let d = apex_cut(held.last.tolerance, w, 1.0).min(reach);
    if d <= MIN_LENGTH {
        return 0.0;
    }
    let feed = held.last.feed.min(next.first.feed);
    Own::ceiling_of(&cut_shape(held, next, d, 1.0), feed, m)
}

/// The speed `held` reaches at its end: its own, within its rise from its entry over its length
/// (as the junction after it bounds that side).
pub(in crate::path) fn end_reach(held: &Span, m: &Machine) -> f64 {
    let s = side(&mut held.clone(), held.last.feed, m);
    match held.entry {
        Some(v) if v < s.v => {
            let b = s.banded();
            let mut slot = None;
            s.v.min(Rise::build_in(&mut slot, &b, v.max(0.0)).max_speed(s.length))
        }
        _ => s.v,
    }
}
