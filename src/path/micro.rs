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
    pending: Option<Pending>,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
struct Pending {
    /// Where the first tiny move began (the end of the last move run) and the last one ends.
    start: Vec3,
    end: Vec3,
    /// The last tiny move, as programmed.
    last: Move,
    /// Their length added up.
    absorbed: f64,
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
            !matches!(mv.source, Source::Line(_)) || mv.exact || p.absorbed > MICRO_SHARE * mv.tolerance
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
        if !mv.exact && total <= MICRO_SHARE * mv.tolerance {
            let start = self.pending.map_or(line.start, |p| p.start);
            self.pending = Some(Pending {
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
            !mv.exact && p.absorbed <= MICRO_SHARE * mv.tolerance,
            "held_before ran them"
        );
        Some(Move {
            source: Source::Line(Line {
                start: p.start,
                end: line.end,
            }),
            tolerance: mv.tolerance - p.absorbed,
            ..mv
        })
    }

    /// The held tiny moves (before a stop, an arc, an exact-stop move or the end), so that the
    /// programmed end point is reached: the line before may end where they end, else they run
    /// as one line.
    pub fn flush(&mut self) -> Option<Tiny> {
        self.pending.take().map(|p| Tiny {
            start: p.start,
            end: p.end,
            absorbed: p.absorbed,
            last: p.last,
        })
    }
}

/// Tiny moves taken from the hold: where they start and end, their length, and the last of
/// them as programmed.
#[derive(Clone, Copy, Debug)]
pub struct Tiny {
    pub start: Vec3,
    pub end: Vec3,
    pub absorbed: f64,
    last: Move,
}

impl Tiny {
    /// Whether a line of tolerance `tolerance` may take them (`MICRO_SHARE` of it).
    pub fn fits(&self, tolerance: f64) -> bool {
        self.absorbed <= MICRO_SHARE * tolerance
    }

    /// The tiny moves as one line, its tolerance lowered by their length.
    pub fn line(&self) -> Move {
        Move {
            source: Source::Line(Line {
                start: self.start,
                end: self.end,
            }),
            tolerance: self.last.tolerance - self.absorbed,
            ..self.last
        }
    }
}
