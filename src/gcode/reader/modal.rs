//! The G and M words of a line: modal settings applied at once, motion / stop and the
//! non-modal codes (group 0: G4, G10, G28, G30, G53, G92, G5.3) returned for `execute`, which
//! runs them in LinuxCNC's order of execution (G-code overview, "Order of Execution").

use super::{fmt_code, LineCodes, Reader};
use crate::config::CutterCorner;
use crate::error::ProgramError;
use crate::gcode::check;
use crate::gcode::words::Word;
use crate::gcode::{PathMode, StopKind};
use crate::geometry::Plane;
use serde::{Deserialize, Serialize};

/// A motion mode (modal group 1, LinuxCNC "Modal Groups").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// G0
    Rapid,
    /// G1
    Linear,
    /// G2 (true) / G3
    Arc(bool),
    /// G5 cubic spline
    Cubic,
    /// G5.1 quadratic spline
    Quadratic,
    /// G5.2 NURBS block (control points until G5.3)
    Nurbs,
    /// G73, G81, G82, G83
    Cycle(u8),
}

impl Mode {
    fn of(code: i64) -> Option<Mode> {
        Some(match code {
            0 => Mode::Rapid,
            10 => Mode::Linear,
            20 | 30 => Mode::Arc(code == 20),
            50 => Mode::Cubic,
            51 => Mode::Quadratic,
            52 => Mode::Nurbs,
            730 | 810 | 820 | 830 => Mode::Cycle((code / 10) as u8),
            _ => return None,
        })
    }

    /// The code as written: `G0`, `G5.1`, `G81`.
    pub fn name(self) -> String {
        match self {
            Mode::Rapid => "G0".into(),
            Mode::Linear => "G1".into(),
            Mode::Arc(cw) => if cw { "G2" } else { "G3" }.into(),
            Mode::Cubic => "G5".into(),
            Mode::Quadratic => "G5.1".into(),
            Mode::Nurbs => "G5.2".into(),
            Mode::Cycle(m) => format!("G{m}"),
        }
    }
}

impl Reader {
    /// G and M words: modal settings applied at once, motion / dwell / stop returned.
    pub(super) fn modal_words(&mut self, line: u32, words: &[Word]) -> Result<LineCodes, ProgramError> {
        let mut codes = LineCodes::default();
        // Modal groups seen on this line, to refuse two words of one group.
        let mut groups: [Option<u32>; 13] = [None; 13];
        // LinuxCNC's read_g drops G80 when another motion code (group 1) is on the line, in
        // either order (its planner tests start `G90 G17 G40 G80 G00 G20`), and a second G80.
        let tenths = |w: &Word| (w.value * 10.0).round() as i64;
        // Asked only where a G80 is met.
        let motion_besides_g80 = || {
            words
                .iter()
                .any(|w| w.letter == b'G' && g_group(tenths(w)) == Some(0) && tenths(w) != 800)
        };
        for w in words.iter().filter(|w| w.letter == b'G' || w.letter == b'M') {
            // Codes with one decimal (G90.1); compare in tenths.
            let code = (w.value * 10.0).round() as i64;
            if ((w.value * 10.0) - code as f64).abs() > 1e-6 {
                let msg = format!("unsupported {}{}", w.letter as char, w.value);
                return Err(self.error(line, w.col, msg));
            }
            if w.letter == b'M' {
                self.m_code(line, code, w.col, &mut codes)?;
                continue;
            }
            if code == 800 && w.letter == b'G' && (groups[0].is_some() || motion_besides_g80()) {
                continue;
            }
            if let Some(g) = g_group(code) {
                if groups[g].replace(w.col).is_some() {
                    return Err(self.error(line, w.col, "two words of the same modal group on one line"));
                }
            }
            self.g_code(line, code, w.col, words, &mut codes)?;
        }
        Ok(codes)
    }

    /// One G code: a modal setting applied at once, or noted in `codes` for `execute`.
    fn g_code(
        &mut self,
        line: u32,
        code: i64,
        col: u32,
        words: &[Word],
        codes: &mut LineCodes,
    ) -> Result<(), ProgramError> {
        match code {
            c if Mode::of(c).is_some() => codes.motion = Mode::of(c).map(|m| (m, col)),
            170 => self.plane = Plane::XY,
            180 => self.plane = Plane::XZ,
            190 => self.plane = Plane::YZ,
            200 | 210 => self.unit = if code == 200 { 25.4e-3 } else { 1e-3 },
            900 | 910 => self.absolute = code == 900,
            901 | 911 => self.arc_absolute = code == 901,
            610 | 611 => self.path_mode = PathMode::ExactStop,
            640 => self.path_mode = self.blend_mode(line, words)?,
            930 | 940 => {
                // A change of feed mode needs a new F (LinuxCNC "G93, G94, G95").
                if self.inverse_time != (code == 930) {
                    self.feed = 0.0;
                }
                self.inverse_time = code == 930;
            }
            c if setup_group(c).is_some() => self.setup_code(code, col, codes),
            // G80 cancels the motion mode; spindle modes and canned-cycle return levels do not
            // move.
            800 => {
                self.motion = None;
                codes.cancel = Some(col);
            }
            980 | 990 => self.set_retract_to_r(code == 990),
            960 | 970 => {}
            _ => {
                let what = unsupported_reason(code);
                return Err(self.error(line, col, format!("unsupported G{}{what}", fmt_code(code))));
            }
        }
        Ok(())
    }

    /// G64 [P tolerance] [Q merge tolerance] (LinuxCNC "G64").
    fn blend_mode(&self, line: u32, words: &[Word]) -> Result<PathMode, ProgramError> {
        let last = |letter: u8| words.iter().rev().find(|w| w.letter == letter).copied();
        let metres = |w: Option<Word>| {
            w.map(|w| {
                check::blend_tolerance(w.letter, w.value, self.unit).map_err(|m| self.error(line, w.col, m))
            })
            .transpose()
        };
        Ok(PathMode::Blend {
            tolerance: metres(last(b'P'))?,
            q: metres(last(b'Q'))?,
        })
    }

    /// Cutter compensation, tool length, work system, non-modal and G450/G451 codes.
    fn setup_code(&mut self, code: i64, col: u32, codes: &mut LineCodes) {
        match code {
            400 | 410 | 411 | 420 | 421 => codes.comp = Some((code, col)),
            430 | 431 | 490 => codes.tlo = Some((code, col)),
            591..=593 => self.work = (code - 585) as usize,
            540..=590 => self.work = ((code - 540) / 10) as usize,
            4500 => self.corner = CutterCorner::Arc,
            4510 => self.corner = CutterCorner::Extension,
            _ => codes.nonmodal = Some((code, col)),
        }
    }

    /// M0/M1/M2/M30 (one of them a line), M6, and the M codes that do not move.
    fn m_code(&self, line: u32, code: i64, col: u32, codes: &mut LineCodes) -> Result<(), ProgramError> {
        let stop = match code {
            10 if !self.nc.optional_stop => None,
            0 => Some(StopKind::Pause),
            10 => Some(StopKind::OptionalPause),
            20 | 300 => Some(StopKind::End),
            60 => {
                codes.tool_change = true;
                None
            }
            610 => {
                codes.set_tool = Some(col);
                None
            }
            // Spindle, coolant, override switches: no motion.
            30 | 40 | 50 | 70 | 80 | 90 | 480 | 490 => None,
            _ => return Err(self.error(line, col, format!("unsupported M{}", fmt_code(code)))),
        };
        if let Some(kind) = stop {
            if codes.stop.is_some() {
                return Err(self.error(line, col, "two words of the same modal group on one line"));
            }
            codes.stop = Some((kind, col));
        }
        Ok(())
    }
}

/// The modal group (index into the line's groups) of a G code, None for codes without one.
fn g_group(code: i64) -> Option<usize> {
    match code {
        0 | 10 | 20 | 30 | 50 | 51 | 52 | 730 | 800 | 810 | 820 | 830 => Some(0),
        170 | 180 | 190 => Some(1),
        200 | 210 => Some(2),
        900 | 910 => Some(3),
        901 | 911 => Some(4),
        610 | 611 | 640 => Some(5),
        930 | 940 => Some(12),
        c => setup_group(c),
    }
}

/// The modal group (index into the line's groups) of a setup code, None for the others.
fn setup_group(code: i64) -> Option<usize> {
    match code {
        400 | 410 | 411 | 420 | 421 => Some(6),
        430 | 431 | 490 => Some(8),
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => Some(9),
        // Group 0 (non-modal): at most one a line.
        40 | 53 | 100 | 280 | 281 | 300 | 301 | 530 | 920..=923 => Some(10),
        4500 | 4510 => Some(11),
        _ => None,
    }
}

/// Why a G code is refused (appended to "unsupported Gn").
fn unsupported_reason(code: i64) -> &'static str {
    match code {
        432 => " (tool length offset from a second tool)",
        330 | 331 | 760 => " (spindle-synchronised motion: this model has no spindle position to follow)",
        380..=389 => " (probing)",
        840..=890 => " (canned cycles other than G73, G81, G82, G83)",
        950 => " (feed per revolution)",
        70 | 80 => " (lathe diameter/radius mode: this controller drives a 3-axis mill)",
        _ => "",
    }
}
