//! G93 inverse-time feed (LinuxCNC "G93, G94, G95"; RS274NGC 3.5.19): F is the inverse of the
//! move's duration in minutes, so the path feed of a move of length L is L·F per minute. The
//! length is the programmed one (with G41/G42 the tool centre's path differs by the offset);
//! the machine's feed cap still applies in the planner.

use crate::gcode::{check, Block};
use crate::path::Source;

/// Path feed (m/s) of `block` taking 1/F minutes; a move of zero length gets the largest feed.
pub fn feed(block: &Block, f: f64) -> f64 {
    let v = length(block) * f / 60.0;
    if v > 0.0 {
        v.min(check::MAX_FEED_M_S)
    } else {
        check::MAX_FEED_M_S
    }
}

/// Length (m) of a line, or of an arc / helix with its extra turns: the path stage's geometry,
/// so that the move takes the programmed time on the path actually run.
pub fn length(block: &Block) -> f64 {
    Source::of_block(block).map_or(0.0, |g| g.length())
}
