//! The documented physical range of every machine key and FMU parameter, in ONE table, enforced
//! by `Machine::check` for the CLI (machine file) and the FMU (fmi2ExitInitializationMode), plus
//! the FMU inputs and outputs. Ranges are wide enough for any real machine and narrow enough that
//! no value can make a tick, a matrix exponential or an allocation run away.

use super::Machine;
use crate::servo::{ServoParams, PARAMETERS};

/// One row: the machine-file key (with the unit it is written in), the FMU name, the range in
/// SI and the factor from the file unit to SI. `zero_ok`: exactly 0 is also allowed (off).
pub struct Range {
    pub key: &'static str,
    pub fmi: &'static str,
    pub min: f64,
    pub max: f64,
    pub factor: f64,
    pub unit: &'static str,
    pub zero_ok: bool,
}

const fn r(
    key: &'static str,
    fmi: &'static str,
    min: f64,
    max: f64,
    factor: f64,
    unit: &'static str,
) -> Range {
    Range {
        key,
        fmi,
        min,
        max,
        factor,
        unit,
        zero_ok: false,
    }
}

use super::{MM, MM_MIN};
const RPM: f64 = 2.0 * std::f64::consts::PI / 60.0;

/// Machine keys (SI ranges; `factor` converts the file's unit).
pub const MACHINE: &[Range] = &[
    r(
        "interpolation_period_s",
        "machine.interpolationPeriod",
        1e-5,
        0.1,
        1.0,
        "s",
    ),
    r(
        "lookahead_blocks",
        "machine.lookaheadBlocks",
        2.0,
        65_536.0,
        1.0,
        "",
    ),
    r("path_tolerance_mm", "machine.pathTolerance", 1e-9, 0.1, MM, "mm"),
    r(
        "chord_tolerance_mm",
        "machine.chordTolerance",
        1e-9,
        0.1,
        MM,
        "mm",
    ),
    r(
        "arc_radius_tolerance_mm",
        "machine.arcRadiusTolerance",
        1e-9,
        0.01,
        MM,
        "mm",
    ),
    r(
        "max_feed_mm_min",
        "machine.maxFeed",
        MM_MIN,
        1e6 * MM_MIN,
        MM_MIN,
        "mm/min",
    ),
    r(
        "max_path_acceleration_mm_s2",
        "machine.maxPathAcceleration",
        1e-3,
        1e3,
        MM,
        "mm/s²",
    ),
    r(
        "max_path_jerk_mm_s3",
        "machine.maxPathJerk",
        1e-2,
        1e6,
        MM,
        "mm/s³",
    ),
    r("max_snap_mm_s4", "machine.maxSnap", 1.0, 1e9, MM, "mm/s⁴"),
    r(
        "max_transition_jerk_mm_s3",
        "machine.maxTransitionJerk",
        1e-2,
        1e7,
        MM,
        "mm/s³",
    ),
];

/// The declared range (SI) of an FMU parameter by its name (`machine.…`, `x.maxJerk`,
/// `y.servo.kv`, …), for `min`/`max` in the modelDescription; None if it has no row here.
/// Parameters where 0 means "none" or "off" are declared from 0.
pub fn declared(fmi_name: &str) -> Option<(f64, f64)> {
    let (table, name) = match fmi_name.split_once('.') {
        Some(("machine", _)) => (MACHINE, fmi_name),
        Some((_, rest)) => match rest.strip_prefix("servo.") {
            Some(servo) => (SERVO, servo),
            None => (AXIS, rest),
        },
        None => return None,
    };
    let r = table.iter().find(|r| r.fmi == name)?;
    let zero_means_none = matches!(
        r.key,
        "max_path_acceleration_mm_s2" | "max_path_jerk_mm_s3" | "max_transition_jerk_mm_s3"
    );
    let min = if r.zero_ok || zero_means_none { 0.0 } else { r.min };
    Some((min, r.max))
}

/// Per-axis keys `[axis.x]` (FMU `x.maxVelocity` …).
pub const AXIS: &[Range] = &[
    r(
        "max_velocity_mm_min",
        "maxVelocity",
        MM_MIN,
        1e6 * MM_MIN,
        MM_MIN,
        "mm/min",
    ),
    r(
        "max_acceleration_mm_s2",
        "maxAcceleration",
        1e-3,
        1e3,
        MM,
        "mm/s²",
    ),
    r("max_jerk_mm_s3", "maxJerk", 1e-2, 1e6, MM, "mm/s³"),
];

/// Drive parameters `[servo.x]` (FMU `x.servo.*`), same order as `servo::PARAMETERS`.
pub const SERVO: &[Range] = &[
    r("screw_lead_mm", "screwLead", 1e-5, 0.1, MM, "mm"),
    r("rotor_inertia_kg_m2", "rotorInertia", 1e-7, 1.0, 1.0, "kg·m²"),
    r("screw_inertia_kg_m2", "screwInertia", 0.0, 1.0, 1.0, "kg·m²"),
    r("table_mass_kg", "tableMass", 1e-2, 1e5, 1.0, "kg"),
    r("axial_stiffness_n_um", "axialStiffness", 1e4, 1e11, 1e6, "N/µm"),
    r("axial_damping_n_s_m", "axialDamping", 0.0, 1e7, 1.0, "N·s/m"),
    r(
        "viscous_friction_n_s_m",
        "viscousFriction",
        0.0,
        1e7,
        1.0,
        "N·s/m",
    ),
    r("coulomb_friction_n", "coulombFriction", 0.0, 1e5, 1.0, "N"),
    r(
        "friction_velocity_mm_s",
        "frictionVelocity",
        1e-7,
        1.0,
        MM,
        "mm/s",
    ),
    r("rated_torque_n_m", "ratedTorque", 1e-3, 1e4, 1.0, "N·m"),
    r("peak_torque_n_m", "peakTorque", 1e-3, 1e4, 1.0, "N·m"),
    r("max_speed_rpm", "maxSpeed", 1.0 * RPM, 1e5 * RPM, RPM, "rpm"),
    Range {
        zero_ok: true,
        ..r("encoder_counts", "encoderCounts", 4.0, 1e9, 1.0, "")
    },
    r("kv_1_s", "kv", 0.1, 1e3, 1.0, "1/s"),
    r(
        "velocity_gain_n_m_s_rad",
        "velocityGain",
        1e-6,
        1e3,
        1.0,
        "N·m·s/rad",
    ),
    r(
        "velocity_integral_time_ms",
        "velocityIntegralTime",
        1e-5,
        10.0,
        MM,
        "ms",
    ),
    r(
        "current_time_constant_ms",
        "currentTimeConstant",
        1e-6,
        0.1,
        MM,
        "ms",
    ),
    r("velocity_feedforward", "velocityFeedforward", 0.0, 1.0, 1.0, ""),
    r(
        "acceleration_feedforward",
        "accelerationFeedforward",
        0.0,
        1.0,
        1.0,
        "",
    ),
    r("linear_scale", "linearScale", 0.0, 1.0, 1.0, "(0 or 1)"),
    r("servo_rate_hz", "servoRate", 100.0, 1e5, 1.0, "Hz"),
];

/// NC setup (`config::nc`): tool numbers `[tool.N]` 1 … MAX_TOOL (LinuxCNC allows pocket
/// numbers well beyond a real magazine); tool radius 0 … 1000 mm; tool length, work offsets
/// `[work_offset.*]` and home positions `[home.*]` within ±100 000 mm (the coordinate range).
pub const MAX_TOOL: u32 = 9_999;
pub const MAX_TOOL_RADIUS_M: f64 = 1.0;
pub const MAX_OFFSET_M: f64 = 100.0;

/// Largest |loadForce| input (N).
pub const MAX_LOAD_FORCE_N: f64 = 1e7;

/// A value out of its range: the dotted machine-file key (to locate it) and the message.
#[derive(Clone, Debug, PartialEq)]
pub struct RangeError {
    pub key: String,
    pub message: String,
}

impl std::fmt::Display for RangeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl Range {
    fn contains(&self, si: f64) -> bool {
        (self.zero_ok && si == 0.0) || (si >= self.min && si <= self.max)
    }

    /// `si` (SI) within the range, else the message in the file's unit with the FMU name.
    pub fn check(&self, prefix: &str, fmi_prefix: &str, si: f64) -> Result<(), RangeError> {
        if self.contains(si) {
            return Ok(());
        }
        let shown = |x: f64| number(x / self.factor);
        let zero = if self.zero_ok { "0 or " } else { "" };
        Err(RangeError {
            key: format!("{prefix}{}", self.key),
            message: format!(
                "{prefix}{} = {} out of range ({zero}{} … {} {}; FMU {fmi_prefix}{})",
                self.key,
                shown(si),
                shown(self.min),
                shown(self.max),
                self.unit,
                self.fmi
            ),
        })
    }
}

/// A number as a reader wants it: plain for ordinary magnitudes, exponent form otherwise.
pub fn number(x: f64) -> String {
    let m = x.abs();
    if m != 0.0 && !(1e-4..1e7).contains(&m) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn row<'a>(table: &'a [Range], key: &str) -> &'a Range {
    table.iter().find(|r| r.key == key).unwrap_or(&table[0])
}

/// Every value of the machine within its range (and the few relations between them).
pub fn check_machine(m: &Machine) -> Result<(), RangeError> {
    let top: [(&str, Option<f64>); 10] = [
        ("interpolation_period_s", Some(m.interpolation_period)),
        ("lookahead_blocks", Some(m.lookahead_blocks as f64)),
        ("path_tolerance_mm", Some(m.path_tolerance)),
        ("chord_tolerance_mm", Some(m.chord_tolerance)),
        ("arc_radius_tolerance_mm", Some(m.arc_radius_tolerance)),
        ("max_feed_mm_min", Some(m.max_feed)),
        ("max_path_acceleration_mm_s2", m.max_path_acceleration),
        ("max_path_jerk_mm_s3", m.max_path_jerk),
        ("max_snap_mm_s4", Some(m.max_snap)),
        ("max_transition_jerk_mm_s3", m.max_transition_jerk),
    ];
    for (key, value) in top {
        if let Some(v) = value {
            row(MACHINE, key).check("", "", v)?;
        }
    }
    for (axis, a) in ["x", "y", "z"].iter().zip(&m.axes) {
        let (prefix, fmi) = (format!("axis.{axis}."), format!("{axis}."));
        row(AXIS, "max_velocity_mm_min").check(&prefix, &fmi, a.max_velocity)?;
        row(AXIS, "max_acceleration_mm_s2").check(&prefix, &fmi, a.max_acceleration)?;
        row(AXIS, "max_jerk_mm_s3").check(&prefix, &fmi, a.max_jerk)?;
    }
    for (axis, s) in ["x", "y", "z"].iter().zip(&m.servo) {
        check_servo(&format!("servo.{axis}."), &format!("{axis}.servo."), s)?;
    }
    Ok(())
}

/// The drive parameters of one axis; `prefix` and `fmi` start the key and the FMU name.
pub fn check_servo(prefix: &str, fmi: &str, s: &ServoParams) -> Result<(), RangeError> {
    for (range, p) in SERVO.iter().zip(PARAMETERS) {
        range.check(prefix, fmi, (p.get)(s))?;
    }
    let located = |key: &str, message: &str| RangeError {
        key: format!("{prefix}{key}"),
        message: format!("{prefix}{key}: {message}"),
    };
    if s.linear_scale != 0.0 && s.linear_scale != 1.0 {
        return Err(located(
            "linear_scale",
            "must be 0 (motor encoder) or 1 (linear scale)",
        ));
    }
    if s.peak_torque < s.rated_torque {
        return Err(located("peak_torque_n_m", "must not be below rated_torque_n_m"));
    }
    Ok(())
}

/// An FMU `loadForce` input: finite, |F| ≤ MAX_LOAD_FORCE_N.
pub fn check_load_force(x: f64) -> Result<f64, String> {
    if x.is_finite() && x.abs() <= MAX_LOAD_FORCE_N {
        Ok(x)
    } else {
        Err(format!(
            "loadForce = {} N out of range (|F| ≤ {MAX_LOAD_FORCE_N} N)",
            number(x)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn servo_rows_follow_the_parameter_table_and_defaults_are_inside() {
        assert_eq!(SERVO.len(), PARAMETERS.len());
        for (r, p) in SERVO.iter().zip(PARAMETERS) {
            assert_eq!((r.key, r.fmi, r.factor), (p.key, p.fmi_name, p.factor));
        }
        assert_eq!(check_machine(&Machine::default()), Ok(()));
    }

    #[test]
    fn messages_name_key_value_range_and_fmu_name() {
        let m = Machine {
            interpolation_period: 1.7976931348623157e308,
            ..Machine::default()
        };
        let e = check_machine(&m).unwrap_err();
        assert_eq!(e.key, "interpolation_period_s");
        assert_eq!(
            e.message,
            "interpolation_period_s = 1.7976931348623157e308 out of range (1e-5 … 0.1 s; FMU machine.interpolationPeriod)"
        );
        let mut m = Machine::default();
        m.servo[1].encoder_counts = 5e-324;
        let e = check_machine(&m).unwrap_err();
        assert_eq!(e.key, "servo.y.encoder_counts");
        assert!(
            e.message.contains("(0 or 4 … 1e9 ; FMU y.servo.encoderCounts)"),
            "{}",
            e.message
        );
        m.servo[1].encoder_counts = 0.0;
        assert_eq!(check_machine(&m), Ok(()));
        assert!(check_load_force(1e308).is_err() && check_load_force(-1e7).is_ok());
    }
}
