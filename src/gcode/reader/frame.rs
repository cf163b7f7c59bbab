//! Program ↔ machine coordinates and the end point of a move (LinuxCNC G-code reference,
//! "Coordinate Systems", "G10 L2" (R: rotation of the XY axes about Z), "G92", "G53", "Tool
//! Length Offsets", "Polar Coordinates"). The offsets compose as LinuxCNC's canonical layer
//! composes them (emccanon `rotate_and_offset`):
//!
//!   machine = R(θ)·(program + G92 offset) + work offset + tool length (Z),
//!
//! θ the rotation of the active system (degrees, counter-clockwise about +Z). The reader keeps
//! the machine position; the program position is this map inverted.

use super::words::LineWords;
use super::Reader;
use crate::error::ProgramError;
use crate::gcode::check;
use crate::geometry::Plane;
use crate::Vec3;

/// cos θ and sin θ of `deg` degrees, exact at multiples of 90° (a rotation by R90 moves X5 to
/// exactly Y5, as the documentation's examples read).
pub fn cos_sin(deg: f64) -> (f64, f64) {
    let d = deg.rem_euclid(360.0);
    if d == 0.0 {
        (1.0, 0.0)
    } else if d == 90.0 {
        (0.0, 1.0)
    } else if d == 180.0 {
        (-1.0, 0.0)
    } else if d == 270.0 {
        (0.0, -1.0)
    } else {
        let t = d.to_radians();
        (t.cos(), t.sin())
    }
}

/// `v` rotated by the angle whose cosine and sine are `cs`.
pub fn rotate(v: [f64; 2], (c, s): (f64, f64)) -> [f64; 2] {
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

impl Reader {
    /// Rotation (degrees) of the active coordinate system.
    pub(super) fn rotation(&self) -> f64 {
        self.nc.work_rotation[self.work]
    }

    pub(super) fn rotated(&self) -> bool {
        self.rotation().rem_euclid(360.0) != 0.0
    }

    fn g92(&self) -> Vec3 {
        if self.g92_on {
            self.g92
        } else {
            [0.0; 3]
        }
    }

    /// A vector of the program's XY (an I/J or G5 control offset, m) in machine axes.
    pub(super) fn rotate_vec(&self, v: [f64; 2]) -> [f64; 2] {
        rotate(v, cos_sin(self.rotation()))
    }

    /// Machine coordinates (m) of a program point (m).
    pub(super) fn to_machine(&self, p: Vec3) -> Vec3 {
        let (g92, off) = (self.g92(), self.nc.work_offsets[self.work]);
        let xy = rotate([p[0] + g92[0], p[1] + g92[1]], cos_sin(self.rotation()));
        [
            xy[0] + off[0],
            xy[1] + off[1],
            p[2] + g92[2] + off[2] + self.tool.length,
        ]
    }

    /// Program coordinates (m) of a machine point (m).
    pub(super) fn to_program(&self, m: Vec3) -> Vec3 {
        self.to_program_in(self.work, m)
    }

    /// Program coordinates (m) of a machine point (m) in work system `system`.
    pub(super) fn to_program_in(&self, system: usize, m: Vec3) -> Vec3 {
        let (g92, off) = (self.g92(), self.nc.work_offsets[system]);
        let (c, s) = cos_sin(self.nc.work_rotation[system]);
        let xy = rotate([m[0] - off[0], m[1] - off[1]], (c, -s));
        [
            xy[0] - g92[0],
            xy[1] - g92[1],
            m[2] - off[2] - g92[2] - self.tool.length,
        ]
    }

    /// End point (machine, m) of a move from the axis and polar words: G53 machine coordinates,
    /// G90 program coordinates, G91 increments; each axis within the coordinate range.
    pub(super) fn target(&self, line: u32, w: &LineWords, machine: bool) -> Result<Vec3, ProgramError> {
        let axes = &w.axes;
        let mut to = self.position;
        let polar = w.polar.iter().any(Option::is_some);
        if machine {
            for (i, a) in axes.iter().enumerate() {
                if let Some((v, _)) = a {
                    to[i] = v * self.unit;
                }
            }
        } else if !self.rotated() && !polar {
            // The program origin in machine axes, worked out once for the axes given.
            let origin = match self.absolute {
                true => self.to_machine([0.0; 3]),
                false => [0.0; 3],
            };
            // Axis by axis, so an axis not programmed keeps its position exactly.
            for (i, a) in axes.iter().enumerate() {
                if let Some((v, _)) = a {
                    to[i] = if self.absolute {
                        v * self.unit + origin[i]
                    } else {
                        self.position[i] + v * self.unit
                    };
                }
            }
        } else {
            let mut p = self.to_program(self.position);
            for (i, a) in axes.iter().enumerate() {
                if let Some((v, _)) = a {
                    p[i] = if self.absolute {
                        v * self.unit
                    } else {
                        p[i] + v * self.unit
                    };
                }
            }
            if polar {
                [p[0], p[1]] = self.polar(line, w, [p[0], p[1]])?;
            }
            let m = self.to_machine(p);
            if axes[0].is_some() || axes[1].is_some() || polar {
                (to[0], to[1]) = (m[0], m[1]);
            }
            if axes[2].is_some() {
                to[2] = m[2];
            }
        }
        self.check_position(line, w, &to)?;
        Ok(to)
    }

    /// Every programmed axis of `to` within the coordinate range.
    pub(super) fn check_position(&self, line: u32, w: &LineWords, to: &Vec3) -> Result<(), ProgramError> {
        let polar_col = w.polar.iter().flatten().map(|p| p.1).min();
        for i in 0..3 {
            let col = w.axes[i].map(|a| a.1).or(if i < 2 { polar_col } else { None });
            if let Some(c) = col.filter(|_| to[i].abs() > check::MAX_COORDINATE_M) {
                let msg = format!(
                    "{} moves the axis to {} mm: out of range (|position| ≤ {} mm)",
                    [b'X', b'Y', b'Z'][i] as char,
                    to[i] * 1e3,
                    check::MAX_COORDINATE_M * 1e3
                );
                return Err(self.error(line, c, msg));
            }
        }
        Ok(())
    }

    /// The XY end point (program, m) of polar words `@` (distance) and `^` (angle, degrees)
    /// from the XY zero of the current system (LinuxCNC "Polar Coordinates"): in G90 a missing
    /// word keeps the current distance or angle, in G91 both add to the current ones.
    /// `cur` is the program XY before the move.
    pub(super) fn polar(&self, line: u32, w: &LineWords, cur: [f64; 2]) -> Result<[f64; 2], ProgramError> {
        let [at, caret] = w.polar;
        let col = [at, caret].iter().flatten().map(|p| p.1).min().unwrap_or(1);
        if let Some((_, c)) = w.axes[0].or(w.axes[1]) {
            let msg = "polar coordinates (@ ^) and X or Y on one line (LinuxCNC \"Polar Coordinates\")";
            return Err(self.error(line, c, msg));
        }
        if self.plane != Plane::XY {
            return Err(self.error(line, col, "polar coordinates (@ ^) only in the G17 (XY) plane"));
        }
        let at_origin = cur == [0.0, 0.0];
        let (r0, t0) = (cur[0].hypot(cur[1]), cur[1].atan2(cur[0]));
        let (r, t) = if self.absolute {
            if at_origin && at.is_some() && caret.is_none() {
                let msg =
                    "@ without ^ at the XY origin: the angle is undefined (LinuxCNC \"Polar Coordinates\")";
                return Err(self.error(line, col, msg));
            }
            (
                at.map_or(r0, |(v, _)| v * self.unit),
                caret.map_or(t0, |(v, _)| v.to_radians()),
            )
        } else {
            if at_origin {
                let msg = "G91 polar move from the XY origin: the angle is undefined (LinuxCNC \"Polar Coordinates\")";
                return Err(self.error(line, col, msg));
            }
            (
                r0 + at.map_or(0.0, |(v, _)| v * self.unit),
                t0 + caret.map_or(0.0, |(v, _)| v.to_radians()),
            )
        };
        let (c, s) = match caret {
            // Exact at multiples of 90° in G90 (`G1 @1 ^90` is `G1 Y1`).
            Some((v, _)) if self.absolute => cos_sin(v),
            _ => (t.cos(), t.sin()),
        };
        Ok([r * c, r * s])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_are_exact_at_right_angles() {
        assert_eq!(rotate([5.0, 0.0], cos_sin(90.0)), [0.0, 5.0]);
        assert_eq!(rotate([5.0, 0.0], cos_sin(-90.0)), [0.0, -5.0]);
        assert_eq!(rotate([1.0, 2.0], cos_sin(540.0)), [-1.0, -2.0]);
        let [x, y] = rotate([1.0, 0.0], cos_sin(30.0));
        assert!((x - 3f64.sqrt() / 2.0).abs() < 1e-15 && (y - 0.5).abs() < 1e-15);
    }
}
