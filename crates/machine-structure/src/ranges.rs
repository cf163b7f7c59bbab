//! The documented range of every MachineStructure parameter, input and state value (README
//! "Machine file" ranges table), checked when a value is set, at fmi2ExitInitializationMode, after
//! a state is deserialized and on the outputs of every step.

use crate::modal::Mode;
use crate::MachineStructure;

/// (name, min, max, unit) of the parameters and inputs.
pub const FREQUENCY_HZ: (f64, f64) = (0.1, 1e4);
pub const DAMPING: (f64, f64) = (0.0, 10.0);
pub const MODAL_MASS_KG: (f64, f64) = (1e-3, 1e6);
pub const COUPLING_MASS_KG: (f64, f64) = (0.0, 1e5);
/// |driveForce| (N).
pub const MAX_DRIVE_FORCE_N: f64 = 1e7;
/// |d driveForce/dt| (N/s): the whole force range in a microsecond.
pub const MAX_DRIVE_RATE_N_S: f64 = 1e13;
/// |q| (m) and |q̇| (m/s) of a modal state: beyond any elastic frame deflection.
pub const MAX_MODAL_DEFLECTION_M: f64 = 1e3;
pub const MAX_MODAL_VELOCITY_M_S: f64 = 1e6;

/// `value` within `range` (inclusive), else "`name` = value out of range (min … max unit)".
pub fn within(name: &str, value: f64, (min, max): (f64, f64), unit: &str) -> Result<(), String> {
    if value >= min && value <= max {
        Ok(())
    } else {
        Err(format!("{name} = {value:e} out of range ({min} … {max} {unit})"))
    }
}

pub fn check_mode(m: &Mode) -> Result<(), String> {
    within("frequency", m.frequency, FREQUENCY_HZ, "Hz")?;
    within("damping", m.damping, DAMPING, "")?;
    within("mass", m.mass, MODAL_MASS_KG, "kg")
}

pub fn check_drive_force(x: f64) -> Result<(), String> {
    within("driveForce", x, (-MAX_DRIVE_FORCE_N, MAX_DRIVE_FORCE_N), "N")
}

pub fn check_drive_rate(x: f64) -> Result<(), String> {
    within(
        "d(driveForce)/dt",
        x,
        (-MAX_DRIVE_RATE_N_S, MAX_DRIVE_RATE_N_S),
        "N/s",
    )
}

/// Parameters, inputs and states (a deserialized state may be corrupted).
pub fn check_structure(s: &MachineStructure) -> Result<(), String> {
    for i in 0..3 {
        for m in &s.modes[i] {
            check_mode(m)?;
        }
        within("couplingMass", s.coupling_mass[i], COUPLING_MASS_KG, "kg")?;
        check_drive_force(s.drive_force[i])?;
        check_drive_rate(s.drive_rate[i])?;
        for st in &s.state[i] {
            let q = MAX_MODAL_DEFLECTION_M;
            within("modal deflection", st.q, (-q, q), "m")?;
            let v = MAX_MODAL_VELOCITY_M_S;
            within("modal velocity", st.v, (-v, v), "m/s")?;
        }
    }
    Ok(())
}

/// Every output finite: never NaN with status OK.
pub fn check_outputs(s: &MachineStructure) -> Result<(), String> {
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        for (name, v) in [
            ("deflection", s.deflection(i)),
            ("acceleration", s.acceleration(i)),
            ("loadForce", s.load_force(i)),
        ] {
            if !v.is_finite() {
                return Err(format!("{axis}.{name} = {v}: not finite"));
            }
        }
    }
    Ok(())
}
