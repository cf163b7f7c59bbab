//! PLACEHOLDER until this law is implemented: delegates to the trapezoid.

pub use super::trapezoid::Trapezoid as Jerk15;
pub use super::trapezoid::{max_entry, max_exit, plan, ramp_distance};
