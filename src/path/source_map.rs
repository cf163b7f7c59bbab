//! The program line a tick reports (the CSV `line`, the FMU's `status.line`) is the block whose
//! programmed geometry the tool is on. In the smooth mode one piece may stand for several moves:
//! a span fitted over a run of short moves, a transition between two moves. These functions say
//! where along such a piece each source block begins (chain.rs keeps the marks), so that every
//! point lies within the tolerance of its reported block's programmed geometry:
//! - a span fitted over moves m_0 … m_n (smooth.rs `fit`) is checked chord by chord: the curve over
//!   u ∈ [U_k, U_k + |m_k|], U_k = Σ_{i<k} |m_i|, lies within the tolerance of m_k's chord, so
//!   m_k begins at U_k;
//! - a transition passes from the move before it to the move after it where the samples of its
//!   tolerance check (each within tol − guard of one of the two, no point farther than the guard
//!   from the nearest sample) turn nearer the second; between two lines, whose transition is
//!   symmetric about the bisector of the corner, at its middle;
//! - where the programmed geometry on one side of a transition is several moves that continue
//!   one line (fit.rs `continues`), each point of the transition on that side reports the move
//!   its foot on the line lies in: the point is within the tolerance of the line, so of that
//!   move.

use super::hermite::Hermite;
use super::smooth::{programmed, start_of, Move};
use super::tolerance::FOOT_BISECTIONS;
use crate::geometry::{dot, sub, unit, Source};

/// Samples of a transition (as its tolerance check, junction.rs).
const SAMPLES: usize = 64;

/// Where each move after the first begins on the span fitted over `moves` (its parameter u).
pub(super) fn span_marks(moves: &[Move]) -> Vec<(f64, u32)> {
    let mut u = 0.0;
    let mut marks = Vec::with_capacity(moves.len().saturating_sub(1));
    for pair in moves.windows(2) {
        u += pair[0].source.length();
        marks.push((u, pair[1].line));
    }
    marks
}

/// The lines transition `h` reports: the block at its start, and where each later one begins
/// (increasing u). It passes from the moves before it (`before`, in order: one move, or moves
/// of one line) to those after it (`after`) at `switch`.
pub(super) fn transition_marks(
    h: &Hermite,
    before: &[Move],
    after: &[Move],
    tol: f64,
    symmetric: bool,
) -> (u32, Vec<(f64, u32)>) {
    let u_switch = switch(h, &programmed(before), &programmed(after), tol, symmetric);
    let mut marks = Vec::new();
    let own = along(h, before, 0.0, u_switch, &mut marks);
    let mut later = Vec::new();
    let at_switch = along(h, after, u_switch, h.length(), &mut later);
    marks.push((u_switch, at_switch));
    marks.extend(later);
    (own, marks)
}

/// For u in [u0, u1] on `h`, near the line of `moves`: the move the foot of h(u0) on the line
/// lies in, and a mark where the foot passes into each later move (bisection: on either part
/// of a transition the foot moves forward along the line, the curve turning less than a right
/// angle from it there).
fn along(h: &Hermite, moves: &[Move], u0: f64, u1: f64, marks: &mut Vec<(f64, u32)>) -> u32 {
    let last = moves[moves.len() - 1];
    if moves.len() == 1 {
        return last.line;
    }
    let Source::Line(line) = programmed(moves) else {
        return last.line;
    };
    let (start, dir) = (start_of(&moves[0]), unit(sub(line.end, line.start)));
    let foot = |u: f64| dot(sub(h.point(u), start), dir);
    let (foot0, foot1) = (foot(u0), foot(u1));
    let mut end = 0.0;
    let mut at_u0 = None;
    for pair in moves.windows(2) {
        end += pair[0].source.length();
        if foot0 >= end {
            continue;
        }
        at_u0.get_or_insert(pair[0].line);
        if foot1 <= end {
            break;
        }
        let (mut lo, mut hi) = (u0, u1);
        for _ in 0..FOOT_BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if foot(mid) < end {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        marks.push((hi, pair[1].line));
    }
    at_u0.unwrap_or(last.line)
}

/// Parameter of transition `h` where it passes from `a` (the move before) to `b` (the move
/// after): the middle of the sample interval where the samples turn nearer `b`, if every sample
/// before it is within `tol` − guard of `a` and every one after within `tol` − guard of `b`;
/// else, and between two lines (`symmetric`), the middle of the transition.
fn switch(h: &Hermite, a: &Source, b: &Source, tol: f64, symmetric: bool) -> f64 {
    let middle = 0.5 * h.length();
    if symmetric {
        return middle;
    }
    let step = h.length() / SAMPLES as f64;
    let guard = h.speed_bound() * step / 2.0;
    let d: Vec<(f64, f64)> = (0..=SAMPLES)
        .map(|k| {
            let p = h.point(step * k as f64);
            (a.distance(p), b.distance(p))
        })
        .collect();
    let valid = |k: usize| {
        d[..k].iter().all(|&(da, _)| da <= tol - guard) && d[k..].iter().all(|&(_, db)| db <= tol - guard)
    };
    let nearer_b = d.iter().position(|&(da, db)| db < da).unwrap_or(SAMPLES).max(1);
    let k = if valid(nearer_b) {
        Some(nearer_b)
    } else {
        (1..=SAMPLES).find(|&k| valid(k))
    };
    k.map_or(middle, |k| step * (k as f64 - 0.5))
}
