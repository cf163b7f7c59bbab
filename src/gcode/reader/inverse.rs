//! G93 inverse-time feed (LinuxCNC "G93, G94, G95"; RS274NGC 3.5.19): F is the inverse of the
//! move's duration in minutes, so the path feed of a move of length L is L·F per minute. The
//! length is the programmed one (with G41/G42 the tool centre's path differs by the offset);
//! the machine's feed cap applies. A spline's pieces share its 1/F minutes.

use crate::gcode::Block;

/// Path feed (m/s) of a move of `length` (m) taking 1/F minutes, capped at `max` (the machine's
/// largest feed); a move of zero length gets the largest feed.
pub fn feed(length: f64, f: f64, max: f64) -> f64 {
    let v = length * f / 60.0;
    if v > 0.0 {
        v.min(max)
    } else {
        max
    }
}

/// Length (m) of a line, or of an arc / helix with its extra turns: the path stage's geometry,
/// so that the move takes the programmed time on the path actually run.
pub fn length(block: &Block) -> f64 {
    block.geometry().map_or(0.0, |g| g.length())
}
