//! G93 inverse-time feed (LinuxCNC "G93, G94, G95"; RS274NGC 3.5.19): F is the inverse of the
//! move's duration in minutes, so the path feed of a move of length L is L·F per minute. The
//! length is the programmed one (with G41/G42 the tool centre's path differs by the offset);
//! the machine's feed cap still applies in the planner.

use super::plane_axes;
use crate::gcode::{check, Block, Motion};
use std::f64::consts::TAU;

/// Path feed (m/s) of `block` taking 1/F minutes; a move of zero length gets the largest feed.
pub fn feed(block: &Block, f: f64) -> f64 {
    let v = length(block) * f / 60.0;
    if v > 0.0 {
        v.min(check::MAX_FEED_M_S)
    } else {
        check::MAX_FEED_M_S
    }
}

/// Length (m) of a line, or of an arc / helix with its extra turns.
pub fn length(block: &Block) -> f64 {
    let from = block.from;
    match block.motion {
        Motion::Linear { to } | Motion::Rapid { to } => {
            let d: [f64; 3] = std::array::from_fn(|i| to[i] - from[i]);
            d.iter().map(|x| x * x).sum::<f64>().sqrt()
        }
        Motion::Arc {
            to,
            center,
            plane,
            clockwise,
            turns,
        } => {
            let (a, b, n) = plane_axes(plane);
            let (sa, sb) = (from[a] - center[a], from[b] - center[b]);
            let (ea, eb) = (to[a] - center[a], to[b] - center[b]);
            // Counter-clockwise angle from start to end in (−π, π]; a closed arc is a full turn.
            let theta = (sa * eb - sb * ea).atan2(sa * ea + sb * eb);
            let ccw = if theta > 0.0 { theta } else { theta + TAU };
            let sweep = if clockwise { TAU - ccw } else { ccw };
            let sweep = if sweep == 0.0 { TAU } else { sweep } + turns as f64 * TAU;
            let planar = sa.hypot(sb) * sweep;
            planar.hypot(to[n] - from[n])
        }
        _ => 0.0,
    }
}
