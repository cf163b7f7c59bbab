//! Creation, initialization, stepping, termination, reset and destruction of an instance.

use super::{opt_str, slice, with, Boolean, Call, CallbackFunctions, Component};
use crate::instance::{Instance, Snapshot, State, Status};
use crate::Model;
use std::ffi::{c_char, c_int, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Tolerance on times given by the master: `|t − t_slave| ≤ 1 µs + 1e-9·|t|`. Masters that
/// accumulate the time in floating point (Ecos adds h every step; libcosim rounds to integer
/// nanoseconds) drift by far less (1e-18 … 1e-9 s), while 1 µs is a thousandth of the default
/// interpolation period, so a master that really skips or repeats time is still refused. The
/// same tolerance lets a last step end at stopTime from an accumulated time.
pub fn time_tolerance(t: f64) -> f64 {
    1e-6 + 1e-9 * t.abs()
}

/// Report a refusal to the importer's logger before an instance exists.
///
/// # Safety
/// `functions` is NULL or the importer's callbacks.
pub unsafe fn report(functions: *const CallbackFunctions, name: &str, msg: &str) {
    let Some(f) = functions.as_ref() else { return };
    let Some(logger) = f.logger else { return };
    let text = CString::new(msg.replace('\0', "").replace('%', "%%")).unwrap_or_default();
    let n = CString::new(name.replace('\0', "")).unwrap_or_default();
    logger(
        f.component_environment,
        n.as_ptr(),
        Status::Error as c_int,
        c"logStatusError".as_ptr(),
        text.as_ptr(),
    );
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
        let name = opt_str(instance_name).unwrap_or("");
        let refuse = |msg: &str| {
            report(functions, name, &format!("fmi2Instantiate: {msg}"));
            std::ptr::null_mut()
        };
        if name.is_empty() {
            return refuse("missing instance name");
        }
        if fmu_type != 1 {
            return refuse("this FMU supports Co-Simulation only (fmi2CoSimulation)");
        }
        let info = M::info();
        match opt_str(guid) {
            Some(g) if g == info.guid => {}
            g => return refuse(&format!("GUID {g:?} does not match this FMU's {}", info.guid)),
        }
        let resources = match opt_str(resource_location) {
            None | Some("") => None,
            Some(uri) => match crate::uri::file_uri_to_path(uri) {
                Ok(p) => Some(p),
                Err(e) => return refuse(&e),
            },
        };
        let (logger, env) = match functions.as_ref() {
            Some(f) => (f.logger.map(super::Logger::Fmi2), f.component_environment),
            None => (None, std::ptr::null_mut()),
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
    with::<M>(c, Call::SetDebugLogging, |inst| {
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
        inst.set_debug_logging("fmi2SetDebugLogging", on != 0, &names)
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
    with::<M>(c, Call::SetupExperiment, |inst| {
        if !start.is_finite() || (stop_defined != 0 && !(stop.is_finite() && stop >= start)) {
            return inst.error(&format!("fmi2SetupExperiment: bad start {start} / stop {stop}"));
        }
        inst.time = start;
        inst.start_time = start;
        inst.stop_time = (stop_defined != 0).then_some(stop);
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn enter_initialization_mode<M: Model>(c: Component) -> c_int {
    with::<M>(c, Call::EnterInitializationMode, |inst| {
        inst.state = State::InitializationMode;
        inst.event("fmi2EnterInitializationMode");
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn exit_initialization_mode<M: Model>(c: Component) -> c_int {
    with::<M>(c, Call::ExitInitializationMode, |inst| {
        match inst.model.exit_initialization() {
            Ok(()) => {
                inst.state = State::StepComplete;
                inst.event("fmi2ExitInitializationMode");
                Status::Ok
            }
            Err(e) => inst.error(&e),
        }
    })
}

/// # Safety
/// C ABI.
pub unsafe fn terminate<M: Model>(c: Component) -> c_int {
    with::<M>(c, Call::Terminate, |inst| {
        inst.state = State::Terminated;
        inst.event("fmi2Terminate");
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn reset<M: Model>(c: Component) -> c_int {
    with::<M>(c, Call::Reset, |inst| reset_instance(inst, "fmi2Reset"))
}

/// The instance as just instantiated (fmi2Reset, fmi3Reset).
pub fn reset_instance<M: Model>(inst: &mut Instance<M>, function: &str) -> Status {
    inst.model = M::new(inst.resources.as_deref());
    inst.state = State::Instantiated;
    inst.time = 0.0;
    inst.start_time = 0.0;
    inst.stop_time = None;
    inst.activated_at.clear();
    inst.last_step = Status::Ok;
    inst.event(function);
    Status::Ok
}

/// # Safety
/// C ABI.
pub unsafe fn do_step<M: Model>(c: Component, t: f64, h: f64, _no_prior: Boolean) -> c_int {
    with::<M>(c, Call::DoStep, |inst| {
        let status = match step(inst, "fmi2DoStep", t, h, false) {
            Ok(_) => Status::Ok,
            Err(s) => s,
        };
        inst.last_step = status;
        status
    })
}

/// One communication step from `t` by `h` (fmi2DoStep, fmi3DoStep: `function`), the arguments
/// checked first; with `early` the model may stop earlier ([`Model::do_step_early`]). The time
/// advanced, or the error status (logged).
pub fn step<M: Model>(
    inst: &mut Instance<M>,
    function: &str,
    t: f64,
    h: f64,
    early: bool,
) -> Result<f64, Status> {
    if !t.is_finite() {
        return Err(inst.error(&format!(
            "{function}: currentCommunicationPoint must be finite, got {t}"
        )));
    }
    if !(h > 0.0 && h.is_finite()) {
        return Err(inst.error(&format!("{function}: communicationStepSize must be > 0, got {h}")));
    }
    if (t - inst.time).abs() > time_tolerance(inst.time) {
        return Err(inst.error(&format!(
            "{function}: currentCommunicationPoint {t} is not the slave's time {}",
            inst.time
        )));
    }
    if let Some(stop) = inst.stop_time {
        if t + h > stop + time_tolerance(stop) {
            return Err(inst.error(&format!(
                "{function}: step to {} goes past the stop time {stop}",
                t + h
            )));
        }
    }
    let done = if early {
        inst.model.do_step_early(h)
    } else {
        inst.model.do_step(h).map(|()| h)
    };
    match done {
        // A full step ends at t + h exactly as the importer computes it.
        Ok(dt) if dt >= h => {
            inst.time = t + h;
            Ok(h)
        }
        Ok(dt) => {
            inst.time = t + dt;
            Ok(dt)
        }
        Err(e) => Err(inst.error(&format!("{function}: {e}"))),
    }
}
