//! The CncMotion FMU: the model table of `model.rs` behind the generic FMI 2.0 layer (crates/fmi2).

use crate::config::Machine;
use crate::engine::Engine;
use crate::model::{self, CncMotion, Slot, ENUMERATIONS};
use fmi2::{EnumerationType, ModelInfo, Value, VariableInfo};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::{Arc, OnceLock};

/// The default program shipped in the FMU's resources (and used by `make demo`).
pub const DEFAULT_PROGRAM: &str = include_str!("../resources/default.ngc");

/// Version of the serialized model state (bincode of [`SavedModel`]).
const STATE_VERSION: u32 = 2;

/// The model as the FMI layer sees it.
#[derive(Clone, Debug)]
pub struct CncMotionFmu(pub CncMotion);

fn table() -> &'static [(VariableInfo, Slot)] {
    static TABLE: OnceLock<Vec<(VariableInfo, Slot)>> = OnceLock::new();
    TABLE.get_or_init(model::rows)
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
            let variables = table().iter().map(|(v, _)| v.clone()).collect();
            let description =
                "CNC motion controller: G-code to jerk-limited axis motion through servo drives";
            let enumerations = ENUMERATIONS.iter().map(|(name, items)| EnumerationType {
                name: name.to_string(),
                items: items
                    .iter()
                    .map(|(n, d)| (n.to_string(), d.to_string()))
                    .collect(),
            });
            ModelInfo {
                version: env!("CARGO_PKG_VERSION").into(),
                author: "cnc-motion authors".into(),
                copyright: "Copyright (c) 2026 the cnc-motion authors".into(),
                license: env!("CARGO_PKG_LICENSE").into(),
                enumerations: enumerations.collect(),
                default_experiment: (0.0, default_stop_time(), 1e-6, 0.001),
                ..ModelInfo::new(model::MODEL_NAME, description, variables)
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
        self.0.get(table()[index].1)
    }

    fn set(&mut self, index: usize, value: Value) -> Result<(), String> {
        self.0.set(table()[index].1, value)
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
            indices: (m.profile_index, m.corner_index),
            servo_enabled: m.servo_enabled,
            feed_override: m.feed_override,
            feed_hold: m.feed_hold,
            load_force: m.load_force,
            engine: m
                .engine
                .as_ref()
                .map(|e| (e.program().to_string(), e.save_state())),
        };
        bincode::serialize(&state).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        let s: SavedModel = bincode::deserialize(bytes).map_err(|e| format!("model state: {e}"))?;
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
            profile_index: s.indices.0,
            corner_index: s.indices.1,
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
    /// machine.profileIndex, machine.cornerIndex.
    indices: (i32, i32),
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
