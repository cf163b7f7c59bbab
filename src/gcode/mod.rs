//! G-code reader (RS274NGC subset): program text → a stream of `Block`s, one per line that moves
//! the machine, dwells or stops. Modal state (units, distance mode, plane, feed, G61/G64) is carried
//! here; positions come out absolute, in metres. Streaming: the reader holds the text and a cursor,
//! never a tree of the whole program.

use crate::error::ProgramError;
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Working plane of G2/G3 (G17, G18, G19).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Plane {
    #[default]
    XY,
    XZ,
    YZ,
}

/// Why the machine stops at the end of a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StopKind {
    /// M0 program stop
    Pause,
    /// M1 optional stop
    OptionalPause,
    /// M2 / M30 program end
    End,
}

/// What a block does.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Motion {
    /// G0: straight line at the rapid feed.
    Rapid { to: Vec3 },
    /// G1: straight line at the programmed feed.
    Linear { to: Vec3 },
    /// G2 (clockwise) / G3: arc or helix in `plane` about `center` (absolute, m), `turns` extra
    /// full turns (P word, default 0). The axis normal to the plane moves linearly (helix).
    Arc {
        to: Vec3,
        center: Vec3,
        plane: Plane,
        clockwise: bool,
        turns: u32,
    },
    /// G4 P: dwell (s).
    Dwell { seconds: f64 },
    /// M0, M1, M2, M30.
    Stop(StopKind),
}

/// Path-control mode in force for a block (G61 exact stop, G64 blending with tolerance).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum PathMode {
    ExactStop,
    /// G64 [P tolerance (m)] [Q (m)]; None = the machine's default tolerance.
    Blend {
        tolerance: Option<f64>,
        q: Option<f64>,
    },
}

/// One block that moves, dwells or stops, with the modal state in force for it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Block {
    /// Source line (1-based).
    pub line: u32,
    /// Position before the block (m, absolute).
    pub from: Vec3,
    pub motion: Motion,
    /// Programmed feed (m/s) in force (G1/G2/G3); 0 if none was ever given.
    pub feed: f64,
    pub path_mode: PathMode,
}

/// Streaming reader. Clone is cheap (the text is shared), so the reader state can be saved.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Reader {
    #[serde(skip)]
    text: Arc<str>,
    file: String,
    /// Byte offset of the next line to read.
    offset: usize,
    /// Number of the next line to read (1-based).
    line: u32,
    position: Vec3,
    feed: f64,
    path_mode: PathMode,
    done: bool,
}

impl Reader {
    /// `file` is the name used in error messages; the machine starts at `start` (m).
    pub fn new(text: Arc<str>, file: &str, start: Vec3) -> Reader {
        Reader {
            text,
            file: file.to_string(),
            offset: 0,
            line: 1,
            position: start,
            feed: 0.0,
            path_mode: PathMode::Blend {
                tolerance: None,
                q: None,
            },
            done: false,
        }
    }

    /// Give back the program text after a state restore (the text is not serialized).
    pub fn attach_text(&mut self, text: Arc<str>) {
        self.text = text;
    }

    /// Next block, `Ok(None)` at the end of the program (or after M2/M30).
    // PLACEHOLDER reader: G0/G1 with X Y Z F only, until the full reader lands.
    pub fn next_block(&mut self) -> Result<Option<Block>, ProgramError> {
        while !self.done && self.offset < self.text.len() {
            let rest = &self.text[self.offset..];
            let end = rest.find('\n').map(|i| i + 1).unwrap_or(rest.len());
            let raw = &rest[..end];
            self.offset += end;
            let line = self.line;
            self.line += 1;
            let mut to = self.position;
            let mut rapid = None;
            let mut moved = false;
            for word in raw.split_whitespace() {
                let (letter, num) = word.split_at(1);
                let value: f64 = match num.parse() {
                    Ok(v) => v,
                    Err(_) => continue,
                };
                match letter {
                    "G" if value == 0.0 => rapid = Some(true),
                    "G" if value == 1.0 => rapid = Some(false),
                    "X" => (to[0], moved) = (value * 1e-3, true),
                    "Y" => (to[1], moved) = (value * 1e-3, true),
                    "Z" => (to[2], moved) = (value * 1e-3, true),
                    "F" => self.feed = value * 1e-3 / 60.0,
                    "M" if value == 2.0 || value == 30.0 => self.done = true,
                    _ => {}
                }
            }
            if moved {
                let from = self.position;
                self.position = to;
                let motion = if rapid == Some(true) {
                    Motion::Rapid { to }
                } else {
                    Motion::Linear { to }
                };
                return Ok(Some(Block {
                    line,
                    from,
                    motion,
                    feed: self.feed,
                    path_mode: self.path_mode,
                }));
            }
        }
        let _ = &self.file;
        Ok(None)
    }
}

/// Read the whole program once, keeping nothing, to report the first error before motion starts.
pub fn validate(text: Arc<str>, file: &str) -> Result<u64, ProgramError> {
    let mut reader = Reader::new(text, file, [0.0; 3]);
    let mut blocks = 0;
    while reader.next_block()?.is_some() {
        blocks += 1;
    }
    Ok(blocks)
}
