//! Creation, initialization, stepping (with early return), termination, reset and destruction of
//! an FMI 3 Co-Simulation instance.

use super::{mask, with3, Boolean, Instance3, ValueReference};
use crate::View;
use fmi2::abi::{opt_str, slice};
use fmi2::instance::{Instance, LogMessageFn, Logger, State, Status};
use fmi2::Model;
use std::ffi::{c_char, c_int, c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

/// Report a refusal to the importer's logger before an instance exists.
unsafe fn report(log: Option<LogMessageFn>, env: *mut c_void, msg: &str) {
    let Some(log) = log else { return };
    let text = CString::new(msg.replace('\0', "")).unwrap_or_default();
    log(
        env,
        Status::Error as c_int,
        c"logStatusError".as_ptr(),
        text.as_ptr(),
    );
}

/// A new instance, or NULL with the reason logged: the checks both interfaces share (instance
/// name, instantiation token, resource path).
#[allow(clippy::too_many_arguments)]
unsafe fn new_instance<M: Model>(
    view: &'static View,
    function: &str,
    instance_name: *const c_char,
    token: *const c_char,
    resource_path: *const c_char,
    logging_on: Boolean,
    env: *mut c_void,
    log: Option<LogMessageFn>,
) -> Option<Instance<M>> {
    let name = opt_str(instance_name).unwrap_or("");
    let refuse = |msg: &str| {
        report(log, env, &format!("{function}: {msg}"));
        None
    };
    if name.trim().is_empty() {
        return refuse("missing instance name");
    }
    match opt_str(token) {
        Some(t) if t == view.token => {}
        t => {
            return refuse(&format!(
                "instantiation token {t:?} does not match this FMU's {}",
                view.token
            ))
        }
    }
    // A native path with a trailing separator (FMI 3.0); a file: URI as FMI 2 passes it is
    // accepted too.
    let resources = match opt_str(resource_path) {
        None | Some("") => None,
        Some(uri) if uri.starts_with("file:") => match fmi2::uri::file_uri_to_path(uri) {
            Ok(p) => Some(p),
            Err(e) => return refuse(&e),
        },
        Some(path) => Some(PathBuf::from(path)),
    };
    let logger = log.map(Logger::Fmi3);
    let mut inst = Instance::<M>::new(name, resources, logger, env, logging_on != 0);
    inst.token = &view.token;
    Some(inst)
}

/// fmi3InstantiateCoSimulation: a Co-Simulation instance, with Event Mode when the importer
/// uses it and the model has clocks (hasEventMode; refused otherwise), without intermediate
/// updates (no variable has intermediateUpdate, so requiredIntermediateVariables must be empty).
///
/// # Safety
/// C ABI: pointers as the FMI 3.0 standard defines them.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_co_simulation<M: Model>(
    view: &'static View,
    instance_name: *const c_char,
    token: *const c_char,
    resource_path: *const c_char,
    _visible: Boolean,
    logging_on: Boolean,
    event_mode_used: Boolean,
    early_return_allowed: Boolean,
    _required: *const ValueReference,
    n_required: usize,
    env: *mut c_void,
    log: Option<LogMessageFn>,
    _intermediate_update: *const c_void,
) -> Instance3 {
    const F: &str = "fmi3InstantiateCoSimulation";
    let r = catch_unwind(AssertUnwindSafe(|| {
        if event_mode_used != 0 && M::info().clocks.is_empty() {
            report(
                log,
                env,
                &format!(
                    "{F}: this FMU has no Event Mode (hasEventMode = false): call with eventModeUsed = false"
                ),
            );
            return std::ptr::null_mut();
        }
        if n_required > 0 {
            report(log, env, &format!(
                "{F}: no variable of this FMU has intermediateUpdate: requiredIntermediateVariables must be empty"
            ));
            return std::ptr::null_mut();
        }
        let Some(mut inst) =
            new_instance::<M>(view, F, instance_name, token, resource_path, logging_on, env, log)
        else {
            return std::ptr::null_mut();
        };
        inst.early_return_allowed = early_return_allowed != 0;
        inst.event_mode_used = event_mode_used != 0;
        inst.event(F);
        Box::into_raw(Box::new(inst)) as Instance3
    }));
    r.unwrap_or(std::ptr::null_mut())
}

/// fmi3InstantiateScheduledExecution: an instance whose clocks' model partitions the importer
/// activates (models with clocks; NULL with the reason logged otherwise). The callbacks are not
/// needed: no output or countdown clock to announce (clockUpdate), and one partition, which
/// nothing preempts (lock/unlockPreemption).
///
/// # Safety
/// C ABI: pointers as the FMI 3.0 standard defines them.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_scheduled_execution<M: Model>(
    view: &'static View,
    instance_name: *const c_char,
    token: *const c_char,
    resource_path: *const c_char,
    _visible: Boolean,
    logging_on: Boolean,
    env: *mut c_void,
    log: Option<LogMessageFn>,
) -> Instance3 {
    const F: &str = "fmi3InstantiateScheduledExecution";
    let r = catch_unwind(AssertUnwindSafe(|| {
        if M::info().clocks.is_empty() {
            report(
                log,
                env,
                &format!("{F}: this FMU has no clocks: Co-Simulation only"),
            );
            return std::ptr::null_mut();
        }
        let Some(mut inst) =
            new_instance::<M>(view, F, instance_name, token, resource_path, logging_on, env, log)
        else {
            return std::ptr::null_mut();
        };
        inst.scheduled = true;
        inst.event(F);
        Box::into_raw(Box::new(inst)) as Instance3
    }));
    r.unwrap_or(std::ptr::null_mut())
}

/// fmi3InstantiateModelExchange: NULL, with the reason logged (no Model Exchange interface).
///
/// # Safety
/// C ABI.
pub unsafe fn refuse_interface(function: &str, env: *mut c_void, log: Option<LogMessageFn>) -> Instance3 {
    let msg =
        format!("{function}: this FMU implements Co-Simulation and, with clocks, Scheduled Execution only");
    let _ = catch_unwind(AssertUnwindSafe(|| report(log, env, &msg)));
    std::ptr::null_mut()
}

/// # Safety
/// C ABI.
pub unsafe fn set_debug_logging<M: Model>(
    c: Instance3,
    on: Boolean,
    n: usize,
    cats: *const *const c_char,
) -> c_int {
    with3::<M>(c, "fmi3SetDebugLogging", mask::ANY, |inst| {
        let Some(cats) = slice(cats, n) else {
            return inst.error("fmi3SetDebugLogging: categories is NULL with nCategories > 0");
        };
        let mut names = Vec::with_capacity(n);
        for &p in cats {
            match opt_str(p) {
                Some(s) => names.push(s.to_string()),
                None => return inst.error("fmi3SetDebugLogging: NULL or non-UTF-8 category"),
            }
        }
        inst.set_debug_logging("fmi3SetDebugLogging", on != 0, &names)
    })
}

/// fmi3EnterInitializationMode: start and stop time (fmi2SetupExperiment's part in FMI 2).
///
/// # Safety
/// C ABI.
pub unsafe fn enter_initialization_mode<M: Model>(
    c: Instance3,
    _tol_defined: Boolean,
    _tol: f64,
    start: f64,
    stop_defined: Boolean,
    stop: f64,
) -> c_int {
    with3::<M>(c, "fmi3EnterInitializationMode", mask::INSTANTIATED, |inst| {
        if !start.is_finite() || (stop_defined != 0 && !(stop.is_finite() && stop >= start)) {
            return inst.error(&format!(
                "fmi3EnterInitializationMode: bad start {start} / stop {stop}"
            ));
        }
        inst.time = start;
        inst.start_time = start;
        inst.stop_time = (stop_defined != 0).then_some(stop);
        inst.state = State::InitializationMode;
        inst.event("fmi3EnterInitializationMode");
        Status::Ok
    })
}

/// fmi3ExitInitializationMode: to Event Mode (Co-Simulation with eventModeUsed), else to Step
/// Mode (Clock Activation Mode in Scheduled Execution). An instance that activates clocks first
/// checks that the parameters in force keep each clock's declared interval.
///
/// # Safety
/// C ABI.
pub unsafe fn exit_initialization_mode<M: Model>(c: Instance3) -> c_int {
    const F: &str = "fmi3ExitInitializationMode";
    with3::<M>(c, F, mask::INIT, |inst| {
        if let Err(e) = inst.model.exit_initialization() {
            return inst.error(&e);
        }
        if inst.scheduled || inst.event_mode_used {
            for (k, clock) in M::info().clocks.iter().enumerate() {
                if let Err(e) = inst.model.check_clock(k, clock.interval) {
                    return inst.error(&format!("{F}: clock '{}': {e}", clock.name));
                }
            }
        }
        inst.state = if inst.event_mode_used {
            State::EventMode
        } else {
            State::StepComplete
        };
        inst.event(F);
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn terminate<M: Model>(c: Instance3) -> c_int {
    with3::<M>(c, "fmi3Terminate", mask::RUNNING, |inst| {
        inst.state = State::Terminated;
        inst.event("fmi3Terminate");
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn reset<M: Model>(c: Instance3) -> c_int {
    with3::<M>(c, "fmi3Reset", mask::ANY, |inst| {
        fmi2::abi::reset_instance(inst, "fmi3Reset")
    })
}

/// fmi3DoStep: the step of fmi2DoStep (the same checks and model call, so both versions give the
/// same outputs); when the importer allows early return, the model may stop at an event inside
/// the step (`earlyReturn`, `lastSuccessfulTime` the time reached). Every clock tick inside the
/// step is computed here, as without Event Mode: no event to handle (`eventHandlingNeeded`
/// false), and the FMU never asks to terminate. Refused for Scheduled Execution instances.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn do_step<M: Model>(
    c: Instance3,
    t: f64,
    h: f64,
    _no_prior: Boolean,
    event_handling_needed: *mut Boolean,
    terminate_simulation: *mut Boolean,
    early_return: *mut Boolean,
    last_successful_time: *mut f64,
) -> c_int {
    with3::<M>(c, "fmi3DoStep", mask::STEP, |inst| {
        let outs = [event_handling_needed, terminate_simulation, early_return];
        if outs.iter().any(|p| p.is_null()) || last_successful_time.is_null() {
            return inst.error("fmi3DoStep: NULL output argument");
        }
        if inst.scheduled {
            return inst
                .error("fmi3DoStep: a Scheduled Execution instance advances by fmi3ActivateModelPartition");
        }
        let early = inst.early_return_allowed;
        let status = match fmi2::abi::step(inst, "fmi3DoStep", t, h, early) {
            Ok(dt) => {
                *event_handling_needed = 0;
                *terminate_simulation = 0;
                *early_return = Boolean::from(dt < h);
                *last_successful_time = inst.time;
                Status::Ok
            }
            Err(s) => s,
        };
        inst.last_step = status;
        status
    })
}
