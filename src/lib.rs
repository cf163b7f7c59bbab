//! cnc-motion: G-code in, jerk-limited axis motion out every interpolation period.
//!
//! The data path, one module per stage, plain data between stages:
//! `gcode` (Block) → `path` (PathBlock with a Segment) → `plan` (Planned: v_in, v_out, Profile)
//! → `feed` (Profile: s/v/a/j at t) → `interp` (Tick) → `servo` (AxisState).
//! `engine` strings the stages together for the CLI and the FMU; `model` is the FMU's variable table.
//! Inside the library everything is SI (m, s, m/s, m/s², m/s³).

pub mod config;
pub mod engine;
pub mod error;
pub mod feed;
pub mod fmu;
pub mod gcode;
pub mod interp;
pub mod model;
pub mod package;
pub mod path;
pub mod plan;
pub mod servo;
pub mod tolerance;

/// A point or vector in machine axes X, Y, Z (m).
pub type Vec3 = [f64; 3];
