//! One FMU instance: the Co-Simulation state machine (FMI 2.0 and, through crates/fmi3, 3.0), the
//! rules on which variable may be set when, the logger, FMU states and their serialization. Plain
//! Rust; abi.rs does the C side.

use crate::{Causality, Model, Type, Value, Variability, VariableInfo};
use std::ffi::{c_char, c_int, c_void, CString};
use std::path::PathBuf;

/// fmi2Status values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

/// The logger callback of fmi2CallbackFunctions (variadic in C; we pass a finished message).
pub type LoggerFn =
    unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char, ...);

/// fmi3LogMessageCallback: environment, status, category, message (a plain string, no format).
pub type LogMessageFn = unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char);

/// The importer's logger, of either version.
#[derive(Clone, Copy)]
pub enum Logger {
    Fmi2(LoggerFn),
    Fmi3(LogMessageFn),
}

/// States of a co-simulation slave (FMI 2.0, section 4.2.4). `Error` is terminal: only get*,
/// status inquiries, reset, free and FMU-state calls are allowed (see `abi::Call::spec`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum State {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
    Fatal,
    /// FMI 3 Co-Simulation Event Mode (instances made with eventModeUsed).
    EventMode,
}

/// Log categories of every FMU built on this layer (declared in the XML).
pub const LOG_CATEGORIES: [(&str, &str); 4] = [
    ("logEvents", "initialization, steps and state changes"),
    ("logStatusWarning", "warnings"),
    (
        "logStatusError",
        "errors: bad calls, bad arguments, model failures",
    ),
    ("logAll", "everything"),
];

/// A saved FMU state (fmi2GetFMUstate, fmi3GetFMUState): a deep copy of the model and the slave's
/// time.
pub struct Snapshot<M> {
    pub model: M,
    pub time: f64,
    pub state: State,
}

/// Serialized FMU state: magic "FMI2RS", format version (u16, big-endian), then GUID (FMI 3: the
/// instantiation token), time, slave state and the model's own bytes, each length-prefixed and
/// checked on reading. Version 3: the models' bytes are postcard (was bincode 1.3).
const SERIAL_MAGIC: &[u8; 8] = b"FMI2RS\x00\x03";

/// Why a value is outside what the variable declares (non-finite Real, min/max, enumeration
/// items), if it is.
pub fn out_of_range<M: Model>(v: &VariableInfo, value: &Value) -> Option<String> {
    let x = match *value {
        Value::Real(x) if !x.is_finite() => return Some(format!("{x} is not finite")),
        Value::Real(x) => x,
        Value::Integer(n) => n as f64,
        _ => return None,
    };
    let (min, max) = match v.kind {
        Type::Enumeration(e) => (Some(1.0), Some(M::info().enumerations[e].items.len() as f64)),
        _ => (v.min, v.max),
    };
    let below = min.is_some_and(|m| x < m);
    let above = max.is_some_and(|m| x > m);
    let bound = |b: Option<f64>| b.map_or("…".into(), crate::xml::real);
    let x = crate::xml::real(x);
    (below || above).then(|| format!("{x} out of range ({} … {})", bound(min), bound(max)))
}

pub struct Instance<M: Model> {
    pub name: CString,
    pub model: M,
    pub state: State,
    pub time: f64,
    pub stop_time: Option<f64>,
    pub resources: Option<PathBuf>,
    /// The GUID (FMI 2) or instantiation token (FMI 3) the importer gave: serialized FMU states
    /// carry it and are refused by an instance of another model or version.
    pub token: &'static str,
    /// FMI 3: the importer allows fmi3DoStep to return early.
    pub early_return_allowed: bool,
    /// FMI 3 Co-Simulation with Event Mode (eventModeUsed).
    pub event_mode_used: bool,
    /// FMI 3 Scheduled Execution: fmi3ActivateModelPartition advances the model (its Clock
    /// Activation Mode is `State::StepComplete`).
    pub scheduled: bool,
    /// Start time of the experiment (clocks tick at start + k·interval).
    pub start_time: f64,
    /// Time of each clock's latest activation (a clock is activated at most once per time);
    /// emptied by a reset or a restored FMU state.
    pub activated_at: Vec<Option<f64>>,
    logger: Option<Logger>,
    env: *mut c_void,
    logging_on: bool,
    categories: [bool; LOG_CATEGORIES.len()],
    /// Strings handed out by fmi2GetString, valid until the next call.
    pub strings: Vec<CString>,
    /// FMU states handed out and not yet freed (checked on Set/Free).
    pub snapshots: Vec<usize>,
    /// Status of the last fmi2DoStep (fmi2GetStatus(fmi2DoStepStatus)).
    pub last_step: Status,
}

// The raw environment pointer belongs to the importer, which may move instances between threads.
unsafe impl<M: Model> Send for Instance<M> {}

impl<M: Model> Instance<M> {
    pub fn new(
        name: &str,
        resources: Option<PathBuf>,
        logger: Option<Logger>,
        env: *mut c_void,
        logging_on: bool,
    ) -> Self {
        Instance {
            name: CString::new(name.replace('\0', "")).unwrap_or_default(),
            model: M::new(resources.as_deref()),
            state: State::Instantiated,
            time: 0.0,
            stop_time: None,
            resources,
            token: &M::info().guid,
            early_return_allowed: false,
            event_mode_used: false,
            scheduled: false,
            start_time: 0.0,
            activated_at: Vec::new(),
            logger,
            env,
            logging_on,
            categories: [true; LOG_CATEGORIES.len()],
            strings: Vec::new(),
            snapshots: Vec::new(),
            last_step: Status::Ok,
        }
    }

    /// Send a message to the importer's logger, if its category is on. Errors are always sent.
    pub fn log(&self, status: Status, category: usize, message: &str) {
        let Some(logger) = self.logger else { return };
        let always = status == Status::Error || status == Status::Fatal;
        if !always && !(self.logging_on && (self.categories[category] || self.categories[3])) {
            return;
        }
        let cat = CString::new(LOG_CATEGORIES[category].0).unwrap_or_default();
        // SAFETY: the importer gave this callback and environment for exactly this use.
        match logger {
            Logger::Fmi2(logger) => {
                // The FMI 2 logger formats its message like printf: escape '%'.
                let text = message.replace('\0', "").replace('%', "%%");
                let text = CString::new(text).unwrap_or_default();
                let name = self.name.as_ptr();
                unsafe { logger(self.env, name, status as c_int, cat.as_ptr(), text.as_ptr()) };
            }
            Logger::Fmi3(logger) => {
                let text = CString::new(message.replace('\0', "")).unwrap_or_default();
                unsafe { logger(self.env, status as c_int, cat.as_ptr(), text.as_ptr()) };
            }
        }
    }

    pub fn error(&self, message: &str) -> Status {
        self.log(Status::Error, 2, message);
        Status::Error
    }

    pub fn event(&self, message: &str) {
        self.log(Status::Ok, 0, message);
    }

    /// fmi2SetDebugLogging/fmi3SetDebugLogging (`function`): all categories for an empty list,
    /// else exactly those named.
    pub fn set_debug_logging(&mut self, function: &str, on: bool, categories: &[String]) -> Status {
        if categories.is_empty() {
            self.categories = [true; LOG_CATEGORIES.len()];
        } else {
            let mut set = [false; LOG_CATEGORIES.len()];
            for c in categories {
                match LOG_CATEGORIES.iter().position(|(n, _)| n == c) {
                    Some(i) => set[i] = true,
                    None => return self.error(&format!("{function}: unknown log category '{c}'")),
                }
            }
            self.categories = set;
        }
        self.logging_on = on;
        Status::Ok
    }

    /// Index of the variable with this value reference and type family.
    #[inline]
    pub fn lookup(&self, function: &str, vr: u32, family: Type) -> Result<usize, Status> {
        // Value references are 1…n in table order: one comparison per read on the way out.
        let vars = &M::info().variables;
        let i = (vr as usize).wrapping_sub(1);
        match vars.get(i) {
            Some(v) if v.value_reference == vr && v.kind.family() == family => Ok(i),
            _ => self.lookup_slow(function, vr, family),
        }
    }

    #[cold]
    fn lookup_slow(&self, function: &str, vr: u32, family: Type) -> Result<usize, Status> {
        let vars = &M::info().variables;
        // Value references are 1…n in table order; fall back to a search for other numberings.
        let i = (vr as usize)
            .checked_sub(1)
            .filter(|&i| i < vars.len() && vars[i].value_reference == vr)
            .or_else(|| vars.iter().position(|v| v.value_reference == vr));
        let Some(i) = i else {
            return Err(self.error(&format!("{function}: unknown value reference {vr}")));
        };
        if vars[i].kind.family() != family {
            let msg = format!(
                "{function}: variable '{}' (vr {vr}) is of type {:?}",
                vars[i].name, vars[i].kind
            );
            return Err(self.error(&msg));
        }
        Ok(i)
    }

    /// Read a variable (the state is checked by the caller's entry in the abi table).
    #[inline]
    pub fn get(&mut self, function: &str, vr: u32, family: Type) -> Result<Value, Status> {
        let i = self.lookup(function, vr, family)?;
        Ok(self.model.get(i))
    }

    /// Set with the rules of FMI 2.0: before initialization ends, variables with a start value;
    /// after, inputs and tunable parameters only.
    pub fn set(&mut self, function: &str, vr: u32, family: Type, value: Value) -> Result<(), Status> {
        let i = self.lookup(function, vr, family)?;
        self.set_at(function, i, value)
    }

    /// Set variable `i` of the table (the rules of [`Instance::set`]; FMI 3.0 has the same for
    /// Co-Simulation without Event Mode: start values before initialization ends, then inputs
    /// and tunable parameters).
    pub fn set_at(&mut self, function: &str, i: usize, value: Value) -> Result<(), Status> {
        let v = &M::info().variables[i];
        let allowed = match self.state {
            State::Instantiated | State::InitializationMode => {
                v.has_start() && v.variability != Variability::Constant
            }
            _ => {
                v.causality == Causality::Input
                    || (v.causality == Causality::Parameter && v.variability == Variability::Tunable)
            }
        };
        if !allowed {
            let msg = format!(
                "{function}: '{}' ({:?}, {:?}) cannot be set in state {:?}",
                v.name, v.causality, v.variability, self.state
            );
            return Err(self.error(&msg));
        }
        if let Some(reason) = out_of_range::<M>(v, &value) {
            return Err(self.error(&format!("{function}: '{}' = {reason}", v.name)));
        }
        let name = v.name.clone();
        self.model
            .set(i, value)
            .map_err(|m| self.error(&format!("{function}: '{name}': {m}")))
    }

    pub fn snapshot(&self) -> Snapshot<M> {
        Snapshot {
            model: self.model.clone(),
            time: self.time,
            state: self.state,
        }
    }

    pub fn restore(&mut self, s: &Snapshot<M>) {
        self.model = s.model.clone();
        self.time = s.time;
        self.state = s.state;
        self.activated_at.clear();
    }

    /// Versioned, size-checked bytes: magic, GUID (or token), time, state, model bytes.
    pub fn serialize(&self, s: &Snapshot<M>) -> Vec<u8> {
        let guid = self.token.as_bytes();
        let body = s.model.serialize();
        let mut out = Vec::with_capacity(32 + guid.len() + body.len());
        out.extend_from_slice(SERIAL_MAGIC);
        out.extend_from_slice(&(guid.len() as u32).to_le_bytes());
        out.extend_from_slice(guid);
        out.extend_from_slice(&s.time.to_le_bytes());
        out.push(s.state as u8);
        out.extend_from_slice(&(body.len() as u64).to_le_bytes());
        out.extend_from_slice(&body);
        out
    }

    pub fn deserialize(&self, bytes: &[u8]) -> Result<Snapshot<M>, String> {
        let mut r = bytes;
        let mut take = |n: usize| -> Result<&[u8], String> {
            if r.len() < n {
                return Err(format!("serialized FMU state truncated ({} bytes)", bytes.len()));
            }
            let (a, b) = r.split_at(n);
            r = b;
            Ok(a)
        };
        if take(8)? != SERIAL_MAGIC {
            return Err("not a serialized state of this FMU (magic/version mismatch)".into());
        }
        let n = u32::from_le_bytes(take(4)?.try_into().map_err(|_| "bad length")?) as usize;
        if take(n)? != self.token.as_bytes() {
            return Err(
                "serialized FMU state belongs to another model or FMI version (GUID mismatch)".into(),
            );
        }
        let time = f64::from_le_bytes(take(8)?.try_into().map_err(|_| "bad time")?);
        if !time.is_finite() {
            return Err(format!("serialized FMU state has a time of {time}"));
        }
        let state = match take(1)?[0] {
            0 => State::Instantiated,
            1 => State::InitializationMode,
            2 => State::StepComplete,
            3 => State::StepFailed,
            4 => State::Terminated,
            5 => State::Error,
            7 if self.event_mode_used => State::EventMode,
            7 => return Err("serialized FMU state was saved in Event Mode; this instance has none".into()),
            _ => return Err("serialized FMU state has an invalid slave state".into()),
        };
        let len = u64::from_le_bytes(take(8)?.try_into().map_err(|_| "bad length")?) as usize;
        let body = take(len)?;
        if !r.is_empty() {
            return Err(format!("serialized FMU state has {} trailing bytes", r.len()));
        }
        let mut model = self.model.clone();
        model.deserialize(body)?;
        Ok(Snapshot { model, time, state })
    }
}
