//! Tools and coordinate systems in the reader (LinuxCNC G-code reference, "Tool Length Offsets",
//! "Coordinate Systems", "G10", "G92", "G53", "G28/G30"): every offset is applied here, so the
//! path stage sees machine coordinates. machine = program + work offset (G54…G59.3) + G92 offset
//! + tool length (Z).

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
    /// Offset (m) from program to machine coordinates of axis `i`.
    pub(super) fn axis_offset(&self, i: usize) -> f64 {
        self.offset_without_tool(i) + if i == 2 { self.tool.length } else { 0.0 }
    }

    fn offset_without_tool(&self, i: usize) -> f64 {
        self.nc.work_offsets[self.work][i] + if self.g92_on { self.g92[i] } else { 0.0 }
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

    /// G10, G28.1, G30.1, G53, G92…G92.3; G28/G30 returned for `execute` to move.
    pub(super) fn non_modal(
        &mut self,
        line: u32,
        codes: &LineCodes,
        extra: &Extra,
        p: Option<(f64, u32)>,
        r: Option<(f64, u32)>,
        axes: &Axes,
    ) -> Result<NonModal, ProgramError> {
        let Some((code, col)) = codes.nonmodal else {
            return Ok(NonModal::None);
        };
        let value = |i: usize| axes[i].map(|(v, _)| v * self.unit);
        match code {
            100 => self.g10(line, col, extra, p, r, axes)?,
            280 | 300 => return Ok(NonModal::Home(if code == 280 { 0 } else { 1 })),
            281 | 301 => self.nc.home[if code == 281 { 0 } else { 1 }] = self.position,
            530 => return Ok(NonModal::Machine),
            920 => {
                if axes.iter().all(Option::is_none) {
                    return Err(self.error(line, col, "G92 needs at least one axis word"));
                }
                // G92: the current point reads the given values (LinuxCNC "G92").
                let old = if self.g92_on { self.g92 } else { [0.0; 3] };
                let base: [f64; 3] = std::array::from_fn(|i| self.axis_offset(i) - old[i]);
                self.g92 = std::array::from_fn(|i| match value(i) {
                    Some(v) => self.position[i] - base[i] - v,
                    None => old[i],
                });
                self.g92_on = true;
            }
            921 => (self.g92, self.g92_on) = ([0.0; 3], false),
            922 => self.g92_on = false,
            _ => self.g92_on = true,
        }
        Ok(NonModal::Consumed)
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
    /// 0 = the active system), LinuxCNC "G10 L1", "G10 L10", "G10 L2", "G10 L20".
    fn g10(
        &mut self,
        line: u32,
        col: u32,
        extra: &Extra,
        p: Option<(f64, u32)>,
        r: Option<(f64, u32)>,
        axes: &Axes,
    ) -> Result<(), ProgramError> {
        let Some(l) = extra.l else {
            return Err(self.error(line, col, "G10 needs L (1, 2, 10 or 20)"));
        };
        let Some(p) = p else {
            return Err(self.error(line, col, "G10 needs P (tool or coordinate system number)"));
        };
        match self.whole(line, 'L', l, 20)? {
            lv @ (1 | 10) => {
                let n = self.whole(line, 'P', p, MAX_TOOL)?;
                if n == 0 {
                    return Err(self.error(line, p.1, "G10 L1/L10: P0 is not a tool"));
                }
                let mut tool = self.nc.tools.get(&n).copied().unwrap_or_default();
                if let Some((v, c)) = r {
                    if v < 0.0 {
                        return Err(self.error(line, c, "G10: the tool radius R must not be negative"));
                    }
                    tool.radius = self.g10_length(line, v, c, MAX_TOOL_RADIUS_M)?;
                }
                if let Some((v, c)) = axes[2] {
                    let z = self.g10_length(line, v, c, MAX_OFFSET_M)?;
                    // L10: the length that makes the current position read Z.
                    tool.length = if lv == 1 {
                        z
                    } else {
                        self.position[2] - self.offset_without_tool(2) - z
                    };
                    tool.length = self.g10_length(line, tool.length / self.unit, c, MAX_OFFSET_M)?;
                }
                self.nc.tools.insert(n, tool);
            }
            lv @ (2 | 20) => {
                let n = self.whole(line, 'P', p, 9)?;
                let system = if n == 0 { self.work } else { n as usize - 1 };
                for (i, a) in axes.iter().enumerate() {
                    if let Some((v, c)) = *a {
                        let v = self.g10_length(line, v, c, MAX_OFFSET_M)?;
                        let g92 = if self.g92_on { self.g92[i] } else { 0.0 };
                        let tlo = if i == 2 { self.tool.length } else { 0.0 };
                        let off = if lv == 2 {
                            v
                        } else {
                            self.position[i] - g92 - tlo - v
                        };
                        let off = self.g10_length(line, off / self.unit, c, MAX_OFFSET_M)?;
                        self.nc.work_offsets[system][i] = off;
                    }
                }
            }
            _ => {
                return Err(self.error(
                    line,
                    l.1,
                    format!("unsupported G10 L{} (L1, L2, L10, L20 are)", l.0),
                ))
            }
        }
        Ok(())
    }
}
