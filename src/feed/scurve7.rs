//! PLACEHOLDER until this law is implemented: delegates to the trapezoid.

pub use super::trapezoid::Trapezoid as Scurve7;
pub use super::trapezoid::{max_entry, max_exit, plan, ramp_distance};
