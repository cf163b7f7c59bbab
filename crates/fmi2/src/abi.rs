//! The fmi2 C functions, generic over the model. `export_fmi2!(Model)` puts them into a model's
//! cdylib under their standard names. Every entry catches panics, checks its pointers and state,
//! and answers fmi2Error with a log line instead of crashing.

use crate::instance::{Instance, LoggerFn, Snapshot, State, Status};
use crate::{Model, Type, Value};
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

pub type Component = *mut c_void;
pub type FmuState = *mut c_void;
pub type ValueReference = c_uint;
pub type Boolean = c_int;

/// fmi2CallbackFunctions.
#[repr(C)]
pub struct CallbackFunctions {
    pub logger: Option<LoggerFn>,
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub step_finished: Option<unsafe extern "C" fn(*mut c_void, c_int)>,
    pub component_environment: *mut c_void,
}

pub static TYPES_PLATFORM: &CStr = c"default";
pub static VERSION: &CStr = c"2.0";

const ALL_ACTIVE: &[State] = &[
    State::Instantiated,
    State::InitializationMode,
    State::StepComplete,
    State::StepFailed,
    State::Terminated,
    State::Error,
];

/// Run `f` on the instance behind `c`, turning a panic into fmi2Fatal (logged).
unsafe fn with<M: Model>(c: Component, f: impl FnOnce(&mut Instance<M>) -> Status) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    let inst = &mut *(c as *mut Instance<M>);
    let result = catch_unwind(AssertUnwindSafe(|| {
        if inst.state == State::Fatal {
            return Status::Error;
        }
        f(inst)
    }));
    match result {
        Ok(s) => s as c_int,
        Err(_) => {
            inst.state = State::Fatal;
            let _ = catch_unwind(AssertUnwindSafe(|| {
                inst.log(Status::Fatal, 2, "internal error (panic); instance is unusable")
            }));
            Status::Fatal as c_int
        }
    }
}

unsafe fn opt_str<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        CStr::from_ptr(p).to_str().ok()
    }
}

/// Slices behind array arguments; NULL is only allowed with n = 0.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts(p, n))
    }
}

unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts_mut(p, n))
    }
}

/// # Safety
/// C ABI: pointers as the FMI 2.0 standard defines them.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate<M: Model>(
    instance_name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    let r = catch_unwind(AssertUnwindSafe(|| {
        let (logger, env) = if functions.is_null() {
            (None, std::ptr::null_mut())
        } else {
            ((*functions).logger, (*functions).component_environment)
        };
        let name = opt_str(instance_name).unwrap_or("");
        // A throw-away logger context to report refusals before an instance exists.
        let report = |msg: &str| {
            if let Some(l) = logger {
                let text = CString::new(msg.replace('%', "%%")).unwrap_or_default();
                let n = CString::new(name).unwrap_or_default();
                l(
                    env,
                    n.as_ptr(),
                    Status::Error as c_int,
                    c"logStatusError".as_ptr(),
                    text.as_ptr(),
                );
            }
        };
        if instance_name.is_null() || name.is_empty() {
            report("fmi2Instantiate: missing instance name");
            return std::ptr::null_mut();
        }
        if fmu_type != 1 {
            report("fmi2Instantiate: this FMU supports Co-Simulation only (fmi2CoSimulation)");
            return std::ptr::null_mut();
        }
        let info = M::info();
        match opt_str(guid) {
            Some(g) if g == info.guid => {}
            g => {
                report(&format!(
                    "fmi2Instantiate: GUID {:?} does not match this FMU's {}",
                    g, info.guid
                ));
                return std::ptr::null_mut();
            }
        }
        let resources = match opt_str(resource_location) {
            None | Some("") => None,
            Some(uri) => match crate::uri::file_uri_to_path(uri) {
                Ok(p) => Some(p),
                Err(e) => {
                    report(&format!("fmi2Instantiate: {e}"));
                    return std::ptr::null_mut();
                }
            },
        };
        let inst = Instance::<M>::new(name, resources, logger, env, logging_on != 0);
        inst.event("fmi2Instantiate");
        Box::into_raw(Box::new(inst)) as Component
    }));
    r.unwrap_or(std::ptr::null_mut())
}

/// # Safety
/// `c` from `instantiate`, not used afterwards.
pub unsafe fn free_instance<M: Model>(c: Component) {
    if c.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        let inst = Box::from_raw(c as *mut Instance<M>);
        for p in &inst.snapshots {
            drop(Box::from_raw(*p as *mut Snapshot<M>));
        }
        drop(inst);
    }));
}

/// # Safety
/// C ABI.
pub unsafe fn set_debug_logging<M: Model>(
    c: Component,
    on: Boolean,
    n: usize,
    cats: *const *const c_char,
) -> c_int {
    with::<M>(c, |inst| {
        let Some(cats) = slice(cats, n) else {
            return inst.error("fmi2SetDebugLogging: categories is NULL with nCategories > 0");
        };
        let mut names = Vec::with_capacity(n);
        for &p in cats {
            match opt_str(p) {
                Some(s) => names.push(s.to_string()),
                None => return inst.error("fmi2SetDebugLogging: NULL or non-UTF-8 category"),
            }
        }
        inst.set_debug_logging(on != 0, &names)
    })
}

/// # Safety
/// C ABI.
pub unsafe fn setup_experiment<M: Model>(
    c: Component,
    _tol_defined: Boolean,
    _tol: f64,
    start: f64,
    stop_defined: Boolean,
    stop: f64,
) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2SetupExperiment", &[State::Instantiated]) {
            return s;
        }
        if !start.is_finite() || (stop_defined != 0 && !(stop.is_finite() && stop >= start)) {
            return inst.error(&format!("fmi2SetupExperiment: bad start {start} / stop {stop}"));
        }
        inst.time = start;
        inst.stop_time = (stop_defined != 0).then_some(stop);
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn enter_initialization_mode<M: Model>(c: Component) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2EnterInitializationMode", &[State::Instantiated]) {
            return s;
        }
        inst.state = State::InitializationMode;
        inst.event("fmi2EnterInitializationMode");
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn exit_initialization_mode<M: Model>(c: Component) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2ExitInitializationMode", &[State::InitializationMode]) {
            return s;
        }
        match inst.model.exit_initialization() {
            Ok(()) => {
                inst.state = State::StepComplete;
                inst.event("fmi2ExitInitializationMode");
                Status::Ok
            }
            Err(e) => {
                inst.state = State::Error;
                inst.error(&e)
            }
        }
    })
}

/// # Safety
/// C ABI.
pub unsafe fn terminate<M: Model>(c: Component) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2Terminate", &[State::StepComplete, State::StepFailed]) {
            return s;
        }
        inst.state = State::Terminated;
        inst.event("fmi2Terminate");
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn reset<M: Model>(c: Component) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2Reset", ALL_ACTIVE) {
            return s;
        }
        inst.model = M::new(inst.resources.as_deref());
        inst.state = State::Instantiated;
        inst.time = 0.0;
        inst.stop_time = None;
        inst.event("fmi2Reset");
        Status::Ok
    })
}

macro_rules! getter {
    ($fn:ident, $name:literal, $t:ty, $family:expr, $pat:pat => $val:expr) => {
        /// # Safety
        /// C ABI.
        pub unsafe fn $fn<M: Model>(
            c: Component,
            vr: *const ValueReference,
            n: usize,
            out: *mut $t,
        ) -> c_int {
            with::<M>(c, |inst| {
                let (Some(vr), Some(out)) = (slice(vr, n), slice_mut(out, n)) else {
                    return inst.error(concat!($name, ": NULL array with nvr > 0"));
                };
                for (r, o) in vr.iter().zip(out.iter_mut()) {
                    match inst.get($name, *r, $family) {
                        Ok($pat) => *o = $val,
                        Ok(_) => {
                            return inst.error(concat!($name, ": model returned a value of another type"))
                        }
                        Err(s) => return s,
                    }
                }
                Status::Ok
            })
        }
    };
}

getter!(get_real, "fmi2GetReal", f64, Type::Real, Value::Real(x) => x);
getter!(get_integer, "fmi2GetInteger", c_int, Type::Integer, Value::Integer(x) => x);
getter!(get_boolean, "fmi2GetBoolean", Boolean, Type::Boolean, Value::Boolean(x) => c_int::from(x));

/// # Safety
/// C ABI. The strings stay valid until the next fmi2GetString on this instance.
pub unsafe fn get_string<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    out: *mut *const c_char,
) -> c_int {
    with::<M>(c, |inst| {
        let (Some(vr), Some(out)) = (slice(vr, n), slice_mut(out, n)) else {
            return inst.error("fmi2GetString: NULL array with nvr > 0");
        };
        inst.strings.clear();
        for r in vr {
            match inst.get("fmi2GetString", *r, Type::String) {
                Ok(Value::String(s)) => inst
                    .strings
                    .push(CString::new(s.replace('\0', "")).unwrap_or_default()),
                Ok(_) => return inst.error("fmi2GetString: model returned a value of another type"),
                Err(s) => return s,
            }
        }
        for (o, s) in out.iter_mut().zip(&inst.strings) {
            *o = s.as_ptr();
        }
        Status::Ok
    })
}

macro_rules! setter {
    ($fn:ident, $name:literal, $t:ty, $family:expr, |$x:ident| $val:expr) => {
        /// # Safety
        /// C ABI.
        pub unsafe fn $fn<M: Model>(
            c: Component,
            vr: *const ValueReference,
            n: usize,
            values: *const $t,
        ) -> c_int {
            with::<M>(c, |inst| {
                let (Some(vr), Some(values)) = (slice(vr, n), slice(values, n)) else {
                    return inst.error(concat!($name, ": NULL array with nvr > 0"));
                };
                for (r, &$x) in vr.iter().zip(values) {
                    if let Err(s) = inst.set($name, *r, $family, $val) {
                        return s;
                    }
                }
                Status::Ok
            })
        }
    };
}

setter!(set_real, "fmi2SetReal", f64, Type::Real, |x| Value::Real(x));
setter!(set_integer, "fmi2SetInteger", c_int, Type::Integer, |x| {
    Value::Integer(x)
});
setter!(set_boolean, "fmi2SetBoolean", Boolean, Type::Boolean, |x| {
    Value::Boolean(x != 0)
});

/// # Safety
/// C ABI.
pub unsafe fn set_string<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    values: *const *const c_char,
) -> c_int {
    with::<M>(c, |inst| {
        let (Some(vr), Some(values)) = (slice(vr, n), slice(values, n)) else {
            return inst.error("fmi2SetString: NULL array with nvr > 0");
        };
        for (r, &p) in vr.iter().zip(values) {
            let Some(s) = opt_str(p) else {
                return inst.error(&format!("fmi2SetString: NULL or non-UTF-8 string for vr {r}"));
            };
            if let Err(st) = inst.set("fmi2SetString", *r, Type::String, Value::String(s.to_string())) {
                return st;
            }
        }
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn do_step<M: Model>(c: Component, t: f64, h: f64, _no_prior: Boolean) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2DoStep", &[State::StepComplete]) {
            return s;
        }
        if !(h > 0.0 && h.is_finite()) {
            return inst.error(&format!("fmi2DoStep: communicationStepSize must be > 0, got {h}"));
        }
        let tol = 1e-9 * inst.time.abs().max(1.0);
        if (t - inst.time).abs() > tol {
            return inst.error(&format!(
                "fmi2DoStep: currentCommunicationPoint {t} is not the slave's time {}",
                inst.time
            ));
        }
        if let Some(stop) = inst.stop_time {
            if t + h > stop + 1e-9 * stop.abs().max(1.0) {
                return inst.error(&format!(
                    "fmi2DoStep: step to {} goes past the stop time {stop}",
                    t + h
                ));
            }
        }
        match inst.model.do_step(h) {
            Ok(()) => {
                inst.time = t + h;
                Status::Ok
            }
            Err(e) => {
                inst.state = State::Error;
                inst.error(&format!("fmi2DoStep: {e}"))
            }
        }
    })
}

/// # Safety
/// C ABI.
pub unsafe fn get_fmu_state<M: Model>(c: Component, state: *mut FmuState) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2GetFMUstate", ALL_ACTIVE) {
            return s;
        }
        if state.is_null() {
            return inst.error("fmi2GetFMUstate: FMUstate pointer is NULL");
        }
        let snap = inst.snapshot();
        if !(*state).is_null() && inst.snapshots.contains(&(*state as usize)) {
            // Overwrite a state the importer already owns.
            *(*state as *mut Snapshot<M>) = snap;
        } else {
            let p = Box::into_raw(Box::new(snap)) as usize;
            inst.snapshots.push(p);
            *state = p as FmuState;
        }
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn set_fmu_state<M: Model>(c: Component, state: FmuState) -> c_int {
    with::<M>(c, |inst| {
        if let Err(s) = inst.require("fmi2SetFMUstate", ALL_ACTIVE) {
            return s;
        }
        if state.is_null() || !inst.snapshots.contains(&(state as usize)) {
            return inst.error("fmi2SetFMUstate: not an FMU state of this instance");
        }
        let snap = &*(state as *const Snapshot<M>);
        inst.restore(snap);
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn free_fmu_state<M: Model>(c: Component, state: *mut FmuState) -> c_int {
    with::<M>(c, |inst| {
        if state.is_null() || (*state).is_null() {
            return Status::Ok;
        }
        let p = *state as usize;
        let Some(k) = inst.snapshots.iter().position(|&q| q == p) else {
            return inst.error("fmi2FreeFMUstate: not an FMU state of this instance");
        };
        inst.snapshots.swap_remove(k);
        drop(Box::from_raw(p as *mut Snapshot<M>));
        *state = std::ptr::null_mut();
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn serialized_fmu_state_size<M: Model>(c: Component, state: FmuState, size: *mut usize) -> c_int {
    with::<M>(c, |inst| {
        if size.is_null() || state.is_null() || !inst.snapshots.contains(&(state as usize)) {
            return inst.error("fmi2SerializedFMUstateSize: bad FMU state or NULL size");
        }
        *size = Instance::<M>::serialize(&*(state as *const Snapshot<M>)).len();
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: Component,
    state: FmuState,
    out: *mut u8,
    size: usize,
) -> c_int {
    with::<M>(c, |inst| {
        if out.is_null() || state.is_null() || !inst.snapshots.contains(&(state as usize)) {
            return inst.error("fmi2SerializeFMUstate: bad FMU state or NULL buffer");
        }
        let bytes = Instance::<M>::serialize(&*(state as *const Snapshot<M>));
        if bytes.len() != size {
            return inst.error(&format!(
                "fmi2SerializeFMUstate: size {size}, the state needs {}",
                bytes.len()
            ));
        }
        std::ptr::copy_nonoverlapping(bytes.as_ptr(), out, size);
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: Component,
    bytes: *const u8,
    size: usize,
    state: *mut FmuState,
) -> c_int {
    with::<M>(c, |inst| {
        let (Some(bytes), false) = (slice(bytes, size), state.is_null()) else {
            return inst.error("fmi2DeSerializeFMUstate: NULL argument");
        };
        match inst.deserialize(bytes) {
            Ok(snap) => {
                if !(*state).is_null() && inst.snapshots.contains(&(*state as usize)) {
                    *(*state as *mut Snapshot<M>) = snap;
                } else {
                    let p = Box::into_raw(Box::new(snap)) as usize;
                    inst.snapshots.push(p);
                    *state = p as FmuState;
                }
                Status::Ok
            }
            Err(e) => inst.error(&format!("fmi2DeSerializeFMUstate: {e}")),
        }
    })
}

/// Functions this FMU does not provide: log and refuse.
///
/// # Safety
/// C ABI.
pub unsafe fn unsupported<M: Model>(c: Component, function: &str) -> c_int {
    with::<M>(c, |inst| {
        inst.error(&format!("{function} is not supported by this FMU"))
    })
}

/// # Safety
/// C ABI.
pub unsafe fn get_status<M: Model>(c: Component, kind: c_int, out: *mut c_int) -> c_int {
    with::<M>(c, |inst| {
        if out.is_null() {
            return inst.error("fmi2GetStatus: NULL value");
        }
        if kind != 0 {
            // Only fmi2DoStepStatus is meaningful; steps are never asynchronous here.
            return Status::Discard;
        }
        *out = Status::Ok as c_int;
        Status::Ok
    })
}

/// Export every fmi2 function of the standard for model `$m` from this cdylib.
#[macro_export]
macro_rules! export_fmi2 {
    ($m:ty) => {
        mod __fmi2_exports {
            use super::*;
            use std::ffi::{c_char, c_int, c_void};
            use $crate::abi::{self, Boolean, CallbackFunctions, Component, FmuState, ValueReference};
            type M = $m;

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                abi::TYPES_PLATFORM.as_ptr()
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                abi::VERSION.as_ptr()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Component,
                on: Boolean,
                n: usize,
                cats: *const *const c_char,
            ) -> c_int {
                abi::set_debug_logging::<M>(c, on, n, cats)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: *const c_char,
                kind: c_int,
                guid: *const c_char,
                resources: *const c_char,
                functions: *const CallbackFunctions,
                visible: Boolean,
                logging_on: Boolean,
            ) -> Component {
                abi::instantiate::<M>(name, kind, guid, resources, functions, visible, logging_on)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
                abi::free_instance::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Component,
                td: Boolean,
                tol: f64,
                start: f64,
                sd: Boolean,
                stop: f64,
            ) -> c_int {
                abi::setup_experiment::<M>(c, td, tol, start, sd, stop)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> c_int {
                abi::enter_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> c_int {
                abi::exit_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Terminate(c: Component) -> c_int {
                abi::terminate::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Reset(c: Component) -> c_int {
                abi::reset::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut f64,
            ) -> c_int {
                abi::get_real::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut c_int,
            ) -> c_int {
                abi::get_integer::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut Boolean,
            ) -> c_int {
                abi::get_boolean::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut *const c_char,
            ) -> c_int {
                abi::get_string::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const f64,
            ) -> c_int {
                abi::set_real::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const c_int,
            ) -> c_int {
                abi::set_integer::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const Boolean,
            ) -> c_int {
                abi::set_boolean::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const *const c_char,
            ) -> c_int {
                abi::set_string::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, s: *mut FmuState) -> c_int {
                abi::get_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, s: FmuState) -> c_int {
                abi::set_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, s: *mut FmuState) -> c_int {
                abi::free_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Component,
                s: FmuState,
                size: *mut usize,
            ) -> c_int {
                abi::serialized_fmu_state_size::<M>(c, s, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Component,
                s: FmuState,
                out: *mut u8,
                size: usize,
            ) -> c_int {
                abi::serialize_fmu_state::<M>(c, s, out, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Component,
                b: *const u8,
                size: usize,
                s: *mut FmuState,
            ) -> c_int {
                abi::deserialize_fmu_state::<M>(c, b, size, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Component,
                _u: *const ValueReference,
                _nu: usize,
                _z: *const ValueReference,
                _nz: usize,
                _dv: *const f64,
                _dz: *mut f64,
            ) -> c_int {
                abi::unsupported::<M>(c, "fmi2GetDirectionalDerivative")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const c_int,
                _v: *const f64,
            ) -> c_int {
                abi::unsupported::<M>(c, "fmi2SetRealInputDerivatives")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const c_int,
                _v: *mut f64,
            ) -> c_int {
                abi::unsupported::<M>(c, "fmi2GetRealOutputDerivatives")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DoStep(c: Component, t: f64, h: f64, no_prior: Boolean) -> c_int {
                abi::do_step::<M>(c, t, h, no_prior)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> c_int {
                abi::unsupported::<M>(c, "fmi2CancelStep (steps are synchronous)")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStatus(c: Component, kind: c_int, v: *mut c_int) -> c_int {
                abi::get_status::<M>(c, kind, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, _kind: c_int, _v: *mut f64) -> c_int {
                abi::unsupported::<M>(c, "fmi2GetRealStatus")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: Component,
                _kind: c_int,
                _v: *mut c_int,
            ) -> c_int {
                abi::unsupported::<M>(c, "fmi2GetIntegerStatus")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Component,
                _kind: c_int,
                _v: *mut Boolean,
            ) -> c_int {
                abi::unsupported::<M>(c, "fmi2GetBooleanStatus")
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Component,
                _kind: c_int,
                _v: *mut *const c_char,
            ) -> c_int {
                abi::unsupported::<M>(c, "fmi2GetStringStatus")
            }
            #[allow(dead_code)]
            fn _unused(_: *mut c_void) {}
        }
    };
}
