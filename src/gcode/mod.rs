//! G-code reader (RS274NGC subset): program text → a stream of `Block`s, one per line that moves
//! the machine, dwells or stops. Modal state (units, distance mode, plane, feed, G61/G64) is carried
//! here; positions come out absolute, in metres. Streaming: the reader holds a byte offset into the
//! text or file (read line by line), never the whole program. Every number is range-checked
//! (`check`).

pub mod check;
pub mod oword;
pub mod params;
mod reader;
pub mod source;
pub mod words;

pub use reader::Reader;
pub use source::ProgramSource;

use crate::geometry::{Arc, Line, Plane, Source};
use crate::Vec3;
use serde::{Deserialize, Serialize};

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

impl Block {
    /// The geometry of a programmed line, rapid or arc (None for other blocks and degenerate
    /// arcs): what the path stage runs and what ticks are measured against.
    pub fn geometry(&self) -> Option<Source> {
        let from = self.from;
        match self.motion {
            Motion::Linear { to } | Motion::Rapid { to } => Some(Source::Line(Line { start: from, end: to })),
            Motion::Arc {
                to,
                center,
                plane,
                clockwise,
                turns,
            } => Arc::from_gcode(from, to, center, plane, clockwise, turns).map(Source::Arc),
            _ => None,
        }
    }

    /// A restored block (`crate::valid`): its numbers within what the reader produces.
    pub fn check_state(&self) -> Result<(), String> {
        use crate::valid::{at_most, point, within, MAX_POSITION_M, MAX_SPEED_M_S};
        point("block start", self.from, MAX_POSITION_M)?;
        match self.motion {
            Motion::Rapid { to } | Motion::Linear { to } => point("block end", to, MAX_POSITION_M)?,
            Motion::Arc {
                to,
                center,
                turns,
                plane,
                ..
            } => {
                if let Plane::Turned { cos, sin, .. } = plane {
                    // A rotation: (cos, sin) on the unit circle.
                    within("arc plane turn", cos.hypot(sin), 1.0 - 1e-12, 1.0 + 1e-12)?;
                }
                point("arc end", to, MAX_POSITION_M)?;
                point("arc centre", center, MAX_POSITION_M)?;
                at_most("arc turns", u64::from(turns), check::MAX_TURNS as u64)?;
            }
            Motion::Dwell { seconds } => within("dwell", seconds, 0.0, check::MAX_DWELL_S)?,
            Motion::Stop(_) => {}
        }
        within("feed", self.feed, 0.0, MAX_SPEED_M_S)?;
        if let PathMode::Blend { tolerance, q } = self.path_mode {
            for x in tolerance.into_iter().chain(q) {
                within("G64 P/Q", x, 0.0, check::MAX_COORDINATE_M)?;
            }
        }
        Ok(())
    }
}

/// Read the whole program once, keeping nothing, to report the first error before motion starts.
pub fn validate(source: impl Into<ProgramSource>, file: &str) -> Result<u64, crate::error::ProgramError> {
    validate_with(Reader::new(source, file, [0.0; 3]))
}

/// `validate` with a configured reader (e.g. the machine's arc tolerance).
pub fn validate_with(mut reader: Reader) -> Result<u64, crate::error::ProgramError> {
    let mut blocks = 0;
    while reader.next_block()?.is_some() {
        blocks += 1;
    }
    Ok(blocks)
}
