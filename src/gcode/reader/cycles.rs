//! Drilling cycles G81, G82, G83, G73 with G98/G99 and G80 (LinuxCNC G-code reference, "G81
//! Drilling Cycle", "G82", "G83 Peck Drilling", "G73 Drilling Cycle with Chip Breaking",
//! "G98/G99", "G80"), expanded in the reader into ordinary rapid and feed moves (and G82's
//! dwell). G17, G90 only; the sticky words R, Z, P, Q carry over to the following holes.

use super::{LineCodes, Reader};
use crate::error::ProgramError;
use crate::gcode::{Block, Motion, Plane};
use serde::{Deserialize, Serialize};

/// LinuxCNC's G83 rapid clearance above the previous peck and G73 chip-break retract, 0.010 in.
pub const PECK_CLEARANCE_M: f64 = 0.254e-3;
/// Most pecks of one hole (depth / Q).
const MAX_PECKS: f64 = 10_000.0;

/// Sticky cycle words (machine Z, m; P s; Q m), the Z before the cycles (G98) and G98/G99.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Cycle {
    r: Option<f64>,
    z: Option<f64>,
    p: f64,
    q: Option<f64>,
    z0: f64,
    g99: bool,
}

impl Cycle {
    /// A restored state: levels in range, the dwell a G4's, the peck depth positive (the peck
    /// loop of a hole runs (R − Z)/Q times).
    pub(super) fn check_state(&self) -> Result<(), String> {
        use crate::valid::{within, MAX_POSITION_M};
        for z in [self.r, self.z, Some(self.z0)].into_iter().flatten() {
            within("cycle level", z, -MAX_POSITION_M, MAX_POSITION_M)?;
        }
        within("cycle dwell", self.p, 0.0, crate::gcode::check::MAX_DWELL_S)?;
        match self.q {
            Some(q) => within("peck depth", q, f64::MIN_POSITIVE, MAX_POSITION_M),
            None => Ok(()),
        }
    }
}

/// Words of a cycle line (value, column).
pub(super) struct CycleWords {
    pub xy: [Option<(f64, u32)>; 3],
    pub r: Option<(f64, u32)>,
    pub p: Option<(f64, u32)>,
    pub q: Option<(f64, u32)>,
}

impl Reader {
    /// G98 (false) / G99 (true): retract to the initial Z or to R.
    pub(super) fn set_retract_to_r(&mut self, g99: bool) {
        self.cycle.g99 = g99;
    }

    /// One hole of cycle `m` (73, 81, 82, 83) at the line's X/Y; the first block, the rest queued.
    pub(super) fn canned(
        &mut self,
        line: u32,
        col: u32,
        m: u8,
        fresh: bool,
        w: CycleWords,
        codes: &LineCodes,
    ) -> Result<Option<Block>, ProgramError> {
        let name = format!("G{m}");
        if self.plane != Plane::XY || !self.absolute {
            return Err(self.error(line, col, format!("{name}: drilling cycles run in G17 G90 only")));
        }
        if self.inverse_time {
            let msg = format!("{name}: drilling cycles are not defined in G93 (inverse time); use G94");
            return Err(self.error(line, col, msg));
        }
        if self.feed <= 0.0 {
            return Err(self.error(line, col, format!("{name} with no feed rate: F was never set")));
        }
        if fresh {
            self.cycle.z0 = self.position[2];
        }
        let (r, z, q) = self.cycle_levels(line, col, m, &w)?;
        let xy = [w.xy[0], w.xy[1], None];
        let hole = self.target(line, &xy, false)?;
        let clear = if self.cycle.g99 { r } else { r.max(self.cycle.z0) };
        let mut out = Vec::new();
        if self.position[2] < r {
            self.step(line, &mut out, None, r, false);
        }
        self.step(line, &mut out, Some(hole), self.position[2], false);
        self.step(line, &mut out, None, r, false);
        let mut depth = r;
        while depth > z {
            if depth < r && m == 83 {
                // Back down near the previous peck after G83's full retract.
                self.step(line, &mut out, None, depth + PECK_CLEARANCE_M, false);
            }
            depth = (depth - q).max(z);
            self.step(line, &mut out, None, depth, true);
            if depth > z {
                let up = if m == 83 { r } else { depth + PECK_CLEARANCE_M };
                self.step(line, &mut out, None, up, false);
            }
        }
        if m == 82 && self.cycle.p > 0.0 {
            out.push(self.block(
                line,
                Motion::Dwell {
                    seconds: self.cycle.p,
                },
            ));
        }
        self.step(line, &mut out, None, clear, false);
        let mut out = out.into_iter();
        let first = out.next();
        self.pending.extend(out);
        Ok(first.map(|b| self.with_stop(b, codes)))
    }

    /// R, Z, P, Q of the line into the cycle state (they stay in force); R, Z (m, machine) and
    /// the peck depth (infinite for G81/G82).
    fn cycle_levels(
        &mut self,
        line: u32,
        col: u32,
        m: u8,
        w: &CycleWords,
    ) -> Result<(f64, f64, f64), ProgramError> {
        let (unit, offset) = (self.unit, self.axis_offset(2));
        let z_of = |v: f64| v * unit + offset;
        if let Some((v, _)) = w.r {
            self.cycle.r = Some(z_of(v));
        }
        if let Some((v, _)) = w.xy[2] {
            self.cycle.z = Some(z_of(v));
        }
        if let Some((v, c)) = w.p {
            self.cycle.p = crate::gcode::check::dwell(v).map_err(|e| self.error(line, c, e))?;
        }
        if let Some((v, c)) = w.q {
            if v <= 0.0 {
                return Err(self.error(line, c, format!("G{m}: Q (peck depth) must be positive")));
            }
            self.cycle.q = Some(v * self.unit);
        }
        let (Some(r), Some(z)) = (self.cycle.r, self.cycle.z) else {
            return Err(self.error(line, col, format!("G{m} needs R (retract level) and Z (bottom)")));
        };
        if z > r {
            return Err(self.error(line, col, format!("G{m}: the bottom Z is above R")));
        }
        let q = match (m, self.cycle.q) {
            (73 | 83, None) => return Err(self.error(line, col, format!("G{m} needs Q (peck depth)"))),
            (73 | 83, Some(q)) if (r - z) / q > MAX_PECKS => {
                return Err(self.error(line, col, format!("G{m}: more than {MAX_PECKS} pecks")))
            }
            (_, q) => q.unwrap_or(f64::INFINITY),
        };
        Ok((r, z, q))
    }

    /// A rapid (or feed) move to `xy` (or here) at height `z`; nothing if already there.
    fn step(&mut self, line: u32, out: &mut Vec<Block>, xy: Option<[f64; 3]>, z: f64, feed: bool) {
        let mut to = xy.unwrap_or(self.position);
        to[2] = z;
        if to == self.position {
            return;
        }
        let motion = if feed {
            Motion::Linear { to }
        } else {
            Motion::Rapid { to }
        };
        out.push(self.block(line, motion));
        self.position = to;
    }
}
