//! Interpolator: samples the planned motion every period T.

use crate::Vec3;
use serde::{Deserialize, Serialize};

/// What the interpolator emits every period (SI).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Tick {
    /// s
    pub t: f64,
    /// Source line of the block being executed.
    pub line: u32,
    pub p: Vec3,
    pub v: Vec3,
    pub a: Vec3,
    pub j: Vec3,
    /// Path speed, acceleration, jerk and distance travelled along the path.
    pub feed: f64,
    pub path_acceleration: f64,
    pub path_jerk: f64,
    pub distance: f64,
    /// The program has ended and the machine stands at its end point.
    pub finished: bool,
}
