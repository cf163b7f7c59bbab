//! The program line a tick reports (the CSV `line`, the FMU's `status.line`) is the block whose
//! programmed geometry the tool is on. In the smooth mode one piece may stand for several moves:
//! a span fitted over a run of short moves, a transition between two moves. These functions say
//! where along such a piece each source block begins (chain.rs keeps the marks), so that every
//! point lies within the tolerance of its reported block's programmed geometry:
//! - a span fitted over moves m_0 … m_n (smooth.rs `fit`) is checked chord by chord: the curve over
//!   u ∈ [U_k, U_k + |m_k|], U_k = Σ_{i<k} |m_i|, lies within the tolerance of m_k's chord, so
//!   m_k begins at U_k;
//! - a transition passes from the move before it to the move after it where the samples of its
//!   tolerance check (each keeping the half-steps about it within the tolerance of one of the
//!   two, cover.rs) turn nearer the second; between two lines, whose transition is symmetric
//!   about the bisector of the corner, at its middle;
//! - where the programmed geometry on one side of a transition is several moves that continue
//!   one line (fit.rs `continues`), each point of the transition on that side reports the move
//!   its foot on the line lies in: the point is within the tolerance of the line, so of that
//!   move.

use super::cover::{lead, Guards, Leads, Sample, UNMEASURED};
use super::hermite::Hermite;
use super::smooth::{programmed, start_of, Move};
use super::tolerance::{FOOT_BISECTIONS, TRANSITION_SAMPLES};
use crate::geometry::{dot, sub, unit, Source};

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
/// (increasing u). It replaces the end of the moves `before` it and the start of those `after`
/// it (in path order). Between two lines (`symmetric`: a move or the moves of one line on each
/// side), each half is within the tolerance of its line: the first half reports the moves before,
/// the second those after, along each line as the foot of its points. Otherwise each sample of
/// the tolerance check reports the nearest move from the last one's on (`nearest_onwards`), or,
/// where that leaves a sample out of reach of its move, the moves in reach in path order
/// (`in_reach`); the report changes halfway between samples: the half-steps about a sample keep
/// the tolerance of the move it reports (cover.rs). `leads`: the distances the cut search's
/// tolerance check measured on `h` (the same samples), taken rather than measured again.
pub(super) fn transition_marks(
    h: &Hermite,
    before: &[Move],
    after: &[Move],
    symmetric: bool,
    leads: &Leads,
) -> (u32, Vec<(f64, u32)>) {
    let mut marks = Vec::new();
    if symmetric {
        let middle = 0.5 * h.length();
        let own = along(h, before, 0.0, middle, &mut marks);
        let mut later = Vec::new();
        let at_middle = along(h, after, middle, h.length(), &mut later);
        marks.push((middle, at_middle));
        marks.extend(later);
        return (own, marks);
    }
    let moves: Vec<&Move> = before.iter().chain(after).collect();
    let g = Guards::of(h);
    let distances = Distances {
        moves: &moves,
        before: before.len(),
        leads,
    };
    let (own, marks, held) = nearest_onwards(h, &distances, &g);
    if held {
        return (own, marks);
    }
    // Reporting the nearest move onwards left a sample with a move it is not within the
    // tolerance of (the path folds back: a later move passed near an earlier stretch, and the
    // report cannot go back).
    in_reach(h, &moves, &g).unwrap_or((own, marks))
}

/// Each sample of `h` reports the nearest of `moves` from the last one's on (or stays where
/// that is out of reach and the last is not); the report changes halfway between samples. Also
/// whether every sample keeps the half-steps about it within the tolerance of the move it
/// reports (cover.rs).
fn nearest_onwards(h: &Hermite, ds: &Distances, g: &Guards) -> (u32, Vec<(f64, u32)>, bool) {
    let moves = ds.moves;
    let (mut at, mut own, mut marks, mut held) = (0, moves[0].line, Vec::new(), true);
    for k in 0..=TRANSITION_SAMPLES {
        let mut s = Lazy { g, h, k, s: None };
        // The nearest move from `at` on (the first of equals), and the distance to `at`'s.
        // Alone from `at` on, its distance is only held to the tolerance: an unmeasured lead
        // holds as it did (`UNMEASURED`).
        let d0 = ds.of(at, &mut s, moves.len() - at == 1);
        let (mut j, mut dj) = (0, d0);
        for i in 1..moves.len() - at {
            let d = ds.of(at + i, &mut s, false);
            if d < dj {
                (j, dj) = (i, d);
            }
        }
        let d_at = if j > 0 && (s.holds(moves[at + j], dj) || !s.holds(moves[at], d0)) {
            at += j;
            if k > 0 {
                marks.push((g.step * (k as f64 - 0.5), moves[at].line));
            }
            dj
        } else {
            d0
        };
        held &= s.holds(moves[at], d_at);
        if k == 0 {
            own = moves[at].line;
        }
    }
    (own, marks, held)
}

/// Sample k of a transition, its point evaluated only where a distance or the finer guard needs
/// it: the lead move's distance is the tolerance check's, and most samples hold by the sample
/// guard alone (past the middle, mostly all a sample needs).
struct Lazy<'a> {
    g: &'a Guards,
    h: &'a Hermite,
    k: usize,
    s: Option<Sample<'a>>,
}

impl<'a> Lazy<'a> {
    fn get(&mut self) -> &Sample<'a> {
        let (g, h, k) = (self.g, self.h, self.k);
        self.s.get_or_insert_with(|| g.sample(h, k))
    }

    /// `Guards::holds`, the sample taken only where the sample guard alone does not hold.
    fn holds(&mut self, mv: &Move, d: f64) -> bool {
        self.g.by_speed(mv, d) || self.g.by_growth(mv, self.get(), d)
    }
}

/// The moves a transition replaces (those before it, then those after) and the distances to
/// them its tolerance check measured (`Leads`).
struct Distances<'a> {
    moves: &'a [&'a Move],
    before: usize,
    leads: &'a Leads,
}

impl Distances<'_> {
    /// The distance from sample `s` to move i: the tolerance check's where it measured it, the
    /// same value; `UNMEASURED` where it was not and `held_only` (only held to the tolerance).
    fn of(&self, i: usize, s: &mut Lazy, held_only: bool) -> f64 {
        match self.leads {
            Some(leads)
                if i == lead(s.k, self.before, self.moves.len() - self.before)
                    && (held_only || leads[s.k] != UNMEASURED) =>
            {
                leads[s.k]
            }
            _ => self.moves[i].source.distance(s.get().p),
        }
    }
}

/// The reports where each sample of `h` reports a move it keeps the half-steps about it within
/// the tolerance of, in path order (a sample never reports a move before the last one's), the
/// distances summed over the samples least: a shortest path over (sample, move), each move
/// reachable from the best of those at or before it one sample back. None where there is no
/// such order.
fn in_reach(h: &Hermite, moves: &[&Move], g: &Guards) -> Option<(u32, Vec<(f64, u32)>)> {
    let n = moves.len();
    let mut cost = vec![0.0; n];
    let mut back = Vec::with_capacity(TRANSITION_SAMPLES + 1);
    for k in 0..=TRANSITION_SAMPLES {
        let s = g.sample(h, k);
        let (mut next, mut from) = (vec![f64::INFINITY; n], vec![0; n]);
        let (mut best, mut best_at) = (f64::INFINITY, 0);
        for (i, mv) in moves.iter().enumerate() {
            if cost[i] < best {
                (best, best_at) = (cost[i], i);
            }
            let d = mv.source.distance(s.p);
            if g.holds(mv, &s, d) && best.is_finite() {
                (next[i], from[i]) = (best + d, best_at);
            }
        }
        cost = next;
        back.push(from);
    }
    let (mut i, total) = cost
        .iter()
        .enumerate()
        .fold((0, f64::INFINITY), |m, (i, &c)| if c < m.1 { (i, c) } else { m });
    if !total.is_finite() {
        return None;
    }
    let mut reported = vec![0; TRANSITION_SAMPLES + 1];
    for k in (0..=TRANSITION_SAMPLES).rev() {
        reported[k] = i;
        i = back[k][i];
    }
    let marks = (1..=TRANSITION_SAMPLES)
        .filter(|&k| reported[k] != reported[k - 1])
        .map(|k| (g.step * (k as f64 - 0.5), moves[reported[k]].line))
        .collect();
    Some((moves[reported[0]].line, marks))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Line;
    use crate::path::hermite::Jet;

    fn line(start: [f64; 3], end: [f64; 3], line: u32) -> Move {
        Move {
            source: Source::Line(Line { start, end }),
            line,
            feed: 0.05,
            tolerance: 0.01,
            exact: false,
            absorbed: 0.0,
        }
    }

    /// A path that folds back: the third move ends 4 µm beside the first one's start, where a
    /// transition along the first move begins. Its first sample is nearest the third move, so
    /// reporting the nearest move onwards leaves the rest of the transition (up to 0.35 away
    /// from it) on the third; the moves in reach in path order keep it on the first, within
    /// 3.5 µm of every sample.
    #[test]
    fn a_path_folding_back_reports_the_moves_in_reach() {
        let moves = [
            line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 10),
            line([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], 11),
            line([1.0, 1.0, 0.0], [0.0, 0.004, 0.0], 12),
        ];
        let jet = |p| Jet {
            p,
            d1: [1.0, 0.0, 0.0],
            d2: [0.0; 3],
        };
        let h = Hermite::new(jet([0.001, 0.0035, 0.0]), jet([0.5, 0.0, 0.0]), 0.5);
        let all: Vec<&Move> = moves.iter().collect();
        let ds = Distances {
            moves: &all,
            before: 1,
            leads: &None,
        };
        let (own, _, held) = nearest_onwards(&h, &ds, &Guards::of(&h));
        assert_eq!((own, held), (12, false));
        assert_eq!(
            transition_marks(&h, &moves[..1], &moves[1..], false, &None),
            (10, vec![])
        );
    }
}
