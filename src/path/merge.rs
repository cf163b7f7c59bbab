//! G64 Q: LinuxCNC's "naive CAM detector". Consecutive G1 moves of one feed whose inner vertices
//! all lie within Q of the straight line from the first start to the last end are one move, so a
//! nearly straight run of CAM points is run as the line it stands for.

use super::{distance_to_segment, dot, sub};
use crate::gcode::{Block, Motion, PathMode};
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
        }
    }

    /// Offer a block: the merged blocks now final come out through `emit` (in order); the block
    /// itself is either absorbed or emitted too.
    pub fn push(&mut self, block: &Block, mut emit: impl FnMut(&Block)) {
        let Motion::Linear { to } = block.motion else {
            self.flush(&mut emit);
            emit(block);
            return;
        };
        let Some(q) = q_of(block) else {
            self.flush(&mut emit);
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
                self.to = to;
                return;
            }
            self.flush(&mut emit);
        }
        self.first = Some(*block);
        self.to = to;
    }

    /// Emit the merged move held, if any.
    pub fn flush(&mut self, emit: &mut impl FnMut(&Block)) {
        if let Some(mut first) = self.first.take() {
            first.motion = Motion::Linear { to: self.to };
            self.vertices.clear();
            emit(&first);
        }
    }
}

impl Default for Merger {
    fn default() -> Self {
        Merger::new()
    }
}
