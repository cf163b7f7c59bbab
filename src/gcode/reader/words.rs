//! The words of one line sorted by letter, each range-checked where it is read.

use super::{offsets::Extra, Reader};
use crate::error::ProgramError;
use crate::gcode::check;
use crate::gcode::words::Word;

/// A word's value and column.
pub type Located = Option<(f64, u32)>;

/// Axis, polar, centre, R, P and the tool / G10 words of a line.
#[derive(Default)]
pub(super) struct LineWords {
    pub axes: [Located; 3],
    /// `@` distance and `^` angle (LinuxCNC "Polar Coordinates").
    pub polar: [Located; 2],
    pub ijk: [Located; 3],
    pub r: Located,
    pub p: Located,
    pub extra: Extra,
    /// F as written (G94 applies it at once; G93 to the line's move).
    pub f: Located,
}

impl LineWords {
    /// Whether the line has an axis or polar word.
    pub fn moves(&self) -> bool {
        self.axes.iter().any(Option::is_some) || self.polar.iter().any(Option::is_some)
    }

    /// Column of the first axis or polar word.
    pub fn first_axis(&self) -> Option<u32> {
        let first = |words: &[Located]| words.iter().flatten().map(|a| a.1).min();
        match (first(&self.axes), first(&self.polar)) {
            (Some(a), Some(p)) => Some(a.min(p)),
            (a, p) => a.or(p),
        }
    }
}

impl Reader {
    /// Sort the words of a line (each letter at most once, LinuxCNC's rule); F is applied at
    /// once in G94 (`f_unit` per minute), capped at the machine's largest feed. `out` starts empty.
    pub(super) fn read_words(
        &mut self,
        line: u32,
        words: &[Word],
        f_unit: f64,
        out: &mut LineWords,
    ) -> Result<(), ProgramError> {
        for w in words {
            let v = w.value;
            let located = |m: String| self.error(line, w.col, m);
            let slot = match w.letter {
                b'X' | b'Y' | b'Z' | b'I' | b'J' | b'K' | b'R' | b'@' => {
                    check::length(w.letter, v, self.unit).map_err(located)?;
                    match w.letter {
                        b'X' | b'Y' | b'Z' => &mut out.axes[(w.letter - b'X') as usize],
                        b'I' | b'J' | b'K' => &mut out.ijk[(w.letter - b'I') as usize],
                        b'R' => &mut out.r,
                        _ => &mut out.polar[0],
                    }
                }
                b'^' => &mut out.polar[1],
                b'P' => &mut out.p,
                b'F' if self.inverse_time => {
                    // G93: moves per minute (the move takes 1/F minutes).
                    check::inverse_feed(v).map_err(located)?;
                    &mut out.f
                }
                b'F' => {
                    // G94: units per minute; an NC runs any F at most at its largest feed.
                    self.feed = check::feed(v, f_unit).map_err(located)?.min(self.max_feed);
                    &mut out.f
                }
                b'T' => &mut out.extra.t,
                b'D' => &mut out.extra.d,
                b'H' => &mut out.extra.h,
                b'L' => &mut out.extra.l,
                b'Q' => &mut out.extra.q,
                b'G' | b'M' | b'N' | b'S' => continue,
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
            };
            if slot.is_some() {
                let msg = format!("{} given twice on one line", w.letter as char);
                return Err(self.error(line, w.col, msg));
            }
            *slot = Some((v, w.col));
        }
        Ok(())
    }
}
