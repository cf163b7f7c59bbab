//! Named tolerances of the engine, the plan and the drives. The path stage keeps its own in
//! [`crate::path::tolerance`], cutter compensation in `gcode/reader/comp_geom.rs`; the feed laws'
//! solver bounds and residuals are in [`crate::feed::tolerance`].

pub use crate::feed::tolerance as feed;

/// Fraction of a period within which two times count as the same instant (rounding of summed
/// step sizes): a tick that close to the end of a step belongs to it, a sub-step that close to a
/// period boundary completes it, a remainder that small is not a step.
pub const PERIOD_SLACK: f64 = 1e-9;
/// A communication point within this of a whole number of interpolation periods (s) is that
/// tick: importers form t and h in floating point (n·h, sums of h, t_{n+1} − t_n, integer ns),
/// which misses n·T by up to a few ulps of t (4.5e-13 s at one hour); a real fraction of a
/// period is far longer (the shortest period is 10 µs).
pub const SAME_INSTANT_S: f64 = 1e-9;
/// Relative difference below which a step size counts as a full period (the cached step is used).
pub const SAME_STEP: f64 = 1e-12;
/// Relative margin by which a speed counts as above a target (re-plan of override and hold).
pub const SPEED_MARGIN: f64 = 1e-12;
