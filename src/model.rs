//! The CncMotion FMU model: its parameters, inputs and outputs as ONE table of variables. The
//! table drives get/set dispatch, start values (read from a default model), Reset and the
//! modelDescription.xml; the FMI glue (crates/fmi2) knows nothing model-specific.

use crate::config::{CornerMode, Machine};
use crate::engine::Engine;
use crate::feed::ProfileKind;
use std::path::PathBuf;
use std::sync::Arc;

/// Value types of the table (FMI 2.0 scalar types; enumerations are integers 1…n).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Real,
    Integer,
    Boolean,
    String,
    /// Index into `ENUMERATIONS`.
    Enumeration(usize),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
    Independent,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

/// Reader of a value; `usize` is the axis (0, 1, 2) or unused.
pub type Get<T> = fn(&CncMotion, usize) -> T;
/// Writer of a value, refusing bad values with a message.
pub type Set<T> = fn(&mut CncMotion, usize, T) -> Result<(), String>;

/// Writer of a string value.
pub type SetStr = for<'a> fn(&mut CncMotion, usize, &'a str) -> Result<(), String>;

/// How a variable is read and written on the model (no writer: outputs).
#[derive(Clone, Copy)]
pub enum Access {
    Real(Get<f64>, Option<Set<f64>>),
    Integer(Get<i32>, Option<Set<i32>>),
    Boolean(Get<bool>, Option<Set<bool>>),
    String(Get<String>, Option<SetStr>),
}

/// One row of the table.
#[derive(Clone)]
pub struct Variable {
    pub name: String,
    pub value_reference: u32,
    pub kind: Kind,
    pub causality: Causality,
    pub variability: Variability,
    /// SI unit (declared in UnitDefinitions) and the unit shown to users.
    pub unit: Option<&'static str>,
    pub display_unit: Option<&'static str>,
    pub description: String,
    pub axis: usize,
    pub access: Access,
}

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
            servo_enabled: true,
            feed_override: 1.0,
            feed_hold: false,
            load_force: [0.0; 3],
            resources: None,
            engine: None,
        }
    }
}

pub const MODEL_NAME: &str = "CncMotion";
/// Changes whenever the variable table changes (checked against modelDescription/).
pub const GUID: &str = "{5c1f0e52-8f3a-4a57-9d7e-cnc-motion-0001}";

const AXES: [&str; 3] = ["x", "y", "z"];

fn positive(name: &str, v: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{name} must be a finite positive number, got {v}"))
    }
}

impl CncMotion {
    /// Load the program (inline text, or the file, relative to the resources folder) and start
    /// the engine. Errors come back as `file:line:col: message`.
    pub fn initialize(&mut self) -> Result<(), String> {
        self.machine.check()?;
        let (text, name) = if !self.program.trim().is_empty() {
            (self.program.clone(), "program".to_string())
        } else {
            let path = PathBuf::from(&self.program_file);
            let path = if path.is_relative() {
                match &self.resources {
                    Some(dir) => dir.join(path),
                    None => path,
                }
            } else {
                path
            };
            let text = crate::gcode::source::read_program_file(&path, &self.program_file)?;
            (text, self.program_file.clone())
        };
        let engine = Engine::new(Arc::from(text), &name, &self.machine)
            .map_err(|e| e.to_string())?
            .with_servo(self.servo_enabled);
        self.engine = Some(engine);
        self.apply_inputs();
        Ok(())
    }

    fn apply_inputs(&mut self) {
        let (k, hold, force) = (self.feed_override, self.feed_hold, self.load_force);
        if let Some(e) = self.engine.as_mut() {
            e.set_feed_override(k);
            e.set_feed_hold(hold);
            e.set_load_force(force);
        }
    }

    /// One communication step of length h (s) from the engine's time.
    pub fn do_step(&mut self, h: f64) -> Result<(), String> {
        self.apply_inputs();
        match self.engine.as_mut() {
            Some(e) => {
                e.advance(h).map_err(|e| e.to_string())?;
                crate::config::ranges::check_outputs(e)
            }
            None => Err("the model is not initialized".into()),
        }
    }

    fn tick(&self) -> crate::interp::Tick {
        self.engine.as_ref().map(|e| *e.tick()).unwrap_or_default()
    }

    fn axis_state(&self, i: usize) -> crate::servo::AxisState {
        self.engine.as_ref().map(|e| e.axes()[i]).unwrap_or_default()
    }
}

macro_rules! real_param {
    ($v:ident, $name:expr, $unit:expr, $disp:expr, $desc:expr, $axis:expr, |$m:ident, $i:ident| $get:expr, |$ms:ident, $is:ident, $x:ident| $set:expr) => {
        $v.push(Variable {
            name: $name.to_string(),
            value_reference: 0,
            kind: Kind::Real,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            unit: $unit,
            display_unit: $disp,
            description: $desc.to_string(),
            axis: $axis,
            access: Access::Real(
                |c, $i| {
                    let $m = &c.machine;
                    $get
                },
                Some(|c, $is, $x| {
                    let $ms = &mut c.machine;
                    $set;
                    Ok(())
                }),
            ),
        })
    };
}

#[allow(clippy::too_many_arguments)]
fn output_real(
    v: &mut Vec<Variable>,
    name: String,
    unit: &'static str,
    display: Option<&'static str>,
    variability: Variability,
    desc: String,
    axis: usize,
    get: fn(&CncMotion, usize) -> f64,
) {
    v.push(Variable {
        name,
        value_reference: 0,
        kind: Kind::Real,
        causality: Causality::Output,
        variability,
        unit: Some(unit),
        display_unit: display,
        description: desc,
        axis,
        access: Access::Real(get, None),
    });
}

/// The table, value references numbered in order from 1 (0 is `time`-free; no independent).
pub fn variables() -> Vec<Variable> {
    let mut v: Vec<Variable> = Vec::new();
    v.push(Variable {
        name: "program".into(),
        value_reference: 0,
        kind: Kind::String,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        unit: None,
        display_unit: None,
        description: "G-code program text; empty: read programFile".into(),
        axis: 0,
        access: Access::String(
            |c, _| c.program.clone(),
            Some(|c, _, s| {
                c.program = s.to_string();
                Ok(())
            }),
        ),
    });
    v.push(Variable {
        name: "programFile".into(),
        value_reference: 0,
        kind: Kind::String,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        unit: None,
        display_unit: None,
        description: "G-code file; relative paths are resolved in the FMU's resources folder".into(),
        axis: 0,
        access: Access::String(
            |c, _| c.program_file.clone(),
            Some(|c, _, s| {
                c.program_file = s.to_string();
                Ok(())
            }),
        ),
    });
    real_param!(
        v,
        "machine.interpolationPeriod",
        Some("s"),
        Some("ms"),
        "interpolation period T",
        0,
        |m, _i| m.interpolation_period,
        |m, _j, x| m.interpolation_period = positive("machine.interpolationPeriod", x)?
    );
    v.push(Variable {
        name: "machine.lookaheadBlocks".into(),
        value_reference: 0,
        kind: Kind::Integer,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        unit: None,
        display_unit: None,
        description: "look-ahead window (segments)".into(),
        axis: 0,
        access: Access::Integer(
            |c, _| c.machine.lookahead_blocks as i32,
            Some(|c, _, n| {
                if !(2..=1_000_000).contains(&n) {
                    return Err(format!("machine.lookaheadBlocks must be 2 … 1000000, got {n}"));
                }
                c.machine.lookahead_blocks = n as usize;
                Ok(())
            }),
        ),
    });
    v.push(Variable {
        name: "machine.profile".into(),
        value_reference: 0,
        kind: Kind::Enumeration(0),
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        unit: None,
        display_unit: None,
        description: "acc/dec law".into(),
        axis: 0,
        access: Access::Integer(
            |c, _| {
                ProfileKind::ALL
                    .iter()
                    .position(|k| *k == c.machine.profile)
                    .unwrap_or(0) as i32
                    + 1
            },
            Some(|c, _, n| {
                let k = usize::try_from(n - 1).ok().and_then(|i| ProfileKind::ALL.get(i));
                c.machine.profile = *k.ok_or(format!("machine.profile must be 1 … 5, got {n}"))?;
                Ok(())
            }),
        ),
    });
    v.push(Variable {
        name: "machine.corner".into(),
        value_reference: 0,
        kind: Kind::Enumeration(1),
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        unit: None,
        display_unit: None,
        description: "corner passage".into(),
        axis: 0,
        access: Access::Integer(
            |c, _| {
                CornerMode::ALL
                    .iter()
                    .position(|k| *k == c.machine.corner)
                    .unwrap_or(0) as i32
                    + 1
            },
            Some(|c, _, n| {
                let k = usize::try_from(n - 1).ok().and_then(|i| CornerMode::ALL.get(i));
                c.machine.corner = *k.ok_or(format!("machine.corner must be 1 … 4, got {n}"))?;
                Ok(())
            }),
        ),
    });
    real_param!(
        v,
        "machine.pathTolerance",
        Some("m"),
        Some("mm"),
        "default G64 path tolerance",
        0,
        |m, _i| m.path_tolerance,
        |m, _j, x| m.path_tolerance = positive("machine.pathTolerance", x)?
    );
    real_param!(
        v,
        "machine.chordTolerance",
        Some("m"),
        Some("mm"),
        "chord error on arcs",
        0,
        |m, _i| m.chord_tolerance,
        |m, _j, x| m.chord_tolerance = positive("machine.chordTolerance", x)?
    );
    real_param!(
        v,
        "machine.arcRadiusTolerance",
        Some("m"),
        Some("mm"),
        "arc end point radius mismatch accepted (G20 programs: 2.54 times it), or 0.1 % of the radius",
        0,
        |m, _i| m.arc_radius_tolerance,
        |m, _j, x| m.arc_radius_tolerance = positive("machine.arcRadiusTolerance", x)?
    );
    real_param!(
        v,
        "machine.maxFeed",
        Some("m/s"),
        Some("mm/min"),
        "maximum feed (also G0)",
        0,
        |m, _i| m.max_feed,
        |m, _j, x| m.max_feed = positive("machine.maxFeed", x)?
    );
    real_param!(
        v,
        "machine.maxPathAcceleration",
        Some("m/s2"),
        Some("mm/s2"),
        "path acceleration limit on top of the axes' (0: none)",
        0,
        |m, _i| m.max_path_acceleration.unwrap_or(0.0),
        |m, _j, x| m.max_path_acceleration = if x == 0.0 {
            None
        } else {
            Some(positive("machine.maxPathAcceleration", x)?)
        }
    );
    real_param!(
        v,
        "machine.maxPathJerk",
        Some("m/s3"),
        Some("mm/s3"),
        "path jerk limit on top of the axes' (0: none)",
        0,
        |m, _i| m.max_path_jerk.unwrap_or(0.0),
        |m, _j, x| m.max_path_jerk = if x == 0.0 {
            None
        } else {
            Some(positive("machine.maxPathJerk", x)?)
        }
    );
    real_param!(
        v,
        "machine.maxSnap",
        Some("m/s4"),
        Some("mm/s4"),
        "snap limit (jerk15)",
        0,
        |m, _i| m.max_snap,
        |m, _j, x| m.max_snap = positive("machine.maxSnap", x)?
    );
    for (i, a) in AXES.iter().enumerate() {
        real_param!(
            v,
            format!("{a}.maxVelocity"),
            Some("m/s"),
            Some("mm/min"),
            format!("{a} axis velocity limit"),
            i,
            |m, i| m.axes[i].max_velocity,
            |m, i, x| m.axes[i].max_velocity = positive("maxVelocity", x)?
        );
        real_param!(
            v,
            format!("{a}.maxAcceleration"),
            Some("m/s2"),
            Some("mm/s2"),
            format!("{a} axis acceleration limit"),
            i,
            |m, i| m.axes[i].max_acceleration,
            |m, i, x| m.axes[i].max_acceleration = positive("maxAcceleration", x)?
        );
        real_param!(
            v,
            format!("{a}.maxJerk"),
            Some("m/s3"),
            Some("mm/s3"),
            format!("{a} axis jerk limit"),
            i,
            |m, i| m.axes[i].max_jerk,
            |m, i, x| m.axes[i].max_jerk = positive("maxJerk", x)?
        );
    }
    for (i, a) in AXES.iter().enumerate() {
        for (k, sp) in crate::servo::PARAMETERS.iter().enumerate() {
            v.push(Variable {
                name: format!("{a}.servo.{}", sp.fmi_name),
                value_reference: 0,
                kind: Kind::Real,
                causality: Causality::Parameter,
                variability: Variability::Fixed,
                unit: Some(sp.unit),
                display_unit: None,
                description: format!("{a} drive: {}", sp.description),
                // Axis and parameter packed in one index: axis·64 + parameter.
                axis: i * 64 + k,
                access: Access::Real(
                    |c, n| (crate::servo::PARAMETERS[n % 64].get)(&c.machine.servo[n / 64]),
                    Some(|c, n, x| c.machine.servo[n / 64].set(crate::servo::PARAMETERS[n % 64].fmi_name, x)),
                ),
            });
        }
    }
    v.push(Variable {
        name: "servo.enabled".into(),
        value_reference: 0,
        kind: Kind::Boolean,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        unit: None,
        display_unit: None,
        description: "simulate the servo drives (off: actual = command)".into(),
        axis: 0,
        access: Access::Boolean(
            |c, _| c.servo_enabled,
            Some(|c, _, b| {
                c.servo_enabled = b;
                Ok(())
            }),
        ),
    });
    // Inputs.
    v.push(Variable {
        name: "feedOverride".into(),
        value_reference: 0,
        kind: Kind::Real,
        causality: Causality::Input,
        variability: Variability::Continuous,
        unit: Some("1"),
        display_unit: None,
        description: "feed override factor 0 … 2 (jerk-limited)".into(),
        axis: 0,
        access: Access::Real(
            |c, _| c.feed_override,
            Some(|c, _, x| {
                if !(0.0..=2.0).contains(&x) {
                    return Err(format!("feedOverride must be 0 … 2, got {x}"));
                }
                c.feed_override = x;
                Ok(())
            }),
        ),
    });
    v.push(Variable {
        name: "feedHold".into(),
        value_reference: 0,
        kind: Kind::Boolean,
        causality: Causality::Input,
        variability: Variability::Discrete,
        unit: None,
        display_unit: None,
        description: "feed hold: stop on the path within the limits; release resumes".into(),
        axis: 0,
        access: Access::Boolean(
            |c, _| c.feed_hold,
            Some(|c, _, b| {
                c.feed_hold = b;
                Ok(())
            }),
        ),
    });
    for (i, a) in AXES.iter().enumerate() {
        v.push(Variable {
            name: format!("{a}.loadForce"),
            value_reference: 0,
            kind: Kind::Real,
            causality: Causality::Input,
            variability: Variability::Continuous,
            unit: Some("N"),
            display_unit: None,
            description: format!("external force on the {a} table (from a structure model)"),
            axis: i,
            access: Access::Real(
                |c, i| c.load_force[i],
                Some(|c, i, x| {
                    c.load_force[i] = crate::config::ranges::check_load_force(x)?;
                    Ok(())
                }),
            ),
        });
    }
    // Outputs: the interpolator's command (changes at period ticks: discrete).
    let d = Variability::Discrete;
    for (i, a) in AXES.iter().enumerate() {
        output_real(
            &mut v,
            format!("{a}.command.position"),
            "m",
            Some("mm"),
            d,
            format!("{a} commanded position"),
            i,
            |c, i| c.tick().p[i],
        );
        output_real(
            &mut v,
            format!("{a}.command.velocity"),
            "m/s",
            Some("mm/min"),
            d,
            format!("{a} commanded velocity"),
            i,
            |c, i| c.tick().v[i],
        );
        output_real(
            &mut v,
            format!("{a}.command.acceleration"),
            "m/s2",
            Some("mm/s2"),
            d,
            format!("{a} commanded acceleration"),
            i,
            |c, i| c.tick().a[i],
        );
        output_real(
            &mut v,
            format!("{a}.command.jerk"),
            "m/s3",
            Some("mm/s3"),
            d,
            format!("{a} commanded jerk"),
            i,
            |c, i| c.tick().j[i],
        );
    }
    output_real(
        &mut v,
        "path.feed".into(),
        "m/s",
        Some("mm/min"),
        d,
        "path speed".into(),
        0,
        |c, _| c.tick().feed,
    );
    output_real(
        &mut v,
        "path.acceleration".into(),
        "m/s2",
        Some("mm/s2"),
        d,
        "path acceleration".into(),
        0,
        |c, _| c.tick().path_acceleration,
    );
    output_real(
        &mut v,
        "path.jerk".into(),
        "m/s3",
        Some("mm/s3"),
        d,
        "path jerk".into(),
        0,
        |c, _| c.tick().path_jerk,
    );
    output_real(
        &mut v,
        "path.distance".into(),
        "m",
        Some("mm"),
        d,
        "path distance travelled".into(),
        0,
        |c, _| c.tick().distance,
    );
    v.push(Variable {
        name: "program.line".into(),
        value_reference: 0,
        kind: Kind::Integer,
        causality: Causality::Output,
        variability: Variability::Discrete,
        unit: None,
        display_unit: None,
        description: "source line of the block being executed".into(),
        axis: 0,
        access: Access::Integer(|c, _| c.tick().line as i32, None),
    });
    v.push(Variable {
        name: "program.finished".into(),
        value_reference: 0,
        kind: Kind::Boolean,
        causality: Causality::Output,
        variability: Variability::Discrete,
        unit: None,
        display_unit: None,
        description: "all motion of the program done".into(),
        axis: 0,
        access: Access::Boolean(|c, _| c.tick().finished, None),
    });
    // Outputs: the drives (continuous, sub-stepped).
    let cont = Variability::Continuous;
    for (i, a) in AXES.iter().enumerate() {
        output_real(
            &mut v,
            format!("{a}.position"),
            "m",
            Some("mm"),
            cont,
            format!("{a} actual position"),
            i,
            |c, i| c.axis_state(i).position,
        );
        output_real(
            &mut v,
            format!("{a}.velocity"),
            "m/s",
            Some("mm/min"),
            cont,
            format!("{a} actual velocity"),
            i,
            |c, i| c.axis_state(i).velocity,
        );
        output_real(
            &mut v,
            format!("{a}.followingError"),
            "m",
            Some("mm"),
            cont,
            format!("{a} following error (command − feedback)"),
            i,
            |c, i| c.axis_state(i).following_error,
        );
        output_real(
            &mut v,
            format!("{a}.motorTorque"),
            "N.m",
            None,
            cont,
            format!("{a} motor torque"),
            i,
            |c, i| c.axis_state(i).motor_torque,
        );
        output_real(
            &mut v,
            format!("{a}.driveForce"),
            "N",
            None,
            cont,
            format!("{a} force of the drive on the machine structure"),
            i,
            |c, i| c.axis_state(i).drive_force,
        );
    }
    output_real(
        &mut v,
        "path.contourError".into(),
        "m",
        Some("mm"),
        cont,
        "distance of the actual tool point from the programmed path".into(),
        0,
        |c, _| c.engine.as_ref().map_or(0.0, |e| e.contour_error()),
    );
    for (k, var) in v.iter_mut().enumerate() {
        var.value_reference = k as u32 + 1;
    }
    v
}
