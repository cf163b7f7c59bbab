//! G64 Q: LinuxCNC's "naive CAM detector". Consecutive G1 moves of one feed whose inner vertices
//! all lie within Q of the straight line from the first start to the last end are one move, so a
//! nearly straight run of CAM points is run as the line it stands for. Every point of that line
//! is then within Q of the programmed moves too (between the feet of two vertices on it, the
//! move joining them is at most the larger of their distances away), and the path keeps the
//! G64 P tolerance from the line: the motion stays within P + Q of the program.
//!
//! With `split` (the smooth mode) the line is emitted in pieces, from foot to foot of the
//! vertices, each with the line number of the move it stands for: the tool then reports the
//! block it is on (source_map.rs).

use crate::gcode::{Block, Motion, PathMode};
use crate::geometry::{add, distance_to_segment, dot, scale, sub};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Inner vertices held at most per merged move (the merge ends there).
const MAX_VERTICES: usize = 256;

/// The merged move being built.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Merger {
    first: Option<Block>,
    to: Vec3,
    vertices: Vec<Vec3>,
    /// Source line of the move that starts at each inner vertex.
    lines: Vec<u32>,
}

fn q_of(b: &Block) -> Option<f64> {
    match (b.motion, b.path_mode) {
        (Motion::Linear { .. }, PathMode::Blend { q: Some(q), .. }) if q > 0.0 => Some(q),
        _ => None,
    }
}

impl Merger {
    /// A restored merge: its points in range, at most MAX_VERTICES of them.
    pub fn check_state(&self) -> Result<(), String> {
        use crate::valid::{at_most, point, MAX_POSITION_M};
        at_most("merged vertices", self.vertices.len() as u64, MAX_VERTICES as u64)?;
        for p in self.vertices.iter().chain([&self.to]) {
            point("merged vertex", *p, MAX_POSITION_M)?;
        }
        self.first.as_ref().map_or(Ok(()), Block::check_state)
    }

    pub fn new() -> Merger {
        Merger {
            first: None,
            to: [0.0; 3],
            vertices: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// Offer a block: the merged blocks now final come out through `emit` (in order, in pieces
    /// with `split`); the block itself is either absorbed or emitted too.
    pub fn push(&mut self, block: &Block, split: bool, mut emit: impl FnMut(&Block)) {
        let Motion::Linear { to } = block.motion else {
            self.flush(split, &mut emit);
            emit(block);
            return;
        };
        let Some(q) = q_of(block) else {
            self.flush(split, &mut emit);
            emit(block);
            return;
        };
        if let Some(first) = self.first {
            let same = first.feed == block.feed && first.path_mode == block.path_mode;
            let start = first.from;
            let forward = dot(sub(to, self.to), sub(self.to, start)) > 0.0;
            let mut inner = self.vertices.iter().chain(std::iter::once(&self.to));
            let within = inner.all(|&v| distance_to_segment(v, start, to) <= q);
            if same && forward && within && self.vertices.len() < MAX_VERTICES {
                self.vertices.push(self.to);
                self.lines.push(block.line);
                self.to = to;
                return;
            }
            self.flush(split, &mut emit);
        }
        self.first = Some(*block);
        self.to = to;
    }

    /// Emit the merged move held, if any (in pieces with `split`).
    pub fn flush(&mut self, split: bool, emit: &mut impl FnMut(&Block)) {
        let Some(first) = self.first.take() else { return };
        let vertices = std::mem::take(&mut self.vertices);
        let lines = std::mem::take(&mut self.lines);
        if !split || vertices.is_empty() {
            emit(&Block {
                motion: Motion::Linear { to: self.to },
                ..first
            });
            return;
        }
        // Feet of the vertices on the line, in order (a foot behind the last is taken as it).
        let (start, d) = (first.from, sub(self.to, first.from));
        let len2 = dot(d, d);
        let mut t_prev = 0.0;
        let mut from = start;
        let mut line = first.line;
        for (v, next_line) in vertices.iter().zip(lines) {
            let t = (dot(sub(*v, start), d) / len2).clamp(t_prev, 1.0);
            let foot = add(start, scale(d, t));
            emit(&Block {
                line,
                from,
                motion: Motion::Linear { to: foot },
                ..first
            });
            (t_prev, from, line) = (t, foot, next_line);
        }
        emit(&Block {
            line,
            from,
            motion: Motion::Linear { to: self.to },
            ..first
        });
    }
}

impl Default for Merger {
    fn default() -> Self {
        Merger::new()
    }
}
