//! The CncMotion FMU model: its variables as ONE table of plain rows ([`ROWS`], fmi2's own
//! Type/Causality/Variability), each naming the [`Slot`] of the model it reads or writes on its
//! axis; get and set are one match over the slots. crates/fmi2 expands the table per axis and
//! generates the XML, the units and the documentation from it.

use crate::config::{CornerMode, Machine};
use crate::engine::Engine;
use crate::feed::ProfileKind;
use crate::servo::PARAMETERS as SERVO;
use fmi2::table::Entry;
use fmi2::Causality::{Input as IN, Output as OUT, Parameter as PAR};
use fmi2::Type::{Boolean as BOOL, Enumeration as ENUM, Integer as INT, Real as REAL, String as STR};
use fmi2::Variability::{Continuous as CONT, Discrete as TICK, Fixed as FIX};
use fmi2::{enum_item, enum_value, EnumerationType, Type, Value, VariableInfo};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::sync::Arc;

pub const MODEL_NAME: &str = "CncMotion";

/// The Enumeration types `Profile` and `Corner`: items 1…n in the order of the library's lists.
pub fn enumerations() -> Vec<EnumerationType> {
    vec![
        EnumerationType::new("Profile", ProfileKind::ALL.map(|k| (k.name(), k.description()))),
        EnumerationType::new("Corner", CornerMode::ALL.map(|c| (c.name(), c.description()))),
    ]
}

/// What a row reads or writes (on the axis of its entry, for `#` rows).
#[derive(Clone, Copy, Debug)]
pub enum Slot {
    Program,
    ProgramFile,
    /// Index into [`MACHINE`].
    Machine(usize),
    Lookahead,
    Profile,
    ProfileIndex,
    Corner,
    CornerIndex,
    /// maxVelocity, maxAcceleration, maxJerk.
    Limit(usize),
    /// Index into `servo::PARAMETERS` (one row of the table stands for all of them).
    Servo(usize),
    ServoEnabled,
    FeedOverride,
    FeedHold,
    LoadForce,
    /// Position, velocity, acceleration, jerk of the command.
    Command(usize),
    /// Feed, acceleration, jerk, distance along the path.
    Path(usize),
    Line,
    Finished,
    /// Position, velocity, followingError, motorTorque, driveForce of the drive.
    Drive(usize),
    ContourError,
}

/// The `machine.*` Reals: read and write their field of [`Machine`] (0 stands for "none" in the
/// optional limits). Values arrive finite and within the declared min/max (fmi2 checks them).
type Field = (fn(&Machine) -> f64, fn(&mut Machine, f64));
#[rustfmt::skip]
const MACHINE: [Field; 9] = [
    (|m| m.interpolation_period, |m, x| m.interpolation_period = x),
    (|m| m.path_tolerance, |m, x| m.path_tolerance = x),
    (|m| m.chord_tolerance, |m, x| m.chord_tolerance = x),
    (|m| m.max_feed, |m, x| m.max_feed = x),
    (|m| m.max_path_acceleration.unwrap_or(0.0), |m, x| m.max_path_acceleration = (x > 0.0).then_some(x)),
    (|m| m.max_path_jerk.unwrap_or(0.0), |m, x| m.max_path_jerk = (x > 0.0).then_some(x)),
    (|m| m.max_snap, |m, x| m.max_snap = x),
    (|m| m.max_transition_jerk.unwrap_or(0.0), |m, x| m.max_transition_jerk = (x > 0.0).then_some(x)),
    (|m| m.arc_radius_tolerance, |m, x| m.arc_radius_tolerance = x),
];

const NO: Option<f64> = None;
const ZERO: Option<f64> = Some(0.0);
/// The Integer twins of the Enumerations range over the same items (0: keep the Enumeration's).
const PROFILES: Option<f64> = Some(ProfileKind::ALL.len() as f64);
const CORNERS: Option<f64> = Some(CornerMode::ALL.len() as f64);

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
    ("machine.profileIndex",        INT,     PAR, FIX,  "",     ZERO, PROFILES,  Slot::ProfileIndex,     "acc/dec law as an Integer (importers without Enumerations): 0 keeps machine.profile, 1… its items"),
    ("machine.corner",              ENUM(1), PAR, FIX,  "",     NO,   NO,        Slot::Corner,           "corner passage"),
    ("machine.cornerIndex",         INT,     PAR, FIX,  "",     ZERO, CORNERS,   Slot::CornerIndex,      "corner passage as an Integer (importers without Enumerations): 0 keeps machine.corner, 1… its items"),
    ("#.maxVelocity",               REAL,    PAR, FIX,  "m/s",  ZERO, NO,        Slot::Limit(0),         "# axis velocity limit"),
    ("#.maxAcceleration",           REAL,    PAR, FIX,  "m/s2", ZERO, NO,        Slot::Limit(1),         "# axis acceleration limit"),
    ("#.maxJerk",                   REAL,    PAR, FIX,  "m/s3", ZERO, NO,        Slot::Limit(2),         "# axis jerk limit"),
    ("#.servo.*",                   REAL,    PAR, FIX,  "",     NO,   NO,        Slot::Servo(0),         "# drive: "),
    ("servo.enabled",               BOOL,    PAR, FIX,  "",     NO,   NO,        Slot::ServoEnabled,     "simulate the drives (off: actual = command)"),
    ("feedOverride",                REAL,    IN,  CONT, "1",    ZERO, Some(2.0), Slot::FeedOverride,     "feed override factor (jerk-limited)"),
    ("feedHold",                    BOOL,    IN,  TICK, "",     NO,   NO,        Slot::FeedHold,         "feed hold: stop on the path within the limits; release resumes"),
    ("#.loadForce",                 REAL,    IN,  CONT, "N",    NO,   NO,        Slot::LoadForce,        "external force on the # table (from a structure model)"),
    ("#.command.position",          REAL,    OUT, TICK, "m",    NO,   NO,        Slot::Command(0),       "# commanded position"),
    ("#.command.velocity",          REAL,    OUT, TICK, "m/s",  NO,   NO,        Slot::Command(1),       "# commanded velocity"),
    ("#.command.acceleration",      REAL,    OUT, TICK, "m/s2", NO,   NO,        Slot::Command(2),       "# commanded acceleration"),
    ("#.command.jerk",              REAL,    OUT, TICK, "m/s3", NO,   NO,        Slot::Command(3),       "# commanded jerk"),
    ("path.feed",                   REAL,    OUT, TICK, "m/s",  NO,   NO,        Slot::Path(0),          "path speed"),
    ("path.acceleration",           REAL,    OUT, TICK, "m/s2", NO,   NO,        Slot::Path(1),          "path acceleration"),
    ("path.jerk",                   REAL,    OUT, TICK, "m/s3", NO,   NO,        Slot::Path(2),          "path jerk"),
    ("path.distance",               REAL,    OUT, TICK, "m",    NO,   NO,        Slot::Path(3),          "path distance travelled"),
    ("status.line",                 INT,     OUT, TICK, "",     NO,   NO,        Slot::Line,             "source line of the block being executed"),
    ("status.finished",             BOOL,    OUT, TICK, "",     NO,   NO,        Slot::Finished,         "all motion of the program done"),
    ("#.position",                  REAL,    OUT, CONT, "m",    NO,   NO,        Slot::Drive(0),         "# actual position"),
    ("#.velocity",                  REAL,    OUT, CONT, "m/s",  NO,   NO,        Slot::Drive(1),         "# actual velocity"),
    ("#.followingError",            REAL,    OUT, CONT, "m",    NO,   NO,        Slot::Drive(2),         "# following error (command − feedback)"),
    ("#.motorTorque",               REAL,    OUT, CONT, "N.m",  NO,   NO,        Slot::Drive(3),         "# motor torque"),
    ("#.driveForce",                REAL,    OUT, CONT, "N",    NO,   NO,        Slot::Drive(4),         "# force of the drive on the machine structure"),
    ("path.contourError",           REAL,    OUT, CONT, "m",    NO,   NO,        Slot::ContourError,     "distance of the actual tool point from the programmed path"),
];

/// FMI type of a servo parameter: counts are Integers, the feedback switch a Boolean.
fn servo_type(fmi_name: &str) -> Type {
    match fmi_name {
        "encoderCounts" => INT,
        "linearScale" => BOOL,
        _ => REAL,
    }
}

/// The table expanded (value references 1…n in this order); the servo row stands for every
/// drive parameter of its axis, from the servo's own table. Parameters declare the documented
/// ranges that `Machine::check` enforces (config/ranges.rs).
pub fn rows() -> Vec<Entry<Slot>> {
    let mut rows = fmi2::table::expand(ROWS, &["x", "y", "z"], |row, axis| match row.7 {
        Slot::Servo(_) => SERVO
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let kind = servo_type(p.fmi_name);
                let name = format!("{axis}.servo.{}", p.fmi_name);
                let v = VariableInfo::new(name, kind, PAR, FIX, format!("{axis} drive: {}", p.description));
                (if kind == REAL { v.unit(p.unit) } else { v }, Slot::Servo(k))
            })
            .collect(),
        _ => fmi2::table::one(row, axis),
    });
    for v in rows.iter_mut().map(|e| &mut e.var) {
        let declared = crate::config::ranges::declared(&v.name);
        if let (Some((min, max)), Type::Real | Type::Integer) = (declared, v.kind) {
            (v.min, v.max) = (Some(min), Some(max));
        }
    }
    rows
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

impl CncMotion {
    /// The value of `slot` on axis `i`. Outputs read what the engine computed once at the end
    /// of the step (zeros before initialization).
    pub fn get(&self, slot: Slot, i: usize) -> Value {
        let (m, a) = (&self.machine, &self.machine.axes[i]);
        let e = self.engine.as_ref();
        let real = |f: &dyn Fn(&Engine) -> f64| Value::Real(e.map_or(0.0, f));
        match slot {
            Slot::Program => Value::String(self.program.clone()),
            Slot::ProgramFile => Value::String(self.program_file.clone()),
            Slot::Machine(k) => Value::Real(MACHINE[k].0(m)),
            Slot::Lookahead => Value::Integer(m.lookahead_blocks as i32),
            Slot::Profile => Value::Integer(enum_value(&ProfileKind::ALL, &m.profile)),
            Slot::ProfileIndex => Value::Integer(self.profile_index),
            Slot::Corner => Value::Integer(enum_value(&CornerMode::ALL, &m.corner)),
            Slot::CornerIndex => Value::Integer(self.corner_index),
            Slot::Limit(k) => Value::Real([a.max_velocity, a.max_acceleration, a.max_jerk][k]),
            Slot::Servo(k) => Value::of_type(servo_type(SERVO[k].fmi_name), (SERVO[k].get)(&m.servo[i])),
            Slot::ServoEnabled => Value::Boolean(self.servo_enabled),
            Slot::FeedOverride => Value::Real(self.feed_override),
            Slot::FeedHold => Value::Boolean(self.feed_hold),
            Slot::LoadForce => Value::Real(self.load_force[i]),
            Slot::Command(k) => real(&|e| {
                let t = e.tick();
                (match k {
                    0 => t.p,
                    1 => t.v,
                    2 => t.a,
                    _ => t.j,
                })[i]
            }),
            Slot::Path(k) => real(&|e| {
                let t = e.tick();
                match k {
                    0 => t.feed,
                    1 => t.path_acceleration,
                    2 => t.path_jerk,
                    _ => t.distance,
                }
            }),
            Slot::Line => Value::Integer(e.map_or(0, |e| e.tick().line as i32)),
            Slot::Finished => Value::Boolean(e.is_some_and(|e| e.tick().finished)),
            Slot::Drive(k) => real(&|e| {
                let d = &e.outputs().axes[i];
                match k {
                    0 => d.position,
                    1 => d.velocity,
                    2 => d.following_error,
                    3 => d.motor_torque,
                    _ => d.drive_force,
                }
            }),
            Slot::ContourError => real(&|e| e.outputs().contour_error),
        }
    }

    /// Write a parameter or input on axis `i`; bad values are refused with the reason (the FMI
    /// layer has already refused non-finite Reals and values outside the declared min/max).
    pub fn set(&mut self, slot: Slot, i: usize, value: Value) -> Result<(), String> {
        let m = &mut self.machine;
        match (slot, value) {
            (Slot::Program, Value::String(s)) => self.program = s,
            (Slot::ProgramFile, Value::String(s)) => self.program_file = s,
            (Slot::Machine(k), Value::Real(x)) => MACHINE[k].1(m, x),
            (Slot::Lookahead, Value::Integer(n)) => m.lookahead_blocks = n as usize,
            (Slot::Profile, Value::Integer(n)) => m.profile = enum_item(&ProfileKind::ALL, n)?,
            (Slot::Corner, Value::Integer(n)) => m.corner = enum_item(&CornerMode::ALL, n)?,
            (Slot::ProfileIndex, Value::Integer(n)) => self.profile_index = n,
            (Slot::CornerIndex, Value::Integer(n)) => self.corner_index = n,
            (Slot::Limit(k), Value::Real(x)) => {
                let l = &mut m.axes[i];
                *[&mut l.max_velocity, &mut l.max_acceleration, &mut l.max_jerk][k] = x;
            }
            (Slot::Servo(k), v) => m.servo[i].set(SERVO[k].fmi_name, v.number()?)?,
            (Slot::ServoEnabled, Value::Boolean(b)) => self.servo_enabled = b,
            (Slot::FeedOverride, Value::Real(x)) => self.feed_override = x,
            (Slot::FeedHold, Value::Boolean(b)) => self.feed_hold = b,
            (Slot::LoadForce, Value::Real(x)) => {
                self.load_force[i] = crate::config::ranges::check_load_force(x)?
            }
            _ => return Err("cannot be set".into()),
        }
        Ok(())
    }

    /// The program's name in messages: `program` for inline text, else the file.
    pub fn source_name(&self) -> &str {
        if self.program.trim().is_empty() {
            &self.program_file
        } else {
            "program"
        }
    }

    /// Load the program (inline text, or the file, relative to the resources folder) and start
    /// the engine. Errors come back as `file:line:col: message`.
    pub fn initialize(&mut self) -> Result<(), String> {
        if self.profile_index != 0 {
            self.machine.profile = enum_item(&ProfileKind::ALL, self.profile_index)?;
        }
        if self.corner_index != 0 {
            self.machine.corner = enum_item(&CornerMode::ALL, self.corner_index)?;
        }
        self.machine.check()?;
        let text = if self.program.trim().is_empty() {
            let dir = self.resources.clone().unwrap_or_default();
            crate::gcode::source::read_program_file(&dir.join(&self.program_file), &self.program_file)?
        } else {
            self.program.clone()
        };
        let engine =
            Engine::new(Arc::from(text), self.source_name(), &self.machine).map_err(|e| e.to_string())?;
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
        e.check_outputs()
    }
}
