//! G5 cubic spline, G5.1 quadratic spline and the G5.2 … G5.3 NURBS block (LinuxCNC G-code
//! reference, "G5 Cubic Spline", "G5.1 Quadratic Spline", "G5.2 G5.3 NURBS Block"), in the XY
//! plane, turned into arcs and lines as LinuxCNC's interpreter turns them into biarcs
//! (`biarc.rs`), here refined until every piece is within SPLINE_SHARE of the machine's chord
//! tolerance (the smaller of `chord_tolerance_mm` and the G64 / path tolerance in force) of the
//! curve: 0.1 µm at the defaults. The path stage then blends and fits them as any arcs.
//! Control points are kept in machine coordinates (a NURBS is invariant under the rotation and
//! offsets between program and machine), so an open G5.2 block is bounded: MAX_NURBS_POINTS.

use super::biarc::{self, Curve, Piece};
use super::modal::Mode;
use super::nurbs::Nurbs;
use super::words::LineWords;
use super::{LineCodes, Reader};
use crate::error::ProgramError;
use crate::gcode::{Block, Motion, PathMode};
use crate::geometry::Plane;
use serde::{Deserialize, Serialize};

/// Share of the chord tolerance a spline's arcs may deviate from the curve.
pub const SPLINE_SHARE: f64 = 0.1;
/// Smallest approximation tolerance (m): 1 nm, however small the machine's tolerances.
const MIN_SPLINE_TOLERANCE_M: f64 = 1e-9;
/// Most arcs and lines one spline becomes.
pub const MAX_SPLINE_PIECES: usize = 100_000;
/// Most control points of one G5.2 block, and its largest order L.
pub const MAX_NURBS_POINTS: usize = 1000;
/// Range of a G5.2 weight P: positive, and within a factor 1e12 of each other so that the
/// weighted sums stay finite and well-conditioned.
pub const MIN_WEIGHT: f64 = 1e-6;
pub const MAX_WEIGHT: f64 = 1e6;
pub const MAX_NURBS_ORDER: u32 = super::nurbs::MAX_ORDER as u32;

pub fn default_chord_tolerance() -> f64 {
    crate::config::Machine::default().chord_tolerance
}

/// An open G5.2 block: control points (machine x, y, weight), order, where it opened.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OpenNurbs {
    points: Vec<[f64; 3]>,
    order: u32,
    line: u32,
}

/// Spline state: the end control vector of the last G5 (program frame, m) for a G5 without
/// I/J, and the open NURBS block.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Splines {
    pub g5_end: Option<[f64; 2]>,
    nurbs: Option<OpenNurbs>,
}

impl Splines {
    /// A restored state: an open NURBS block within the bounds its words are read with.
    pub(super) fn check_state(&self) -> Result<(), String> {
        use crate::valid::{at_most, point, within, MAX_POSITION_M};
        if let Some(end) = self.g5_end {
            point("G5 end vector", [end[0], end[1], 0.0], MAX_POSITION_M)?;
        }
        let Some(n) = &self.nurbs else {
            return Ok(());
        };
        at_most(
            "NURBS control points",
            n.points.len() as u64,
            MAX_NURBS_POINTS as u64,
        )?;
        within("NURBS order", f64::from(n.order), 2.0, f64::from(MAX_NURBS_ORDER))?;
        for p in &n.points {
            point("NURBS control point", [p[0], p[1], 0.0], MAX_POSITION_M)?;
            within("NURBS weight", p[2], MIN_WEIGHT, MAX_WEIGHT)?;
        }
        Ok(())
    }
}

impl Curve for Nurbs {
    fn point(&self, u: f64) -> [f64; 2] {
        Nurbs::point(self, u)
    }
    fn derivative(&self, u: f64) -> [f64; 2] {
        Nurbs::derivative(self, u)
    }
}

impl Reader {
    /// Checks common to the spline codes: G17, no Z, no cutter compensation, a feed.
    fn spline_checks(&self, line: u32, col: u32, mode: Mode, w: &LineWords) -> Result<(), ProgramError> {
        let name = mode.name();
        if self.plane != Plane::XY {
            return Err(self.error(
                line,
                col,
                format!("{name}: splines run in the G17 (XY) plane only"),
            ));
        }
        if let Some((_, c)) = w.axes[2] {
            return Err(self.error(line, c, format!("{name}: splines move X and Y only, no Z")));
        }
        if self.comp_on() {
            let msg = format!("{name} with cutter compensation on (LinuxCNC: cannot convert spline with cutter radius compensation)");
            return Err(self.error(line, col, msg));
        }
        self.check_feed(line, col, mode, w)
    }

    /// A program-frame offset word pair (program units) as a machine-frame vector (m).
    fn offset_vec(&self, a: Option<(f64, u32)>, b: Option<(f64, u32)>) -> [f64; 2] {
        let v = [a, b].map(|w| w.map_or(0.0, |(v, _)| v * self.unit));
        self.rotate_vec(v)
    }

    /// G5 (cubic: I J from the start to the first control point, P Q from the end to the
    /// second) or G5.1 (quadratic: I J from the start to the control point).
    pub(super) fn spline(
        &mut self,
        line: u32,
        col: u32,
        mode: Mode,
        w: &LineWords,
    ) -> Result<(), ProgramError> {
        self.spline_checks(line, col, mode, w)?;
        let [i, j, _] = w.ijk;
        let start = [self.position[0], self.position[1]];
        let to = self.target(line, w, false)?;
        let end = [to[0], to[1]];
        let add = |p: [f64; 2], v: [f64; 2]| [p[0] + v[0], p[1] + v[1]];
        let controls = if mode == Mode::Cubic {
            let (Some(p), Some(q)) = (w.p, w.extra.q) else {
                return Err(self.error(line, col, "G5 needs both P and Q (the end's control offset)"));
            };
            for (letter, (v, c)) in [(b'P', p), (b'Q', q)] {
                crate::gcode::check::length(letter, v, self.unit).map_err(|m| self.error(line, c, m))?;
            }
            let first = match (i, j, self.spline.g5_end) {
                (Some(_), Some(_), _) => self.offset_vec(i, j),
                (None, None, Some(v)) => self.rotate_vec(v),
                (None, None, None) => {
                    let msg = "G5 needs I and J unless it follows a G5 (LinuxCNC \"G5 Cubic Spline\")";
                    return Err(self.error(line, col, msg));
                }
                _ => {
                    let c = i.or(j).map_or(col, |x| x.1);
                    return Err(self.error(line, c, "G5: give both I and J, or neither"));
                }
            };
            let last = self.offset_vec(Some(p), Some(q));
            self.spline.g5_end = Some([-p.0 * self.unit, -q.0 * self.unit]);
            vec![start, add(start, first), add(end, last), end]
        } else {
            let v = [i, j].map(|x| x.map_or(0.0, |(v, _)| v));
            if v == [0.0, 0.0] {
                let msg = "G5.1 needs I or J, not both zero (LinuxCNC \"G5.1 Quadratic Spline\")";
                return Err(self.error(line, col, msg));
            }
            vec![start, add(start, self.offset_vec(i, j)), end]
        };
        let points: Vec<[f64; 3]> = controls.iter().map(|p| [p[0], p[1], 1.0]).collect();
        self.emit_spline(line, col, &points, controls.len() as u32, w, to)
    }

    /// A line of a G5.2 block: the first opens it (the current point is the first control
    /// point, its weight the P of a G5.2 without X Y), each X Y [P] adds a control point.
    pub(super) fn nurbs_point(
        &mut self,
        line: u32,
        col: u32,
        w: &LineWords,
        first: bool,
    ) -> Result<(), ProgramError> {
        if self.inverse_time {
            let msg = "G5.2 in G93: a NURBS block spans several lines, no one F gives its time; use G94";
            return Err(self.error(line, col, msg));
        }
        self.spline_checks(line, col, Mode::Nurbs, w)?;
        let p = w.p;
        if let Some((v, c)) = p.filter(|(v, _)| !(MIN_WEIGHT..=MAX_WEIGHT).contains(v)) {
            let msg = format!("G5.2: the weight P{v} out of range ({MIN_WEIGHT} … {MAX_WEIGHT})");
            return Err(self.error(line, c, msg));
        }
        let xy = w.axes[0].is_some() && w.axes[1].is_some() || w.polar.iter().any(Option::is_some);
        if !xy && (w.axes[0].is_some() || w.axes[1].is_some()) {
            let c = w.first_axis().unwrap_or(col);
            return Err(self.error(line, c, "G5.2: a control point needs both X and Y"));
        }
        if first || self.spline.nurbs.is_none() {
            let weight = if xy { 1.0 } else { p.map_or(1.0, |x| x.0) };
            self.spline.nurbs = Some(OpenNurbs {
                points: vec![[self.position[0], self.position[1], weight]],
                order: 3,
                line,
            });
        } else if !xy && p.is_some() {
            let msg = "G5.2: P without X Y only for the first control point";
            return Err(self.error(line, col, msg));
        }
        if let Some(l) = w.extra.l {
            let order = self.whole(line, 'L', l, MAX_NURBS_ORDER)?;
            if order < 3 {
                let msg = format!(
                    "G5.2 L{order}: the order must be 3 … {MAX_NURBS_ORDER} (LinuxCNC runs a lower L as 3)"
                );
                return Err(self.error(line, l.1, msg));
            }
            if let Some(n) = self.spline.nurbs.as_mut() {
                n.order = order;
            }
        }
        if xy {
            let to = self.target(line, w, false)?;
            let weight = p.map_or(1.0, |x| x.0);
            let full = self
                .spline
                .nurbs
                .as_ref()
                .is_some_and(|n| n.points.len() >= MAX_NURBS_POINTS);
            if full {
                let msg = format!("G5.2: more than {MAX_NURBS_POINTS} control points in one block");
                return Err(self.error(line, col, msg));
            }
            if let Some(n) = self.spline.nurbs.as_mut() {
                n.points.push([to[0], to[1], weight]);
            }
        }
        Ok(())
    }

    /// G5.3: the NURBS block's curve, ending at its last control point; no motion mode after.
    pub(super) fn nurbs_end(&mut self, line: u32, col: u32) -> Result<(), ProgramError> {
        let open = self
            .spline
            .nurbs
            .take()
            .filter(|_| self.motion == Some(Mode::Nurbs));
        let Some(n) = open else {
            return Err(self.error(
                line,
                col,
                "G5.3 without G5.2 first (LinuxCNC \"G5.2 G5.3 NURBS Block\")",
            ));
        };
        if n.points.len() < n.order as usize {
            let msg = format!(
                "G5.3: the NURBS block of line {} has {} control points, fewer than its order L{}",
                n.line,
                n.points.len(),
                n.order
            );
            return Err(self.error(line, col, msg));
        }
        self.motion = None;
        let last = n.points[n.points.len() - 1];
        let to = [last[0], last[1], self.position[2]];
        self.emit_spline(line, col, &n.points, n.order, &LineWords::default(), to)
    }

    /// The arcs and lines of the spline with control points `points` and order `k`, from the
    /// current position to `to`, queued with the feed of the move (G93: 1/F minutes for all).
    fn emit_spline(
        &mut self,
        line: u32,
        col: u32,
        points: &[[f64; 3]],
        k: u32,
        w: &LineWords,
        to: crate::Vec3,
    ) -> Result<(), ProgramError> {
        let Some(curve) = Nurbs::new(points, k as usize) else {
            return Err(self.error(line, col, "spline: bad control points"));
        };
        let mut breaks = vec![0.0];
        breaks.extend(curve.breaks());
        breaks.push(curve.u_max());
        let tol = self.spline_tolerance();
        // LinuxCNC divides into 4 per control point; here 4 per knot span, then refines.
        let pieces = biarc::fit(&curve, &breaks, 4, tol, MAX_SPLINE_PIECES).map_err(|_| {
            let msg = format!(
                "spline: more than {MAX_SPLINE_PIECES} arcs within {} mm (check its control points)",
                tol * 1e3
            );
            self.error(line, col, msg)
        })?;
        if pieces.iter().any(|p| !p.to().iter().all(|x| x.is_finite())) {
            return Err(self.error(
                line,
                col,
                "spline: the curve is not finite (check its control points)",
            ));
        }
        let z = self.position[2];
        let mut blocks: Vec<Block> = Vec::with_capacity(pieces.len());
        let mut from = self.position;
        for (i, piece) in pieces.iter().enumerate() {
            let end = if i + 1 == pieces.len() {
                to
            } else {
                [piece.to()[0], piece.to()[1], z]
            };
            let motion = match *piece {
                Piece::Line { .. } => Motion::Linear { to: end },
                Piece::Arc { center, ccw, .. } => Motion::Arc {
                    to: end,
                    center: [center[0], center[1], 0.0],
                    plane: Plane::XY,
                    clockwise: !ccw,
                    turns: 0,
                },
            };
            blocks.push(Block {
                from,
                ..self.block(line, motion)
            });
            from = end;
        }
        if !blocks.is_empty() {
            self.timed(line, col, w, &mut blocks)?;
        }
        self.position = to;
        self.pending.extend(blocks);
        Ok(())
    }

    /// The approximation tolerance: SPLINE_SHARE of the smaller of the chord tolerance and the
    /// G64 P in force, at least MIN_SPLINE_TOLERANCE_M.
    fn spline_tolerance(&self) -> f64 {
        let g64 = match self.path_mode {
            PathMode::Blend {
                tolerance: Some(p), ..
            } if p > 0.0 => p,
            _ => f64::INFINITY,
        };
        (SPLINE_SHARE * self.chord_tolerance.min(g64)).max(MIN_SPLINE_TOLERANCE_M)
    }

    /// Between G5.2 and G5.3 only G5.2 control points (LinuxCNC "G5.2 G5.3 NURBS Block").
    pub(super) fn check_nurbs_open(&self, line: u32, codes: &LineCodes) -> Result<(), ProgramError> {
        let Some(n) = &self.spline.nurbs else {
            return Ok(());
        };
        let other = codes
            .motion
            .filter(|m| m.0 != Mode::Nurbs)
            .map(|m| (m.0.name(), m.1))
            .or(codes.cancel.map(|c| ("G80".to_string(), c)));
        if let Some((name, c)) = other {
            let msg = format!(
                "{name} inside the NURBS block opened on line {} (close it with G5.3 first)",
                n.line
            );
            return Err(self.error(line, c, msg));
        }
        Ok(())
    }

    /// At the end of the program (or its closing `%`): no NURBS block left open.
    pub(super) fn check_spline_closed(&self) -> Result<(), ProgramError> {
        match &self.spline.nurbs {
            Some(n) => Err(self.error(
                n.line,
                1,
                "G5.2 NURBS block not closed by G5.3 before the end of the program",
            )),
            None => Ok(()),
        }
    }
}
