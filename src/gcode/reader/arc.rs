//! G2/G3: the centre from I/J/K (end points off the circle within the tolerance are moved
//! onto it) or from R (LinuxCNC "G2, G3": "Center Format Arcs", "Radius Format Arcs").

use super::words::LineWords;
use super::{Reader, ARC_TOLERANCE_REL};
use crate::error::ProgramError;
use crate::gcode::{check, Block, Motion};
use crate::geometry::Plane;
use crate::Vec3;

impl Reader {
    /// G2/G3 in the current plane, centre by I/J/K (relative or absolute) or by R.
    pub(super) fn arc(
        &self,
        line: u32,
        col: u32,
        clockwise: bool,
        to: Vec3,
        w: &LineWords,
    ) -> Result<Block, ProgramError> {
        let (ijk, r, p) = (w.ijk, w.r, w.p);
        let name = if clockwise { "G2" } else { "G3" };
        let n = self.plane.axes().2;
        // G18/G19 of a rotated system: the arc is found in program coordinates, its plane turned
        // with the XY axes about Z (LinuxCNC's canon turns the end, the centre and the plane's
        // axes alike), so it lies in a vertical plane that is not one of the machine's.
        let turned = self.plane != Plane::XY && self.rotation().rem_euclid(360.0) != 0.0;
        let (from, end) = if turned {
            (self.to_program(self.position), self.to_program(to))
        } else {
            (self.position, to)
        };
        // The centre word not in the plane (K in G17, J in G18, I in G19) is an error.
        if let Some((_, c)) = ijk[n] {
            let letter = [b'I', b'J', b'K'][n] as char;
            return Err(self.error(line, c, format!("{letter} is not a centre word in this plane")));
        }
        let turns = match p {
            None => 0,
            Some((v, pc)) => check::turns(name, v).map_err(|m| self.error(line, pc, m))?,
        };
        let at = (line, col, name);
        let center = if ijk.iter().any(Option::is_some) {
            if r.is_some() {
                return Err(self.error(line, col, format!("{name}: give either I/J/K or R, not both")));
            }
            self.center_by_offsets(at, [from, end], &ijk, turned)?
        } else if let Some(r) = r {
            self.center_by_radius(at, clockwise, [from, end], r)?
        } else {
            let words = ["J/K", "I/K", "I/J"][n];
            let msg = format!("{name} needs a centre ({words}) or a radius (R)");
            return Err(self.error(line, col, msg));
        };
        let (center, plane) = if turned {
            let mut c = center;
            c[n] = from[n];
            let (cos, sin) = super::frame::cos_sin(self.rotation());
            let yz = self.plane == Plane::YZ;
            (self.to_machine(c), Plane::Turned { yz, cos, sin })
        } else {
            (center, self.plane)
        };
        let motion = Motion::Arc {
            to,
            center,
            plane,
            clockwise,
            turns,
        };
        Ok(self.block(line, motion))
    }

    /// The centre from I/J/K; an end point off the circle within the tolerance moves the centre
    /// onto the chord's bisector. `from`, `to` and the centre are machine points, or program
    /// points where `program` (a turned plane).
    fn center_by_offsets(
        &self,
        (line, col, name): (u32, u32, &str),
        [from, to]: [Vec3; 2],
        ijk: &[Option<(f64, u32)>; 3],
        program: bool,
    ) -> Result<Vec3, ProgramError> {
        let (a, b, n) = self.plane.axes();
        let mut center = from;
        let words = ijk.map(|w| w.map_or(0.0, |(v, _)| v * self.unit));
        if program {
            for &i in &[a, b] {
                center[i] = if self.arc_absolute {
                    words[i]
                } else {
                    from[i] + words[i]
                };
            }
        } else if self.arc_absolute {
            // G90.1: I/J/K are a point of the current system (LinuxCNC "G90.1, G91.1").
            let mut p = self.to_program(from);
            for &i in &[a, b] {
                p[i] = words[i];
            }
            let m = self.to_machine(p);
            (center[a], center[b]) = (m[a], m[b]);
        } else if self.plane == Plane::XY {
            let v = self.rotate_vec([words[0], words[1]]);
            (center[0], center[1]) = (from[0] + v[0], from[1] + v[1]);
        } else {
            for &i in &[a, b] {
                center[i] = from[i] + words[i];
            }
        }
        center[n] = 0.0;
        let r1 = (from[a] - center[a]).hypot(from[b] - center[b]);
        let r2 = (to[a] - center[a]).hypot(to[b] - center[b]);
        if r1 <= 0.0 {
            let msg = format!("{name}: the centre is the start point (radius zero)");
            return Err(self.error(line, col, msg));
        }
        let miss = (r1 - r2).abs();
        let tolerance_abs = self.arc_tolerance_abs();
        if miss > tolerance_abs && miss > ARC_TOLERANCE_REL * r1 {
            let msg = format!(
                "{name}: end point is {:.4} mm off the circle (radius {:.4} mm at the start, {:.4} mm at the end; \
                 tolerance {:.4} mm or {} % of the radius, machine key arc_radius_tolerance_mm)",
                miss * 1e3,
                r1 * 1e3,
                r2 * 1e3,
                tolerance_abs * 1e3,
                ARC_TOLERANCE_REL * 100.0
            );
            return Err(self.error(line, col, msg));
        }
        let (chord_a, chord_b) = (to[a] - from[a], to[b] - from[b]);
        let chord = chord_a.hypot(chord_b);
        if chord > 0.0 && miss > 0.0 {
            // Within tolerance: move the centre onto the chord's bisector (by at most the
            // tolerance), so the arc is an exact circle through both end points.
            let (ua, ub) = (chord_a / chord, chord_b / chord);
            let (ma, mb) = (0.5 * (from[a] + to[a]), 0.5 * (from[b] + to[b]));
            let along = (center[a] - ma) * ua + (center[b] - mb) * ub;
            center[a] -= along * ua;
            center[b] -= along * ub;
        }
        Ok(center)
    }

    /// The centre from R: at most half a circle for R > 0, the larger arc for R < 0.
    fn center_by_radius(
        &self,
        (line, _, name): (u32, u32, &str),
        clockwise: bool,
        [from, to]: [Vec3; 2],
        (rv, rc): (f64, u32),
    ) -> Result<Vec3, ProgramError> {
        let (a, b, n) = self.plane.axes();
        let mut center = from;
        center[n] = 0.0;
        let (chord_a, chord_b) = (to[a] - from[a], to[b] - from[b]);
        let chord = chord_a.hypot(chord_b);
        let radius = rv.abs() * self.unit;
        if chord == 0.0 {
            return Err(self.error(line, rc, format!("{name}: a full circle needs I/J/K, not R")));
        }
        if radius <= 0.0 {
            return Err(self.error(line, rc, format!("{name}: R must not be zero")));
        }
        let half = 0.5 * chord;
        if half > radius * (1.0 + 1e-12) + self.arc_tolerance_abs() {
            let msg = format!(
                "{name}: R{} is smaller than half the chord ({:.4} mm)",
                rv,
                half / self.unit
            );
            return Err(self.error(line, rc, msg));
        }
        let h = (radius * radius - half * half).max(0.0).sqrt();
        // Left normal of the chord; G3 with R > 0 (at most half a circle) has its centre on
        // the left, G2 on the right; R < 0 asks for the larger arc, centre on the other side.
        let (la, lb) = (-chord_b / chord, chord_a / chord);
        let side = if clockwise { -1.0 } else { 1.0 } * if rv < 0.0 { -1.0 } else { 1.0 };
        center[a] = 0.5 * (from[a] + to[a]) + side * h * la;
        center[b] = 0.5 * (from[b] + to[b]) + side * h * lb;
        Ok(center)
    }

    /// The absolute arc tolerance in force: the machine's for G21, 2.54 times it for G20
    /// (0.028 mm → 0.0028 in, as LinuxCNC's two constants).
    fn arc_tolerance_abs(&self) -> f64 {
        if self.unit > 1e-3 {
            self.arc_tolerance * 2.54
        } else {
            self.arc_tolerance
        }
    }
}
