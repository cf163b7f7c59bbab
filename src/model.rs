//! The CncMotion FMU model: its variables as ONE table of plain rows ([`ROWS`], fmi2's own
//! Type/Causality/Variability), each naming the [`Slot`] of the model it reads or writes on its
//! axis; get and set are one match over the slots. crates/fmi2 expands the table per axis and
//! generates the XML, the units and the documentation from it.

use crate::config::ranges;
use crate::config::{CornerMode, Machine};
use crate::engine::Engine;
use crate::feed::ProfileKind;
use crate::gcode::ProgramSource;
use crate::servo::{Kind, PARAMETERS as SERVO};
use fmi2::table::Entry;
use fmi2::Causality::{Input as IN, Output as OUT, Parameter as PAR};
use fmi2::Type::{Boolean as BOOL, Enumeration as ENUM, Integer as INT, Real as REAL, String as STR};
use fmi2::Variability::{Continuous as CONT, Discrete as TICK, Fixed as FIX};
use fmi2::{enum_item, enum_value, EnumerationType, Type, Value, VariableInfo};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub const MODEL_NAME: &str = "CncMotion";

/// Output derivatives the FMU gives (maxOutputDerivativeOrder): the command's, up to jerk from
/// position ([`CncMotion::output_derivative`]).
pub const MAX_OUTPUT_DERIVATIVE_ORDER: u32 = 3;

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
    MachineFile,
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

/// The `machine.*` Reals: their machine-file key (for the range, config/ranges.rs), and how they
/// read and write their field of [`Machine`] (0 stands for "none" in the optional limits).
type Field = (&'static str, fn(&Machine) -> f64, fn(&mut Machine, f64));
#[rustfmt::skip]
const MACHINE: [Field; 9] = [
    ("interpolation_period_s", |m| m.interpolation_period, |m, x| m.interpolation_period = x),
    ("path_tolerance_mm", |m| m.path_tolerance, |m, x| m.path_tolerance = x),
    ("chord_tolerance_mm", |m| m.chord_tolerance, |m, x| m.chord_tolerance = x),
    ("max_feed_mm_min", |m| m.max_feed, |m, x| m.max_feed = x),
    ("max_path_acceleration_mm_s2", |m| m.max_path_acceleration.unwrap_or(0.0), |m, x| m.max_path_acceleration = (x > 0.0).then_some(x)),
    ("max_path_jerk_mm_s3", |m| m.max_path_jerk.unwrap_or(0.0), |m, x| m.max_path_jerk = (x > 0.0).then_some(x)),
    ("max_snap_mm_s4", |m| m.max_snap, |m, x| m.max_snap = x),
    ("max_transition_jerk_mm_s3", |m| m.max_transition_jerk.unwrap_or(0.0), |m, x| m.max_transition_jerk = (x > 0.0).then_some(x)),
    ("arc_radius_tolerance_mm", |m| m.arc_radius_tolerance, |m, x| m.arc_radius_tolerance = x),
];

/// No range in the table: every declared min/max comes from config/ranges.rs ([`rows`]).
const NO: Option<f64> = None;

/// See [`fmi2::table::Row`]: `#` rows are per axis. Outputs depend on no input (inputs act from
/// the next step on).
type Row = fmi2::table::Row<Slot>;

#[rustfmt::skip]
pub const ROWS: &[Row] = &[
    ("program",                     STR,     PAR, FIX,  "",     NO,   NO,        Slot::Program,          "G-code program text; empty: read programFile"),
    ("programFile",                 STR,     PAR, FIX,  "",     NO,   NO,        Slot::ProgramFile,      "G-code file: relative to the FMU's resources, an absolute path or a file: URI"),
    ("machineFile",                 STR,     PAR, FIX,  "",     NO,   NO,        Slot::MachineFile,      "machine file (TOML, the CLI's --machine): relative to the FMU's resources, an absolute path or a file: URI; empty: none. Parameters not at their start value override its keys"),
    ("machine.interpolationPeriod", REAL,    PAR, FIX,  "s",    NO,   NO,        Slot::Machine(0),       "interpolation period T"),
    ("machine.pathTolerance",       REAL,    PAR, FIX,  "m",    NO,   NO,        Slot::Machine(1),       "default G64 path tolerance"),
    ("machine.chordTolerance",      REAL,    PAR, FIX,  "m",    NO,   NO,        Slot::Machine(2),       "chord error on arcs"),
    ("machine.maxFeed",             REAL,    PAR, FIX,  "m/s",  NO,   NO,        Slot::Machine(3),       "maximum feed (also G0)"),
    ("machine.maxPathAcceleration", REAL,    PAR, FIX,  "m/s2", NO,   NO,        Slot::Machine(4),       "path acceleration limit on top of the axes' (0: none)"),
    ("machine.maxPathJerk",         REAL,    PAR, FIX,  "m/s3", NO,   NO,        Slot::Machine(5),       "path jerk limit on top of the axes' (0: none)"),
    ("machine.maxSnap",             REAL,    PAR, FIX,  "m/s4", NO,   NO,        Slot::Machine(6),       "snap limit (jerk15)"),
    ("machine.maxTransitionJerk",   REAL,    PAR, FIX,  "m/s3", NO,   NO,        Slot::Machine(7),       "axis jerk on passage of a curvature discontinuity (seed 004 Table 1: eq. 10 junctions, circular corner arcs; 0: the axes' own)"),
    ("machine.arcRadiusTolerance",  REAL,    PAR, FIX,  "m",    NO,   NO,        Slot::Machine(8),       "arc end point radius mismatch accepted (G20 programs: 2.54 times it), or 0.1 % of the radius"),
    ("machine.lookaheadBlocks",     INT,     PAR, FIX,  "",     NO,   NO,        Slot::Lookahead,        "look-ahead window (segments)"),
    ("machine.profile",             ENUM(0), PAR, FIX,  "",     NO,   NO,        Slot::Profile,          "acc/dec law"),
    ("machine.profileIndex",        INT,     PAR, FIX,  "",     NO,   NO,        Slot::ProfileIndex,     "acc/dec law as an Integer (importers without Enumerations): 0 keeps machine.profile, 1… its items"),
    ("machine.corner",              ENUM(1), PAR, FIX,  "",     NO,   NO,        Slot::Corner,           "corner passage"),
    ("machine.cornerIndex",         INT,     PAR, FIX,  "",     NO,   NO,        Slot::CornerIndex,      "corner passage as an Integer (importers without Enumerations): 0 keeps machine.corner, 1… its items"),
    ("#.maxVelocity",               REAL,    PAR, FIX,  "m/s",  NO,   NO,        Slot::Limit(0),         "# axis velocity limit"),
    ("#.maxAcceleration",           REAL,    PAR, FIX,  "m/s2", NO,   NO,        Slot::Limit(1),         "# axis acceleration limit"),
    ("#.maxJerk",                   REAL,    PAR, FIX,  "m/s3", NO,   NO,        Slot::Limit(2),         "# axis jerk limit"),
    ("#.servo.*",                   REAL,    PAR, FIX,  "",     NO,   NO,        Slot::Servo(0),         "# drive: "),
    ("servo.enabled",               BOOL,    PAR, FIX,  "",     NO,   NO,        Slot::ServoEnabled,     "simulate the drives (off: actual = command)"),
    ("feedOverride",                REAL,    IN,  CONT, "1",    NO,   NO,        Slot::FeedOverride,     "feed override factor (jerk-limited)"),
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

/// The FMI 3 terminal a tool wires to MachineStructure's (same name, `plug` rule): the drive
/// forces out, the load forces in (arrays over x, y, z).
pub fn terminals() -> Vec<fmi2::Terminal> {
    vec![fmi2::Terminal {
        name: "frame".into(),
        kind: "org.cnc-motion.frameCoupling".into(),
        description: "two-way coupling with a machine-structure model: drive forces out, load forces in"
            .into(),
        members: vec![
            ("driveForce".into(), "driveForce".into()),
            ("loadForce".into(), "loadForce".into()),
        ],
    }]
}

/// The FMI 3 clock `tick`: the interpolation period of the default machine, whose every
/// activation computes the interpolator's ticks and the drives up to its time (Scheduled
/// Execution; in Co-Simulation fmi3DoStep computes them).
pub fn tick_clock() -> fmi2::Clock {
    fmi2::Clock {
        name: "tick".into(),
        description: "interpolation tick (machine.interpolationPeriod of the default machine): an activation computes the interpolator and the drives up to its time".into(),
        interval: Machine::default().interpolation_period,
        priority: 0,
    }
}

/// FMI type of a drive parameter, from its kind in the servo table.
fn servo_type(kind: Kind) -> Type {
    match kind {
        Kind::Real => REAL,
        Kind::Count => INT,
        Kind::Switch => BOOL,
    }
}

/// The table expanded (value references 1…n in this order); the servo row stands for every
/// drive parameter of its axis, from the servo's own table. Every declared min/max comes from
/// config/ranges.rs (the ranges `Machine::check` enforces; the table itself declares none).
pub fn rows() -> Vec<Entry<Slot>> {
    let mut rows = fmi2::table::expand(ROWS, &["x", "y", "z"], |row, axis| match row.7 {
        Slot::Servo(_) => SERVO
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let kind = servo_type(p.kind);
                let name = format!("{axis}.servo.{}", p.fmi_name);
                let v = VariableInfo::new(name, kind, PAR, FIX, format!("{axis} drive: {}", p.description));
                (if kind == REAL { v.unit(p.unit) } else { v }, Slot::Servo(k))
            })
            .collect(),
        _ => fmi2::table::one(row, axis),
    });
    for v in rows.iter_mut().map(|e| &mut e.var) {
        let declared = ranges::declared(&v.name);
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
    /// The machine file ("" for none); its machine becomes `machine` at initialization.
    pub machine_file: String,
    pub machine: Machine,
    /// `machine.profileIndex`/`machine.cornerIndex`: 0 keeps the Enumeration's choice, 1…n
    /// replace it (for importers that cannot set Enumerations, e.g. libcosim).
    pub profile_index: i32,
    pub corner_index: i32,
    pub servo_enabled: bool,
    pub feed_override: f64,
    pub feed_hold: bool,
    pub load_force: [f64; 3],
    /// The FMU's resources folder (for relative `programFile` and `machineFile`).
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
            machine_file: String::new(),
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
            Slot::MachineFile => Value::String(self.machine_file.clone()),
            Slot::Machine(k) => Value::Real(MACHINE[k].1(m)),
            Slot::Lookahead => Value::Integer(m.lookahead_blocks as i32),
            Slot::Profile => Value::Integer(enum_value(&ProfileKind::ALL, &m.profile)),
            Slot::ProfileIndex => Value::Integer(self.profile_index),
            Slot::Corner => Value::Integer(enum_value(&CornerMode::ALL, &m.corner)),
            Slot::CornerIndex => Value::Integer(self.corner_index),
            Slot::Limit(k) => Value::Real([a.max_velocity, a.max_acceleration, a.max_jerk][k]),
            Slot::Servo(k) => Value::of_type(servo_type(SERVO[k].kind), (SERVO[k].get)(&m.servo[i])),
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

    /// The `order`-th time derivative of output `slot` on axis `i` where the feed law gives it
    /// exactly: the command p, v, a, j are each the derivative of the one before (chain rule of
    /// x(s(t)), interp::axis_motion), at the latest tick (the current time when the step is a
    /// multiple of the interpolation period). None past jerk (the feed laws give no snap) and for
    /// the other outputs: path.distance is the programmed length, which blends and chords cut.
    pub fn output_derivative(&self, slot: Slot, i: usize, order: u32) -> Option<f64> {
        let (Slot::Command(k), true) = (slot, order > 0) else {
            return None;
        };
        let slot = Slot::Command(Some(k + order as usize).filter(|&d| d <= 3)?);
        match self.get(slot, i) {
            Value::Real(x) => Some(x),
            _ => None,
        }
    }

    /// Write a parameter or input on axis `i`. Each value's own range is checked here (the FMI
    /// layer has already refused non-finite Reals and values outside the declared min/max; this
    /// also refuses the gaps, e.g. 0 < x < min where 0 means "none"); relations between values
    /// only at initialization, so that parameters can be set in any order.
    pub fn set(&mut self, slot: Slot, i: usize, value: Value) -> Result<(), String> {
        let m = &mut self.machine;
        match (slot, value) {
            (Slot::Program, Value::String(s)) => self.program = s,
            (Slot::ProgramFile, Value::String(s)) => self.program_file = s,
            (Slot::MachineFile, Value::String(s)) => self.machine_file = s,
            (Slot::Machine(k), Value::Real(x)) => {
                ranges::row(ranges::MACHINE, MACHINE[k].0)
                    .map_err(|e| e.message)?
                    .fmu_check(x)?;
                MACHINE[k].2(m, x)
            }
            (Slot::Lookahead, Value::Integer(n)) => m.lookahead_blocks = n as usize,
            (Slot::Profile, Value::Integer(n)) => m.profile = enum_item(&ProfileKind::ALL, n)?,
            (Slot::Corner, Value::Integer(n)) => m.corner = enum_item(&CornerMode::ALL, n)?,
            (Slot::ProfileIndex, Value::Integer(n)) => self.profile_index = n,
            (Slot::CornerIndex, Value::Integer(n)) => self.corner_index = n,
            (Slot::Limit(k), Value::Real(x)) => {
                ranges::AXIS[k].fmu_check(x)?;
                let l = &mut m.axes[i];
                *[&mut l.max_velocity, &mut l.max_acceleration, &mut l.max_jerk][k] = x;
            }
            (Slot::Servo(k), v) => {
                let x = v.number()?;
                ranges::check_servo_value(&SERVO[k], x)?;
                (SERVO[k].set)(&mut m.servo[i], x)
            }
            (Slot::ServoEnabled, Value::Boolean(b)) => self.servo_enabled = b,
            (Slot::FeedOverride, Value::Real(x)) => self.feed_override = x,
            (Slot::FeedHold, Value::Boolean(b)) => self.feed_hold = b,
            (Slot::LoadForce, Value::Real(x)) => self.load_force[i] = ranges::check_load_force(x)?,
            _ => return Err("cannot be set".into()),
        }
        Ok(())
    }

    /// A clocked instance runs at the clock's interval: the machine in force (after the machine
    /// file) must keep the default interpolation period.
    pub fn check_tick(&self, interval: f64) -> Result<(), String> {
        let period = self.machine.interpolation_period;
        if period != interval {
            return Err(format!(
                "machine.interpolationPeriod is {period} s, the clock ticks every {interval} s: \
                 with clocks (Scheduled Execution, Event Mode) keep the default period"
            ));
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

    /// Where a file parameter points: a `file:` URI, an absolute path, or a path relative to the
    /// FMU's resources folder (to the current directory when the importer gave none).
    pub fn resolve(&self, name: &str) -> Result<PathBuf, String> {
        if name.starts_with("file:") {
            return fmi2::uri::file_uri_to_path(name).map_err(|e| format!("{name}: {e}"));
        }
        Ok(self.resources.clone().unwrap_or_default().join(Path::new(name)))
    }

    /// The parameters that make the machine, on each axis: every one `set` writes into it.
    fn machine_slots() -> impl Iterator<Item = (Slot, usize)> {
        let top = (0..MACHINE.len()).map(Slot::Machine);
        let top = top.chain([Slot::Lookahead, Slot::Profile, Slot::Corner]);
        let per_axis = (0..3).map(Slot::Limit).chain((0..SERVO.len()).map(Slot::Servo));
        let per_axis: Vec<Slot> = per_axis.collect();
        top.map(|s| (s, 0))
            .chain((0..3).flat_map(move |i| per_axis.clone().into_iter().map(move |s| (s, i))))
    }

    /// The machine of `machineFile` with every machine parameter whose value differs from its
    /// declared start value written over it. Importers write every start value, in any order:
    /// a parameter left at its start value keeps the file's value.
    fn over_file(&self, file: Machine) -> Result<Machine, String> {
        let start = CncMotion::default();
        let mut merged = CncMotion {
            machine: file,
            ..CncMotion::default()
        };
        for (slot, i) in Self::machine_slots() {
            let value = self.get(slot, i);
            if value != start.get(slot, i) {
                merged.set(slot, i, value)?;
            }
        }
        Ok(merged.machine)
    }

    /// The machine file read by the CLI's loader (`Machine::from_toml`: every section; errors as
    /// `file:line:col: message`), with the parameters over it.
    fn read_machine_file(&self) -> Result<Machine, String> {
        let name = &self.machine_file;
        let path = self.resolve(name)?;
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{name}: {e}"))?;
        let dir = path.parent().unwrap_or(Path::new(""));
        let file = Machine::from_toml_in(&text, name, dir).map_err(|e| e.to_string())?;
        self.over_file(file)
    }

    /// Read the machine file (if any) under the parameters, check the machine (ranges and the
    /// relations between values), load the program (inline text, or `programFile`) and start the
    /// engine. Errors come back as `file:line:col: message`.
    pub fn initialize(&mut self) -> Result<(), String> {
        if !self.machine_file.trim().is_empty() {
            self.machine = self.read_machine_file()?;
        }
        if self.profile_index != 0 {
            self.machine.profile = enum_item(&ProfileKind::ALL, self.profile_index)?;
        }
        if self.corner_index != 0 {
            self.machine.corner = enum_item(&CornerMode::ALL, self.corner_index)?;
        }
        self.machine.check()?;
        // A program file's directory is searched for subroutine files, as the CLI searches it.
        let source = if self.program.trim().is_empty() {
            let path = self.resolve(&self.program_file)?;
            let text = crate::gcode::source::read_program_file(&path, &self.program_file)?;
            ProgramSource::FileText(Arc::from(text), path)
        } else {
            ProgramSource::Text(Arc::from(self.program.as_str()))
        };
        let engine = Engine::new(source, self.source_name(), &self.machine).map_err(|e| e.to_string())?;
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

    /// [`CncMotion::do_step`] that ends early at the tick where the program finishes (FMI 3 early
    /// return): the time advanced. Taken tick by tick (`Engine::step`, which is `advance` by one
    /// period) from a tick over a whole number of ticks while the program runs and no hold is
    /// set; otherwise, and for one tick, exactly `do_step`.
    pub fn do_step_early(&mut self, h: f64) -> Result<f64, String> {
        let period = self.machine.interpolation_period;
        let e = self.engine.as_mut().ok_or("the model is not initialized")?;
        let n = (h / period).round();
        let at_tick = e.time() == e.ticks() as f64 * period;
        let whole = n >= 2.0 && (n * period - h).abs() <= crate::tolerance::SAME_INSTANT_S;
        if !(at_tick && whole) || e.finished() || self.feed_hold {
            return self.do_step(h).map(|()| h);
        }
        e.set_feed_override(self.feed_override);
        e.set_feed_hold(self.feed_hold);
        e.set_load_force(self.load_force);
        let n = n as u64;
        for k in 1..=n {
            e.step().map_err(|e| e.to_string())?;
            if e.finished() && k < n {
                e.check_outputs()?;
                return Ok(k as f64 * period);
            }
        }
        e.check_outputs()?;
        Ok(h)
    }
}
