//! cnc-motion: G-code in, jerk-limited axis motion out every interpolation period.
//!
//! The data path, one module per stage, plain data between stages:
//! `gcode` (Block) → `path` (PathBlock with a Segment) → `plan` (Planned: v_in, v_out, Profile)
//! → `feed` (Profile: s/v/a/j at t) → `interp` (Tick) → `servo` (AxisState).
//! `engine` strings the stages together for the CLI and the FMU; `model` is the FMU's variable table.
//! Below the stages: `geometry` (Vec3, planes, the programmed line or arc of a block), `si` (unit
//! factors), `valid`, `error`; `config` (the machine) sits above `feed` and `servo`, below the
//! rest. No import cycle among these modules (tests/house.rs).
//! Inside the library everything is SI (m, s, m/s, m/s², m/s³).

// `unused_crate_dependencies` (workspace lints) sees the library alone: these are the binary's
// dependencies (one package, one list), and in the unit-test build the integration tests'.
use clap as _;
use csv as _;
use indicatif as _;
use serde_json as _;
#[cfg(test)]
use {criterion as _, libc as _, libloading as _, proptest as _};

pub mod config;
pub mod engine;
pub mod error;
pub mod feed;
pub mod fmu;
pub mod gcode;
pub mod geometry;
pub mod interp;
pub mod model;
pub mod package;
pub mod path;
pub mod plan;
pub mod servo;
pub mod si;
#[cfg(test)]
mod test_rng;
pub mod tolerance;
pub mod valid;

pub use geometry::Vec3;
