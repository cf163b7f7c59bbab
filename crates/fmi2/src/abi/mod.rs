//! The fmi2 C functions, generic over the model, split by concern: [`lifecycle`] (instantiate …
//! doStep … free), [`values`] (get/set), [`state`] (FMU state and status inquiries) and
//! [`export`] (`export_fmi2!`, the `#[no_mangle]` symbols).
//!
//! Every entry goes through [`with`], the `BEGIN_FUNCTION` of the Modelica Reference-FMUs: it
//! checks the instance pointer, refuses a call whose state is not in the function's mask of
//! [`Call::spec`] (one table for all functions), catches panics, and moves the instance to the
//! terminal [`State::Error`] whenever a function answers fmi2Error. In that state only get*,
//! status inquiries, reset, free and the FMU-state functions are allowed (FMI 2.0 §2.1.3); a
//! saved FMU state or fmi2Reset brings the instance back. A panic is fmi2Fatal, logged with its
//! message, and for good: the instance then answers fmi2Error to everything but fmi2FreeInstance.

pub mod derivatives;
pub mod lifecycle;
pub mod state;
pub mod values;
#[macro_use]
pub mod export;

pub use derivatives::*;
pub use lifecycle::*;
pub use state::*;
pub use values::*;

pub use crate::instance::Logger;
use crate::instance::{Instance, LoggerFn, State, Status};
use crate::Model;
use std::ffi::{c_char, c_int, c_uint, c_void, CStr};
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

/// Bit masks of the slave states ([`State`] as a set).
pub mod mask {
    use crate::instance::State;
    pub const INSTANTIATED: u16 = 1 << State::Instantiated as u16;
    pub const INIT: u16 = 1 << State::InitializationMode as u16;
    pub const STEP_COMPLETE: u16 = 1 << State::StepComplete as u16;
    pub const STEP_FAILED: u16 = 1 << State::StepFailed as u16;
    pub const TERMINATED: u16 = 1 << State::Terminated as u16;
    pub const ERROR: u16 = 1 << State::Error as u16;
    /// Every state of a live instance (Fatal is refused before any mask is looked at).
    pub const ANY: u16 = INSTANTIATED | INIT | STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR;
    /// Where values can be read: everything after initialization started, Error included.
    pub const GET: u16 = INIT | STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR;
    pub const SET: u16 = INSTANTIATED | INIT | STEP_COMPLETE;
    pub const STATUS: u16 = STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR;
}

/// Every fmi2 function that takes an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    SetDebugLogging,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    GetFmuState,
    SetFmuState,
    FreeFmuState,
    SerializedFmuStateSize,
    SerializeFmuState,
    DeserializeFmuState,
    GetDirectionalDerivative,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    GetRealStatus,
    GetIntegerStatus,
    GetBooleanStatus,
    GetStringStatus,
}

impl Call {
    /// Every call, in declaration order.
    pub const ALL: [Call; 30] = [
        Call::SetDebugLogging,
        Call::SetupExperiment,
        Call::EnterInitializationMode,
        Call::ExitInitializationMode,
        Call::Terminate,
        Call::Reset,
        Call::GetReal,
        Call::GetInteger,
        Call::GetBoolean,
        Call::GetString,
        Call::SetReal,
        Call::SetInteger,
        Call::SetBoolean,
        Call::SetString,
        Call::GetFmuState,
        Call::SetFmuState,
        Call::FreeFmuState,
        Call::SerializedFmuStateSize,
        Call::SerializeFmuState,
        Call::DeserializeFmuState,
        Call::GetDirectionalDerivative,
        Call::SetRealInputDerivatives,
        Call::GetRealOutputDerivatives,
        Call::DoStep,
        Call::CancelStep,
        Call::GetStatus,
        Call::GetRealStatus,
        Call::GetIntegerStatus,
        Call::GetBooleanStatus,
        Call::GetStringStatus,
    ];

    /// The table: C name and the states in which the call is allowed (as the Reference-FMUs'
    /// `MASK_fmi2…`; set* additionally follow the causality/variability rules in `Instance::set`).
    pub const fn spec(self) -> (&'static str, u16) {
        use mask::*;
        match self {
            Call::SetDebugLogging => ("fmi2SetDebugLogging", ANY),
            Call::SetupExperiment => ("fmi2SetupExperiment", INSTANTIATED),
            Call::EnterInitializationMode => ("fmi2EnterInitializationMode", INSTANTIATED),
            Call::ExitInitializationMode => ("fmi2ExitInitializationMode", INIT),
            Call::Terminate => ("fmi2Terminate", STEP_COMPLETE | STEP_FAILED),
            Call::Reset => ("fmi2Reset", ANY),
            Call::GetReal => ("fmi2GetReal", GET),
            Call::GetInteger => ("fmi2GetInteger", GET),
            Call::GetBoolean => ("fmi2GetBoolean", GET),
            Call::GetString => ("fmi2GetString", GET),
            Call::SetReal => ("fmi2SetReal", SET),
            Call::SetInteger => ("fmi2SetInteger", SET),
            Call::SetBoolean => ("fmi2SetBoolean", SET),
            Call::SetString => ("fmi2SetString", SET),
            Call::GetFmuState => ("fmi2GetFMUstate", ANY),
            Call::SetFmuState => ("fmi2SetFMUstate", ANY),
            Call::FreeFmuState => ("fmi2FreeFMUstate", ANY),
            Call::SerializedFmuStateSize => ("fmi2SerializedFMUstateSize", ANY),
            Call::SerializeFmuState => ("fmi2SerializeFMUstate", ANY),
            Call::DeserializeFmuState => ("fmi2DeSerializeFMUstate", ANY),
            // The Jacobian at a communication point (the model's states are knowns there).
            Call::GetDirectionalDerivative => (
                "fmi2GetDirectionalDerivative",
                STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR,
            ),
            Call::SetRealInputDerivatives => {
                ("fmi2SetRealInputDerivatives", INSTANTIATED | INIT | STEP_COMPLETE)
            }
            Call::GetRealOutputDerivatives => ("fmi2GetRealOutputDerivatives", STATUS),
            Call::DoStep => ("fmi2DoStep", STEP_COMPLETE),
            // Steps are synchronous: there is never a step in progress to cancel.
            Call::CancelStep => ("fmi2CancelStep", 0),
            Call::GetStatus => ("fmi2GetStatus", STATUS),
            Call::GetRealStatus => ("fmi2GetRealStatus", STATUS),
            Call::GetIntegerStatus => ("fmi2GetIntegerStatus", STATUS),
            Call::GetBooleanStatus => ("fmi2GetBooleanStatus", STATUS),
            Call::GetStringStatus => ("fmi2GetStringStatus", STATUS),
        }
    }

    pub const fn name(self) -> &'static str {
        self.spec().0
    }
}

/// Run `f` on the instance behind `c` if `call` is allowed in its state (BEGIN_FUNCTION); an
/// fmi2Error answer moves the instance to [`State::Error`], a panic to `Fatal` (END_FUNCTION).
/// Fatal is for good (FMI 2.0 §2.1.3: only fmi2FreeInstance may follow): every later call
/// answers fmi2Error with a log line and never reaches the model, whose state a panic may have
/// left half-updated.
///
/// # Safety
/// `c` is NULL or an instance of model `M` from `instantiate`.
pub unsafe fn with<M: Model>(c: Component, call: Call, f: impl FnOnce(&mut Instance<M>) -> Status) -> c_int {
    let (name, allowed) = call.spec();
    guard(c, name, allowed, State::Error, "fmi2FreeInstance", f)
}

/// The state machine of both versions: run `f` on the instance behind `c` if its state is in
/// the mask `allowed`; an Error answer moves the instance to `on_error` (FMI 2: the Error state;
/// FMI 3.0 §2.3.1: Terminated), a panic to Fatal for good (`free` names the one call left).
///
/// # Safety
/// `c` is NULL or an instance of model `M`.
pub unsafe fn guard<M: Model>(
    c: Component,
    name: &str,
    allowed: u16,
    on_error: State,
    free: &str,
    f: impl FnOnce(&mut Instance<M>) -> Status,
) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    let inst = &mut *(c as *mut Instance<M>);
    if inst.state == State::Fatal {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            inst.error(&format!(
                "{name}: the instance failed fatally; only {free} is allowed"
            ))
        }));
        return Status::Error as c_int;
    }
    let result = catch_unwind(AssertUnwindSafe(|| {
        if allowed & (1 << inst.state as u16) == 0 {
            return inst.error(&format!("{name}: not allowed in state {:?}", inst.state));
        }
        f(inst)
    }));
    match result {
        Ok(Status::Error) => {
            inst.state = on_error;
            Status::Error as c_int
        }
        Ok(s) => s as c_int,
        Err(payload) => {
            inst.state = State::Fatal;
            let message = panic_message(payload.as_ref());
            let _ = catch_unwind(AssertUnwindSafe(|| {
                inst.log(
                    Status::Fatal,
                    2,
                    &format!("{name}: internal error (panic: {message}); the instance is unusable, only {free} is allowed"),
                )
            }));
            Status::Fatal as c_int
        }
    }
}

/// The message of a panic (`panic!("…")` carries a `&str` or a `String`).
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "no message"
    }
}

/// A C string as UTF-8 (None for NULL or invalid UTF-8).
///
/// # Safety
/// `p` is NULL or a NUL-terminated string.
pub unsafe fn opt_str<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        CStr::from_ptr(p).to_str().ok()
    }
}

/// Slices behind array arguments; NULL is only allowed with n = 0.
///
/// # Safety
/// `p` is NULL or points to `n` values.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts(p, n))
    }
}

/// # Safety
/// `p` is NULL or points to `n` values.
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts_mut(p, n))
    }
}

/// Functions this FMU does not provide: log and refuse.
///
/// # Safety
/// C ABI.
pub unsafe fn unsupported<M: Model>(c: Component, call: Call) -> c_int {
    with::<M>(c, call, |inst| {
        inst.error(&format!("{} is not supported by this FMU", call.name()))
    })
}

#[cfg(test)]
mod tests {
    use super::{mask, Call};

    #[test]
    fn in_the_error_state_only_get_status_reset_and_fmu_state_calls_are_allowed() {
        use Call::*;
        let all = Call::ALL;
        let allowed: Vec<&str> = all
            .iter()
            .filter(|c| c.spec().1 & mask::ERROR != 0)
            .map(|c| c.name())
            .collect();
        for name in &allowed {
            let ok = name.starts_with("fmi2Get")
                || name.contains("FMUstate")
                || *name == "fmi2Reset"
                || *name == "fmi2SetDebugLogging";
            assert!(ok, "{name} allowed in Error");
        }
        assert!(!allowed.contains(&"fmi2DoStep") && !allowed.contains(&"fmi2Terminate"));
        assert!(allowed.contains(&"fmi2SetFMUstate") && allowed.contains(&"fmi2GetReal"));
        // Set* follow the standard: before initialization ends and in StepComplete only.
        assert_eq!(
            SetReal.spec().1,
            mask::INSTANTIATED | mask::INIT | mask::STEP_COMPLETE
        );
    }
}
