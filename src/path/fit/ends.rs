//! How a span being fitted meets its neighbours (fit.rs): the corners at its run's ends, with
//! the span waiting for its junction before it and the move after, against those its first or
//! last line would make, and whether the run stands alone.

use super::baseline::{slower_between, slower_from_entry};
use super::{line_of, Fit};
use crate::config::Machine;
use crate::path::chain::{Curve, CurveLimits, Piece};
use crate::path::hermite::Hermite;
use crate::path::junction::{corner_ceiling, end_reach};
use crate::path::smooth::{joined, Move, SmoothBuilder, Span};

/// Share of a curve's top speed below which the ceiling of the corner a run enters at counts as
/// rest: a ramp from it covers about the length of one from rest (a fifth of the speed, a
/// twenty-fifth of the length). Of 12 000 random programs a larger tolerance lengthened 47 at
/// 0.1, 45 at 0.2 (a 0.49 mm line and a 0.07 mm one entering at 5 mm/s under a 25 mm/s curve).
const NEAR_REST: f64 = 0.2;
/// Share of its first line's corner ceiling (and of what the span before reaches) below which a
/// curve over a run's first two moves enters clearly more sharply (`slower_entry`). Without it,
/// curves within 0.02 % of the line's ceiling were dropped: a random program 0.8 % longer.
const SHARPER_ENTRY: f64 = 0.9;

impl SmoothBuilder {
    /// Whether the span waiting for its junction is a line: a span left straight.
    pub(super) fn line_waits(&self) -> bool {
        matches!(
            self.waiting.as_ref().map(|w| &w.piece.curve),
            Some(Curve::Line(_))
        )
    }

    /// Whether the span waiting is a line that starts at rest (nothing held before it): the
    /// first of a run left straight.
    pub(super) fn line_waits_from_rest(&self) -> bool {
        self.held.is_none() && self.line_waits()
    }

    /// Whether a curve over a run's first line, or its first two moves, turns more sharply from
    /// the span before than that line does (a lower `corner_ceiling`): it starts on the run's
    /// end circle, which stood for the whole run. A 0.54 mm line before a 9 µm hook and a
    /// corner, fitted alone at 3.9 times the tolerance, met the arc before it at 11.0 mm/s where
    /// the line meets it at 18.9 (+1.06 %); a 0.34 mm line and a 40 µm one after an arc, fitted
    /// as one curve at 1.08 times the tolerance, met it at 8.4 mm/s where the line meets it at
    /// 11.6 (+0.75 %; both in tests/monotone_found.rs). Not over more moves (LinuxCNC's
    /// random_lines_0.001in then lost curves over up to 38, +1.2 %, whose gains inside the
    /// corner speeds miss), except a whole run before a stop that is also slower from there to
    /// rest than its moves (`slower_from_entry`).
    pub(super) fn slower_entry(&self, span: Fit, h: &Hermite, own: &CurveLimits, m: &Machine) -> bool {
        let whole = span.stop_after && span.to == span.run.len();
        if span.from != 0 || span.run.len() < 2 || span.to > 2 && !whole {
            return false;
        }
        let Some([entry, straight]) = self.entry_ceilings(span, h, m) else {
            return false;
        };
        if span.to == 1 {
            return entry < straight;
        }
        // Over several moves, the lines may lose more at their own corners.
        if whole && entry < straight && slower_from_entry(span, h.length(), own, [entry, straight], m) {
            return true;
        }
        if span.to > 2 {
            return false;
        }
        // Over two moves, only where it enters clearly more sharply than the line and than the
        // span before reaches, and the lines pass their inner corner no slower than the curve
        // passes its slower end: it then gains nothing inside for what it loses there.
        let Some(before) = &self.waiting else {
            return false;
        };
        let pass = entry.min(span.far_corner(m));
        entry < SHARPER_ENTRY * straight
            && (1..span.to).all(|k| span.vertices.corner_speed(span.run, k, m) >= pass)
            && entry < SHARPER_ENTRY * end_reach(before, m)
    }

    /// Whether the curve over several moves at an end of its run is slower than its lines
    /// between the corners at its ends (`slower_between`): the run's corners with its neighbours
    /// where it ends the run (their ceilings, `entry_ceilings` and `exit_ceilings`), else the
    /// vertex's corner between its lines. Only at a run's end: asked of every span over several
    /// moves it gave the same rates, and 3D_Chips +0.31 % at jerk 5e4 and +4.1 % instructions on
    /// the CAM-like 10 k lines.
    pub(super) fn slower_between_corners(
        &self,
        span: Fit,
        h: &Hermite,
        own: &CurveLimits,
        m: &Machine,
    ) -> bool {
        let inner = |k: usize| Some([span.vertices.corner_speed(span.run, k, m); 2]);
        let entry = match span.from {
            0 => self.entry_ceilings(span, h, m),
            k => inner(k),
        };
        let exit = match span.to {
            k if k == span.run.len() => exit_ceilings(span, h, m),
            k => inner(k),
        };
        entry
            .zip(exit)
            .is_some_and(|(a, b)| slower_between(span, h, own, [a, b], m))
    }

    /// The ceilings of the corner before the run's span `span` from 0 (as `junction` estimates
    /// it; none where the span continues the one before) with the curve `h` and with its first
    /// line; `None` after a stop.
    fn entry_ceilings(&self, span: Fit, h: &Hermite, m: &Machine) -> Option<[f64; 2]> {
        let first = span.run[0];
        let moves = &span.run[span.from..span.to];
        let curve = Span::fitted(Piece::whole(Curve::Hermite(*h), first.line), moves);
        let straight = Span::single(Curve::Line(line_of(&first)), first);
        Some([self.entry_ceiling(&curve, m)?, self.entry_ceiling(&straight, m)?])
    }

    /// Whether the moves, the whole run, stand alone: from rest after a stop, or entering at a
    /// corner they nearly stop at (`enters_near_rest`) where they pass every corner between them
    /// at the curve's top speed `class`. Two lines between a 10 µm arc (a 1.4 mm/s corner) and
    /// a reversal, fitted as one curve from rest to rest, took 0.204 s where the lines through
    /// their 23.4 mm/s corner take 0.187 (+0.46 %, tests/monotone_found/fit.rs).
    pub(super) fn stands_alone(&self, span: Fit, class: f64, m: &Machine) -> bool {
        span.to - span.from > 1
            && span.from == 0
            && span.to == span.run.len()
            && (self.at_rest()
                || span.passes_corners(class, m) && self.enters_near_rest(span.run[0], class, m))
    }

    /// Whether the run's first move meets the span waiting at a corner whose ceiling is under
    /// `NEAR_REST` of `class` (a reversal, a corner too tight to cut): the run then starts
    /// about as from rest.
    fn enters_near_rest(&self, first: Move, class: f64, m: &Machine) -> bool {
        let straight = Span::single(Curve::Line(line_of(&first)), first);
        self.entry_ceiling(&straight, m)
            .is_some_and(|v| v < NEAR_REST * class)
    }

    /// The ceiling of the corner between the span waiting and `next`, as `junction` estimates
    /// it: infinite where `next` continues that span, none where nothing waits.
    fn entry_ceiling(&self, next: &Span, m: &Machine) -> Option<f64> {
        let before = self.waiting.as_ref()?;
        if joined(before, next) {
            return Some(f64::INFINITY);
        }
        let shared = self.held.as_ref().is_some_and(|held| !joined(held, before));
        Some(corner_ceiling(before, next, shared, m))
    }
}

/// The ceilings of the corner after the run (`corner_ceiling`) with the curve `h` and with its
/// last line; rest before a stop, `None` where the move after is not known.
pub(super) fn exit_ceilings(span: Fit, h: &Hermite, m: &Machine) -> Option<[f64; 2]> {
    if span.stop_after {
        return Some([0.0; 2]);
    }
    let next = span.after?;
    let after = Span::programmed(*next);
    let moves = &span.run[span.from..span.to];
    let last = moves[moves.len() - 1];
    let curve = Span::fitted(Piece::whole(Curve::Hermite(*h), moves[0].line), moves);
    let straight = Span::single(Curve::Line(line_of(&last)), last);
    Some([
        corner_ceiling(&curve, &after, true, m),
        corner_ceiling(&straight, &after, true, m),
    ])
}
