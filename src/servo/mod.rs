//! Servo-axis model: a cascaded feed drive per axis, sub-stepped at the servo rate inside the
//! interpolation period (docs/servo.md has the structure, equations and defaults).

mod drive;
mod params;

pub use drive::{expm, plant_matrix, AxisCommand, PlantState, ServoAxis, MAX_SQUARINGS};
pub use params::{Kind, ServoParameter, ServoParams, PARAMETERS};

use serde::{Deserialize, Serialize};

/// Actual state of one axis after the drive (SI): what the FMU outputs as `x.position`, ...
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisState {
    /// m (table position, tool point)
    pub position: f64,
    /// m/s
    pub velocity: f64,
    /// command − feedback position (m)
    pub following_error: f64,
    /// N·m
    pub motor_torque: f64,
    /// Force the drive puts on the structure (N)
    pub drive_force: f64,
}
