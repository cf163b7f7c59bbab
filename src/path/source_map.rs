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
//!   symmetric about the bisector of the corner, at its middle.

use super::hermite::Hermite;
use super::smooth::Move;
use crate::geometry::Source;

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

/// Parameter of transition `h` where it passes from `a` (the move before) to `b` (the move
/// after): the middle of the sample interval where the samples turn nearer `b`, if every sample
/// before it is within `tol` − guard of `a` and every one after within `tol` − guard of `b`;
/// else, and between two lines (`symmetric`), the middle of the transition.
pub(super) fn switch(h: &Hermite, a: &Source, b: &Source, tol: f64, symmetric: bool) -> f64 {
    let middle = 0.5 * h.length();
    if symmetric {
        return middle;
    }
    let step = h.length() / SAMPLES as f64;
    let guard = h.speed_bound() * step / 2.0;
    let points: [_; SAMPLES + 1] = std::array::from_fn(|k| h.point(step * k as f64));
    let db = points.map(|p| b.distance(p));
    // The distances to `a` up to where the samples turn nearer `b` (the rest only if needed:
    // the switch is valid there on every transition but a few).
    let mut da = [f64::NAN; SAMPLES + 1];
    let mut turn = None;
    for k in 0..=SAMPLES {
        da[k] = a.distance(points[k]);
        if db[k] < da[k] {
            turn = Some(k);
            break;
        }
    }
    let nearer_b = turn.unwrap_or(SAMPLES).max(1);
    let valid = |da: &[f64], k: usize| {
        da[..k].iter().all(|&d| d <= tol - guard) && db[k..].iter().all(|&d| d <= tol - guard)
    };
    let k = if valid(&da, nearer_b) {
        Some(nearer_b)
    } else {
        for k in turn.map_or(SAMPLES + 1, |k| k + 1)..=SAMPLES {
            da[k] = a.distance(points[k]);
        }
        (1..=SAMPLES).find(|&k| valid(&da, k))
    };
    k.map_or(middle, |k| step * (k as f64 - 0.5))
}
