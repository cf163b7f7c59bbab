//! The path stage's numerical tolerances and iteration bounds in one place (as feed/tolerance.rs):
//! when a number counts as zero, two directions as one, and how much rounding a bound allows.
//! The method's own parameters (shares of a budget, knot spacing, cell sizes) stay with the code
//! they shape.

/// Moves and pieces shorter than this (m) are dropped.
pub const MIN_LENGTH: f64 = 1e-12;
/// A per-axis derivative (|p'_i|, |p''_i|, |p'''_i| of a unit-speed curve, or its jump at a
/// junction) at or below this does not limit the axis: the axis does not move along the curve,
/// or does not curve.
pub const NEGLIGIBLE: f64 = 1e-12;
/// Directions closer than this (1 − cos θ) are one direction: no corner.
pub const COLLINEAR_EPS: f64 = 1e-12;
/// Tangent-continuous junction (1 − cos θ) involving arcs.
pub const TANGENT_EPS: f64 = 1e-9;
/// Turns sharper than this (cos of the turning angle below it) stop exactly: the transition
/// would be a near-cusp whose speed limit is practically zero anyway.
pub const REVERSAL_COS: f64 = -0.996;
/// Three points count as on one line when sin² of their angle is at most this (|u × w|² ≤
/// this·|u|²·|w|²): the circle through them is a line.
pub const COLLINEAR_SIN2: f64 = 1e-30;
/// Pieces joined with first derivatives this close and second derivatives this close (1/m)
/// need no transition.
pub const JOINT_D1_EPS: f64 = 1e-9;
pub const JOINT_D2_EPS: f64 = 1e-3;
/// Relative amount by which A_c and J_c may fall short of their shares (rounding).
pub const SHARE_SLACK: f64 = 1e-9;
/// Relative steps (doubling from one ulp) that bring a closed-form speed back inside the budget
/// as evaluated, when rounding puts it a hair outside.
pub const FIT_STEPS: usize = 64;
/// Samples of a transition checked against the programmed geometry (junction.rs), which also
/// say which move each stretch of it reports (source_map.rs).
pub const TRANSITION_SAMPLES: usize = 64;
/// Relative guard on a sum of bounds (Taylor bounds of a polynomial, a piece's end against its
/// curve's length) for the rounding of the sum.
pub const BOUND_ROUNDING: f64 = 1e-12;
/// Relative margin by which x must exceed v³ before ∛x is known to exceed v without taking the
/// root (arc.rs `min_cbrt`): far above the rounding of v³ and of the root.
pub const CUBE_MARGIN: f64 = 1e-9;
/// Absolute guard (m) on a part's length within its whole, beside `BOUND_ROUNDING`.
pub const LENGTH_ROUNDING: f64 = 1e-15;
/// A part that reaches within this share of its whole's length reaches its end.
pub const END_SHARE: f64 = 1e-15;
/// Bisection steps finding where a point's foot on a line passes a move's end (source_map.rs):
/// the interval shrinks to 2⁻⁶⁰ of a transition, far below rounding of its points.
pub const FOOT_BISECTIONS: usize = 60;
/// A neighbour's ramp over what a transition leaves of it (junction.rs): the distance within this
/// share of it, in at most `RAMP_STEPS` steps (a cost to compare cuts by).
pub const RAMP_FIT: f64 = 1e-3;
pub const RAMP_STEPS: usize = 12;
/// A run's cumulative length within this share of a knot's target places the knot there.
pub const KNOT_SLACK: f64 = 1e-9;
/// A restored curve must end within this share of its scale at its end point, and no power term
/// may exceed `MAX_TERM` times its scale (`Hermite::check`).
pub const END_CHECK: f64 = 1e-9;
pub const MAX_TERM: f64 = 1e6;
