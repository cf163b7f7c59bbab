//! The CncMotion FMU: the model table of `model.rs` behind the generic FMI 2.0 layer (crates/fmi2).

use crate::config::Machine;
use crate::engine::Engine;
use crate::model::{self, CncMotion, Slot};
use fmi2::table::Entry;
use fmi2::{ModelInfo, Value};
use std::path::Path;
use std::sync::{Arc, OnceLock};

/// The default program shipped in the FMU's resources (and used by `make demo`).
pub const DEFAULT_PROGRAM: &str = include_str!("../resources/default.ngc");

/// Version of the serialized model state (see `serialize`); 3: `machineFile`.
const STATE_VERSION: u32 = 3;

/// The model as the FMI layer sees it.
#[derive(Clone, Debug)]
pub struct CncMotionFmu(pub CncMotion);

fn table() -> &'static [Entry<Slot>] {
    static TABLE: OnceLock<Vec<Entry<Slot>>> = OnceLock::new();
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
            let description =
                "CNC motion controller: G-code to jerk-limited axis motion through servo drives";
            ModelInfo {
                enumerations: model::enumerations(),
                default_experiment: (0.0, default_stop_time(), 1e-6, 0.001),
                ..fmi2::crate_model_info!(model::MODEL_NAME, description, fmi2::table::variables(table()))
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
        self.0.get(table()[index].slot, table()[index].axis)
    }

    fn set(&mut self, index: usize, value: Value) -> Result<(), String> {
        self.0.set(table()[index].slot, table()[index].axis, value)
    }

    fn exit_initialization(&mut self) -> Result<(), String> {
        self.0.initialize()
    }

    fn do_step(&mut self, h: f64) -> Result<(), String> {
        self.0.do_step(h)
    }

    /// bincode of (model version, parameters and inputs, program text and engine state).
    fn serialize(&self) -> Vec<u8> {
        let engine = self
            .0
            .engine
            .as_ref()
            .map(|e| (e.program().text().unwrap_or_default().to_string(), e.save_state()));
        bincode::serialize(&(STATE_VERSION, &self.0, engine)).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        type Saved = (u32, CncMotion, Option<(String, Vec<u8>)>);
        let (version, mut m, engine): Saved =
            bincode::deserialize(bytes).map_err(|e| format!("model state: {e}"))?;
        if version != STATE_VERSION {
            return Err(format!("model state version {version}, expected {STATE_VERSION}"));
        }
        if let Some((text, bytes)) = engine {
            let mut e =
                Engine::new(Arc::from(text), m.source_name(), &m.machine).map_err(|e| e.to_string())?;
            e.restore_state(&bytes)?;
            m.engine = Some(e);
        }
        m.resources = self.0.resources.clone();
        self.0 = m;
        Ok(())
    }
}

/// modelDescription.xml of CncMotion, start values read from a default model.
pub fn model_description() -> String {
    fmi2::model_description::<CncMotionFmu>()
}

fmi2::export_fmi2!(crate::fmu::CncMotionFmu);
