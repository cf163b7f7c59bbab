//! The CncMotion FMU model: its variables as ONE table of plain rows (fmi2's own
//! Type/Causality/Variability, units and ranges), each naming the [`Slot`] of the model it reads
//! or writes; get and set are one match over the slots. The FMI layer (crates/fmi2) generates the
//! XML, the units and the documentation from the rows.

use crate::config::{CornerMode, Machine};
use crate::engine::Engine;
use crate::feed::ProfileKind;
use crate::servo::PARAMETERS as SERVO;
use fmi2::{Causality, Type, Value, Variability, VariableInfo};
use std::path::PathBuf;
use std::sync::Arc;

pub const MODEL_NAME: &str = "CncMotion";
const AXES: [&str; 3] = ["x", "y", "z"];

/// Enumeration types: name and items (name, description); values are 1-based.
pub const ENUMERATIONS: [(&str, &[(&str, &str)]); 2] = [
    (
        "Profile",
        &[
            ("scurve7", "7-phase jerk-limited S-curve (Pessoles et al.)"),
            ("quintic", "quintic polynomial feedrate (Chen et al.)"),
            ("jerk15", "15-phase jerk-continuous law (Ji et al.)"),
            ("mixed57", "mixed 7/5-period S-curve (Zhang et al.)"),
            ("trapezoid", "linear acceleration/deceleration"),
        ],
    ),
    (
        "Corner",
        &[
            ("exact_stop", "stop at every corner"),
            (
                "acceleration_period",
                "corner feed A·T/(1−cos θ) per axis (seed 003)",
            ),
            ("circular", "circular blend within the path tolerance"),
            (
                "polynomial",
                "quintic transition within the path tolerance (seed 004)",
            ),
        ],
    ),
];

/// The model: parameters and inputs as set by the importer, and the running engine.
#[derive(Clone, Debug)]
pub struct CncMotion {
    pub program: String,
    pub program_file: String,
    pub machine: Machine,
    /// `machine.profileIndex`/`machine.cornerIndex`: 0 keeps the Enumeration's choice, 1…n
    /// replace it (for importers that cannot set Enumerations, e.g. libcosim).
    pub profile_index: i32,
    pub corner_index: i32,
    pub servo_enabled: bool,
    pub feed_override: f64,
    pub feed_hold: bool,
    pub load_force: [f64; 3],
    /// The FMU's resources folder (for relative `programFile`).
    pub resources: Option<PathBuf>,
    pub engine: Option<Engine>,
}

impl Default for CncMotion {
    fn default() -> Self {
        CncMotion {
            program: String::new(),
            program_file: "default.ngc".into(),
            machine: Machine::default(),
            profile_index: 0,
            corner_index: 0,
            servo_enabled: true,
            feed_override: 1.0,
            feed_hold: false,
            load_force: [0.0; 3],
            resources: None,
            engine: None,
        }
    }
}

/// What a row reads or writes: axis indices and field indices, never packed.
#[derive(Clone, Copy, Debug)]
pub enum Slot {
    Program,
    ProgramFile,
    /// Scalar Real of the machine, index into `MACHINE_REALS`.
    Machine(usize),
    Lookahead,
    Profile,
    ProfileIndex,
    Corner,
    CornerIndex,
    /// Axis limit: velocity, acceleration, jerk.
    Limit(usize, usize),
    /// Axis, index into `servo::PARAMETERS`.
    Servo(usize, usize),
    ServoEnabled,
    FeedOverride,
    FeedHold,
    LoadForce(usize),
    /// Axis, position/velocity/acceleration/jerk of the command.
    Command(usize, usize),
    /// feed, acceleration, jerk, distance along the path.
    Path(usize),
    Line,
    Finished,
    /// Axis, position/velocity/followingError/motorTorque/driveForce of the drive.
    Drive(usize, usize),
    ContourError,
}

/// Scalar machine Reals: name, unit, description (0 means "none" for the optional limits).
const MACHINE_REALS: [(&str, &str, &str); 7] = [
    ("interpolationPeriod", "s", "interpolation period T"),
    ("pathTolerance", "m", "default G64 path tolerance"),
    ("chordTolerance", "m", "chord error on arcs"),
    ("maxFeed", "m/s", "maximum feed (also G0)"),
    (
        "maxPathAcceleration",
        "m/s2",
        "path acceleration limit on top of the axes' (0: none)",
    ),
    (
        "maxPathJerk",
        "m/s3",
        "path jerk limit on top of the axes' (0: none)",
    ),
    ("maxSnap", "m/s4", "snap limit (jerk15)"),
];
const LIMITS: [(&str, &str); 3] = [
    ("maxVelocity", "m/s"),
    ("maxAcceleration", "m/s2"),
    ("maxJerk", "m/s3"),
];
const COMMAND: [(&str, &str); 4] = [
    ("position", "m"),
    ("velocity", "m/s"),
    ("acceleration", "m/s2"),
    ("jerk", "m/s3"),
];
const PATH: [(&str, &str, &str); 4] = [
    ("feed", "m/s", "path speed"),
    ("acceleration", "m/s2", "path acceleration"),
    ("jerk", "m/s3", "path jerk"),
    ("distance", "m", "path distance travelled"),
];
const DRIVE: [(&str, &str, &str); 5] = [
    ("position", "m", "actual position"),
    ("velocity", "m/s", "actual velocity"),
    ("followingError", "m", "following error (command − feedback)"),
    ("motorTorque", "N.m", "motor torque"),
    ("driveForce", "N", "force of the drive on the machine structure"),
];

/// FMI type of a servo parameter: counts are Integers, the feedback switch a Boolean.
fn servo_type(fmi_name: &str) -> Type {
    match fmi_name {
        "encoderCounts" => Type::Integer,
        "linearScale" => Type::Boolean,
        _ => Type::Real,
    }
}

/// The table, in value-reference order (1…n): parameters, inputs, then [`outputs`].
pub fn rows() -> Vec<(VariableInfo, Slot)> {
    use Causality::{Input, Parameter};
    use Type::{Boolean, Enumeration, Integer, Real};
    let par =
        |name: &str, kind, desc: &str| VariableInfo::new(name, kind, Parameter, Variability::Fixed, desc);
    let input = |name: &str, kind, desc: &str| {
        let variability = if kind == Boolean {
            Variability::Discrete
        } else {
            Variability::Continuous
        };
        VariableInfo::new(name, kind, Input, variability, desc)
    };
    let mut t = Vec::new();
    let mut add = |slot, v| t.push((v, slot));
    add(
        Slot::Program,
        par(
            "program",
            Type::String,
            "G-code program text; empty: read programFile",
        ),
    );
    add(
        Slot::ProgramFile,
        par(
            "programFile",
            Type::String,
            "G-code file, relative to the FMU's resources",
        ),
    );
    for (k, (name, unit, desc)) in MACHINE_REALS.iter().enumerate() {
        let v = par(&format!("machine.{name}"), Real, desc).unit(unit);
        add(Slot::Machine(k), v.range(Some(0.0), None));
    }
    let lookahead = par("machine.lookaheadBlocks", Integer, "look-ahead window (segments)");
    add(Slot::Lookahead, lookahead.range(Some(2.0), Some(1e6)));
    add(
        Slot::Profile,
        par("machine.profile", Enumeration(0), "acc/dec law"),
    );
    let index = "as an Integer for importers without Enumerations: 0 keeps";
    let v = par(
        "machine.profileIndex",
        Integer,
        &format!("acc/dec law {index} machine.profile, 1…5"),
    );
    add(Slot::ProfileIndex, v.range(Some(0.0), Some(5.0)));
    add(
        Slot::Corner,
        par("machine.corner", Enumeration(1), "corner passage"),
    );
    let v = par(
        "machine.cornerIndex",
        Integer,
        &format!("corner passage {index} machine.corner, 1…4"),
    );
    add(Slot::CornerIndex, v.range(Some(0.0), Some(4.0)));
    for (i, a) in AXES.iter().enumerate() {
        for (k, (name, unit)) in LIMITS.iter().enumerate() {
            let desc = format!("{a} axis {} limit", &name[3..].to_lowercase());
            add(
                Slot::Limit(i, k),
                par(&format!("{a}.{name}"), Real, &desc)
                    .unit(unit)
                    .range(Some(0.0), None),
            );
        }
    }
    for (i, a) in AXES.iter().enumerate() {
        for (k, p) in SERVO.iter().enumerate() {
            let (kind, desc) = (servo_type(p.fmi_name), format!("{a} drive: {}", p.description));
            let mut v = par(&format!("{a}.servo.{}", p.fmi_name), kind, &desc);
            if kind == Real {
                v = v.unit(p.unit);
            }
            if p.description.ends_with("0…1") {
                v = v.range(Some(0.0), Some(1.0));
            }
            add(Slot::Servo(i, k), v);
        }
    }
    add(
        Slot::ServoEnabled,
        par(
            "servo.enabled",
            Boolean,
            "simulate the drives (off: actual = command)",
        ),
    );
    let v = input("feedOverride", Real, "feed override factor (jerk-limited)").unit("1");
    add(Slot::FeedOverride, v.range(Some(0.0), Some(2.0)));
    add(
        Slot::FeedHold,
        input(
            "feedHold",
            Boolean,
            "feed hold: stop on the path within the limits",
        ),
    );
    for (i, a) in AXES.iter().enumerate() {
        let desc = format!("external force on the {a} table (from a structure model)");
        add(
            Slot::LoadForce(i),
            input(&format!("{a}.loadForce"), Real, &desc).unit("N"),
        );
    }
    outputs(&mut t);
    t
}

/// Outputs: none depends directly on an input (inputs act from the next step on).
fn outputs(t: &mut Vec<(VariableInfo, Slot)>) {
    use Type::{Boolean, Integer, Real};
    let (tick, cont) = (Variability::Discrete, Variability::Continuous);
    let mut add = |slot, name: &str, kind, variability, unit: Option<&str>, desc: &str| {
        let v = VariableInfo::new(name, kind, Causality::Output, variability, desc).depends_on(vec![]);
        t.push((unit.map_or(v.clone(), |u| v.unit(u)), slot));
    };
    for (i, a) in AXES.iter().enumerate() {
        for (k, (name, unit)) in COMMAND.iter().enumerate() {
            let desc = format!("{a} commanded {name}");
            add(
                Slot::Command(i, k),
                &format!("{a}.command.{name}"),
                Real,
                tick,
                Some(unit),
                &desc,
            );
        }
    }
    for (k, (name, unit, desc)) in PATH.iter().enumerate() {
        add(
            Slot::Path(k),
            &format!("path.{name}"),
            Real,
            tick,
            Some(unit),
            desc,
        );
    }
    add(
        Slot::Line,
        "status.line",
        Integer,
        tick,
        None,
        "source line of the block being executed",
    );
    add(
        Slot::Finished,
        "status.finished",
        Boolean,
        tick,
        None,
        "all motion of the program done",
    );
    for (i, a) in AXES.iter().enumerate() {
        for (k, (name, unit, desc)) in DRIVE.iter().enumerate() {
            add(
                Slot::Drive(i, k),
                &format!("{a}.{name}"),
                Real,
                cont,
                Some(unit),
                &format!("{a} {desc}"),
            );
        }
    }
    let desc = "distance of the actual tool point from the programmed path";
    add(
        Slot::ContourError,
        "path.contourError",
        Real,
        cont,
        Some("m"),
        desc,
    );
}

fn positive(x: f64) -> Result<f64, String> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(format!("must be a finite positive number, got {x}"))
    }
}

/// 0 → None (no limit), else a positive limit.
fn optional(x: f64) -> Result<Option<f64>, String> {
    if x == 0.0 {
        Ok(None)
    } else {
        positive(x).map(Some)
    }
}

/// Item `n` (1-based) of a list of choices.
fn item<T: Copy>(all: &[T], n: i32) -> Result<T, String> {
    let i = usize::try_from(n - 1).ok().filter(|&i| i < all.len());
    i.map(|i| all[i])
        .ok_or(format!("must be 1 … {}, got {n}", all.len()))
}

fn index_of<T: PartialEq>(all: &[T], x: &T) -> i32 {
    all.iter().position(|k| k == x).unwrap_or(0) as i32 + 1
}

impl CncMotion {
    pub fn get(&self, slot: Slot) -> Value {
        let m = &self.machine;
        let tick = || self.engine.as_ref().map(|e| *e.tick()).unwrap_or_default();
        let drive = |i: usize| self.engine.as_ref().map(|e| e.axes()[i]).unwrap_or_default();
        match slot {
            Slot::Program => Value::String(self.program.clone()),
            Slot::ProgramFile => Value::String(self.program_file.clone()),
            Slot::Machine(k) => Value::Real(
                [
                    m.interpolation_period,
                    m.path_tolerance,
                    m.chord_tolerance,
                    m.max_feed,
                    m.max_path_acceleration.unwrap_or(0.0),
                    m.max_path_jerk.unwrap_or(0.0),
                    m.max_snap,
                ][k],
            ),
            Slot::Lookahead => Value::Integer(m.lookahead_blocks as i32),
            Slot::Profile => Value::Integer(index_of(&ProfileKind::ALL, &m.profile)),
            Slot::ProfileIndex => Value::Integer(self.profile_index),
            Slot::Corner => Value::Integer(index_of(&CornerMode::ALL, &m.corner)),
            Slot::CornerIndex => Value::Integer(self.corner_index),
            Slot::Limit(i, k) => {
                let l = &m.axes[i];
                Value::Real([l.max_velocity, l.max_acceleration, l.max_jerk][k])
            }
            Slot::Servo(i, k) => {
                let x = (SERVO[k].get)(&m.servo[i]);
                match servo_type(SERVO[k].fmi_name) {
                    Type::Integer => Value::Integer(x as i32),
                    Type::Boolean => Value::Boolean(x != 0.0),
                    _ => Value::Real(x),
                }
            }
            Slot::ServoEnabled => Value::Boolean(self.servo_enabled),
            Slot::FeedOverride => Value::Real(self.feed_override),
            Slot::FeedHold => Value::Boolean(self.feed_hold),
            Slot::LoadForce(i) => Value::Real(self.load_force[i]),
            Slot::Command(i, k) => {
                let t = tick();
                Value::Real([t.p, t.v, t.a, t.j][k][i])
            }
            Slot::Path(k) => {
                let t = tick();
                Value::Real([t.feed, t.path_acceleration, t.path_jerk, t.distance][k])
            }
            Slot::Line => Value::Integer(tick().line as i32),
            Slot::Finished => Value::Boolean(tick().finished),
            Slot::Drive(i, k) => {
                let d = drive(i);
                Value::Real(
                    [
                        d.position,
                        d.velocity,
                        d.following_error,
                        d.motor_torque,
                        d.drive_force,
                    ][k],
                )
            }
            Slot::ContourError => Value::Real(self.engine.as_ref().map_or(0.0, |e| e.contour_error())),
        }
    }

    /// Write a parameter or input; bad values are refused with the reason.
    pub fn set(&mut self, slot: Slot, value: Value) -> Result<(), String> {
        let m = &mut self.machine;
        match (slot, value) {
            (Slot::Program, Value::String(s)) => self.program = s,
            (Slot::ProgramFile, Value::String(s)) => self.program_file = s,
            (Slot::Machine(k), Value::Real(x)) => match k {
                0 => m.interpolation_period = positive(x)?,
                1 => m.path_tolerance = positive(x)?,
                2 => m.chord_tolerance = positive(x)?,
                3 => m.max_feed = positive(x)?,
                4 => m.max_path_acceleration = optional(x)?,
                5 => m.max_path_jerk = optional(x)?,
                _ => m.max_snap = positive(x)?,
            },
            (Slot::Lookahead, Value::Integer(n)) if (2..=1_000_000).contains(&n) => {
                m.lookahead_blocks = n as usize
            }
            (Slot::Lookahead, Value::Integer(n)) => return Err(format!("must be 2 … 1000000, got {n}")),
            (Slot::Profile, Value::Integer(n)) => m.profile = item(&ProfileKind::ALL, n)?,
            (Slot::Corner, Value::Integer(n)) => m.corner = item(&CornerMode::ALL, n)?,
            (Slot::ProfileIndex, Value::Integer(n)) => {
                self.profile_index = if n == 0 { 0 } else { item(&[1, 2, 3, 4, 5], n)? }
            }
            (Slot::CornerIndex, Value::Integer(n)) => {
                self.corner_index = if n == 0 { 0 } else { item(&[1, 2, 3, 4], n)? }
            }
            (Slot::Limit(i, k), Value::Real(x)) => {
                let l = &mut m.axes[i];
                *[&mut l.max_velocity, &mut l.max_acceleration, &mut l.max_jerk][k] = positive(x)?;
            }
            (Slot::Servo(i, k), v) => {
                let x = match v {
                    Value::Real(x) => x,
                    Value::Integer(n) => n as f64,
                    Value::Boolean(b) => f64::from(u8::from(b)),
                    Value::String(_) => return Err("not a number".into()),
                };
                m.servo[i].set(SERVO[k].fmi_name, x)?
            }
            (Slot::ServoEnabled, Value::Boolean(b)) => self.servo_enabled = b,
            (Slot::FeedOverride, Value::Real(x)) if (0.0..=2.0).contains(&x) => self.feed_override = x,
            (Slot::FeedOverride, Value::Real(x)) => {
                return Err(format!("feedOverride must be 0 … 2, got {x}"))
            }
            (Slot::FeedHold, Value::Boolean(b)) => self.feed_hold = b,
            (Slot::LoadForce(i), Value::Real(x)) if x.is_finite() => self.load_force[i] = x,
            (Slot::LoadForce(_), Value::Real(x)) => return Err(format!("loadForce must be finite, got {x}")),
            _ => return Err("cannot be set".into()),
        }
        Ok(())
    }

    /// Load the program (inline text, or the file, relative to the resources folder) and start
    /// the engine. Errors come back as `file:line:col: message`.
    pub fn initialize(&mut self) -> Result<(), String> {
        if self.profile_index != 0 {
            self.machine.profile = item(&ProfileKind::ALL, self.profile_index)?;
        }
        if self.corner_index != 0 {
            self.machine.corner = item(&CornerMode::ALL, self.corner_index)?;
        }
        self.machine.check()?;
        let (text, name) = if !self.program.trim().is_empty() {
            (self.program.clone(), "program".to_string())
        } else {
            let path = match &self.resources {
                Some(dir) => dir.join(&self.program_file),
                None => PathBuf::from(&self.program_file),
            };
            let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            (text, self.program_file.clone())
        };
        let engine = Engine::new(Arc::from(text), &name, &self.machine).map_err(|e| e.to_string())?;
        self.engine = Some(engine.with_servo(self.servo_enabled));
        Ok(())
    }

    /// One communication step of length h (s) from the engine's time, with the current inputs.
    pub fn do_step(&mut self, h: f64) -> Result<(), String> {
        let e = self.engine.as_mut().ok_or("the model is not initialized")?;
        e.set_feed_override(self.feed_override);
        e.set_feed_hold(self.feed_hold);
        e.set_load_force(self.load_force);
        e.advance(h).map_err(|e| e.to_string())
    }
}
