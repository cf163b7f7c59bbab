//! The reader alone, as the G-code test files drive it (`mod reading;`): the blocks of a program
//! text, its located error, and the end points of its moves.
#![allow(dead_code)] // not every file that includes the module uses every function

use cnc_motion::config::Machine;
use cnc_motion::gcode::{Block, Motion, Reader};
use std::sync::Arc;

pub fn blocks_with(text: &str, machine: &Machine) -> Result<Vec<Block>, String> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]).with_machine(machine);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().map_err(|e| e.to_string())? {
        out.push(b);
    }
    Ok(out)
}

pub fn blocks(text: &str) -> Vec<Block> {
    blocks_with(text, &Machine::default()).unwrap_or_else(|e| panic!("{e}"))
}

pub fn error(text: &str) -> String {
    blocks_with(text, &Machine::default()).unwrap_err()
}

pub fn end_of(b: &Block) -> Option<[f64; 3]> {
    match b.motion {
        Motion::Rapid { to } | Motion::Linear { to } | Motion::Arc { to, .. } => Some(to),
        _ => None,
    }
}

/// End points of the moves, in program units `unit` (1 mm or 25.4 mm), rounded to 1e-9.
pub fn ends_in(text: &str, unit: f64) -> Vec<[f64; 3]> {
    blocks(text)
        .iter()
        .filter_map(end_of)
        .map(|p| p.map(|v| (v * 1e3 / unit * 1e9).round() / 1e9))
        .collect()
}

/// End points of the moves in mm, rounded to 1e-9.
pub fn ends(text: &str) -> Vec<[f64; 3]> {
    ends_in(text, 1.0)
}
