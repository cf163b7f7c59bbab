//! The words of one line sorted by letter, each range-checked where it is read.

use super::{offsets::Extra, Reader};
use crate::error::ProgramError;
use crate::gcode::check;
use crate::gcode::words::Word;

/// A word's value and column.
pub type Located = Option<(f64, u32)>;

/// Axis, centre, R, P and the tool / G10 words of a line.
#[derive(Default)]
pub(super) struct LineWords {
    pub axes: [Located; 3],
    pub ijk: [Located; 3],
    pub r: Located,
    pub p: Located,
    pub extra: Extra,
    /// F in G93 (per minute), applied to the line's move.
    pub f: Located,
}

impl Reader {
    /// Sort the words of a line; F is applied at once (G94: units per minute).
    pub(super) fn read_words(&mut self, line: u32, words: &[Word]) -> Result<LineWords, ProgramError> {
        let mut out = LineWords::default();
        let LineWords {
            axes,
            ijk,
            r,
            p,
            extra,
            f,
        } = &mut out;
        for w in words {
            let v = w.value;
            let located = |m: String| self.error(line, w.col, m);
            match w.letter {
                b'X' | b'Y' | b'Z' => {
                    let i = (w.letter - b'X') as usize;
                    if axes[i].is_some() {
                        return Err(self.error(line, w.col, format!("{} given twice", w.letter as char)));
                    }
                    check::length(w.letter, v, self.unit).map_err(located)?;
                    axes[i] = Some((v, w.col));
                }
                b'I' | b'J' | b'K' | b'R' => {
                    check::length(w.letter, v, self.unit).map_err(located)?;
                    match w.letter {
                        b'R' => *r = Some((v, w.col)),
                        l => ijk[(l - b'I') as usize] = Some((v, w.col)),
                    }
                }
                b'P' => *p = Some((v, w.col)),
                b'F' if self.inverse_time => {
                    // G93: moves per minute (the move takes 1/F minutes).
                    check::inverse_feed(v).map_err(located)?;
                    *f = Some((v, w.col));
                }
                b'F' => {
                    // G94: units per minute.
                    self.feed = check::feed(v, self.unit).map_err(located)?;
                }
                b'T' => extra.t = Some((v, w.col)),
                b'D' => extra.d = Some((v, w.col)),
                b'H' => extra.h = Some((v, w.col)),
                b'L' => extra.l = Some((v, w.col)),
                b'Q' => extra.q = Some((v, w.col)),
                b'G' | b'M' | b'N' | b'S' => {}
                b'A' | b'B' | b'C' | b'U' | b'V' | b'W' => {
                    let msg = format!(
                        "unsupported axis word {} (only X, Y, Z are machine axes)",
                        w.letter as char
                    );
                    return Err(self.error(line, w.col, msg));
                }
                other => {
                    let msg = format!("unsupported word {}", other as char);
                    return Err(self.error(line, w.col, msg));
                }
            }
        }
        Ok(out)
    }
}
