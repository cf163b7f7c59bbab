//! The documented physical range of every machine key and FMU parameter, ONE source: the tables
//! below (machine keys, axis keys) and the drive table `servo::PARAMETERS`. The FMU declares its
//! `min`/`max` from here ([`declared`]), checks each value's own range when it is set
//! ([`Range::fmu_check`], [`check_servo_value`]) and the relations between values (peak ≥ rated
//! torque) at fmi2ExitInitializationMode with the whole machine (`Machine::check`), as the CLI
//! does for a machine file. Ranges are wide enough for any real machine and narrow enough that no
//! value can make a tick, a matrix exponential or an allocation run away.

use super::{CornerMode, Machine};
use crate::feed::ProfileKind;
use crate::servo::{Kind, ServoParameter, ServoParams, PARAMETERS};

/// One row: the machine-file key (with the unit it is written in), the FMU name, the range in
/// SI and the factor from the file unit to SI. `zero_ok`: exactly 0 is also allowed (off);
/// `none_at_zero`: an optional limit, absent from the file when not wanted, which the FMU
/// parameter sets to 0 for "none".
#[derive(Debug)]
pub struct Range {
    pub key: &'static str,
    pub fmi: &'static str,
    pub min: f64,
    pub max: f64,
    pub factor: f64,
    pub unit: &'static str,
    pub zero_ok: bool,
    pub none_at_zero: bool,
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
        none_at_zero: false,
    }
}

/// An optional limit (`none_at_zero`).
const fn optional(r: Range) -> Range {
    Range {
        none_at_zero: true,
        ..r
    }
}

use super::{MM, MM_MIN};

/// Largest |coordinate| of an axis position, a centre offset (I/J/K), a radius (R), a G64
/// tolerance, a tool length, work offset or home position: 100 m, far beyond any machine table,
/// far below where metres lose sub-µm precision (programs: `gcode::check`).
pub const MAX_COORDINATE_M: f64 = 100.0;
/// Largest feed any machine runs, the top of `max_feed_mm_min` and of the axes'
/// `max_velocity_mm_min`: 1 000 000 mm/min (16.7 m/s). A larger F is not an error: as on an NC,
/// it runs at the machine's largest feed.
pub const MAX_FEED_MM_MIN: f64 = 1e6;

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
        MAX_FEED_MM_MIN * MM_MIN,
        MM_MIN,
        "mm/min",
    ),
    optional(r(
        "max_path_acceleration_mm_s2",
        "machine.maxPathAcceleration",
        1e-3,
        1e3,
        MM,
        "mm/s²",
    )),
    optional(r(
        "max_path_jerk_mm_s3",
        "machine.maxPathJerk",
        1e-2,
        1e6,
        MM,
        "mm/s³",
    )),
    r("max_snap_mm_s4", "machine.maxSnap", 1.0, 1e9, MM, "mm/s⁴"),
    optional(r(
        "max_transition_jerk_mm_s3",
        "machine.maxTransitionJerk",
        1e-2,
        1e7,
        MM,
        "mm/s³",
    )),
];

/// Per-axis keys `[axis.x]` (FMU `x.maxVelocity` …).
pub const AXIS: &[Range] = &[
    r(
        "max_velocity_mm_min",
        "maxVelocity",
        MM_MIN,
        MAX_FEED_MM_MIN * MM_MIN,
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

/// NC setup (`config::nc`): tool numbers `[tool.N]` 1 … MAX_TOOL (LinuxCNC allows pocket
/// numbers well beyond a real magazine); tool radius 0 … 1000 mm; tool length, work offsets
/// `[work_offset.*]` and home positions `[home.*]` within ±100 000 mm (the coordinate range).
pub const MAX_TOOL: u32 = 9_999;
pub const MAX_TOOL_RADIUS_M: f64 = 1.0;
pub const MAX_OFFSET_M: f64 = MAX_COORDINATE_M;

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

    /// The range of a drive parameter, from its row of `servo::PARAMETERS`.
    pub fn of_servo(p: &ServoParameter) -> Range {
        Range {
            key: p.key,
            fmi: p.fmi_name,
            min: p.min,
            max: p.max,
            factor: p.factor,
            unit: p.file_unit,
            zero_ok: p.zero_ok,
            none_at_zero: false,
        }
    }

    /// The lowest value the FMU parameter accepts: 0 where 0 means "off" or "none".
    pub fn fmu_min(&self) -> f64 {
        if self.zero_ok || self.none_at_zero {
            0.0
        } else {
            self.min
        }
    }

    /// An FMU parameter's own range, checked when it is set (SI, as the FMU declares it).
    pub fn fmu_check(&self, si: f64) -> Result<(), String> {
        if self.contains(si) || (self.none_at_zero && si == 0.0) {
            return Ok(());
        }
        let zero = if self.zero_ok || self.none_at_zero {
            "0 or "
        } else {
            ""
        };
        Err(format!(
            "{} out of range ({zero}{} … {})",
            number(si),
            number(self.min),
            number(self.max)
        ))
    }

    /// `si` (SI) within the range, else the message in the file's unit with the FMU name.
    pub fn check(&self, prefix: &str, fmi_prefix: &str, si: f64) -> Result<(), RangeError> {
        self.check_in(prefix, fmi_prefix, si, false)
    }

    /// `check` for a file in `inch` units (`units = "inch"`): a length key's value and range
    /// are quoted in inches, as the file wrote them.
    pub fn check_in(&self, prefix: &str, fmi_prefix: &str, si: f64, inch: bool) -> Result<(), RangeError> {
        if self.contains(si) {
            return Ok(());
        }
        let inches = inch && self.unit.starts_with("mm");
        let (factor, unit) = if inches {
            (self.factor * INCH_MM, self.unit.replacen("mm", "in", 1))
        } else {
            (self.factor, self.unit.to_string())
        };
        let shown = |x: f64| {
            let v = x / factor;
            number(if inches { significant(v) } else { v })
        };
        let zero = if self.zero_ok { "0 or " } else { "" };
        Err(RangeError {
            key: format!("{prefix}{}", self.key),
            message: format!(
                "{prefix}{} = {} out of range ({zero}{} … {} {unit}; FMU {fmi_prefix}{})",
                self.key,
                shown(si),
                shown(self.min),
                shown(self.max),
                self.fmi
            ),
        })
    }
}

/// Millimetres per inch.
pub const INCH_MM: f64 = 25.4;

/// `x` to 12 significant digits: a value converted to SI and back (× 25.4 ÷ 25.4) reads as
/// written, not 400000.00000000006.
pub fn significant(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(11 - x.abs().log10().floor() as i32);
    if scale.is_finite() && (x * scale).is_finite() {
        (x * scale).round() / scale
    } else {
        x
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

/// The row of `key` in `table`; a key without a row is an error (a programming error: every
/// key `check_machine` names is in the tables, which its tests run through).
pub fn row<'a>(table: &'a [Range], key: &str) -> Result<&'a Range, RangeError> {
    table.iter().find(|r| r.key == key).ok_or_else(|| RangeError {
        key: key.to_string(),
        message: format!("{key}: no documented range (internal error)"),
    })
}

/// Largest feed override factor (FMU input `feedOverride`, 0 … this).
pub const MAX_FEED_OVERRIDE: f64 = 2.0;

/// The declared range (SI) of an FMU variable by its name (`machine.…`, `x.maxJerk`,
/// `y.servo.kv`, `feedOverride`, `z.loadForce`, …), for `min`/`max` in the modelDescription;
/// None if it has none. Parameters where 0 means "none" or "off" are declared from 0; Booleans
/// (`linearScale`) declare nothing.
pub fn declared(fmi_name: &str) -> Option<(f64, f64)> {
    let enum_index = |n: usize| Some((0.0, n as f64));
    match fmi_name {
        "feedOverride" => return Some((0.0, MAX_FEED_OVERRIDE)),
        "machine.profileIndex" => return enum_index(ProfileKind::ALL.len()),
        "machine.cornerIndex" => return enum_index(CornerMode::ALL.len()),
        _ => {}
    }
    let (axis_or_machine, rest) = fmi_name.split_once('.')?;
    if axis_or_machine == "machine" {
        let r = MACHINE.iter().find(|r| r.fmi == fmi_name)?;
        return Some((r.fmu_min(), r.max));
    }
    if rest == "loadForce" {
        return Some((-MAX_LOAD_FORCE_N, MAX_LOAD_FORCE_N));
    }
    if let Some(servo) = rest.strip_prefix("servo.") {
        let p = PARAMETERS.iter().find(|p| p.fmi_name == servo)?;
        let r = Range::of_servo(p);
        return (p.kind != Kind::Switch).then(|| (r.fmu_min(), r.max));
    }
    let r = AXIS.iter().find(|r| r.fmi == rest)?;
    Some((r.fmu_min(), r.max))
}

/// A drive parameter's own range (and kind: whole counts, 0/1 switches), checked when the FMU
/// parameter is set.
pub fn check_servo_value(p: &ServoParameter, si: f64) -> Result<(), String> {
    Range::of_servo(p).fmu_check(si)?;
    match p.kind {
        _ if p.admits(si) => Ok(()),
        Kind::Switch => Err(format!("{} is neither 0 nor 1", number(si))),
        _ => Err(format!("{} is not a whole number", number(si))),
    }
}

/// Every value of the machine within its range, then the relations between values.
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
    let inch = m.nc.inch;
    for (key, value) in top {
        if let Some(v) = value {
            row(MACHINE, key)?.check_in("", "", v, inch)?;
        }
    }
    for (axis, a) in ["x", "y", "z"].iter().zip(&m.axes) {
        let (prefix, fmi) = (format!("axis.{axis}."), format!("{axis}."));
        row(AXIS, "max_velocity_mm_min")?.check_in(&prefix, &fmi, a.max_velocity, inch)?;
        row(AXIS, "max_acceleration_mm_s2")?.check_in(&prefix, &fmi, a.max_acceleration, inch)?;
        row(AXIS, "max_jerk_mm_s3")?.check_in(&prefix, &fmi, a.max_jerk, inch)?;
    }
    for (axis, s) in ["x", "y", "z"].iter().zip(&m.servo) {
        check_servo(&format!("servo.{axis}."), &format!("{axis}.servo."), s)?;
    }
    Ok(())
}

/// The drive parameters of one axis, each in its range, then the relation between them (peak ≥
/// rated torque); `prefix` and `fmi` start the key and the FMU name. A relation's message names
/// both values, as keys and as FMU parameters.
pub fn check_servo(prefix: &str, fmi: &str, s: &ServoParams) -> Result<(), RangeError> {
    for p in PARAMETERS {
        let v = (p.get)(s);
        Range::of_servo(p).check(prefix, fmi, v)?;
        if !p.admits(v) {
            let what = if p.kind == Kind::Switch {
                "0 or 1"
            } else {
                "a whole number"
            };
            return Err(RangeError {
                key: format!("{prefix}{}", p.key),
                message: format!("{prefix}{} = {}: must be {what}", p.key, number(v)),
            });
        }
    }
    if s.peak_torque < s.rated_torque {
        return Err(RangeError {
            key: format!("{prefix}peak_torque_n_m"),
            message: format!(
                "{prefix}peak_torque_n_m = {} must not be below {prefix}rated_torque_n_m = {} \
                 (FMU {fmi}peakTorque, {fmi}ratedTorque)",
                number(s.peak_torque),
                number(s.rated_torque)
            ),
        });
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
    fn defaults_are_inside_and_an_unknown_key_is_an_error() {
        assert_eq!(check_machine(&Machine::default()), Ok(()));
        for p in PARAMETERS {
            assert!(p.admits((p.get)(&ServoParams::default())), "{}", p.key);
        }
        let e = row(MACHINE, "max_fed_mm_min").unwrap_err();
        assert_eq!(e.key, "max_fed_mm_min");
        assert!(e.message.contains("no documented range"), "{}", e.message);
    }

    #[test]
    fn a_relation_names_both_values_and_both_fmu_parameters() {
        let mut m = Machine::default();
        m.servo[2].rated_torque = 3.0;
        let e = check_machine(&m).unwrap_err();
        assert_eq!(e.key, "servo.z.peak_torque_n_m");
        assert_eq!(
            e.message,
            "servo.z.peak_torque_n_m = 1.9 must not be below servo.z.rated_torque_n_m = 3 \
             (FMU z.servo.peakTorque, z.servo.ratedTorque)"
        );
        m.servo[2].peak_torque = 9.0;
        assert_eq!(check_machine(&m), Ok(()));
    }

    #[test]
    fn own_ranges_of_fmu_parameters() {
        let path_acc = row(MACHINE, "max_path_acceleration_mm_s2").unwrap();
        assert_eq!(path_acc.fmu_check(0.0), Ok(()), "0: no path limit");
        assert!(path_acc
            .fmu_check(1e-5)
            .unwrap_err()
            .contains("(0 or 0.001 … 1000)"));
        let counts = PARAMETERS.iter().find(|p| p.kind == Kind::Count).unwrap();
        assert!(check_servo_value(counts, 4.5)
            .unwrap_err()
            .contains("whole number"));
        assert!(check_servo_value(counts, 2.0)
            .unwrap_err()
            .contains("out of range (0 or 4"));
        assert_eq!(check_servo_value(counts, 0.0), Ok(()));
        assert_eq!(declared("x.servo.linearScale"), None, "a Boolean");
        assert_eq!(declared("y.servo.encoderCounts"), Some((0.0, 1e9)));
        assert_eq!(declared("machine.lookaheadBlocks"), Some((2.0, 65_536.0)));
        assert_eq!(declared("machine.maxPathJerk"), Some((0.0, 1e6)));
        assert_eq!(declared("z.loadForce"), Some((-1e7, 1e7)));
        assert_eq!(declared("feedOverride"), Some((0.0, 2.0)));
        assert_eq!(declared("x.command.position"), None);
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
