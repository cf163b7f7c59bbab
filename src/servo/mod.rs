//! Servo-axis model: a cascaded feed drive per axis, sub-stepped inside the interpolation period.
//! PLACEHOLDER until the servo model lands: parameters only.

use serde::{Deserialize, Serialize};

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
