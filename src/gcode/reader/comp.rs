//! Cutter radius compensation G41/G42/G40, G41.1/G42.1 (LinuxCNC G-code reference "G40",
//! "G41, G42", "G41.1, G42.1"; Siemens 840D G450/G451), on the reader's machine-coordinate
//! blocks with one element of look-ahead: an element is emitted once the next one fixes its
//! corner. Entry: the G41/G42 move (a line) ends on the offset start of the next element,
//! perpendicular to it; exit: the last element ends perpendicular at its end, then the G40 move
//! goes to its programmed point. Inside corners: intersection of the offset elements; outside
//! corners: a transition arc about the corner (G450) or the tangents extended (G451).

use super::comp_geom::{entry_arc_center, intersect, Curve, Elem, EntryArc, JOIN};
use super::Reader;
use crate::config::CutterCorner;
use crate::error::ProgramError;
use crate::gcode::{check, Block, Motion, StopKind};
use crate::geometry::vec2::{along, cross, dist, dot, P2};
use crate::geometry::Plane;
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Most blocks without motion in the plane (Z moves, dwells, stops) held while compensating.
const MAX_DEFERRED: usize = 64;

/// Compensation mode and the blocks held for the look-ahead (bounded: one element, one entry
/// move, at most MAX_DEFERRED blocks between).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Comp {
    /// +1 G41 (tool left of the path), −1 G42, 0 G40.
    side: f64,
    /// Side of the held element (G40 may have come since).
    held_side: f64,
    held_radius: f64,
    radius: f64,
    plane: Plane,
    entry: Option<Block>,
    held: Option<Block>,
    /// In-plane centre of the tool path of the held element when it is an entry arc (LinuxCNC
    /// `convert_arc_comp1`): not the programmed centre.
    held_center: Option<P2>,
    deferred: Vec<Block>,
    out: VecDeque<Block>,
    tool: Vec3,
    finished: bool,
}

impl Comp {
    /// A restored state: sides ±1 or 0, radii in range, the held blocks ones the look-ahead
    /// holds (the held element moves in the plane), at most MAX_DEFERRED blocks between.
    pub(super) fn check_state(&self) -> Result<(), String> {
        use crate::valid::{at_most, point, within, MAX_POSITION_M};
        for side in [self.side, self.held_side] {
            if ![-1.0, 0.0, 1.0].contains(&side) {
                return Err(format!("cutter compensation side {side}"));
            }
        }
        within("compensation radius", self.radius, 0.0, MAX_POSITION_M)?;
        within("compensation radius", self.held_radius, 0.0, MAX_POSITION_M)?;
        point("compensation tool point", self.tool, MAX_POSITION_M)?;
        if let Some(c) = self.held_center {
            if self.held.is_none() {
                return Err("an entry arc's centre without its element".into());
            }
            point("entry arc centre", [c[0], c[1], 0.0], MAX_POSITION_M)?;
        }
        at_most("deferred blocks", self.deferred.len() as u64, MAX_DEFERRED as u64)?;
        let (a, b, _) = self.plane.axes();
        if self.held.is_some_and(|h| Elem::of(&h, a, b).is_none()) {
            return Err("the held compensation element does not move in its plane".into());
        }
        let mut blocks = self
            .entry
            .iter()
            .chain(&self.held)
            .chain(&self.deferred)
            .chain(&self.out);
        blocks.try_for_each(Block::check_state)
    }
}

impl Reader {
    /// G40 / G41 / G42 (D: tool number, radius from the table) / G41.1 / G42.1 (D: the tool
    /// diameter, LinuxCNC "G41.1, G42.1": "the ability to program the tool diameter").
    pub(super) fn set_comp(
        &mut self,
        line: u32,
        code: i64,
        col: u32,
        d: Option<(f64, u32)>,
    ) -> Result<(), ProgramError> {
        if code == 400 {
            self.comp.side = 0.0;
            return Ok(());
        }
        let side = if code == 410 || code == 411 { 1.0 } else { -1.0 };
        let radius = if code == 411 || code == 421 {
            let Some((v, c)) = d else {
                return Err(self.error(line, col, "G41.1/G42.1 needs D (the tool diameter)"));
            };
            if v < 0.0 {
                return Err(self.error(line, c, "D (tool diameter) must not be negative"));
            }
            0.5 * check::length(b'D', v, self.unit).map_err(|m| self.error(line, c, m))?
        } else {
            // D (LinuxCNC: the tool number; 840D: the loaded tool's edge), else the loaded tool.
            let n = self.tool.d.unwrap_or(self.tool.loaded);
            let at = d.map_or(col, |(_, c)| c);
            self.tool_entry(line, 'D', (n as f64, at))?.radius
        };
        if self.comp.side != 0.0 && (self.comp.side != side || self.comp.radius != radius) {
            let m = "cutter compensation is already on: cancel it with G40 before changing side or radius";
            return Err(self.error(line, col, m));
        }
        self.comp.side = side;
        self.comp.radius = radius;
        self.comp.plane = self.plane;
        Ok(())
    }

    /// Whether G41/G42 is in force.
    pub(super) fn comp_on(&self) -> bool {
        self.comp.side != 0.0
    }

    /// Next block after cutter compensation.
    pub(super) fn next_compensated(&mut self) -> Result<Option<Block>, ProgramError> {
        loop {
            if let Some(b) = self.comp.out.pop_front() {
                return Ok(Some(b));
            }
            if self.comp.finished {
                return Ok(None);
            }
            let idle = self.comp.entry.is_none() && self.comp.held.is_none();
            match self.next_raw()? {
                Some(b) if idle && self.comp.side == 0.0 => return Ok(Some(b)),
                Some(b) => self.compensate(b)?,
                None => {
                    self.finish_held()?;
                    self.comp.finished = true;
                }
            }
        }
    }

    fn compensate(&mut self, b: Block) -> Result<(), ProgramError> {
        let (a, bb, _) = self.comp.plane.axes();
        let Some(elem) = Elem::of(&b, a, bb) else {
            return self.not_in_plane(b);
        };
        if self.comp.side != 0.0 && self.plane != self.comp.plane {
            let m = "the plane changed while cutter compensation is on (G40 first)";
            return Err(self.error(b.line, 1, m));
        }
        if self.comp.side != 0.0 && self.comp.plane != Plane::XY && self.rotated() {
            // The offsets are taken in the machine's plane; a turned G18/G19 plane is none.
            let m = format!(
                "cutter compensation in G18/G19 while the coordinate system is rotated (R{}): \
                 the rotated plane is not one of the machine's",
                self.rotation()
            );
            return Err(self.error(b.line, 1, m));
        }
        let (side, r) = (self.comp.side, self.comp.radius);
        self.check_arc_radius(&b, &elem)?;
        if let Some(entry) = self.comp.entry.take() {
            if side == 0.0 {
                self.emit(entry, None);
                self.flush_deferred();
                self.emit_plain(b);
            } else {
                let s2 = elem.offset_point(elem.start(), side, r);
                self.emit(entry, Some(s2));
                self.flush_deferred();
                self.comp.held = Some(b);
                (self.comp.held_side, self.comp.held_radius) = (side, r);
            }
        } else if let Some(held) = self.comp.held.take() {
            if side == 0.0 {
                if matches!(b.motion, Motion::Arc { .. }) {
                    return Err(self.error(b.line, 1, "the G40 exit move must be a straight line (G0/G1)"));
                }
                self.end_held(held, None);
                self.flush_deferred();
                self.emit_plain(b);
            } else {
                self.corner(held, b, elem)?;
            }
        } else if side != 0.0 {
            self.comp.tool = b.from;
            if matches!(b.motion, Motion::Arc { .. }) {
                return self.entry_arc(b, &elem);
            }
            let length = dist(elem.start(), elem.end());
            if length <= r + JOIN {
                // LinuxCNC "G41, G42": "The lead in move must be at least as long as the tool
                // radius"; its interpreter refuses one not longer.
                let m = format!(
                    "the G41/G42 entry move is {} mm long, not longer than the tool radius {} mm \
                     (LinuxCNC: \"Length of cutter compensation entry move is not greater than the tool radius\")",
                    shown_mm(length),
                    shown_mm(r)
                );
                return Err(self.error(b.line, 1, m));
            }
            self.comp.entry = Some(b);
        } else {
            self.emit_plain(b);
        }
        Ok(())
    }

    /// A G41/G42 entry move that is an arc (LinuxCNC "Cutter Compensation", "Programming Entry
    /// Moves": any move at least the tool radius long; `convert_arc_comp1`): the tool runs from
    /// where it is on an arc turning as programmed to the perpendicular offset of the
    /// programmed end, arriving along the offset contour; the arc is then held as any element,
    /// its end fixed by the corner that follows.
    fn entry_arc(&mut self, b: Block, elem: &Elem) -> Result<(), ProgramError> {
        let (side, r) = (self.comp.side, self.comp.radius);
        let Elem::Arc { center, .. } = *elem else {
            return Ok(());
        };
        let (s, p) = (self.plane_of(b.from), elem.end());
        if dist(s, p) <= r + JOIN {
            let m = format!(
                "the G41/G42 entry arc ends {} mm from its start, not farther than the tool radius {} mm \
                 (LinuxCNC: \"Radius of cutter compensation entry arc is not greater than the tool radius\")",
                shown_mm(dist(s, p)),
                shown_mm(r)
            );
            return Err(self.error(b.line, 1, m));
        }
        let a = elem.offset_point(p, side, r);
        let c = entry_arc_center(s, a, center).map_err(|why| {
            let m = match why {
                EntryArc::Backwards => {
                    "the G41/G42 entry arc starts behind the tangent at its offset end: the tool would loop \
                     round and arrive against the contour's direction (gouge); lead in on a longer arc or a line"
                }
                EntryArc::Flat => {
                    "the G41/G42 entry arc's tool path would be nearly straight (LinuxCNC: \"Tool radius not \
                     less than arc radius with comp\"); lead in on a line"
                }
            };
            self.error(b.line, 1, m)
        })?;
        self.comp.held = Some(b);
        self.comp.held_center = Some(c);
        (self.comp.held_side, self.comp.held_radius) = (side, r);
        Ok(())
    }

    /// The held element's tool path where it is not the programmed one's offset: the entry
    /// arc from the tool's position to the offset end `p1`.
    fn held_path(&self, e1: &Elem, p1: P2) -> Option<Elem> {
        let (c, Elem::Arc { cw, .. }) = (self.comp.held_center?, *e1) else {
            return None;
        };
        Some(Elem::Arc {
            start: self.plane_of(self.comp.tool),
            end: p1,
            center: c,
            radius: dist(c, p1),
            cw,
        })
    }

    /// A block without motion in the plane: held back while an element waits for its corner.
    /// After G40 a move without motion in the plane is the exit move all the same: LinuxCNC's
    /// `convert_cutter_compensation_off` ends the held element at the compensated point and
    /// takes the programmed one for the current point, so the next move, even along Z alone,
    /// brings the tool back to the programmed point.
    fn not_in_plane(&mut self, b: Block) -> Result<(), ProgramError> {
        let exit = self.comp.side == 0.0 && matches!(b.motion, Motion::Rapid { .. } | Motion::Linear { .. });
        if matches!(b.motion, Motion::Stop(StopKind::End)) {
            self.finish_held()?;
            self.emit(b, None);
        } else if let Some(held) = exit.then(|| self.comp.held.take()).flatten() {
            self.end_held(held, None);
            self.flush_deferred();
            self.emit_plain(b);
        } else if self.comp.entry.is_some() || self.comp.held.is_some() {
            if self.comp.deferred.len() >= MAX_DEFERRED {
                let m =
                    format!("more than {MAX_DEFERRED} blocks without motion in the plane while compensating");
                return Err(self.error(b.line, 1, m));
            }
            self.comp.deferred.push(b);
        } else {
            self.comp.tool = b.from;
            self.emit(b, None);
        }
        Ok(())
    }

    /// An arc whose offset radius on the tool's side vanishes (within JOIN) is a gouge
    /// (LinuxCNC: "tool radius not less than arc radius with comp").
    fn check_arc_radius(&self, b: &Block, elem: &Elem) -> Result<(), ProgramError> {
        let (side, r) = (self.comp.side, self.comp.radius);
        if side == 0.0 {
            return Ok(());
        }
        if let (Some(rr), Elem::Arc { radius, .. }) = (elem.offset_radius(side, r), elem) {
            if rr <= JOIN {
                let relation = if rr < -JOIN { "smaller than" } else { "equal to" };
                let (a, t) = shown_pair(*radius, r);
                let m = format!(
                    "arc radius {a} mm is {relation} the tool radius {t} mm on the tool's side: \
                     the tool cannot follow it (gouge)"
                );
                return Err(self.error(b.line, 1, m));
            }
        }
        Ok(())
    }

    /// The corner between the held element and the next one `next` (its plane element `e2`).
    fn corner(&mut self, held: Block, next: Block, e2: Elem) -> Result<(), ProgramError> {
        let (a, b, _) = self.comp.plane.axes();
        let (side, r) = (self.comp.side, self.comp.radius);
        let e1 = Elem::of(&held, a, b).expect("held blocks move in the plane");
        let c = e1.end();
        let (t1, t2) = (e1.tangent(c), e2.tangent(c));
        let (p1, p2) = (e1.offset_point(c, side, r), e2.offset_point(c, side, r));
        let turn = cross(t1, t2);
        if dist(p1, p2) < JOIN {
            self.end_held(held, Some(p1));
        } else if side * turn > 0.0 {
            let curve = |e: &Elem, t: P2, p: P2| match e.offset_radius(side, r) {
                None => Curve::Line(p, t),
                Some(rr) => match *e {
                    Elem::Arc { center, .. } => Curve::Circle(center, rr),
                    Elem::Line { .. } => unreachable!(),
                },
            };
            // An entry arc's tool path is its own circle, and it runs as itself.
            let path1 = self.held_path(&e1, p1);
            let curve1 = match path1 {
                Some(Elem::Arc { center, radius, .. }) => Curve::Circle(center, radius),
                _ => curve(&e1, t1, p1),
            };
            let mid = [(p1[0] + p2[0]) / 2.0, (p1[1] + p2[1]) / 2.0];
            let x = intersect(&curve1, &curve(&e2, t2, p2), mid);
            let start1 = self.plane_of(self.comp.tool);
            let end2 = e2.offset_point(e2.end(), side, r);
            let forward1 = |x: P2| match &path1 {
                Some(p) => p.runs_forward(start1, x),
                None => e1.runs_forward(start1, x),
            };
            let reachable = x.filter(|x| forward1(*x) && e2.runs_forward(*x, end2));
            let Some(x) = reachable else {
                let m = format!(
                    "concave corner cannot be reached by the tool (radius {} mm): the offset elements do not meet (gouge)",
                    shown_mm(r)
                );
                return Err(self.error(next.line, 1, m));
            };
            self.end_held(held, Some(x));
        } else {
            self.outside_corner(held, &e1, &e2, c, p1, p2);
        }
        self.flush_deferred();
        self.comp.held = Some(next);
        (self.comp.held_side, self.comp.held_radius) = (side, r);
        Ok(())
    }

    /// An outside corner: transition arc (G450) or extended tangents (G451).
    fn outside_corner(&mut self, held: Block, e1: &Elem, e2: &Elem, c: P2, p1: P2, p2: P2) {
        let (side, r) = (self.comp.side, self.comp.radius);
        let (t1, t2) = (e1.tangent(c), e2.tangent(c));
        let piece = |reader: &Reader, motion: Motion| Block {
            motion,
            ..reader.piece_of(&held)
        };
        // A rapid has no programmed feed for an arc: its outside corners are extended lines.
        let rapid = matches!(held.motion, Motion::Rapid { .. });
        if self.corner == CutterCorner::Arc && !rapid {
            self.end_held(held, Some(p1));
            let (a, b, _) = self.comp.plane.axes();
            let mut center = [0.0; 3];
            center[a] = c[0];
            center[b] = c[1];
            let to = self.point3(p2);
            let arc = Motion::Arc {
                to,
                center,
                plane: self.comp.plane,
                clockwise: side > 0.0,
                turns: 0,
            };
            let blk = piece(self, arc);
            self.emit(blk, None);
            return;
        }
        let (ea, eb) = if dot(t1, t2) >= 0.0 {
            let x = intersect(&Curve::Line(p1, t1), &Curve::Line(p2, t2), c).unwrap_or(p1);
            (x, x)
        } else {
            (along(p1, t1, r), along(p2, t2, -r))
        };
        let is_line = |e: &Elem| matches!(e, Elem::Line { .. });
        let line_to = |reader: &mut Reader, p: P2| {
            if dist(reader.plane_of(reader.comp.tool), p) > JOIN {
                let to = reader.point3(p);
                let m = match held.motion {
                    Motion::Rapid { .. } => Motion::Rapid { to },
                    _ => Motion::Linear { to },
                };
                let blk = piece(reader, m);
                reader.emit(blk, None);
            }
        };
        if is_line(e1) {
            self.end_held(held, Some(ea));
        } else {
            self.end_held(held, Some(p1));
            line_to(self, ea);
        }
        line_to(self, eb);
        if !is_line(e2) {
            line_to(self, p2);
        }
    }

    /// In-plane coordinates of a point.
    fn plane_of(&self, p: Vec3) -> P2 {
        let (a, b, _) = self.comp.plane.axes();
        [p[a], p[b]]
    }

    /// The tool position with the in-plane coordinates `p`.
    fn point3(&self, p: P2) -> Vec3 {
        let (a, b, _) = self.comp.plane.axes();
        let mut q = self.comp.tool;
        q[a] = p[0];
        q[b] = p[1];
        q
    }

    /// A corner piece of `held`'s line, feed and path mode.
    fn piece_of(&self, held: &Block) -> Block {
        Block {
            motion: Motion::Stop(StopKind::Pause),
            from: self.comp.tool,
            ..*held
        }
    }

    /// Queue `b` from the tool position, its in-plane end moved to `to` if given.
    fn emit(&mut self, mut b: Block, to: Option<P2>) {
        let (a, bb, _) = self.comp.plane.axes();
        b.from = self.comp.tool;
        if let Motion::Rapid { to: end } | Motion::Linear { to: end } | Motion::Arc { to: end, .. } =
            &mut b.motion
        {
            if let Some(p) = to {
                end[a] = p[0];
                end[bb] = p[1];
            }
            self.comp.tool = *end;
        }
        self.comp.out.push_back(b);
    }

    /// An uncompensated block from the tool position to its programmed end.
    fn emit_plain(&mut self, b: Block) {
        self.emit(b, None);
    }

    /// Emit the held element ending at `end` (None: perpendicular offset of its end); an entry
    /// arc about its tool path's centre.
    fn end_held(&mut self, mut held: Block, end: Option<P2>) {
        let (a, b, _) = self.comp.plane.axes();
        let e = Elem::of(&held, a, b).expect("held blocks move in the plane");
        let end = end.unwrap_or_else(|| e.offset_point(e.end(), self.comp.held_side, self.comp.held_radius));
        if let (Some(c), Motion::Arc { center, .. }) = (self.comp.held_center.take(), &mut held.motion) {
            (center[a], center[b]) = (c[0], c[1]);
        }
        self.emit(held, Some(end));
    }

    /// Blocks without motion in the plane, held while the corner was open: at the tool's place.
    fn flush_deferred(&mut self) {
        let tool = self.plane_of(self.comp.tool);
        for b in std::mem::take(&mut self.comp.deferred) {
            self.emit(b, Some(tool));
        }
    }

    /// At the end of the program (M2/M30 or the last line): the held element ends
    /// perpendicular, the entry move as programmed.
    fn finish_held(&mut self) -> Result<(), ProgramError> {
        if let Some(entry) = self.comp.entry.take() {
            self.emit(entry, None);
        }
        if let Some(held) = self.comp.held.take() {
            self.end_held(held, None);
        }
        self.flush_deferred();
        Ok(())
    }
}

/// Two lengths (m) in mm with as many decimals (4 … 9) as tell them apart.
fn shown_pair(a: f64, b: f64) -> (String, String) {
    let mut d = 4;
    while d < 9 && format!("{:.d$}", a * 1e3) == format!("{:.d$}", b * 1e3) && (a - b).abs() > JOIN {
        d += 1;
    }
    (format!("{:.d$}", a * 1e3), format!("{:.d$}", b * 1e3))
}

/// A length (m) in mm for messages: four decimals, more where they are needed to tell it apart
/// (a 1 µm tool is 0.001 mm, a 0.3 µm one 3e-4 mm).
fn shown_mm(m: f64) -> String {
    let mm = m * 1e3;
    if mm == 0.0 || mm.abs() >= 1e-3 {
        format!("{mm:.4}")
    } else {
        format!("{mm:.3e}")
    }
}
