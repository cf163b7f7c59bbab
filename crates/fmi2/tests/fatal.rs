//! Fatal stays fatal (FMI 2.0 §2.1.3): a panic in any model callback answers fmi2Fatal and logs
//! the panic's message; from then on every call on that instance but fmi2FreeInstance answers
//! fmi2Error with a log line and never reaches the model.

// The dev-dependencies of the crate are shared by its test targets.
#![allow(unused_crate_dependencies)]

use fmi2::abi::{self, CallbackFunctions, Component, FmuState};
use fmi2::instance::LoggerFn;
use fmi2::{Causality, Model, ModelInfo, Type, Value, Variability, VariableInfo};
use std::cell::{Cell, RefCell};
use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::Path;
use std::sync::OnceLock;

const OK: c_int = 0;
const ERROR: c_int = 3;
const FATAL: c_int = 4;

/// The model callbacks, by name: the one armed in `PANIC_IN` panics.
const CALLBACKS: [&str; 8] = [
    "new",
    "get",
    "set",
    "exit_initialization",
    "do_step",
    "serialize",
    "deserialize",
    "clone",
];

thread_local! {
    /// The callback that panics next (tests run on their own threads).
    static PANIC_IN: Cell<&'static str> = const { Cell::new("") };
    /// Callbacks the model has run, to show that nothing reaches it after fmi2Fatal.
    static CALLS: Cell<usize> = const { Cell::new(0) };
    static LOG: RefCell<Vec<(c_int, String)>> = const { RefCell::new(Vec::new()) };
}

fn enter(callback: &str) {
    CALLS.set(CALLS.get() + 1);
    if PANIC_IN.get() == callback {
        panic!("boom in {callback}");
    }
}

/// One Real parameter `p` and one Real output `y = 2·p·t`.
struct Panicky {
    p: f64,
    t: f64,
}

impl Clone for Panicky {
    fn clone(&self) -> Self {
        enter("clone");
        Panicky { p: self.p, t: self.t }
    }
}

impl Model for Panicky {
    fn info() -> &'static ModelInfo {
        static INFO: OnceLock<ModelInfo> = OnceLock::new();
        INFO.get_or_init(|| {
            let v = |name, causality, variability| {
                VariableInfo::new(name, Type::Real, causality, variability, name)
            };
            let vars = vec![
                v("p", Causality::Parameter, Variability::Fixed),
                v("y", Causality::Output, Variability::Continuous),
            ];
            ModelInfo::new("Panicky", "panics on demand", vars)
        })
    }
    fn new(_resources: Option<&Path>) -> Self {
        enter("new");
        Panicky { p: 1.0, t: 0.0 }
    }
    fn get(&self, index: usize) -> Value {
        enter("get");
        Value::Real(if index == 0 { self.p } else { 2.0 * self.p * self.t })
    }
    fn set(&mut self, _index: usize, value: Value) -> Result<(), String> {
        enter("set");
        self.p = value.number()?;
        Ok(())
    }
    fn exit_initialization(&mut self) -> Result<(), String> {
        enter("exit_initialization");
        Ok(())
    }
    fn do_step(&mut self, h: f64) -> Result<(), String> {
        enter("do_step");
        self.t += h;
        Ok(())
    }
    fn serialize(&self) -> Vec<u8> {
        enter("serialize");
        [self.p.to_le_bytes(), self.t.to_le_bytes()].concat()
    }
    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        enter("deserialize");
        let word = |k: usize| {
            bytes
                .get(8 * k..8 * k + 8)
                .and_then(|b| b.try_into().ok())
                .map(f64::from_le_bytes)
        };
        (self.p, self.t) = word(0).zip(word(1)).ok_or("8 + 8 bytes expected")?;
        Ok(())
    }
}

type M = Panicky;

type RawLogger = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

unsafe extern "C" fn logger(
    _env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    _cat: *const c_char,
    msg: *const c_char,
) {
    let text = CStr::from_ptr(msg).to_string_lossy().replace("%%", "%");
    LOG.with_borrow_mut(|l| l.push((status, text)));
}

fn callbacks() -> CallbackFunctions {
    // SAFETY: the layer calls the logger with exactly these five arguments and no variadic
    // ones (it formats the message itself); a non-variadic callee reads them the same way.
    let logger = unsafe { std::mem::transmute::<RawLogger, LoggerFn>(logger) };
    CallbackFunctions {
        logger: Some(logger),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    }
}

fn last_log() -> (c_int, String) {
    LOG.with_borrow(|l| l.last().cloned().unwrap_or_default())
}

/// An instance in StepComplete at t = 0.01, with a serialized state of it.
unsafe fn running(cb: &CallbackFunctions) -> (Component, Vec<u8>, FmuState) {
    let guid = std::ffi::CString::new(M::info().guid.clone()).unwrap();
    let c = abi::instantiate::<M>(c"panicky".as_ptr(), 1, guid.as_ptr(), std::ptr::null(), cb, 0, 1);
    assert!(!c.is_null());
    assert_eq!(abi::setup_experiment::<M>(c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(abi::enter_initialization_mode::<M>(c), OK);
    assert_eq!(abi::exit_initialization_mode::<M>(c), OK);
    assert_eq!(abi::do_step::<M>(c, 0.0, 0.01, 1), OK);
    let mut state: FmuState = std::ptr::null_mut();
    assert_eq!(abi::get_fmu_state::<M>(c, &mut state), OK);
    let mut size = 0;
    assert_eq!(abi::serialized_fmu_state_size::<M>(c, state, &mut size), OK);
    let mut bytes = vec![0u8; size];
    assert_eq!(
        abi::serialize_fmu_state::<M>(c, state, bytes.as_mut_ptr(), size),
        OK
    );
    (c, bytes, state)
}

/// The call that runs `callback` (from StepComplete, or from the fresh instance for the
/// initialization callbacks).
unsafe fn trigger(c: Component, callback: &str, bytes: &[u8], state: FmuState) -> c_int {
    let vr = 1u32;
    let mut x = 0.0;
    let mut size = 0usize;
    let mut s: FmuState = std::ptr::null_mut();
    match callback {
        "new" => abi::reset::<M>(c),
        "get" => abi::get_real::<M>(c, &vr, 1, &mut x),
        "set" => abi::set_real::<M>(c, &vr, 1, &2.0),
        "exit_initialization" => abi::exit_initialization_mode::<M>(c),
        "do_step" => abi::do_step::<M>(c, 0.01, 0.01, 1),
        "serialize" => abi::serialized_fmu_state_size::<M>(c, state, &mut size),
        "deserialize" => abi::deserialize_fmu_state::<M>(c, bytes.as_ptr(), bytes.len(), &mut s),
        "clone" => abi::get_fmu_state::<M>(c, &mut s),
        _ => unreachable!("{callback}"),
    }
}

/// Every fmi2 function that takes an instance, with valid arguments: the status of each.
unsafe fn every_call(c: Component, bytes: &[u8], state: FmuState) -> Vec<(&'static str, c_int)> {
    let vr = [1u32, 2];
    let (mut r, mut i, mut b, mut st) = ([0.0; 2], [0 as c_int; 2], [0 as c_int; 2], [std::ptr::null(); 2]);
    let strs: [*const c_char; 1] = [c"x".as_ptr()];
    let mut s: FmuState = state;
    let mut fresh: FmuState = std::ptr::null_mut();
    let mut size = 0usize;
    let mut buf = vec![0u8; bytes.len()];
    let (mut status, mut real, mut boolean) = (0 as c_int, 0.0, 0 as c_int);
    let mut out = vec![
        (
            "fmi2SetDebugLogging",
            abi::set_debug_logging::<M>(c, 1, 0, std::ptr::null()),
        ),
        (
            "fmi2SetupExperiment",
            abi::setup_experiment::<M>(c, 0, 0.0, 0.0, 0, 0.0),
        ),
        (
            "fmi2EnterInitializationMode",
            abi::enter_initialization_mode::<M>(c),
        ),
        (
            "fmi2ExitInitializationMode",
            abi::exit_initialization_mode::<M>(c),
        ),
        (
            "fmi2GetReal",
            abi::get_real::<M>(c, vr.as_ptr(), 2, r.as_mut_ptr()),
        ),
        (
            "fmi2GetInteger",
            abi::get_integer::<M>(c, vr.as_ptr(), 0, i.as_mut_ptr()),
        ),
        (
            "fmi2GetBoolean",
            abi::get_boolean::<M>(c, vr.as_ptr(), 0, b.as_mut_ptr()),
        ),
        (
            "fmi2GetString",
            abi::get_string::<M>(c, vr.as_ptr(), 0, st.as_mut_ptr()),
        ),
        (
            "fmi2SetReal",
            abi::set_real::<M>(c, vr.as_ptr(), 1, [3.0].as_ptr()),
        ),
        (
            "fmi2SetInteger",
            abi::set_integer::<M>(c, vr.as_ptr(), 0, i.as_ptr()),
        ),
        (
            "fmi2SetBoolean",
            abi::set_boolean::<M>(c, vr.as_ptr(), 0, b.as_ptr()),
        ),
        (
            "fmi2SetString",
            abi::set_string::<M>(c, vr.as_ptr(), 0, strs.as_ptr()),
        ),
        ("fmi2GetFMUstate", abi::get_fmu_state::<M>(c, &mut fresh)),
        ("fmi2SetFMUstate", abi::set_fmu_state::<M>(c, s)),
        (
            "fmi2SerializedFMUstateSize",
            abi::serialized_fmu_state_size::<M>(c, s, &mut size),
        ),
        (
            "fmi2SerializeFMUstate",
            abi::serialize_fmu_state::<M>(c, s, buf.as_mut_ptr(), buf.len()),
        ),
        (
            "fmi2DeSerializeFMUstate",
            abi::deserialize_fmu_state::<M>(c, bytes.as_ptr(), bytes.len(), &mut fresh),
        ),
        ("fmi2DoStep", abi::do_step::<M>(c, 0.01, 0.01, 1)),
        ("fmi2CancelStep", abi::unsupported::<M>(c, abi::Call::CancelStep)),
        (
            "fmi2GetStatus",
            abi::get_status::<M>(c, abi::DO_STEP_STATUS, &mut status),
        ),
        (
            "fmi2GetRealStatus",
            abi::get_real_status::<M>(c, abi::LAST_SUCCESSFUL_TIME, &mut real),
        ),
        (
            "fmi2GetIntegerStatus",
            abi::get_integer_status::<M>(c, 0, &mut status),
        ),
        (
            "fmi2GetBooleanStatus",
            abi::get_boolean_status::<M>(c, abi::TERMINATED, &mut boolean),
        ),
        (
            "fmi2GetStringStatus",
            abi::get_string_status::<M>(c, 0, st.as_mut_ptr()),
        ),
        ("fmi2Terminate", abi::terminate::<M>(c)),
        ("fmi2Reset", abi::reset::<M>(c)),
        ("fmi2FreeFMUstate", abi::free_fmu_state::<M>(c, &mut s)),
    ];
    out.push((
        "fmi2GetDirectionalDerivative",
        abi::unsupported::<M>(c, abi::Call::GetDirectionalDerivative),
    ));
    out
}

#[test]
fn a_panic_in_any_callback_is_fatal_for_good() {
    // The default hook would print every deliberate panic of this test (and only those are quiet).
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !fmi2::abi::panic_message(info.payload()).starts_with("boom") {
            default(info)
        }
    }));
    let cb = callbacks();
    for callback in CALLBACKS {
        unsafe {
            let (c, bytes, state) = running(&cb);
            // A fixed parameter is set before initialization ends.
            if callback == "exit_initialization" || callback == "set" {
                assert_eq!(abi::reset::<M>(c), OK);
                assert_eq!(abi::enter_initialization_mode::<M>(c), OK);
            }
            PANIC_IN.set(callback);
            assert_eq!(trigger(c, callback, &bytes, state), FATAL, "{callback}");
            PANIC_IN.set("");
            let (status, message) = last_log();
            assert_eq!(status, FATAL, "{callback}: {message}");
            assert!(
                message.contains(&format!("panic: boom in {callback}"))
                    && message.contains("fmi2FreeInstance"),
                "{callback}: {message}"
            );
            let calls = CALLS.get();
            let logged = LOG.with_borrow(|l| l.len());
            for (name, status) in every_call(c, &bytes, state) {
                assert_eq!(status, ERROR, "{callback}, then {name}");
            }
            assert_eq!(
                CALLS.get(),
                calls,
                "{callback}: the model was called after fmi2Fatal"
            );
            // Each refused call said why.
            LOG.with_borrow(|l| {
                assert_eq!(l.len() - logged, 28, "{callback}");
                for (status, message) in &l[logged..] {
                    assert!(
                        *status == ERROR && message.contains("only fmi2FreeInstance is allowed"),
                        "{message}"
                    );
                }
            });
            abi::free_instance::<M>(c);
        }
    }
}

#[test]
fn without_a_panic_the_same_calls_run_the_model() {
    // The control: the instance and calls of the test above reach the model when nothing panics.
    let cb = callbacks();
    unsafe {
        let (c, bytes, state) = running(&cb);
        let calls = CALLS.get();
        let statuses = every_call(c, &bytes, state);
        assert!(statuses.iter().any(|&(_, s)| s == OK), "{statuses:?}");
        assert!(CALLS.get() > calls);
        abi::free_instance::<M>(c);
    }
}
