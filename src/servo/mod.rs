//! Servo-axis model: a cascaded feed drive per axis, sub-stepped inside the interpolation period.
//! PLACEHOLDER until the servo model lands: parameters only.

use serde::{Deserialize, Serialize};

/// Actual state of one axis after the drive (SI): what the FMU outputs as `x.position`, ...
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisState {
    /// m (table position, tool point)
    pub position: f64,
    /// m/s
    pub velocity: f64,
    /// command − actual position (m)
    pub following_error: f64,
    /// N·m
    pub motor_torque: f64,
    /// Force the drive puts on the structure (N)
    pub drive_force: f64,
}

/// Drive parameters of one axis (SI), `[servo.x]` in the machine file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ServoParams {}

impl ServoParams {
    /// Read `[servo.x]` keys over the defaults.
    pub fn from_table(table: &toml::Table) -> Result<ServoParams, String> {
        if let Some(key) = table.keys().next() {
            return Err(format!("unknown servo key `{key}`"));
        }
        Ok(ServoParams::default())
    }
}
