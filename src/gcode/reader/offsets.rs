//! Tools and coordinate systems in the reader (LinuxCNC G-code reference, "Tool Length Offsets",
//! "Coordinate Systems", "G10", "G92", "G53", "G28/G30"): every offset is applied here, so the
//! path stage sees machine coordinates. machine = R·(program + G92 offset) + work offset
//! (G54…G59.3) + tool length (Z), R the system's XY rotation (`frame.rs`).

use super::words::LineWords;
use super::{LineCodes, Reader};
use crate::config::nc::{Tool, MAX_OFFSET_M, MAX_TOOL, MAX_TOOL_RADIUS_M};
use crate::error::ProgramError;
use crate::gcode::check;
use serde::{Deserialize, Serialize};

/// Tool state: T (selected), M6 (loaded), D (the tool whose radius compensation uses, None:
/// the loaded tool's), tool length offset (m).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ToolState {
    pub selected: u32,
    pub loaded: u32,
    pub d: Option<u32>,
    pub length: f64,
}

/// The T, D, H, L, P, R words of a line, with their columns.
#[derive(Default, Clone, Copy)]
pub(super) struct Extra {
    pub t: Option<(f64, u32)>,
    pub d: Option<(f64, u32)>,
    pub h: Option<(f64, u32)>,
    pub l: Option<(f64, u32)>,
    pub q: Option<(f64, u32)>,
}

/// What a non-modal code leaves for the motion of its line.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum NonModal {
    /// Nothing (no non-modal code).
    None,
    /// The axis words were data (G10, G92): no motion.
    Consumed,
    /// G53: the axis words are machine coordinates for this block.
    Machine,
    /// G28 (0) / G30 (1): through the programmed point to the home position.
    Home(usize),
}

type Axes = [Option<(f64, u32)>; 3];

impl Reader {
    /// Offset (m) from program to machine Z.
    pub(super) fn z_offset(&self) -> f64 {
        self.to_machine([0.0; 3])[2]
    }

    /// A whole, non-negative number word (tool, register, L, P) within `max`.
    pub(super) fn whole(
        &self,
        line: u32,
        letter: char,
        w: (f64, u32),
        max: u32,
    ) -> Result<u32, ProgramError> {
        if w.0 >= 0.0 && w.0 <= max as f64 && w.0.fract() == 0.0 {
            Ok(w.0 as u32)
        } else {
            let m = format!("{letter}{} out of range (a whole number 0 … {max})", w.0);
            Err(self.error(line, w.1, m))
        }
    }

    pub(super) fn tool_entry(&self, line: u32, letter: char, w: (f64, u32)) -> Result<Tool, ProgramError> {
        let n = self.whole(line, letter, w, MAX_TOOL)?;
        if n == 0 {
            return Ok(Tool::default());
        }
        self.nc.tools.get(&n).copied().ok_or_else(|| {
            let m = format!("{letter}{n}: tool {n} is not in the machine's tool table ([tool.{n}])");
            self.error(line, w.1, m)
        })
    }

    /// T, M6, D, G43 H / G43.1 / G49 (LinuxCNC "T", "M6", "G43", "G43.1", "G49"; D as in G41 D).
    pub(super) fn apply_tool(
        &mut self,
        line: u32,
        codes: &LineCodes,
        extra: &Extra,
        axes: &mut Axes,
    ) -> Result<(), ProgramError> {
        if let Some(t) = extra.t {
            // Any tool may be loaded; its table entry is needed only by G41/G42 and G43.
            self.tool.selected = self.whole(line, 'T', t, MAX_TOOL)?;
        }
        if codes.tool_change {
            self.tool.loaded = self.tool.selected;
        }
        if let Some(col) = codes.set_tool {
            // M61 Q (LinuxCNC "M61 Set Current Tool"): the tool in the spindle, no change and
            // no new length offset (G43 after it does that).
            let Some(q) = extra.q else {
                return Err(self.error(line, col, "M61 needs Q (the tool number, 0 or greater)"));
            };
            self.tool.loaded = self.whole(line, 'Q', q, MAX_TOOL)?;
        }
        if let (Some(d), false) = (extra.d, matches!(codes.comp, Some((411 | 421, _)))) {
            self.tool.d = Some(self.whole(line, 'D', d, MAX_TOOL)?);
        }
        match codes.tlo {
            Some((430, _)) => {
                let h = extra.h.unwrap_or((self.tool.loaded as f64, 1));
                self.tool.length = self.tool_entry(line, 'H', h)?.length;
            }
            Some((431, col)) => {
                let Some((z, zc)) = axes[2].take() else {
                    return Err(self.error(line, col, "G43.1 needs Z (the tool length offset)"));
                };
                self.tool.length = check::length(b'Z', z, self.unit).map_err(|m| self.error(line, zc, m))?;
            }
            Some(_) => self.tool.length = 0.0,
            None => {}
        }
        Ok(())
    }

    /// G10, G28.1, G30.1, G53, G92…G92.3, G5.3; G28/G30 returned for `execute` to move.
    pub(super) fn non_modal(
        &mut self,
        line: u32,
        codes: &LineCodes,
        w: &LineWords,
    ) -> Result<NonModal, ProgramError> {
        let Some((code, col)) = codes.nonmodal else {
            return Ok(NonModal::None);
        };
        match code {
            100 => self.g10(line, col, w)?,
            53 => self.nurbs_end(line, col)?,
            280 | 300 => return Ok(NonModal::Home(if code == 280 { 0 } else { 1 })),
            281 | 301 => self.nc.home[if code == 281 { 0 } else { 1 }] = self.position,
            530 => return Ok(NonModal::Machine),
            920 => {
                if !w.moves() {
                    return Err(self.error(line, col, "G92 needs at least one axis word"));
                }
                // G92: the current point reads the given values (LinuxCNC "G92"): the offset
                // is what lies between the point in the unshifted system and the values.
                let mut unshifted = self.to_program(self.position);
                let old = if self.g92_on { self.g92 } else { [0.0; 3] };
                for (u, o) in unshifted.iter_mut().zip(old) {
                    *u += o;
                }
                self.g92 = std::array::from_fn(|i| match w.axes[i] {
                    Some((v, _)) => unshifted[i] - v * self.unit,
                    None => old[i],
                });
                self.g92_on = true;
            }
            921 => (self.g92, self.g92_on) = ([0.0; 3], false),
            922 => self.g92_on = false,
            923 => self.g92_on = true,
            // G4 (run before) and the codes that leave the axis words to the motion.
            _ => return Ok(NonModal::None),
        }
        Ok(if matches!(code, 281 | 301 | 921 | 922 | 923) {
            // These take no axis words: a modal motion runs with them (LinuxCNC "Modal Groups").
            NonModal::None
        } else {
            NonModal::Consumed
        })
    }

    /// A G10 length (program units) in metres within ±max.
    fn g10_length(&self, line: u32, v: f64, c: u32, max: f64) -> Result<f64, ProgramError> {
        let m = v * self.unit;
        if m.is_finite() && m.abs() <= max {
            Ok(m)
        } else {
            Err(self.error(
                line,
                c,
                format!("G10 value {v} out of range (|value| ≤ {} mm)", max * 1e3),
            ))
        }
    }

    /// G10 L1 / L10 (tool table: P tool, R radius, Z length) and L2 / L20 (work offsets: P 0…9,
    /// 0 = the active system; L2 R: the system's XY rotation about Z in degrees), LinuxCNC
    /// "G10 L1", "G10 L10", "G10 L2", "G10 L20".
    fn g10(&mut self, line: u32, col: u32, w: &LineWords) -> Result<(), ProgramError> {
        let Some(l) = w.extra.l else {
            return Err(self.error(line, col, "G10 needs L (1, 2, 10 or 20)"));
        };
        let Some(p) = w.p else {
            return Err(self.error(line, col, "G10 needs P (tool or coordinate system number)"));
        };
        match self.whole(line, 'L', l, 20)? {
            lv @ (1 | 10) => self.g10_tool(line, lv, p, w),
            lv @ (2 | 20) => self.g10_system(line, lv, p, w),
            _ => Err(self.error(
                line,
                l.1,
                format!("unsupported G10 L{} (L1, L2, L10, L20 are)", l.0),
            )),
        }
    }

    /// G10 L1 / L10: tool P's radius R and length Z (L10: the length that makes the current
    /// position read Z).
    fn g10_tool(&mut self, line: u32, lv: u32, p: (f64, u32), w: &LineWords) -> Result<(), ProgramError> {
        let n = self.whole(line, 'P', p, MAX_TOOL)?;
        if n == 0 {
            return Err(self.error(line, p.1, "G10 L1/L10: P0 is not a tool"));
        }
        let mut tool = self.nc.tools.get(&n).copied().unwrap_or_default();
        if let Some((v, c)) = w.r {
            if v < 0.0 {
                return Err(self.error(line, c, "G10: the tool radius R must not be negative"));
            }
            tool.radius = self.g10_length(line, v, c, MAX_TOOL_RADIUS_M)?;
        }
        if let Some((v, c)) = w.axes[2] {
            let z = self.g10_length(line, v, c, MAX_OFFSET_M)?;
            tool.length = if lv == 1 {
                z
            } else {
                // The program Z without the tool length, minus the value it should read.
                self.to_program(self.position)[2] + self.tool.length - z
            };
            tool.length = self.g10_length(line, tool.length / self.unit, c, MAX_OFFSET_M)?;
        }
        self.nc.tools.insert(n, tool);
        Ok(())
    }

    /// G10 L2 / L20: the origin (and L2 R, rotation) of system P. L2: the offsets given;
    /// L20: the offsets that make the current point read the given values in that system, with
    /// its rotation (LinuxCNC "G10 L20"; R is not allowed with L20, as in LinuxCNC).
    fn g10_system(&mut self, line: u32, lv: u32, p: (f64, u32), w: &LineWords) -> Result<(), ProgramError> {
        let n = self.whole(line, 'P', p, 9)?;
        let system = if n == 0 { self.work } else { n as usize - 1 };
        if system == self.work && self.comp_on() {
            let msg = "G10 changes the active coordinate system while cutter compensation is on (G40 first)";
            return Err(self.error(line, p.1, msg));
        }
        let mut off = self.nc.work_offsets[system];
        let mut rotation = self.nc.work_rotation[system];
        if let Some((v, c)) = w.r {
            if lv == 20 {
                return Err(self.error(line, c, "R (rotation) is not allowed in G10 L20, only in L2"));
            }
            if !v.is_finite() || v.abs() > check::MAX_ROTATION_DEG {
                let m = format!(
                    "G10 R{v} out of range (|R| ≤ {} degrees)",
                    check::MAX_ROTATION_DEG
                );
                return Err(self.error(line, c, m));
            }
            rotation = v;
        }
        let mut given = [None; 3];
        for (i, a) in w.axes.iter().enumerate() {
            if let Some((v, c)) = *a {
                given[i] = Some((self.g10_length(line, v, c, MAX_OFFSET_M)?, c));
            }
        }
        if lv == 2 {
            for (i, g) in given.iter().enumerate() {
                if let Some((v, _)) = g {
                    off[i] = *v;
                }
            }
        } else {
            // Where the machine is, and where the point should read in system P:
            // machine = R·(program + G92) + offset.
            let g92 = if self.g92_on { self.g92 } else { [0.0; 3] };
            let here = self.to_program_in(system, self.position);
            let want: [f64; 3] = std::array::from_fn(|i| given[i].map_or(here[i], |g| g.0));
            let xy = super::frame::rotate(
                [want[0] + g92[0], want[1] + g92[1]],
                super::frame::cos_sin(rotation),
            );
            let new = [
                self.position[0] - xy[0],
                self.position[1] - xy[1],
                self.position[2] - self.tool.length - g92[2] - want[2],
            ];
            for i in 0..3 {
                if given[i].is_some() || (i < 2 && (given[0].is_some() || given[1].is_some())) {
                    off[i] = new[i];
                }
            }
        }
        for (i, g) in given.iter().enumerate() {
            if let Some((_, c)) = g {
                self.g10_length(line, off[i] / self.unit, *c, MAX_OFFSET_M)?;
            }
        }
        self.nc.work_offsets[system] = off;
        self.nc.work_rotation[system] = rotation;
        Ok(())
    }
}
