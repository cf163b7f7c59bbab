//! One line executed in LinuxCNC's order (G-code overview, "Order of Execution"): feed mode and
//! F, T, M6, the modal settings (plane, units, distance, path mode, applied as the G words are
//! read), then dwell G4, cutter compensation G40/G41/G42, tool length G43/G49, coordinate data
//! G10 / G92 and G28 / G30, the motion (as modified by G53), and last the stops M0/M1/M2/M30.
//! Every block the line makes is queued in `pending`, in that order.

use super::modal::Mode;
use super::offsets::NonModal;
use super::words::LineWords;
use super::{LineCodes, Reader};
use crate::error::ProgramError;
use crate::gcode::{check, Block, Motion};

impl Reader {
    /// Apply one line's words to the modal state; queue the blocks it makes.
    pub(super) fn execute(
        &mut self,
        line: u32,
        words: &[crate::gcode::words::Word],
    ) -> Result<(), ProgramError> {
        // F (step 4) comes before G20/G21 (step 16): read in the units in force before the line.
        let f_unit = self.unit;
        let codes = self.modal_words(line, words)?;
        // Filled in place: returned, the record (a few hundred bytes) was copied twice.
        let mut w = LineWords::default();
        self.read_words(line, words, f_unit, &mut w)?;
        self.check_group_zero(line, &codes, &w)?;
        self.check_nurbs_open(line, &codes)?;
        self.apply_tool(line, &codes, &w.extra, &mut w.axes)?;
        if let Some((40, col)) = codes.nonmodal {
            self.dwell(line, col, w.p)?;
        }
        if let Some((code, col)) = codes.comp {
            self.set_comp(line, code, col, w.extra.d)?;
        }
        match self.non_modal(line, &codes, &w)? {
            NonModal::Home(i) => self.go_home(line, i, &w)?,
            NonModal::Consumed => {}
            other => self.motion(line, &codes, &w, other == NonModal::Machine)?,
        }
        if let Some((kind, _)) = codes.stop {
            if kind == crate::gcode::StopKind::End {
                self.check_spline_closed()?;
            }
            self.pending.push_back(self.block(line, Motion::Stop(kind)));
            self.finish_on(kind);
        }
        Ok(())
    }

    /// LinuxCNC "Modal Groups" and "G53", "G4": the group-0 code of a line against its motion.
    fn check_group_zero(&self, line: u32, codes: &LineCodes, w: &LineWords) -> Result<(), ProgramError> {
        let Some((code, col)) = codes.nonmodal else {
            return Ok(());
        };
        let name = format!("G{}", super::fmt_code(code));
        // G10, G28, G30 and G92 take the axis words: no motion code may share the line.
        if let (true, Some((m, mc))) = (matches!(code, 100 | 280 | 300 | 920), codes.motion) {
            let msg = format!(
                "{} and {name} on one line: both use the axis words (LinuxCNC \"Modal Groups\")",
                m.name()
            );
            return Err(self.error(line, mc, msg));
        }
        if let (true, Some((_, c))) = (matches!(code, 100 | 920), w.polar.iter().flatten().next()) {
            let msg = format!("polar coordinates (@ ^) are for motion, not for {name}");
            return Err(self.error(line, *c, msg));
        }
        let to_be = codes
            .motion
            .map(|m| m.0)
            .or(if w.moves() { self.motion } else { None });
        match code {
            40 if matches!(to_be, Some(Mode::Arc(_))) => {
                let msg = "G4 and G2/G3 on one line: both use P (LinuxCNC \"G4\")";
                Err(self.error(line, col, msg))
            }
            530 if !matches!(to_be, Some(Mode::Rapid | Mode::Linear)) => {
                let msg = "G53 needs a G0 or G1 move on its line (LinuxCNC \"G53\")";
                Err(self.error(line, col, msg))
            }
            530 if !self.absolute => {
                let msg = "G53 in G91: machine coordinates are absolute (NIST RS274NGC v3, \"G53\")";
                Err(self.error(line, col, msg))
            }
            530 if w.polar.iter().any(Option::is_some) => {
                Err(self.error(line, col, "polar coordinates (@ ^) cannot be used with G53"))
            }
            53 if codes.motion.is_some_and(|m| m.0 != Mode::Nurbs) || w.moves() => {
                let msg = "G5.3 ends a NURBS block: only G5.2 may share its line, no axis words";
                Err(self.error(line, col, msg))
            }
            _ => Ok(()),
        }
    }

    /// G4 P: a dwell, before the line's motion.
    fn dwell(&mut self, line: u32, col: u32, p: Option<(f64, u32)>) -> Result<(), ProgramError> {
        let Some((seconds, pcol)) = p else {
            return Err(self.error(line, col, "G4 needs P (dwell time in seconds)"));
        };
        let seconds = check::dwell(seconds).map_err(|m| self.error(line, pcol, m))?;
        self.pending
            .push_back(self.block(line, Motion::Dwell { seconds }));
        Ok(())
    }

    /// The motion of a line: its group-1 code, or the modal one when axis words are given (I/J/K
    /// alone in G2/G3 mode, as LinuxCNC); words that need a motion are errors without one.
    fn motion_of(
        &self,
        line: u32,
        codes: &LineCodes,
        w: &LineWords,
    ) -> Result<Option<(Mode, u32)>, ProgramError> {
        if let (Some(c), Some(ac)) = (codes.cancel, w.first_axis()) {
            let msg = "axis words with G80 (LinuxCNC: cannot use axis values with G80)";
            return Err(self.error(line, ac.min(c), msg));
        }
        let ijk = w.ijk.iter().flatten().map(|a| a.1).min();
        Ok(match (codes.motion, w.first_axis(), self.motion) {
            (Some(m), _, _) => Some(m),
            (None, Some(col), Some(m)) => Some((m, col)),
            (None, Some(col), None) => {
                let msg = "axis words without a motion mode (G0, G1, G2, G3, G5, G5.1, G5.2, G73, G81…G83)";
                return Err(self.error(line, col, msg));
            }
            (None, None, Some(m @ Mode::Arc(_))) if ijk.is_some() => ijk.map(|c| (m, c)),
            (None, None, _) => None,
        })
    }

    /// The line's motion (LinuxCNC "Order of Execution", step "perform motion").
    fn motion(
        &mut self,
        line: u32,
        codes: &LineCodes,
        w: &LineWords,
        machine: bool,
    ) -> Result<(), ProgramError> {
        let Some((mode, col)) = self.motion_of(line, codes, w)? else {
            return self.unused_words(line, w);
        };
        let explicit = codes.motion.is_some();
        let needs_axes = matches!(mode, Mode::Cycle(_) | Mode::Cubic | Mode::Quadratic);
        if explicit && needs_axes && !w.moves() {
            let msg = format!(
                "{} without axis words (LinuxCNC: all axes missing with motion code)",
                mode.name()
            );
            return Err(self.error(line, col, msg));
        }
        if mode != Mode::Cubic {
            self.spline.g5_end = None;
        }
        let fresh = !matches!(self.motion, Some(Mode::Cycle(_)));
        let was_nurbs = self.motion == Some(Mode::Nurbs);
        self.motion = Some(mode);
        match mode {
            Mode::Cycle(m) => self.canned(line, col, m, fresh, w),
            Mode::Cubic | Mode::Quadratic => self.spline(line, col, mode, w),
            Mode::Nurbs => self.nurbs_point(line, col, w, !was_nurbs),
            _ => {
                if machine && self.comp_on() {
                    let msg =
                        "G53 with cutter compensation on (LinuxCNC: cannot use G53 with cutter radius comp)";
                    return Err(self.error(line, col, msg));
                }
                self.move_block(line, mode, col, w, machine)
            }
        }
    }

    /// R, I, J, K with no code on the line that uses them (LinuxCNC "G2, G3", "G81"): errors.
    fn unused_words(&self, line: u32, w: &LineWords) -> Result<(), ProgramError> {
        if let Some((_, c)) = w.r {
            let msg = "R with no G code that uses it: G2/G3, or a drilling cycle with X, Y or Z on the line";
            return Err(self.error(line, c, msg));
        }
        if let Some((_, c)) = w.ijk.iter().flatten().next() {
            let msg = "I/J/K with no G code that uses them (G2/G3, G5, G5.1)";
            return Err(self.error(line, *c, msg));
        }
        Ok(())
    }

    /// A G0…G3 move to the axis words (none for G0/G1 without them); G93 sets its feed.
    fn move_block(
        &mut self,
        line: u32,
        mode: Mode,
        col: u32,
        w: &LineWords,
        machine: bool,
    ) -> Result<(), ProgramError> {
        let to = self.target(line, w, machine)?;
        let feeds = mode != Mode::Rapid && (w.moves() || matches!(mode, Mode::Arc(_)));
        if feeds {
            self.check_feed(line, col, mode, w)?;
        }
        let block = match mode {
            Mode::Rapid | Mode::Linear if !w.moves() => return Ok(()),
            Mode::Rapid => self.block(line, Motion::Rapid { to }),
            Mode::Linear => self.block(line, Motion::Linear { to }),
            Mode::Arc(cw) => self.arc(line, col, cw, to, w)?,
            _ => return Ok(()),
        };
        let mut blocks = [block];
        if feeds {
            self.timed(line, col, w, &mut blocks)?;
        }
        self.position = to;
        let [block] = blocks;
        self.pending.push_back(block);
        Ok(())
    }

    /// A feed move needs a feed: F on its line in G93, F set before in G94.
    pub(super) fn check_feed(
        &self,
        line: u32,
        col: u32,
        mode: Mode,
        w: &LineWords,
    ) -> Result<(), ProgramError> {
        if self.inverse_time && w.f.is_none() {
            let msg = format!(
                "{} in G93 needs F on its line (inverse time: the move takes 1/F minutes)",
                mode.name()
            );
            return Err(self.error(line, col, msg));
        }
        if !self.inverse_time && self.feed <= 0.0 {
            let msg = format!("{} with a zero feed rate (F0, or F never set)", mode.name());
            return Err(self.error(line, col, msg));
        }
        Ok(())
    }

    /// The feed of the feed moves `blocks` of one programmed move (G93: together they take 1/F
    /// minutes), refused when they would take longer than `check::MAX_MOVE_TIME_S`.
    pub(super) fn timed(
        &self,
        line: u32,
        col: u32,
        w: &LineWords,
        blocks: &mut [Block],
    ) -> Result<(), ProgramError> {
        let length: f64 = blocks.iter().map(super::inverse::length).sum();
        let g93 = w.f.filter(|_| self.inverse_time);
        let time = match g93 {
            Some((f, _)) => {
                for b in blocks.iter_mut() {
                    b.feed = super::inverse::feed(length, f, self.max_feed);
                }
                60.0 / f
            }
            None => length / self.feed,
        };
        if time <= check::MAX_MOVE_TIME_S {
            return Ok(());
        }
        let (at, what) = match g93 {
            Some((f, fc)) => (fc, format!("G93 F{f}: the move takes 1/F = {} min", 1.0 / f)),
            None => (
                w.f.map_or(col, |f| f.1),
                format!(
                    "the move takes {time} s at F{}",
                    check::feed_shown(self.feed, self.unit)
                ),
            ),
        };
        let msg = format!(
            "{what}: longer than the longest move ({} s, one day)",
            check::MAX_MOVE_TIME_S
        );
        Err(self.error(line, at, msg))
    }

    /// G28 / G30 (LinuxCNC "G28, G28.1", "G30, G30.1"): a rapid to the programmed point if any,
    /// then a rapid of the named axes (all without axis words) to the stored home position.
    fn go_home(&mut self, line: u32, i: usize, w: &LineWords) -> Result<(), ProgramError> {
        let via = self.target(line, w, false)?;
        let none = !w.moves();
        let polar = w.polar.iter().any(Option::is_some);
        let home: [f64; 3] = std::array::from_fn(|k| {
            let named = w.axes[k].is_some() || (polar && k < 2);
            if none || named {
                self.nc.home[i][k]
            } else {
                via[k]
            }
        });
        let first = self.block(line, Motion::Rapid { to: via });
        self.position = via;
        let second = self.block(line, Motion::Rapid { to: home });
        // The motion mode stays (LinuxCNC's G28 changes no modal state).
        self.position = home;
        self.pending.extend([first, second]);
        Ok(())
    }

    pub(super) fn finish_on(&mut self, kind: crate::gcode::StopKind) {
        if kind == crate::gcode::StopKind::End {
            self.done = true;
        }
    }
}
