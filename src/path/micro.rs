//! Sub-tolerance moves in the `smooth` mode. A line shorter than `MICRO_SHARE` of the path
//! tolerance (a CAM rounding jog, a repeated point) is not run as a piece of its own: its turns,
//! often sharp, would need transitions a few nanometres long — in effect a stop. The next line
//! starts where the tiny moves began instead. Each of its points is then at most the tiny moves'
//! length from the programmed line (the two lines share their end; the starts differ by that
//! much), so its tolerance is lowered by that length and every tick stays within the programmed
//! tolerance. Where no line follows (an arc, an exact-stop move, a stop or the program's end),
//! the line before ends where the tiny moves end, by the same argument (smooth.rs,
//! `SmoothBuilder::end_last_at`); only where neither can take them do they run as one line.

use super::smooth::Move;
use crate::geometry::Line;
use crate::geometry::Source;
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Share of the tolerance that the tiny moves absorbed into one line may add up to.
const MICRO_SHARE: f64 = 0.1;

/// Tiny line moves held until the next line absorbs them.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize)]
pub struct MicroMoves {
    pending: Option<Tiny>,
}

/// Tiny moves held, or taken from the hold (`MicroMoves::flush`).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Tiny {
    /// Where the first tiny move began (the end of the last move run) and the last one ends.
    pub start: Vec3,
    end: Vec3,
    /// The last tiny move, as programmed.
    last: Move,
    /// Their length added up.
    absorbed: f64,
}

/// Whether a line of tolerance `tolerance` may take tiny moves of length `absorbed`.
fn fits(absorbed: f64, tolerance: f64) -> bool {
    absorbed <= MICRO_SHARE * tolerance
}

/// `mv` as the line from `start` to `end`, taking tiny moves of length `absorbed`: each of its
/// points lies at most that far from one of `mv`'s, so its tolerance is lowered by that.
fn line_taking(mv: &Move, start: Vec3, end: Vec3, absorbed: f64) -> Move {
    Move {
        source: Source::Line(Line { start, end }),
        tolerance: mv.tolerance - absorbed,
        absorbed: mv.absorbed + absorbed,
        ..*mv
    }
}

impl MicroMoves {
    /// A restored run of tiny moves: its points in range, its moves checked.
    pub fn check_state(&self) -> Result<(), String> {
        use crate::valid::{point, within, MAX_POSITION_M};
        let Some(p) = &self.pending else { return Ok(()) };
        point("tiny move start", p.start, MAX_POSITION_M)?;
        point("tiny move end", p.end, MAX_POSITION_M)?;
        within("tiny moves' length", p.absorbed, 0.0, MAX_POSITION_M)?;
        super::check::programmed(&p.last)
    }

    /// Whether the held tiny moves must run (`flush`) before `mv`: it is not a line that takes
    /// them (an arc, an exact-stop move, or one whose tolerance is too small for them).
    pub fn held_before(&self, mv: &Move) -> bool {
        self.pending.is_some_and(|p| {
            !matches!(mv.source, Source::Line(_)) || mv.exact || !fits(p.absorbed, mv.tolerance)
        })
    }

    /// The move to run for `mv` (after `held_before`'s tiny moves have run): none while it is
    /// held as tiny; otherwise `mv`, its start moved back over the held moves.
    pub fn take(&mut self, mv: Move) -> Option<Move> {
        let Source::Line(line) = mv.source else {
            return Some(mv);
        };
        let absorbed = self.pending.map_or(0.0, |p| p.absorbed);
        let total = absorbed + line.length();
        if !mv.exact && fits(total, mv.tolerance) {
            let start = self.pending.map_or(line.start, |p| p.start);
            self.pending = Some(Tiny {
                start,
                end: line.end,
                last: mv,
                absorbed: total,
            });
            return None;
        }
        let Some(p) = self.pending.take() else {
            return Some(mv);
        };
        debug_assert!(
            !mv.exact && fits(p.absorbed, mv.tolerance),
            "held_before ran them"
        );
        Some(line_taking(&mv, p.start, line.end, p.absorbed))
    }

    /// The held tiny moves (before a stop, an arc, an exact-stop move or the end), so that the
    /// programmed end point is reached: the line before may end where they end, else they run
    /// as one line.
    pub fn flush(&mut self) -> Option<Tiny> {
        self.pending.take()
    }
}

impl Tiny {
    /// Whether a line of tolerance `tolerance` may take them (`MICRO_SHARE` of it).
    pub fn fits(&self, tolerance: f64) -> bool {
        fits(self.absorbed, tolerance)
    }

    /// The tiny moves as one line, its tolerance lowered by their length (a line of them, not
    /// one that took them).
    pub fn line(&self) -> Move {
        Move {
            absorbed: 0.0,
            ..line_taking(&self.last, self.start, self.end, self.absorbed)
        }
    }

    /// The line `before` them, from `start`, ending where they end (it takes them).
    pub fn ending(&self, before: &Move, start: Vec3) -> Move {
        line_taking(before, start, self.end, self.absorbed)
    }
}
