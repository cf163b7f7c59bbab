//! Drive parameters of one axis: ONE table gives the machine-file key (with its unit), the FMU
//! name and type, the SI factor and the documented range, so the TOML reader, the range check
//! (config/ranges.rs), the FMU variables and the docs agree.

use serde::{Deserialize, Serialize};

/// Drive parameters of one axis (SI), `[servo.x]` in the machine file.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ServoParams {
    /// Ball-screw lead (m per motor revolution).
    pub screw_lead: f64,
    /// Motor rotor inertia (kg·m²).
    pub rotor_inertia: f64,
    /// Screw and coupling inertia on the motor side (kg·m²).
    pub screw_inertia: f64,
    /// Table (and workpiece) mass (kg).
    pub table_mass: f64,
    /// Axial stiffness of screw, nut and bearings (N/m).
    pub axial_stiffness: f64,
    /// Axial damping (N·s/m).
    pub axial_damping: f64,
    /// Viscous friction on the table (N·s/m).
    pub viscous_friction: f64,
    /// Coulomb friction on the table (N), smoothed over `friction_velocity`.
    pub coulomb_friction: f64,
    /// Velocity band of the smoothed Coulomb friction, F·tanh(v/v_band) (m/s).
    pub friction_velocity: f64,
    /// Rated and peak motor torque (N·m); the torque command saturates at the peak.
    pub rated_torque: f64,
    pub peak_torque: f64,
    /// Maximum motor speed (rad/s): the drive's rating, declared for the machine file and the FMU;
    /// the model does not limit by it (the axis velocity limits bound the command).
    pub max_speed: f64,
    /// Encoder resolution (counts per motor revolution); 0 = ideal.
    pub encoder_counts: f64,
    /// Position loop gain k_v (1/s).
    pub kv: f64,
    /// Velocity loop PI: proportional gain (N·m·s/rad) and integral time (s).
    pub velocity_gain: f64,
    pub velocity_integral_time: f64,
    /// Current (torque) loop as a first-order lag (s).
    pub current_time_constant: f64,
    /// Velocity and acceleration feed-forward (0…1).
    pub velocity_feedforward: f64,
    pub acceleration_feedforward: f64,
    /// Position feedback: 0 motor encoder (semi-closed loop), 1 linear scale on the table.
    pub linear_scale: f64,
    /// Servo (sub-step) rate (Hz).
    pub servo_rate: f64,
}

impl Default for ServoParams {
    /// Seed 000, Table 1 (a real 3-axis mill) for the motor and screw; the rest chosen for a small
    /// mill and documented in docs/servo.md.
    fn default() -> Self {
        ServoParams {
            screw_lead: 1.2e-3,
            rotor_inertia: 0.42e-4,
            screw_inertia: 0.20e-4,
            table_mass: 50.0,
            axial_stiffness: 1.5e8,
            axial_damping: 2.0e3,
            viscous_friction: 200.0,
            coulomb_friction: 20.0,
            friction_velocity: 1e-4,
            rated_torque: 0.64,
            peak_torque: 1.9,
            max_speed: 5000.0 * 2.0 * std::f64::consts::PI / 60.0,
            encoder_counts: 10000.0,
            kv: 40.0,
            velocity_gain: 0.06,
            velocity_integral_time: 4e-3,
            current_time_constant: 2e-4,
            velocity_feedforward: 1.0,
            acceleration_feedforward: 0.0,
            linear_scale: 0.0,
            servo_rate: 8000.0,
        }
    }
}

/// How a parameter is kept (f64 in [`ServoParams`]) and shown to an FMU importer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A physical value (FMU Real).
    Real,
    /// A whole number of counts (FMU Integer).
    Count,
    /// 0 or 1 (FMU Boolean).
    Switch,
}

/// One parameter, the ONE table of what the machine file, the range check and the FMU know about
/// it: machine-file key (its unit in the name), FMU name, SI unit (FMU), the unit the file writes
/// and its factor to SI, the documented range in SI (`zero_ok`: exactly 0 is also allowed, "off"
/// or "ideal"), the kind and the description.
pub struct ServoParameter {
    pub key: &'static str,
    pub fmi_name: &'static str,
    pub unit: &'static str,
    pub file_unit: &'static str,
    pub factor: f64,
    pub min: f64,
    pub max: f64,
    pub zero_ok: bool,
    pub kind: Kind,
    pub description: &'static str,
    pub get: fn(&ServoParams) -> f64,
    pub set: fn(&mut ServoParams, f64),
}

impl ServoParameter {
    /// `x` (SI) is within the documented range (and a whole number, or 0 or 1, for counts and
    /// switches).
    pub fn admits(&self, x: f64) -> bool {
        let kind_ok = match self.kind {
            Kind::Real => true,
            Kind::Count => x.fract() == 0.0,
            Kind::Switch => x == 0.0 || x == 1.0,
        };
        kind_ok && ((self.zero_ok && x == 0.0) || (x >= self.min && x <= self.max))
    }
}

macro_rules! p {
    ($key:literal, $fmi:literal, $unit:literal, $file_unit:literal, $factor:expr, $min:expr, $max:expr,
     $kind:ident, $field:ident, $desc:literal) => {
        ServoParameter {
            key: $key,
            fmi_name: $fmi,
            unit: $unit,
            file_unit: $file_unit,
            factor: $factor,
            min: $min,
            max: $max,
            zero_ok: false,
            kind: Kind::$kind,
            description: $desc,
            get: |s| s.$field,
            set: |s, v| s.$field = v,
        }
    };
}

const RPM: f64 = 2.0 * std::f64::consts::PI / 60.0;
use crate::si::MM;

/// Every drive parameter. Ranges (SI) are wide enough for any real feed drive and narrow enough
/// that no value can make the matrix exponential or the sub-stepping run away.
#[rustfmt::skip]
pub const PARAMETERS: &[ServoParameter] = &[
    p!("screw_lead_mm", "screwLead", "m", "mm", MM, 1e-5, 0.1, Real, screw_lead, "ball-screw lead per motor revolution"),
    p!("rotor_inertia_kg_m2", "rotorInertia", "kg.m2", "kg·m²", 1.0, 1e-7, 1.0, Real, rotor_inertia, "motor rotor inertia"),
    p!("screw_inertia_kg_m2", "screwInertia", "kg.m2", "kg·m²", 1.0, 0.0, 1.0, Real, screw_inertia, "screw and coupling inertia"),
    p!("table_mass_kg", "tableMass", "kg", "kg", 1.0, 1e-2, 1e5, Real, table_mass, "table and workpiece mass"),
    p!("axial_stiffness_n_um", "axialStiffness", "N/m", "N/µm", 1e6, 1e4, 1e11, Real, axial_stiffness, "axial stiffness of screw, nut, bearings"),
    p!("axial_damping_n_s_m", "axialDamping", "N.s/m", "N·s/m", 1.0, 0.0, 1e7, Real, axial_damping, "axial damping"),
    p!("viscous_friction_n_s_m", "viscousFriction", "N.s/m", "N·s/m", 1.0, 0.0, 1e7, Real, viscous_friction, "viscous friction on the table"),
    p!("coulomb_friction_n", "coulombFriction", "N", "N", 1.0, 0.0, 1e5, Real, coulomb_friction, "Coulomb friction on the table"),
    p!("friction_velocity_mm_s", "frictionVelocity", "m/s", "mm/s", MM, 1e-7, 1.0, Real, friction_velocity, "smoothing band of Coulomb friction"),
    p!("rated_torque_n_m", "ratedTorque", "N.m", "N·m", 1.0, 1e-3, 1e4, Real, rated_torque, "rated motor torque"),
    p!("peak_torque_n_m", "peakTorque", "N.m", "N·m", 1.0, 1e-3, 1e4, Real, peak_torque, "peak motor torque (saturation; not below ratedTorque)"),
    p!("max_speed_rpm", "maxSpeed", "rad/s", "rpm", RPM, 1.0 * RPM, 1e5 * RPM, Real, max_speed, "maximum motor speed"),
    ServoParameter {
        zero_ok: true,
        ..p!("encoder_counts", "encoderCounts", "1", "", 1.0, 4.0, 1e9, Count, encoder_counts, "encoder counts per revolution (0: ideal)")
    },
    p!("kv_1_s", "kv", "1/s", "1/s", 1.0, 0.1, 1e3, Real, kv, "position loop gain"),
    p!("velocity_gain_n_m_s_rad", "velocityGain", "N.m.s/rad", "N·m·s/rad", 1.0, 1e-6, 1e3, Real, velocity_gain, "velocity loop proportional gain"),
    p!("velocity_integral_time_ms", "velocityIntegralTime", "s", "ms", MM, 1e-5, 10.0, Real, velocity_integral_time, "velocity loop integral time"),
    p!("current_time_constant_ms", "currentTimeConstant", "s", "ms", MM, 1e-6, 0.1, Real, current_time_constant, "current loop time constant"),
    p!("velocity_feedforward", "velocityFeedforward", "1", "", 1.0, 0.0, 1.0, Real, velocity_feedforward, "velocity feed-forward 0…1"),
    p!("acceleration_feedforward", "accelerationFeedforward", "1", "", 1.0, 0.0, 1.0, Real, acceleration_feedforward, "acceleration feed-forward 0…1"),
    p!("linear_scale", "linearScale", "1", "(0 or 1)", 1.0, 0.0, 1.0, Switch, linear_scale, "position feedback: 0 motor encoder, 1 linear scale"),
    p!("servo_rate_hz", "servoRate", "Hz", "Hz", 1.0, 100.0, 1e5, Real, servo_rate, "servo sub-step rate"),
];

impl ServoParams {
    /// Read `[servo.x]` keys over the defaults; an unknown key or a value that is not a number
    /// is an error naming the key (the ranges are checked with the whole machine).
    pub fn from_table(table: &toml::Table) -> Result<ServoParams, (String, String)> {
        let mut s = ServoParams::default();
        for (key, value) in table {
            let p = PARAMETERS.iter().find(|p| p.key == key).ok_or_else(|| {
                let keys: Vec<&str> = PARAMETERS.iter().map(|p| p.key).collect();
                let msg = format!("unknown servo key `{key}` (known: {})", keys.join(", "));
                (key.clone(), msg)
            })?;
            let v = value
                .as_float()
                .or_else(|| value.as_integer().map(|i| i as f64))
                .ok_or_else(|| (key.clone(), format!("servo key `{key}` must be a number")))?;
            (p.set)(&mut s, v * p.factor);
        }
        Ok(s)
    }
}
