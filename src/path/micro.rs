//! Sub-tolerance moves in the `smooth` mode. A line shorter than `MICRO_SHARE` of the path
//! tolerance (a CAM rounding jog, a repeated point) is not run as a piece of its own: its turns,
//! often sharp, would need transitions a few nanometres long — in effect a stop. The next line
//! starts where the tiny moves began instead. Each of its points is then at most the tiny moves'
//! length from the programmed line (the two lines share their end; the starts differ by that
//! much), so its tolerance is lowered by that length and every tick stays within the programmed
//! tolerance.

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

    /// The moves to run for `mv`, in order: none while it is held as tiny; otherwise `mv` (its
    /// start moved back over the held moves), or the held moves as one line and then `mv`.
    pub fn take(&mut self, mv: Move) -> [Option<Move>; 2] {
        let Source::Line(line) = mv.source else {
            return [self.flush(), Some(mv)];
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
            return [None, None];
        }
        match self.pending {
            Some(p) if !mv.exact && p.absorbed <= MICRO_SHARE * mv.tolerance => {
                self.pending = None;
                let source = Source::Line(Line {
                    start: p.start,
                    end: line.end,
                });
                let tolerance = mv.tolerance - p.absorbed;
                [
                    Some(Move {
                        source,
                        tolerance,
                        ..mv
                    }),
                    None,
                ]
            }
            _ => [self.flush(), Some(mv)],
        }
    }

    /// The held tiny moves as one line (before a stop, an arc, an exact-stop move or the end),
    /// so that the programmed end point is reached.
    pub fn flush(&mut self) -> Option<Move> {
        let p = self.pending.take()?;
        let source = Source::Line(Line {
            start: p.start,
            end: p.end,
        });
        let tolerance = p.last.tolerance - p.absorbed;
        Some(Move {
            source,
            tolerance,
            ..p.last
        })
    }
}
