//! The CncMotion FMU model: its variables as ONE table of plain rows ([`ROWS`], fmi2's own
//! Type/Causality/Variability), each naming the [`Slot`] of the model it reads or writes; get and
//! set are one match over the slots. crates/fmi2 generates the XML, the units and the
//! documentation from the rows.

use crate::config::{CornerMode, Machine};
use crate::engine::Engine;
use crate::feed::ProfileKind;
use crate::servo::PARAMETERS as SERVO;
use fmi2::Causality::{Input as IN, Output as OUT, Parameter as PAR};
use fmi2::Type::{Boolean as BOOL, Enumeration as ENUM, Integer as INT, Real as REAL, String as STR};
use fmi2::Variability::{Continuous as CONT, Discrete as TICK, Fixed as FIX};
use fmi2::{EnumerationType, Type, Value, VariableInfo};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::sync::Arc;

pub const MODEL_NAME: &str = "CncMotion";

/// What an acc/dec law is (an Enumeration item's description; every law must have one).
fn profile_doc(k: ProfileKind) -> &'static str {
    match k {
        ProfileKind::Scurve7 => "7-phase jerk-limited S-curve (Pessoles et al.)",
        ProfileKind::Quintic => "quintic polynomial feedrate (Chen et al.)",
        ProfileKind::Jerk15 => "15-phase jerk-continuous law (Ji et al.)",
        ProfileKind::Mixed57 => "mixed 7/5-period S-curve (Zhang et al.)",
        ProfileKind::Trapezoid => "linear acceleration/deceleration",
    }
}

fn corner_doc(c: CornerMode) -> &'static str {
    match c {
        CornerMode::ExactStop => "stop at every corner",
        CornerMode::AccelerationPeriod => "corner feed A·T/(1−cos θ) per axis (seed 003)",
        CornerMode::Circular => "circular blend within the path tolerance",
        CornerMode::Polynomial => "quintic transition at one speed within the path tolerance (seed 004)",
        CornerMode::Smooth => "C2 quintic transitions planned with the path, micro-segment runs as one curve",
    }
}

/// The Enumeration types `Profile` and `Corner`: items (name, description) 1…n in the order of
/// `ProfileKind::ALL` / `CornerMode::ALL`, so the XML follows the library's lists.
pub fn enumerations() -> Vec<EnumerationType> {
    let profiles = ProfileKind::ALL.iter().map(|&k| (k.name(), profile_doc(k)));
    let corners = CornerMode::ALL.iter().map(|&c| (c.name(), corner_doc(c)));
    vec![
        EnumerationType::new("Profile", profiles),
        EnumerationType::new("Corner", corners),
    ]
}

/// What a row reads or writes. `A` in a slot of the table is the axis, filled in per axis.
#[derive(Clone, Copy, Debug)]
pub enum Slot {
    Program,
    ProgramFile,
    /// interpolationPeriod, pathTolerance, chordTolerance, maxFeed, maxPathAcceleration,
    /// maxPathJerk, maxSnap, maxTransitionJerk, arcRadiusTolerance.
    Machine(usize),
    Lookahead,
    Profile,
    ProfileIndex,
    Corner,
    CornerIndex,
    /// Axis; maxVelocity, maxAcceleration, maxJerk.
    Limit(usize, usize),
    /// Axis; index into `servo::PARAMETERS` (one row of the table stands for all of them).
    Servo(usize, usize),
    ServoEnabled,
    FeedOverride,
    FeedHold,
    LoadForce(usize),
    /// Axis; position, velocity, acceleration, jerk of the command.
    Command(usize, usize),
    /// feed, acceleration, jerk, distance along the path.
    Path(usize),
    Line,
    Finished,
    /// Axis; position, velocity, followingError, motorTorque, driveForce of the drive.
    Drive(usize, usize),
    ContourError,
}

const A: usize = usize::MAX;
const NO: Option<f64> = None;
const ZERO: Option<f64> = Some(0.0);

/// See [`fmi2::table::Row`]: `#` rows are per axis. Outputs depend on no input (inputs act from
/// the next step on).
type Row = fmi2::table::Row<Slot>;

#[rustfmt::skip]
pub const ROWS: &[Row] = &[
    ("program",                     STR,     PAR, FIX,  "",     NO,   NO,        Slot::Program,          "G-code program text; empty: read programFile"),
    ("programFile",                 STR,     PAR, FIX,  "",     NO,   NO,        Slot::ProgramFile,      "G-code file, relative to the FMU's resources"),
    ("machine.interpolationPeriod", REAL,    PAR, FIX,  "s",    ZERO, NO,        Slot::Machine(0),       "interpolation period T"),
    ("machine.pathTolerance",       REAL,    PAR, FIX,  "m",    ZERO, NO,        Slot::Machine(1),       "default G64 path tolerance"),
    ("machine.chordTolerance",      REAL,    PAR, FIX,  "m",    ZERO, NO,        Slot::Machine(2),       "chord error on arcs"),
    ("machine.maxFeed",             REAL,    PAR, FIX,  "m/s",  ZERO, NO,        Slot::Machine(3),       "maximum feed (also G0)"),
    ("machine.maxPathAcceleration", REAL,    PAR, FIX,  "m/s2", ZERO, NO,        Slot::Machine(4),       "path acceleration limit on top of the axes' (0: none)"),
    ("machine.maxPathJerk",         REAL,    PAR, FIX,  "m/s3", ZERO, NO,        Slot::Machine(5),       "path jerk limit on top of the axes' (0: none)"),
    ("machine.maxSnap",             REAL,    PAR, FIX,  "m/s4", ZERO, NO,        Slot::Machine(6),       "snap limit (jerk15)"),
    ("machine.maxTransitionJerk",   REAL,    PAR, FIX,  "m/s3", ZERO, NO,        Slot::Machine(7),       "axis jerk in constant-speed corner transitions (polynomial, circular; 0: the axes' own)"),
    ("machine.arcRadiusTolerance",  REAL,    PAR, FIX,  "m",    ZERO, NO,        Slot::Machine(8),       "arc end point radius mismatch accepted (G20 programs: 2.54 times it), or 0.1 % of the radius"),
    ("machine.lookaheadBlocks",     INT,     PAR, FIX,  "",     Some(2.0), Some(1e6), Slot::Lookahead,   "look-ahead window (segments)"),
    ("machine.profile",             ENUM(0), PAR, FIX,  "",     NO,   NO,        Slot::Profile,          "acc/dec law"),
    ("machine.profileIndex",        INT,     PAR, FIX,  "",     ZERO, NO,        Slot::ProfileIndex,     "acc/dec law as an Integer (importers without Enumerations): 0 keeps machine.profile, 1… its items"),
    ("machine.corner",              ENUM(1), PAR, FIX,  "",     NO,   NO,        Slot::Corner,           "corner passage"),
    ("machine.cornerIndex",         INT,     PAR, FIX,  "",     ZERO, NO,        Slot::CornerIndex,      "corner passage as an Integer (importers without Enumerations): 0 keeps machine.corner, 1… its items"),
    ("#.maxVelocity",               REAL,    PAR, FIX,  "m/s",  ZERO, NO,        Slot::Limit(A, 0),      "# axis velocity limit"),
    ("#.maxAcceleration",           REAL,    PAR, FIX,  "m/s2", ZERO, NO,        Slot::Limit(A, 1),      "# axis acceleration limit"),
    ("#.maxJerk",                   REAL,    PAR, FIX,  "m/s3", ZERO, NO,        Slot::Limit(A, 2),      "# axis jerk limit"),
    ("#.servo.*",                   REAL,    PAR, FIX,  "",     NO,   NO,        Slot::Servo(A, 0),      "# drive: "),
    ("servo.enabled",               BOOL,    PAR, FIX,  "",     NO,   NO,        Slot::ServoEnabled,     "simulate the drives (off: actual = command)"),
    ("feedOverride",                REAL,    IN,  CONT, "1",    ZERO, Some(2.0), Slot::FeedOverride,     "feed override factor (jerk-limited)"),
    ("feedHold",                    BOOL,    IN,  TICK, "",     NO,   NO,        Slot::FeedHold,         "feed hold: stop on the path within the limits; release resumes"),
    ("#.loadForce",                 REAL,    IN,  CONT, "N",    NO,   NO,        Slot::LoadForce(A),     "external force on the # table (from a structure model)"),
    ("#.command.position",          REAL,    OUT, TICK, "m",    NO,   NO,        Slot::Command(A, 0),    "# commanded position"),
    ("#.command.velocity",          REAL,    OUT, TICK, "m/s",  NO,   NO,        Slot::Command(A, 1),    "# commanded velocity"),
    ("#.command.acceleration",      REAL,    OUT, TICK, "m/s2", NO,   NO,        Slot::Command(A, 2),    "# commanded acceleration"),
    ("#.command.jerk",              REAL,    OUT, TICK, "m/s3", NO,   NO,        Slot::Command(A, 3),    "# commanded jerk"),
    ("path.feed",                   REAL,    OUT, TICK, "m/s",  NO,   NO,        Slot::Path(0),          "path speed"),
    ("path.acceleration",           REAL,    OUT, TICK, "m/s2", NO,   NO,        Slot::Path(1),          "path acceleration"),
    ("path.jerk",                   REAL,    OUT, TICK, "m/s3", NO,   NO,        Slot::Path(2),          "path jerk"),
    ("path.distance",               REAL,    OUT, TICK, "m",    NO,   NO,        Slot::Path(3),          "path distance travelled"),
    ("status.line",                 INT,     OUT, TICK, "",     NO,   NO,        Slot::Line,             "source line of the block being executed"),
    ("status.finished",             BOOL,    OUT, TICK, "",     NO,   NO,        Slot::Finished,         "all motion of the program done"),
    ("#.position",                  REAL,    OUT, CONT, "m",    NO,   NO,        Slot::Drive(A, 0),      "# actual position"),
    ("#.velocity",                  REAL,    OUT, CONT, "m/s",  NO,   NO,        Slot::Drive(A, 1),      "# actual velocity"),
    ("#.followingError",            REAL,    OUT, CONT, "m",    NO,   NO,        Slot::Drive(A, 2),      "# following error (command − feedback)"),
    ("#.motorTorque",               REAL,    OUT, CONT, "N.m",  NO,   NO,        Slot::Drive(A, 3),      "# motor torque"),
    ("#.driveForce",                REAL,    OUT, CONT, "N",    NO,   NO,        Slot::Drive(A, 4),      "# force of the drive on the machine structure"),
    ("path.contourError",           REAL,    OUT, CONT, "m",    NO,   NO,        Slot::ContourError,     "distance of the actual tool point from the programmed path"),
];

impl Slot {
    fn on_axis(self, i: usize) -> Slot {
        match self {
            Slot::Limit(_, k) => Slot::Limit(i, k),
            Slot::Servo(_, k) => Slot::Servo(i, k),
            Slot::LoadForce(_) => Slot::LoadForce(i),
            Slot::Command(_, k) => Slot::Command(i, k),
            Slot::Drive(_, k) => Slot::Drive(i, k),
            s => s,
        }
    }
}

/// FMI type of a servo parameter: counts are Integers, the feedback switch a Boolean.
fn servo_type(fmi_name: &str) -> Type {
    match fmi_name {
        "encoderCounts" => INT,
        "linearScale" => BOOL,
        _ => REAL,
    }
}

/// The table expanded (value references 1…n in this order); the servo row stands for every
/// drive parameter of its axis.
pub fn rows() -> Vec<(VariableInfo, Slot)> {
    let mut rows = fmi2::table::expand(ROWS, &["x", "y", "z"], |row, i, axis| match row.7 {
        Slot::Servo(..) => servo_rows(i, axis).collect(),
        slot => vec![(variable(row, axis), slot.on_axis(i))],
    });
    // Parameters declare the documented ranges that `Machine::check` enforces (config/ranges.rs).
    for (v, _) in &mut rows {
        if matches!(v.kind, Type::Real | Type::Integer) {
            if let Some((min, max)) = crate::config::ranges::declared(&v.name) {
                v.min = Some(min);
                v.max = Some(max);
            }
        }
    }
    rows
}

fn variable(row: &Row, axis: &str) -> VariableInfo {
    let v = fmi2::table::variable(row, axis);
    // The Integer twins of the Enumerations range over the same items.
    match row.7 {
        Slot::ProfileIndex => v.range(Some(0.0), Some(ProfileKind::ALL.len() as f64)),
        Slot::CornerIndex => v.range(Some(0.0), Some(CornerMode::ALL.len() as f64)),
        _ => v,
    }
}

/// The drive parameters of one axis, from the servo's own table.
fn servo_rows(i: usize, axis: &str) -> impl Iterator<Item = (VariableInfo, Slot)> + '_ {
    SERVO.iter().enumerate().map(move |(j, p)| {
        let (name, kind) = (format!("{axis}.servo.{}", p.fmi_name), servo_type(p.fmi_name));
        let mut v = VariableInfo::new(name, kind, PAR, FIX, format!("{axis} drive: {}", p.description));
        if kind == REAL {
            v = v.unit(p.unit);
        }
        if p.description.ends_with("0…1") {
            v = v.range(Some(0.0), Some(1.0));
        }
        (v, Slot::Servo(i, j))
    })
}

/// The model: parameters and inputs as set by the importer, and the running engine (serialized
/// by the FMU separately, with the program text it needs).
#[derive(Clone, Debug, Serialize, Deserialize)]
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
    #[serde(skip)]
    pub resources: Option<PathBuf>,
    #[serde(skip)]
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
                    m.max_transition_jerk.unwrap_or(0.0),
                    m.arc_radius_tolerance,
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

    /// Write a parameter or input; bad values are refused with the reason (the FMI layer has
    /// already refused non-finite Reals and values outside the declared min/max).
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
                6 => m.max_snap = positive(x)?,
                7 => m.max_transition_jerk = optional(x)?,
                _ => m.arc_radius_tolerance = positive(x)?,
            },
            (Slot::Lookahead, Value::Integer(n)) => m.lookahead_blocks = n as usize,
            (Slot::Profile, Value::Integer(n)) => m.profile = item(&ProfileKind::ALL, n)?,
            (Slot::Corner, Value::Integer(n)) => m.corner = item(&CornerMode::ALL, n)?,
            (Slot::ProfileIndex, Value::Integer(n)) => self.profile_index = n,
            (Slot::CornerIndex, Value::Integer(n)) => self.corner_index = n,
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
            (Slot::FeedOverride, Value::Real(x)) => self.feed_override = x,
            (Slot::FeedHold, Value::Boolean(b)) => self.feed_hold = b,
            (Slot::LoadForce(i), Value::Real(x)) => {
                self.load_force[i] = crate::config::ranges::check_load_force(x)?
            }
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
            let text = crate::gcode::source::read_program_file(&path, &self.program_file)?;
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
        e.advance(h).map_err(|e| e.to_string())?;
        crate::config::ranges::check_outputs(e)
    }
}
