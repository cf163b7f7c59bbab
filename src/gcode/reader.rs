//! The streaming reader: a cursor into the program text and the modal state, one line at a time.

mod arc;
mod biarc;
mod comp;
mod comp_geom;
mod cycles;
mod execute;
mod files;
mod flow;
pub mod frame;
mod inverse;
mod modal;
pub mod nurbs;
mod offsets;
mod spline;
mod state;
mod words;

use super::params::Params;
use super::source::{Lines, ProgramSource};
use super::words::{split_with, Sets, Word};
use super::{Block, Motion, PathMode, StopKind};
use crate::config::{CutterCorner, NcSetup, DEFAULT_ARC_TOLERANCE_M};
use crate::error::ProgramError;
use crate::geometry::Plane;
use crate::Vec3;
use modal::Mode;
use serde::{Deserialize, Serialize};

/// Share of the radius by which arc end points may disagree with the centre, beside the machine's
/// `arc_radius_tolerance_mm` (`config::DEFAULT_ARC_TOLERANCE_M`); an arc is refused only when it
/// exceeds both.
const ARC_TOLERANCE_REL: f64 = 1e-3;

/// `%` demarcation (LinuxCNC G-code overview, "File Requirements"): a program whose first
/// non-blank line is `%` ends at the next `%` line, which it must have.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
enum Percent {
    /// No non-blank line read yet.
    #[default]
    Unknown,
    /// Opened by `%` on this line.
    Open(u32),
    /// The first non-blank line was not `%`.
    None,
}

/// Streaming reader. Clone is cheap (the text is shared, a file is reopened at the offset), so
/// the reader state can be saved.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Reader {
    #[serde(skip)]
    lines: Lines,
    /// Absolute arc radius tolerance (m, for G21; × 2.54 in G20).
    arc_tolerance: f64,
    /// Largest feed (m/s): a larger F runs at this one (machine `max_feed_mm_min`).
    max_feed: f64,
    /// Chord tolerance (m) of the machine: splines are approximated within a share of it.
    chord_tolerance: f64,
    file: String,
    /// Subroutine files called (sources 1, 2, …; source 0 is the program).
    subfiles: Vec<files::SubFile>,
    /// Source of the next line to read.
    src: u32,
    /// Byte offset of the next line to read.
    offset: usize,
    /// Number of the next line to read (1-based).
    line: u32,
    position: Vec3,
    /// Programmed feed (m/s), capped at `max_feed`.
    feed: f64,
    path_mode: PathMode,
    /// Metres per program unit (G21 mm, G20 inch).
    unit: f64,
    /// G90 (true) / G91.
    absolute: bool,
    /// G90.1 (true) / G91.1: arc centres absolute or relative to the start point.
    arc_absolute: bool,
    plane: Plane,
    /// Modal motion (group 1), None before the first and after G80.
    motion: Option<Mode>,
    done: bool,
    percent: Percent,
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
    /// G5 continuation and the open G5.2 NURBS block.
    spline: Box<spline::Splines>,
    /// Blocks decoded but not yet returned (a line can give a dwell, moves and a stop; G28 two
    /// moves, a cycle or a spline many).
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
    motion: Option<(Mode, u32)>,
    /// G80 on the line.
    cancel: Option<u32>,
    stop: Option<(StopKind, u32)>,
    tool_change: bool,
    /// M61 on the line (its column).
    set_tool: Option<u32>,
    comp: Option<(i64, u32)>,
    tlo: Option<(i64, u32)>,
    /// The group-0 code (G4, G10, G28, G30, G53, G92…, G5.3), in tenths.
    nonmodal: Option<(i64, u32)>,
}

impl Reader {
    /// `file` is the name used in error messages; the machine starts at `start` (m).
    pub fn new(source: impl Into<ProgramSource>, file: &str, start: Vec3) -> Reader {
        Reader {
            lines: Lines::new(source.into()),
            arc_tolerance: DEFAULT_ARC_TOLERANCE_M,
            max_feed: super::check::MAX_FEED_M_S,
            chord_tolerance: spline::default_chord_tolerance(),
            file: file.to_string(),
            subfiles: Vec::new(),
            src: 0,
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
            percent: Percent::Unknown,
            nc: Box::default(),
            corner: CutterCorner::Arc,
            tool: offsets::ToolState::default(),
            work: 0,
            g92: [0.0; 3],
            g92_on: false,
            inverse_time: false,
            comp: Box::default(),
            cycle: cycles::Cycle::default(),
            spline: Box::default(),
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

    /// The machine's arc tolerance, feed cap, chord tolerance and NC setup (switches, tool
    /// table, offsets, home positions).
    pub fn with_machine(mut self, machine: &crate::config::Machine) -> Reader {
        self.arc_tolerance = machine.arc_radius_tolerance;
        self.max_feed = machine.max_feed;
        self.chord_tolerance = machine.chord_tolerance.min(machine.path_tolerance);
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

    /// Byte offset of the next line of the program to read: progress through the program
    /// (while a subroutine file runs, the offset of its call).
    pub fn offset(&self) -> usize {
        match self.src {
            0 => self.offset,
            _ => self.flow.program_offset().unwrap_or(self.offset),
        }
    }

    /// Number of the next line to read (1-based): progress through the program.
    pub fn line(&self) -> u32 {
        self.line
    }

    /// An error at `line`:`col` of the source being read.
    fn error(&self, line: u32, col: u32, message: impl Into<String>) -> ProgramError {
        self.error_in(self.src, line, col, message)
    }

    /// Next block, `Ok(None)` at the end of the program (or after M2/M30).
    pub fn next_block(&mut self) -> Result<Option<Block>, ProgramError> {
        self.next_compensated()
    }

    /// Next block in machine coordinates before cutter compensation.
    fn next_raw(&mut self) -> Result<Option<Block>, ProgramError> {
        loop {
            if let Some(b) = self.pending.pop_front() {
                return Ok(Some(b));
            }
            if self.done {
                return Ok(None);
            }
            let mut buf = std::mem::take(&mut self.line_buf);
            let result = self.read_and_execute(&mut buf);
            let end = buf.len();
            self.line_buf = buf;
            // Advance only past a line that was read without error, so a retry reports it again.
            result.inspect_err(|_| {
                self.close(self.src);
                self.pending.clear();
            })?;
            if end == 0 {
                self.end_of_text()?;
                self.done = true;
                continue;
            }
            match self.jump.take() {
                Some(p) => {
                    if p.src != self.src {
                        self.close(self.src);
                    }
                    (self.src, self.offset, self.line) = (p.src, p.offset, p.line);
                }
                None => {
                    self.offset += end;
                    self.line += 1;
                }
            }
        }
    }

    /// At the end of the text: nothing may be left open. A subroutine file ends inside its
    /// sub only if its endsub was never reached (an `if` around it).
    fn end_of_text(&self) -> Result<(), ProgramError> {
        if self.src != 0 {
            let msg = "the end of the subroutine file inside its sub: its endsub was not reached";
            return Err(self.error(self.line, 1, msg));
        }
        if let Percent::Open(line) = self.percent {
            let msg =
                "the program opens with '%' but has no closing '%' line (LinuxCNC \"File Requirements\")";
            return Err(self.error(line, 1, msg));
        }
        self.check_spline_closed()?;
        self.check_flow_closed()
    }

    /// The line of the opening `%`, if the program has one.
    fn opening_percent(&self) -> Option<u32> {
        match self.percent {
            Percent::Open(line) => Some(line),
            _ => None,
        }
    }

    /// `%` lines (LinuxCNC "File Requirements"): true if the line was one and is done with.
    fn percent_line(&mut self, line: u32, raw: &str) -> Result<bool, ProgramError> {
        // Only the program is demarcated; in a subroutine file `%` is no word.
        let state = if self.src == 0 {
            self.percent
        } else {
            Percent::None
        };
        // Once demarcation is settled, only a line's start is looked at (the end test below).
        let text = match state {
            Percent::None => raw.trim_start(),
            _ => raw.trim(),
        };
        let is_percent = text == "%";
        match state {
            Percent::Unknown if text.is_empty() => return Ok(true),
            Percent::Unknown if is_percent => {
                self.percent = Percent::Open(line);
                return Ok(true);
            }
            Percent::Unknown => self.percent = Percent::None,
            Percent::Open(_) if is_percent => {
                // The program ends here; the rest of the file is not read.
                self.percent = Percent::None;
                self.check_spline_closed()?;
                self.check_flow_closed()?;
                self.done = true;
                return Ok(true);
            }
            _ => {}
        }
        if text.starts_with('%') {
            let col = raw.len() - raw.trim_start().len() + 1;
            let msg = "'%' alone on a line ends a program only when its first non-blank line is '%' \
                       (LinuxCNC \"File Requirements\"); elsewhere '%' is not a word";
            return Err(self.error(line, col as u32, msg));
        }
        Ok(false)
    }

    /// Read the next line into `buf` (left empty at the end) and execute it.
    fn read_and_execute(&mut self, buf: &mut Vec<u8>) -> Result<(), ProgramError> {
        let line = self.line;
        let at = flow::Place {
            src: self.src,
            offset: self.offset,
            line,
        };
        self.read_at(at, buf)?;
        if buf.is_empty() {
            return Ok(());
        }
        let mut raw = std::str::from_utf8(buf).map_err(|e| {
            let msg = "invalid UTF-8 (a program is ASCII or UTF-8 text)";
            self.error(line, e.valid_up_to() as u32 + 1, msg)
        })?;
        if line == 1 {
            // A UTF-8 byte-order mark; columns count from after it, as editors show them.
            raw = raw.strip_prefix('\u{feff}').unwrap_or(raw);
        }
        if self.percent_line(line, raw)? {
            return Ok(());
        }
        let deleted;
        if raw.trim_start().starts_with('/') {
            // Block delete (LinuxCNC "Block Delete"): with the switch on the line is skipped,
            // with it off the '/' is ignored (a space keeps the columns).
            if self.nc.block_delete {
                return Ok(());
            }
            deleted = raw.replacen('/', " ", 1);
            raw = &deleted;
        }
        if let Some(head) = super::oword::head_run(raw, &self.params) {
            let head = head.map_err(|(c, m)| self.error(line, c as u32 + 1, m))?;
            let here = at;
            let next = flow::Place {
                src: self.src,
                offset: self.offset + buf.len(),
                line: line.saturating_add(1),
            };
            return self.o_word(here, next, raw, head);
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
