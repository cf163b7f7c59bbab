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

/// Version of the serialized model state (see `serialize`); 3: `machineFile`; 4: postcard
/// instead of bincode.
const STATE_VERSION: u32 = 4;

/// The model as the FMI layer sees it.
#[derive(Clone, Debug)]
pub struct CncMotionFmu(pub CncMotion);

#[inline]
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
            let info =
                fmi2::crate_model_info!(model::MODEL_NAME, description, fmi2::table::variables(table()));
            let capabilities = fmi2::Capabilities {
                max_output_derivative_order: model::MAX_OUTPUT_DERIVATIVE_ORDER,
                // The interpolation period (of the default machine; machine.interpolationPeriod
                // sets another).
                fixed_internal_step: Some(Machine::default().interpolation_period),
                might_return_early: true,
                ..info.capabilities
            };
            ModelInfo {
                enumerations: model::enumerations(),
                default_experiment: (0.0, default_stop_time(), 1e-6, 0.001),
                terminals: model::terminals(),
                clocks: vec![model::tick_clock()],
                ..info.with_capabilities(capabilities)
            }
        })
    }

    fn new(resources: Option<&Path>) -> Self {
        CncMotionFmu(CncMotion {
            resources: resources.map(Path::to_path_buf),
            ..CncMotion::default()
        })
    }

    #[inline]
    fn get(&self, index: usize) -> Value {
        let e = &table()[index];
        self.0.get(e.slot, e.axis)
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

    fn do_step_early(&mut self, h: f64) -> Result<f64, String> {
        self.0.do_step_early(h)
    }

    fn check_clock(&self, _clock: usize, interval: f64) -> Result<(), String> {
        self.0.check_tick(interval)
    }

    fn output_derivative(&self, index: usize, order: u32) -> Option<f64> {
        let e = &table()[index];
        self.0.output_derivative(e.slot, e.axis, order)
    }

    /// The model version, then postcard of (parameters and inputs, program text and engine
    /// state).
    fn serialize(&self) -> Vec<u8> {
        let engine = self
            .0
            .engine
            .as_ref()
            .map(|e| (e.program().text().unwrap_or_default().to_string(), e.save_state()));
        let mut out = STATE_VERSION.to_le_bytes().to_vec();
        out.extend(postcard::to_stdvec(&(&self.0, engine)).unwrap_or_default());
        out
    }

    /// Every part checked before it is used: the version, the parameters and inputs as
    /// fmi2Set*/initialization check them, the program as initialization checks it, and the
    /// engine state field by field (`Engine::restore_state`).
    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        let Some((version, body)) = bytes.split_first_chunk::<4>() else {
            return Err(format!("model state too short: {} bytes", bytes.len()));
        };
        let version = u32::from_le_bytes(*version);
        if version != STATE_VERSION {
            return Err(format!("model state version {version}, expected {STATE_VERSION}"));
        }
        type Saved = (CncMotion, Option<(String, Vec<u8>)>);
        let ((mut m, engine), rest): (Saved, _) =
            postcard::take_from_bytes(body).map_err(|e| format!("model state: {e}"))?;
        if !rest.is_empty() {
            return Err(format!("model state: {} bytes after its end", rest.len()));
        }
        check_inputs(&m).map_err(|e| format!("model state: {e}"))?;
        if let Some((text, bytes)) = engine {
            m.machine.check().map_err(|e| format!("model state: {e}"))?;
            let mut e =
                Engine::new(Arc::from(text), m.source_name(), &m.machine).map_err(|e| e.to_string())?;
            e.restore_state(&bytes)?;
            if e.servo() != m.servo_enabled {
                return Err("model state: the engine's drives do not match servo.enabled".into());
            }
            m.engine = Some(e);
        }
        m.resources = self.0.resources.clone();
        self.0 = m;
        Ok(())
    }
}

/// The inputs and index parameters of a restored model within what fmi2Set* accepts.
fn check_inputs(m: &CncMotion) -> Result<(), String> {
    if !(0.0..=2.0).contains(&m.feed_override) {
        return Err(format!("feedOverride = {} out of range (0 … 2)", m.feed_override));
    }
    for f in m.load_force {
        crate::config::ranges::check_load_force(f)?;
    }
    let profiles = 0..=crate::feed::ProfileKind::ALL.len() as i32;
    let corners = 0..=crate::config::CornerMode::ALL.len() as i32;
    if !(profiles.contains(&m.profile_index) && corners.contains(&m.corner_index)) {
        return Err("machine.profileIndex or machine.cornerIndex out of range".into());
    }
    Ok(())
}

/// modelDescription.xml of CncMotion, start values read from a default model.
pub fn model_description() -> String {
    fmi2::model_description::<CncMotionFmu>()
}

fmi2::export_fmi2!(crate::fmu::CncMotionFmu);
fmi3::export_fmi3!(crate::fmu::CncMotionFmu);
