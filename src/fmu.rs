//! The CncMotion FMU: the model table of `model.rs` behind the generic FMI 2.0 layer (crates/fmi2).

use crate::config::Machine;
use crate::engine::Engine;
use crate::model::{self, Access, Causality, CncMotion, Kind, Variability, ENUMERATIONS};
use fmi2::{DisplayUnit, EnumerationType, ModelInfo, UnitDefinition, Value, VariableInfo};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::{Arc, OnceLock};

/// The default program shipped in the FMU's resources (and used by `make demo`).
pub const DEFAULT_PROGRAM: &str = include_str!("../resources/default.ngc");

/// Version of the serialized model state.
const STATE_VERSION: u32 = 1;

/// The model as the FMI layer sees it.
#[derive(Clone, Debug)]
pub struct CncMotionFmu(pub CncMotion);

fn table() -> &'static [model::Variable] {
    static TABLE: OnceLock<Vec<model::Variable>> = OnceLock::new();
    TABLE.get_or_init(model::variables)
}

/// SI units used by the table, with their base-unit exponents (kg, m, s, A, K, mol, cd, rad) and
/// display units.
fn units() -> Vec<UnitDefinition> {
    let d = |name: &str, factor: f64| DisplayUnit {
        name: name.into(),
        factor,
        offset: 0.0,
    };
    let u = |name: &str, base: [i32; 8], display: Vec<DisplayUnit>| UnitDefinition {
        name: name.into(),
        base,
        display,
    };
    vec![
        u("s", [0, 0, 1, 0, 0, 0, 0, 0], vec![d("ms", 1e3)]),
        u("m", [0, 1, 0, 0, 0, 0, 0, 0], vec![d("mm", 1e3)]),
        u(
            "m/s",
            [0, 1, -1, 0, 0, 0, 0, 0],
            vec![d("mm/min", 6e4), d("mm/s", 1e3)],
        ),
        u("m/s2", [0, 1, -2, 0, 0, 0, 0, 0], vec![d("mm/s2", 1e3)]),
        u("m/s3", [0, 1, -3, 0, 0, 0, 0, 0], vec![d("mm/s3", 1e3)]),
        u("m/s4", [0, 1, -4, 0, 0, 0, 0, 0], vec![d("mm/s4", 1e3)]),
        u("N", [1, 1, -2, 0, 0, 0, 0, 0], vec![]),
        u("N.m", [1, 2, -2, 0, 0, 0, 0, 0], vec![]),
        u("1", [0, 0, 0, 0, 0, 0, 0, 0], vec![]),
        u("kg", [1, 0, 0, 0, 0, 0, 0, 0], vec![]),
        u("kg.m2", [1, 2, 0, 0, 0, 0, 0, 0], vec![]),
        u("1/s", [0, 0, -1, 0, 0, 0, 0, 0], vec![]),
        u("N/m", [1, 0, -2, 0, 0, 0, 0, 0], vec![]),
        u("N.s/m", [1, 0, -1, 0, 0, 0, 0, 0], vec![]),
        u("Hz", [0, 0, -1, 0, 0, 0, 0, 0], vec![]),
        u(
            "rad/s",
            [0, 0, -1, 0, 0, 0, 0, 1],
            vec![d("rpm", 60.0 / (2.0 * std::f64::consts::PI))],
        ),
        u("N.m.s/rad", [1, 2, -1, 0, 0, 0, 0, -1], vec![]),
    ]
}

/// Time the default program takes on the default machine, rounded up to a whole second plus one.
fn default_stop_time() -> f64 {
    let mut e = match Engine::new(Arc::from(DEFAULT_PROGRAM), "default.ngc", &Machine::default()) {
        Ok(e) => e,
        Err(_) => return 10.0,
    };
    while !e.finished() && e.time() < 3600.0 {
        if e.step().is_err() {
            break;
        }
    }
    e.time().ceil() + 1.0
}

impl fmi2::Model for CncMotionFmu {
    fn info() -> &'static ModelInfo {
        static INFO: OnceLock<ModelInfo> = OnceLock::new();
        INFO.get_or_init(|| {
            let variables: Vec<VariableInfo> = table()
                .iter()
                .map(|v| VariableInfo {
                    name: v.name.clone(),
                    value_reference: v.value_reference,
                    kind: match v.kind {
                        Kind::Real => fmi2::Type::Real,
                        Kind::Integer => fmi2::Type::Integer,
                        Kind::Boolean => fmi2::Type::Boolean,
                        Kind::String => fmi2::Type::String,
                        Kind::Enumeration(e) => fmi2::Type::Enumeration(e),
                    },
                    causality: match v.causality {
                        Causality::Parameter => fmi2::Causality::Parameter,
                        Causality::Input => fmi2::Causality::Input,
                        Causality::Output => fmi2::Causality::Output,
                        Causality::Independent => fmi2::Causality::Independent,
                    },
                    variability: match v.variability {
                        Variability::Fixed => fmi2::Variability::Fixed,
                        Variability::Tunable => fmi2::Variability::Tunable,
                        Variability::Discrete => fmi2::Variability::Discrete,
                        Variability::Continuous => fmi2::Variability::Continuous,
                    },
                    unit: v.unit.map(str::to_string),
                    display_unit: v.display_unit.map(str::to_string),
                    description: v.description.clone(),
                })
                .collect();
            ModelInfo {
                model_name: model::MODEL_NAME.into(),
                model_identifier: model::MODEL_NAME.into(),
                guid: fmi2::guid_of(&variables),
                description: "CNC motion controller: G-code to jerk-limited axis motion through servo drives"
                    .into(),
                version: env!("CARGO_PKG_VERSION").into(),
                variables,
                enumerations: ENUMERATIONS
                    .iter()
                    .map(|(name, items)| EnumerationType {
                        name: name.to_string(),
                        items: items
                            .iter()
                            .map(|(n, d)| (n.to_string(), d.to_string()))
                            .collect(),
                    })
                    .collect(),
                units: units(),
                log_categories: Vec::new(),
                default_experiment: (0.0, default_stop_time(), 1e-6, 0.001),
            }
        })
    }

    fn new(resources: Option<&Path>) -> Self {
        CncMotionFmu(CncMotion {
            resources: resources.map(Path::to_path_buf),
            ..CncMotion::default()
        })
    }

    fn get(&self, index: usize) -> Value {
        let v = &table()[index];
        match v.access {
            Access::Real(get, _) => Value::Real(get(&self.0, v.axis)),
            Access::Integer(get, _) => Value::Integer(get(&self.0, v.axis)),
            Access::Boolean(get, _) => Value::Boolean(get(&self.0, v.axis)),
            Access::String(get, _) => Value::String(get(&self.0, v.axis)),
        }
    }

    fn set(&mut self, index: usize, value: Value) -> Result<(), String> {
        let v = &table()[index];
        match (v.access, value) {
            (Access::Real(_, Some(set)), Value::Real(x)) => set(&mut self.0, v.axis, x),
            (Access::Integer(_, Some(set)), Value::Integer(x)) => set(&mut self.0, v.axis, x),
            (Access::Boolean(_, Some(set)), Value::Boolean(x)) => set(&mut self.0, v.axis, x),
            (Access::String(_, Some(set)), Value::String(x)) => set(&mut self.0, v.axis, &x),
            _ => Err(format!("'{}' cannot be set", v.name)),
        }
    }

    fn exit_initialization(&mut self) -> Result<(), String> {
        self.0.initialize()
    }

    fn do_step(&mut self, h: f64) -> Result<(), String> {
        self.0.do_step(h)
    }

    fn serialize(&self) -> Vec<u8> {
        let m = &self.0;
        let state = SavedModel {
            version: STATE_VERSION,
            program: m.program.clone(),
            program_file: m.program_file.clone(),
            machine: m.machine.clone(),
            servo_enabled: m.servo_enabled,
            feed_override: m.feed_override,
            feed_hold: m.feed_hold,
            load_force: m.load_force,
            engine: m
                .engine
                .as_ref()
                .map(|e| (e.program().text().unwrap_or_default().to_string(), e.save_state())),
        };
        serde_json::to_vec(&state).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        let s: SavedModel = serde_json::from_slice(bytes).map_err(|e| format!("model state: {e}"))?;
        if s.version != STATE_VERSION {
            return Err(format!(
                "model state version {}, expected {STATE_VERSION}",
                s.version
            ));
        }
        let engine = match s.engine {
            Some((text, bytes)) => {
                let mut e =
                    Engine::new(Arc::from(text), &s.program_file, &s.machine).map_err(|e| e.to_string())?;
                e.restore_state(&bytes)?;
                Some(e)
            }
            None => None,
        };
        self.0 = CncMotion {
            program: s.program,
            program_file: s.program_file,
            machine: s.machine,
            servo_enabled: s.servo_enabled,
            feed_override: s.feed_override,
            feed_hold: s.feed_hold,
            load_force: s.load_force,
            resources: self.0.resources.clone(),
            engine,
        };
        Ok(())
    }
}

#[derive(Serialize, Deserialize)]
struct SavedModel {
    version: u32,
    program: String,
    program_file: String,
    machine: Machine,
    servo_enabled: bool,
    feed_override: f64,
    feed_hold: bool,
    load_force: [f64; 3],
    /// Program text and engine state.
    engine: Option<(String, Vec<u8>)>,
}

/// modelDescription.xml of CncMotion, start values read from a default model.
pub fn model_description() -> String {
    fmi2::model_description::<CncMotionFmu>()
}

fmi2::export_fmi2!(crate::fmu::CncMotionFmu);
