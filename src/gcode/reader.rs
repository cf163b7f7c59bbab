//! The streaming reader: a cursor into the program text and the modal state, one line at a time.

mod arc;
mod comp;
mod comp_geom;
mod cycles;
mod flow;
mod inverse;
mod modal;
mod offsets;
mod state;
mod words;

use super::check;
use super::params::Params;
use super::source::{LineError, Lines, ProgramSource, MAX_LINE_BYTES};
use super::words::{split_with, Sets, Word};
use super::{Block, Motion, PathMode, Plane, StopKind};
use crate::config::{CutterCorner, NcSetup};
use crate::error::ProgramError;
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Arc end points may disagree with the centre by the machine's `arc_radius_tolerance_mm`
/// (default 0.028 mm, LinuxCNC's CENTER_ARC_RADIUS_TOLERANCE; in G20 programs 2.54 times that,
/// 0.0028 in, LinuxCNC's inch value) or by this share of the radius; an arc is refused only when
/// it exceeds both.
pub const DEFAULT_ARC_TOLERANCE_M: f64 = 0.028e-3;
const ARC_TOLERANCE_REL: f64 = 1e-3;

/// Axis indices (a, b, normal) of a plane, right-handed so that G3 is a positive rotation about
/// the normal: G17 (X, Y, Z), G18 (Z, X, Y), G19 (Y, Z, X).
pub fn plane_axes(plane: Plane) -> (usize, usize, usize) {
    match plane {
        Plane::XY => (0, 1, 2),
        Plane::XZ => (2, 0, 1),
        Plane::YZ => (1, 2, 0),
    }
}

/// Streaming reader. Clone is cheap (the text is shared, a file is reopened at the offset), so
/// the reader state can be saved.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Reader {
    #[serde(skip)]
    lines: Lines,
    /// Absolute arc radius tolerance (m, for G21; × 2.54 in G20).
    arc_tolerance: f64,
    file: String,
    /// Byte offset of the next line to read.
    offset: usize,
    /// Number of the next line to read (1-based).
    line: u32,
    position: Vec3,
    /// Programmed feed (m/s).
    feed: f64,
    path_mode: PathMode,
    /// Metres per program unit (G21 mm, G20 inch).
    unit: f64,
    /// G90 (true) / G91.
    absolute: bool,
    /// G90.1 (true) / G91.1: arc centres absolute or relative to the start point.
    arc_absolute: bool,
    plane: Plane,
    /// Modal motion: 0, 1, 2, 3 (G0…G3), None before the first.
    motion: Option<u8>,
    done: bool,
    /// Switches, tool table, work offsets, home positions (machine file; G10 changes them).
    nc: Box<NcSetup>,
    /// Outside-corner strategy of cutter compensation (G450 / G451, machine default).
    corner: CutterCorner,
    /// T (selected), M6 (loaded) tool numbers; D radius register (m); tool length offset (m).
    tool: offsets::ToolState,
    /// Active work system (0 = G54 … 8 = G59.3), G92 offset (m) and whether it is applied.
    work: usize,
    g92: Vec3,
    g92_on: bool,
    /// G93 inverse-time feed (true) / G94 units per minute.
    inverse_time: bool,
    /// Cutter compensation: mode, and the blocks held back for one block of look-ahead.
    comp: Box<comp::Comp>,
    /// Drilling cycle words and retract mode.
    cycle: cycles::Cycle,
    /// Blocks decoded but not yet returned (a line can give a motion and a stop, G28 two moves).
    #[serde(skip)]
    pending: std::collections::VecDeque<Block>,
    #[serde(skip)]
    words: Vec<Word>,
    /// Numbered and named parameters (bounded), and the settings of the line being read.
    params: Box<Params>,
    #[serde(skip)]
    sets: Sets,
    #[serde(skip)]
    line_buf: Vec<u8>,
    /// O-word control flow: subroutines seen, open loops and conditionals, calls.
    flow: Box<flow::Flow>,
    /// Where the line just executed sends the cursor (an O-word jump), instead of the next line.
    #[serde(skip)]
    jump: Option<flow::Place>,
}

/// What the G and M words of a line ask for.
#[derive(Default)]
struct LineCodes {
    motion: Option<(u8, u32)>,
    dwell: Option<u32>,
    stop: Option<(StopKind, u32)>,
    tool_change: bool,
    comp: Option<(i64, u32)>,
    tlo: Option<(i64, u32)>,
    nonmodal: Option<(i64, u32)>,
}

impl Reader {
    /// `file` is the name used in error messages; the machine starts at `start` (m).
    pub fn new(source: impl Into<ProgramSource>, file: &str, start: Vec3) -> Reader {
        Reader {
            lines: Lines::new(source.into()),
            arc_tolerance: DEFAULT_ARC_TOLERANCE_M,
            file: file.to_string(),
            offset: 0,
            line: 1,
            position: start,
            feed: 0.0,
            path_mode: PathMode::Blend {
                tolerance: None,
                q: None,
            },
            unit: 1e-3,
            absolute: true,
            arc_absolute: false,
            plane: Plane::XY,
            motion: None,
            done: false,
            nc: Box::default(),
            corner: CutterCorner::Arc,
            tool: offsets::ToolState::default(),
            work: 0,
            g92: [0.0; 3],
            g92_on: false,
            inverse_time: false,
            comp: Box::default(),
            cycle: cycles::Cycle::default(),
            pending: Default::default(),
            words: Vec::new(),
            params: Box::default(),
            sets: Vec::new(),
            line_buf: Vec::new(),
            flow: Box::default(),
            jump: None,
        }
    }

    /// The absolute arc radius tolerance (m) for G21 programs (machine `arc_radius_tolerance_mm`).
    pub fn with_arc_tolerance(mut self, tolerance: f64) -> Reader {
        self.arc_tolerance = tolerance;
        self
    }

    /// The machine's arc tolerance and NC setup (switches, tool table, offsets, home positions).
    pub fn with_machine(mut self, machine: &crate::config::Machine) -> Reader {
        self.arc_tolerance = machine.arc_radius_tolerance;
        self.corner = machine.nc.cutter_corner;
        if machine.nc.inch {
            self.unit = 25.4e-3;
        }
        self.nc = Box::new(machine.nc.clone());
        self
    }

    /// Give back the program after a state restore (the source is not serialized).
    pub fn attach_text(&mut self, source: impl Into<ProgramSource>) {
        self.lines = Lines::new(source.into());
    }

    /// The program's name in messages.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// Byte offset of the next line to read: progress through the program.
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// Number of the next line to read (1-based): progress through the program.
    pub fn line(&self) -> u32 {
        self.line
    }

    fn error(&self, line: u32, col: u32, message: impl Into<String>) -> ProgramError {
        ProgramError::new(&self.file, line, col, message)
    }

    /// Next block, `Ok(None)` at the end of the program (or after M2/M30).
    pub fn next_block(&mut self) -> Result<Option<Block>, ProgramError> {
        self.next_compensated()
    }

    /// Next block in machine coordinates before cutter compensation.
    fn next_raw(&mut self) -> Result<Option<Block>, ProgramError> {
        if let Some(b) = self.pending.pop_front() {
            return Ok(Some(b));
        }
        while !self.done {
            let mut buf = std::mem::take(&mut self.line_buf);
            let result = self.read_and_execute(&mut buf);
            let end = buf.len();
            self.line_buf = buf;
            // Advance only past a line that was read without error, so a retry reports it again.
            let block = result.inspect_err(|_| self.lines.reset())?;
            if end == 0 {
                self.check_flow_closed()?;
                break;
            }
            match self.jump.take() {
                Some(p) => (self.offset, self.line) = (p.offset, p.line),
                None => {
                    self.offset += end;
                    self.line += 1;
                }
            }
            if let Some(b) = block {
                return Ok(Some(b));
            }
            if let Some(b) = self.pending.pop_front() {
                return Ok(Some(b));
            }
        }
        Ok(None)
    }

    /// Read the next line into `buf` (left empty at the end) and execute it.
    fn read_and_execute(&mut self, buf: &mut Vec<u8>) -> Result<Option<Block>, ProgramError> {
        let line = self.line;
        self.lines.read_line(self.offset, buf).map_err(|e| match e {
            LineError::Io(e) => self.error(line, 1, format!("cannot read the program: {e}")),
            LineError::TooLong => self.error(
                line,
                1,
                format!("line out of range (longer than {MAX_LINE_BYTES} bytes)"),
            ),
        })?;
        if buf.is_empty() {
            return Ok(None);
        }
        let mut raw = std::str::from_utf8(buf).map_err(|e| {
            let msg = "invalid UTF-8 (a program is ASCII or UTF-8 text)";
            self.error(line, e.valid_up_to() as u32 + 1, msg)
        })?;
        if line == 1 {
            // A UTF-8 byte-order mark; columns count from after it, as editors show them.
            raw = raw.strip_prefix('\u{feff}').unwrap_or(raw);
        }
        let deleted;
        if raw.trim_start().starts_with('/') {
            // Block delete (LinuxCNC "Block Delete"): with the switch on the line is skipped,
            // with it off the '/' is ignored (a space keeps the columns).
            if self.nc.block_delete {
                return Ok(None);
            }
            deleted = raw.replacen('/', " ", 1);
            raw = &deleted;
        }
        if let Some(head) = super::oword::head(raw, Some(&self.params)) {
            let head = head.map_err(|(c, m)| self.error(line, c as u32 + 1, m))?;
            let here = flow::Place {
                offset: self.offset,
                line,
            };
            let next = flow::Place {
                offset: self.offset + buf.len(),
                line: line.saturating_add(1),
            };
            self.o_word(here, next, raw, head)?;
            return Ok(None);
        }
        let mut words = std::mem::take(&mut self.words);
        let mut sets = std::mem::take(&mut self.sets);
        let parsed = split_with(raw, &mut words, &self.params, &mut sets)
            .map_err(|e| self.error(line, e.col, e.message))
            .and_then(|()| {
                let set = self.params.set(&mut sets);
                set.map_err(|(c, m)| self.error(line, c as u32 + 1, m))
            });
        self.sets = sets;
        let result = parsed.and_then(|()| self.execute(line, &words));
        self.words = words;
        result
    }

    /// Apply one line's words to the modal state; the block it makes, if any.
    fn execute(&mut self, line: u32, words: &[Word]) -> Result<Option<Block>, ProgramError> {
        let codes = self.modal_words(line, words)?;
        let words::LineWords {
            mut axes,
            ijk,
            mut r,
            p,
            extra,
            f,
        } = self.read_words(line, words)?;
        self.apply_tool(line, &codes, &extra, &mut axes)?;
        if let Some((code, col)) = codes.comp {
            self.set_comp(line, code, col, extra.d)?;
        }
        let non_modal = self.non_modal(line, &codes, &extra, p, r, &axes)?;
        if non_modal == offsets::NonModal::Consumed {
            // The words were data (G10 L1 R, G92 X…).
            (axes, r) = ([None; 3], None);
        }
        if let offsets::NonModal::Home(i) = non_modal {
            return self.go_home(line, i, &axes, &codes);
        }
        if let Some(col) = codes.dwell {
            let Some((seconds, pcol)) = p else {
                return Err(self.error(line, col, "G4 needs P (dwell time in seconds)"));
            };
            let seconds = check::dwell(seconds).map_err(|m| self.error(line, pcol, m))?;
            if axes.iter().any(Option::is_some) {
                return Err(self.error(line, col, "G4 cannot move axes on the same line"));
            }
            let block = self.block(line, Motion::Dwell { seconds });
            return Ok(Some(self.with_stop(block, &codes)));
        }
        let motion = self.motion_of(line, &codes, &axes)?;
        if let Some((m, col)) = motion.filter(|m| m.0 >= 73) {
            let fresh = !matches!(self.motion, Some(73..));
            self.motion = Some(m);
            let xy = axes;
            let (r, q) = (r, extra.q);
            return self.canned(line, col, m, fresh, cycles::CycleWords { xy, r, p, q }, &codes);
        }
        let mut block = None;
        if let Some((m, col)) = motion {
            let machine = non_modal == offsets::NonModal::Machine;
            let words = words::LineWords {
                axes,
                ijk,
                r,
                p,
                extra,
                f,
            };
            block = self.move_block(line, m, col, &words, machine)?;
        } else if let Some((_, col)) = ijk.iter().flatten().next().or(r.as_ref()) {
            return Err(self.error(line, *col, "arc words without G2/G3"));
        }
        Ok(match block {
            Some(b) => Some(self.with_stop(b, &codes)),
            None => codes.stop.map(|(kind, _)| {
                self.finish_on(kind);
                self.block(line, Motion::Stop(kind))
            }),
        })
    }

    /// The motion of a line: its G0…G3 / cycle code, or the modal one when axis words are given.
    fn motion_of(
        &self,
        line: u32,
        codes: &LineCodes,
        axes: &[words::Located; 3],
    ) -> Result<Option<(u8, u32)>, ProgramError> {
        let first_axis = || axes.iter().flatten().map(|a| a.1).min();
        Ok(match (codes.motion, first_axis()) {
            (Some(m), _) => Some(m),
            (None, Some(col)) => match self.motion {
                Some(m) => Some((m, col)),
                None => {
                    let msg = "axis words without a motion mode (G0, G1, G2, G3, G73, G81…G83)";
                    return Err(self.error(line, col, msg));
                }
            },
            (None, None) => None,
        })
    }

    /// A G0…G3 move to the axis words (None for G0/G1 without them); G93 sets its feed.
    fn move_block(
        &mut self,
        line: u32,
        m: u8,
        col: u32,
        w: &words::LineWords,
        machine: bool,
    ) -> Result<Option<Block>, ProgramError> {
        self.motion = Some(m);
        let any_axis = w.axes.iter().any(Option::is_some);
        let to = self.target(line, &w.axes, machine)?;
        let feeds = m != 0 && (any_axis || m >= 2);
        if feeds && self.inverse_time && w.f.is_none() {
            let msg = format!("G{m} in G93 needs F on its line (inverse time: the move takes 1/F minutes)");
            return Err(self.error(line, col, msg));
        }
        if feeds && !self.inverse_time && self.feed <= 0.0 {
            return Err(self.error(line, col, format!("G{m} with no feed rate: F was never set")));
        }
        let mut block = match m {
            0 | 1 if !any_axis => return Ok(None),
            0 => self.block(line, Motion::Rapid { to }),
            1 => self.block(line, Motion::Linear { to }),
            _ => self.arc(line, col, m == 2, to, w.ijk, w.r, w.p)?,
        };
        if let (true, Some((f, _))) = (self.inverse_time && m != 0, w.f) {
            block.feed = inverse::feed(&block, f);
        }
        self.position = to;
        Ok(Some(block))
    }

    /// End point of a motion from the axis words (G90/G91), each within the coordinate range.
    fn target(&self, line: u32, axes: &[Option<(f64, u32)>; 3], machine: bool) -> Result<Vec3, ProgramError> {
        let mut to = self.position;
        for (i, a) in axes.iter().enumerate() {
            if let Some((v, c)) = a {
                to[i] = if machine {
                    v * self.unit
                } else if self.absolute {
                    v * self.unit + self.axis_offset(i)
                } else {
                    self.position[i] + v * self.unit
                };
                if to[i].abs() > check::MAX_COORDINATE_M {
                    let msg = format!(
                        "{} moves the axis to {} mm: out of range (|position| ≤ {} mm)",
                        [b'X', b'Y', b'Z'][i] as char,
                        to[i] * 1e3,
                        check::MAX_COORDINATE_M * 1e3
                    );
                    return Err(self.error(line, *c, msg));
                }
            }
        }
        Ok(to)
    }

    /// G28 / G30 (LinuxCNC "G28, G28.1", "G30, G30.1"): a rapid to the programmed point if any,
    /// then a rapid of the named axes (all without axis words) to the stored home position.
    fn go_home(
        &mut self,
        line: u32,
        i: usize,
        axes: &[Option<(f64, u32)>; 3],
        codes: &LineCodes,
    ) -> Result<Option<Block>, ProgramError> {
        let via = self.target(line, axes, false)?;
        let none = axes.iter().all(Option::is_none);
        let home: Vec3 = std::array::from_fn(|k| {
            if none || axes[k].is_some() {
                self.nc.home[i][k]
            } else {
                via[k]
            }
        });
        let first = self.block(line, Motion::Rapid { to: via });
        self.position = via;
        let second = self.block(line, Motion::Rapid { to: home });
        self.position = home;
        self.motion = Some(0);
        let second = self.with_stop(second, codes);
        self.pending.push_front(second);
        Ok(Some(first))
    }

    /// A line with a motion and M0/M1/M2/M30: the motion first, the stop after it.
    fn with_stop(&mut self, block: Block, codes: &LineCodes) -> Block {
        if let Some((kind, _)) = codes.stop {
            self.pending.push_back(self.block(block.line, Motion::Stop(kind)));
            self.finish_on(kind);
        }
        block
    }

    fn finish_on(&mut self, kind: StopKind) {
        if kind == StopKind::End {
            self.done = true;
        }
    }

    fn block(&self, line: u32, motion: Motion) -> Block {
        let feed = match motion {
            Motion::Rapid { .. } => 0.0,
            _ => self.feed,
        };
        Block {
            line,
            from: self.position,
            motion,
            feed,
            path_mode: self.path_mode,
        }
    }
}

/// A code in tenths as written: 410 → "41", 901 → "90.1".
fn fmt_code(tenths: i64) -> String {
    if tenths % 10 == 0 {
        format!("{}", tenths / 10)
    } else {
        format!("{}.{}", tenths / 10, (tenths % 10).abs())
    }
}
