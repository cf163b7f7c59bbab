//! Drilling cycles G81, G82, G83, G73 with G98/G99, G80 and L repeats (LinuxCNC G-code
//! reference, "G81 Drilling Cycle", "G82", "G83 Peck Drilling", "G73 Drilling Cycle with Chip
//! Breaking", "G98/G99", "G80", "Canned Cycles": "Repeat … L"), expanded in the reader into
//! ordinary rapid and feed moves (and G82's dwell). G17 only. G90: X Y Z R absolute, L holes at
//! the same place; G91: X Y (and @ ^) are increments from the previous hole, R is measured from
//! the Z where the cycles began, Z from R. The sticky words R, Z, P, Q carry over to the
//! following holes.

use super::words::LineWords;
use super::Reader;
use crate::error::ProgramError;
use crate::gcode::{check, Block, Motion};
use crate::geometry::Plane;
use serde::{Deserialize, Serialize};

/// LinuxCNC's G83 rapid clearance above the previous peck and G73 chip-break retract, 0.010 in.
pub const PECK_CLEARANCE_M: f64 = 0.254e-3;
/// Most pecks of one hole (depth / Q).
pub const MAX_PECKS: f64 = 10_000.0;
/// A depth / Q within this share of a whole number is that number of pecks: 10 mm in Q0.001
/// is 10000.000000000002 in binary, exactly 10 000 pecks as written.
pub const PECK_COUNT_TOLERANCE: f64 = 1e-9;
/// Most blocks one cycle line expands to (holes × (3 per peck + 4)), so a line cannot fill the
/// memory: 100 000 (about 15 MB of queued blocks).
pub const MAX_CYCLE_BLOCKS: f64 = 100_000.0;

/// Sticky cycle words as written (m, program frame; P s; Q m), the Z before the cycles (machine,
/// for G98 and G91's R) and G98/G99.
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

/// The levels of one cycle line (machine Z, m) and the peck depth (m, infinite for G81/G82).
struct Levels {
    r: f64,
    z: f64,
    q: f64,
    clear: f64,
}

impl Reader {
    /// G98 (false) / G99 (true): retract to the initial Z or to R.
    pub(super) fn set_retract_to_r(&mut self, g99: bool) {
        self.cycle.g99 = g99;
    }

    /// The holes of cycle `m` (73, 81, 82, 83) of one line, L times.
    pub(super) fn canned(
        &mut self,
        line: u32,
        col: u32,
        m: u8,
        fresh: bool,
        w: &LineWords,
    ) -> Result<(), ProgramError> {
        let name = format!("G{m}");
        if self.plane != Plane::XY {
            return Err(self.error(line, col, format!("{name}: drilling cycles run in G17 only")));
        }
        if self.inverse_time {
            let msg = format!("{name}: drilling cycles are not defined in G93 (inverse time); use G94");
            return Err(self.error(line, col, msg));
        }
        if self.comp_on() {
            let msg = format!("{name} with cutter compensation on (LinuxCNC: G40 first)");
            return Err(self.error(line, col, msg));
        }
        if self.feed <= 0.0 {
            return Err(self.error(
                line,
                col,
                format!("{name} with a zero feed rate (F0, or F never set)"),
            ));
        }
        if fresh {
            self.cycle.z0 = self.position[2];
        }
        let repeats = match w.extra.l {
            None => 1,
            Some(l) => match self.whole(line, 'L', l, u32::MAX)? {
                0 => return Err(self.error(line, l.1, format!("{name} L0: zero repeats (L ≥ 1)"))),
                n => n,
            },
        };
        let levels = self.cycle_levels(line, col, m, w)?;
        let longest = (levels.r - levels.z).min(levels.q);
        if longest / self.feed > check::MAX_MOVE_TIME_S {
            let msg = format!(
                "{name}: a feed move takes {} s at F{}: longer than the longest move ({} s, one day)",
                longest / self.feed,
                check::feed_shown(self.feed, self.unit),
                check::MAX_MOVE_TIME_S
            );
            return Err(self.error(line, col, msg));
        }
        let pecks = peck_count(levels.r - levels.z, levels.q);
        if repeats as f64 * (3.0 * pecks + 4.0) > MAX_CYCLE_BLOCKS {
            let msg = format!(
                "{name}: {repeats} holes of {pecks} pecks are more than {MAX_CYCLE_BLOCKS} moves on one line"
            );
            return Err(self.error(line, col, msg));
        }
        let mut hole = self.to_program(self.position);
        let unit = self.unit;
        let step = w.axes.map(|a| a.map_or(0.0, |(v, _)| v * unit));
        for k in 0..repeats {
            if self.absolute && k == 0 {
                let target = self.target(line, &xy_only(w), false)?;
                hole = self.to_program(target);
            } else if !self.absolute {
                (hole[0], hole[1]) = (hole[0] + step[0], hole[1] + step[1]);
                if w.polar.iter().any(Option::is_some) {
                    [hole[0], hole[1]] = self.polar(line, w, [hole[0], hole[1]])?;
                }
                let at = self.to_machine(hole);
                self.check_position(line, &xy_only(w), &at)?;
            }
            let at = self.to_machine(hole);
            self.hole(line, m, [at[0], at[1]], &levels, pecks);
        }
        Ok(())
    }

    /// One hole at machine XY `xy`: to R, the pecks, the dwell, back to the clearance level.
    fn hole(&mut self, line: u32, m: u8, xy: [f64; 2], lv: &Levels, pecks: f64) {
        if self.position[2] < lv.r {
            self.step(line, None, lv.r, false);
        }
        self.step(line, Some(xy), self.position[2], false);
        self.step(line, None, lv.r, false);
        let n = pecks as u32;
        for k in 1..=n {
            if k > 1 && m == 83 {
                // Back down near the previous peck after G83's full retract.
                let previous = lv.r - (k - 1) as f64 * lv.q;
                self.step(line, None, previous + PECK_CLEARANCE_M, false);
            }
            let depth = if k == n { lv.z } else { lv.r - k as f64 * lv.q };
            self.step(line, None, depth, true);
            if k < n {
                let up = if m == 83 { lv.r } else { depth + PECK_CLEARANCE_M };
                self.step(line, None, up, false);
            }
        }
        if m == 82 && self.cycle.p > 0.0 {
            let dwell = self.block(
                line,
                Motion::Dwell {
                    seconds: self.cycle.p,
                },
            );
            self.pending.push_back(dwell);
        }
        self.step(line, None, lv.clear, false);
    }

    /// R, Z, P, Q of the line into the cycle state (they stay in force); the levels in machine Z.
    fn cycle_levels(&mut self, line: u32, col: u32, m: u8, w: &LineWords) -> Result<Levels, ProgramError> {
        let unit = self.unit;
        if let Some((v, _)) = w.r {
            self.cycle.r = Some(v * unit);
        }
        if let Some((v, _)) = w.axes[2] {
            self.cycle.z = Some(v * unit);
        }
        if let Some((v, c)) = w.p {
            self.cycle.p = check::dwell(v).map_err(|e| self.error(line, c, e))?;
        }
        if let Some((v, c)) = w.extra.q {
            if v <= 0.0 {
                return Err(self.error(line, c, format!("G{m}: Q (peck depth) must be positive")));
            }
            self.cycle.q = Some(v * unit);
        }
        let (Some(rw), Some(zw)) = (self.cycle.r, self.cycle.z) else {
            return Err(self.error(line, col, format!("G{m} needs R (retract level) and Z (bottom)")));
        };
        let (r, z) = if self.absolute {
            let offset = self.z_offset();
            (rw + offset, zw + offset)
        } else {
            // G91 (LinuxCNC "G81", incremental example): R from the initial Z, Z from R.
            (self.cycle.z0 + rw, self.cycle.z0 + rw + zw)
        };
        if z > r {
            return Err(self.error(line, col, format!("G{m}: the bottom Z is above R")));
        }
        let q = match (m, self.cycle.q) {
            (73 | 83, None) => return Err(self.error(line, col, format!("G{m} needs Q (peck depth)"))),
            (73 | 83, Some(q)) if peck_count(r - z, q) > MAX_PECKS => {
                return Err(self.error(line, col, format!("G{m}: more than {MAX_PECKS} pecks")))
            }
            (_, q) => q.unwrap_or(f64::INFINITY),
        };
        let clear = if self.cycle.g99 { r } else { r.max(self.cycle.z0) };
        Ok(Levels { r, z, q, clear })
    }

    /// A rapid (or feed) move to `xy` (or here) at height `z`; nothing if already there.
    fn step(&mut self, line: u32, xy: Option<[f64; 2]>, z: f64, feed: bool) {
        let mut to = self.position;
        if let Some([x, y]) = xy {
            (to[0], to[1]) = (x, y);
        }
        to[2] = z;
        if to == self.position {
            return;
        }
        let motion = if feed {
            Motion::Linear { to }
        } else {
            Motion::Rapid { to }
        };
        let block: Block = self.block(line, motion);
        self.pending.push_back(block);
        self.position = to;
    }
}

/// The line's words with Z and R taken out: the hole's position only.
fn xy_only(w: &LineWords) -> LineWords {
    LineWords {
        axes: [w.axes[0], w.axes[1], None],
        polar: w.polar,
        ..LineWords::default()
    }
}

/// Pecks of depth `d` with pecks of `q` (1 for G81/G82, q infinite): ⌈d / q⌉, a quotient within
/// PECK_COUNT_TOLERANCE of a whole number counting as that number; at least 1.
pub fn peck_count(d: f64, q: f64) -> f64 {
    let n = d / q;
    let whole = n.round();
    let count = if (n - whole).abs() <= PECK_COUNT_TOLERANCE * whole.max(1.0) {
        whole
    } else {
        n.ceil()
    };
    count.max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peck_counts_round_within_the_tolerance() {
        // R1 Z-9 in Q0.001 (mm): 10 mm of 0.001 mm pecks is 10000.000000000002 in binary.
        let unit = 1e-3;
        let d = 1.0 * unit - -9.0 * unit;
        assert_eq!(d / 1e-6, 10_000.000_000_000_002);
        assert_eq!(peck_count(d, 1e-6), 10_000.0);
        assert_eq!(peck_count(10.0e-3, 3e-3), 4.0);
        assert_eq!(peck_count(0.0, 1e-3), 1.0);
        assert_eq!(peck_count(5e-3, f64::INFINITY), 1.0);
        assert_eq!(peck_count(1e-3 * (1.0 + 1e-6), 1e-4), 11.0);
    }
}
