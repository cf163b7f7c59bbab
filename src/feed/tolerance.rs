//! The feed laws' numerical tolerances and iteration bounds in one place (as Ruckig's profile.hpp):
//! every solver is bounded, and every closed-form root is made exact against the distance function
//! by stepping down a few ulps, so these bound work, not accuracy.

/// Bracketed Newton steps (quadratic convergence: 3–8 used; the bracket halves otherwise).
pub const NEWTON_STEPS: usize = 64;
/// Bisection steps: the bracket reaches adjacent floats long before.
pub const BISECTIONS: usize = 110;
/// Relative width (of the larger end) at which a regula falsi's bracket ends: far above the
/// rounding of the distances it inverts (a few ulps; below it the steps only chase that noise),
/// far below anything a tick shows (1e-12 of a speed is 1e-15 m over a 1 ms tick at 1 m/s).
pub const ROOT_TOL: f64 = 1e-12;
/// Steps of `fit_down` (ulps, doubling): covers any start within a factor 2 of the target.
pub const FIT_DOWN_STEPS: usize = 64;
/// Doublings of the bracket in the generic `largest_within` search.
pub const BRACKET_DOUBLINGS: usize = 80;
/// First bracket width (m/s) of `largest_within` from a standstill.
pub const BRACKET_START: f64 = 1e-3;
/// Relative residual at which scurve7's peak Newton stops (the rest is taken by `fit_down`).
pub const PEAK_RESIDUAL: f64 = 1e-8;
/// Relative step at which scurve7's peak Newton stops.
pub const PEAK_STEP: f64 = 1e-15;
/// Relative slack with which a closed-form root just outside its regime (by rounding) is kept.
pub const ROOT_SLACK: f64 = 1e-12;
/// Relative Newton step after which the bracketed Newton stops (the error left is about its square).
pub const NEWTON_STEP: f64 = 1e-9;
/// Residual of a distance equation, relative to the length, at which the Newton iterations stop
/// (a few ulps: `fit_down` then takes at most a step or two).
pub const RESIDUAL: f64 = 4.0 * f64::EPSILON;
/// Newton steps of scurve7's peak speed (quadratic convergence from a Cardano start: 3–6 used).
pub const PEAK_NEWTON_STEPS: usize = 40;
