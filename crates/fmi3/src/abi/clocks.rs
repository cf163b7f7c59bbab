//! Clocks and Event Mode. A model's clocks ([`fmi2::ModelInfo::clocks`]) are periodic
//! time-based input clocks of constant interval: activations at t_start + k·interval, each
//! running the clock's model partition up to its time ([`Model::activate`]).
//!
//! - Scheduled Execution: fmi3ActivateModelPartition(clock, t) in Clock Activation Mode (here
//!   `State::StepComplete` of an instance made by fmi3InstantiateScheduledExecution) is the only
//!   way time advances; outputs are read after it.
//! - Co-Simulation with eventModeUsed: fmi3EnterEventMode, fmi3SetClock, fmi3UpdateDiscreteStates
//!   and fmi3EnterStepMode. fmi3DoStep computes every tick inside its step, as without Event Mode,
//!   so activating a clock in Event Mode at a tick finds the partition done up to that time:
//!   outputs are the same whether or not the importer activates it.
//!
//! As the FMI 3.0 standard asks: activation times on the clock's grid and increasing, each clock
//! activated once per time, intervals read as fmi3IntervalUnchanged (constant clocks), no
//! fractions (supportsFraction = false), no output clocks (fmi3GetClock refused).

use super::{mask, with3, Boolean, Instance3, ValueReference};
use crate::View;
use fmi2::abi::lifecycle::time_tolerance;
use fmi2::abi::{slice, slice_mut};
use fmi2::instance::{Instance, State, Status};
use fmi2::Model;
use std::ffi::c_int;

/// fmi3IntervalUnchanged: a constant clock's interval never changes.
pub const INTERVAL_UNCHANGED: c_int = 1;

/// The clocks (indices in the model's list) of `vrs`, or an error naming `f`.
fn clocks_of<M: Model>(
    inst: &Instance<M>,
    view: &View,
    f: &str,
    vrs: &[ValueReference],
) -> Result<Vec<usize>, Status> {
    vrs.iter()
        .map(|&vr| {
            view.clock(vr).ok_or_else(|| {
                let what = view
                    .get(vr)
                    .map_or("unknown".to_string(), |v| format!("'{}' is not a clock", v.name));
                inst.error(&format!("{f}: value reference {vr}: {what}"))
            })
        })
        .collect()
}

/// Run clock `k`'s partition up to `t` (`f`: the calling function, for messages): `t` must be a
/// tick of the clock (t_start + n·interval, within the time tolerance of FMI 2's doStep), not
/// before the instance's time, within the stop time, and the clock not yet activated at `t`.
fn activate_at<M: Model>(inst: &mut Instance<M>, f: &str, k: usize, t: f64) -> Status {
    let clock = &M::info().clocks[k];
    let tol = time_tolerance(t);
    let n = ((t - inst.start_time) / clock.interval).round();
    if !t.is_finite() || n < 0.0 || (inst.start_time + n * clock.interval - t).abs() > tol {
        return inst.error(&format!(
            "{f}: '{}' ticks at {} + k·{} s; {t} is not one of its ticks",
            clock.name, inst.start_time, clock.interval
        ));
    }
    inst.activated_at.resize(M::info().clocks.len(), None);
    if inst.activated_at[k].is_some_and(|a| (a - t).abs() <= tol) {
        return inst.error(&format!("{f}: '{}' was already activated at {t}", clock.name));
    }
    if t < inst.time - tol {
        return inst.error(&format!(
            "{f}: activation times must increase; the instance is at {}, got {t}",
            inst.time
        ));
    }
    if let Some(stop) = inst.stop_time.filter(|&s| t > s + time_tolerance(s)) {
        return inst.error(&format!("{f}: {t} is past the stop time {stop}"));
    }
    let h = t - inst.time;
    if h > tol {
        if let Err(e) = inst.model.activate(k, h) {
            return inst.error(&format!("{f}: {e}"));
        }
        inst.time = t;
    }
    inst.activated_at[k] = Some(t);
    Status::Ok
}

/// fmi3ActivateModelPartition: Scheduled Execution instances, in Clock Activation Mode.
///
/// # Safety
/// C ABI.
pub unsafe fn activate_model_partition<M: Model>(
    view: &'static View,
    c: Instance3,
    clock: ValueReference,
    activation_time: f64,
) -> c_int {
    const F: &str = "fmi3ActivateModelPartition";
    with3::<M>(c, F, mask::STEP, |inst| {
        if !inst.scheduled {
            return inst.error(&format!(
                "{F}: only for Scheduled Execution instances (Co-Simulation: fmi3SetClock in Event Mode)"
            ));
        }
        match clocks_of(inst, view, F, &[clock]) {
            Ok(k) => activate_at(inst, F, k[0], activation_time),
            Err(s) => s,
        }
    })
}

/// fmi3SetClock: in Event Mode of a Co-Simulation instance, an active clock is activated at the
/// instance's time (an inactive one is left as it is).
///
/// # Safety
/// C ABI.
pub unsafe fn set_clock<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n: usize,
    values: *const Boolean,
) -> c_int {
    const F: &str = "fmi3SetClock";
    with3::<M>(c, F, mask::EVENT, |inst| {
        let (Some(vr), Some(values)) = (slice(vr, n), slice(values, n)) else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        let clocks = match clocks_of(inst, view, F, vr) {
            Ok(k) => k,
            Err(s) => return s,
        };
        for (k, &on) in clocks.into_iter().zip(values) {
            let t = inst.time;
            if on != 0 && activate_at(inst, F, k, t) != Status::Ok {
                return Status::Error;
            }
        }
        Status::Ok
    })
}

/// fmi3GetClock: for output clocks, which this FMU does not have.
///
/// # Safety
/// C ABI.
pub unsafe fn get_clock<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n: usize,
) -> c_int {
    const F: &str = "fmi3GetClock";
    with3::<M>(c, F, mask::ANY, |inst| {
        let Some(vr) = slice(vr, n) else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        if let Err(s) = clocks_of(inst, view, F, vr) {
            return s;
        }
        inst.error(&format!(
            "{F}: this FMU has input clocks only (no output clock to read)"
        ))
    })
}

/// The states where intervals and shifts can be read: Initialization Mode, Event Mode, and
/// Clock Activation Mode of Scheduled Execution.
fn may_read_intervals<M: Model>(inst: &Instance<M>, f: &str) -> Result<(), Status> {
    if inst.state == State::StepComplete && !inst.scheduled {
        return Err(inst.error(&format!("{f}: not in Step Mode (Initialization or Event Mode)")));
    }
    Ok(())
}

/// fmi3GetIntervalDecimal: the declared interval, qualifier fmi3IntervalUnchanged.
///
/// # Safety
/// C ABI.
pub unsafe fn get_interval_decimal<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n: usize,
    intervals: *mut f64,
    qualifiers: *mut c_int,
) -> c_int {
    const F: &str = "fmi3GetIntervalDecimal";
    with3::<M>(c, F, mask::INIT | mask::STEP | mask::EVENT, |inst| {
        let (Some(vr), Some(out), Some(q)) =
            (slice(vr, n), slice_mut(intervals, n), slice_mut(qualifiers, n))
        else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        let clocks = match may_read_intervals(inst, F).and_then(|()| clocks_of(inst, view, F, vr)) {
            Ok(k) => k,
            Err(s) => return s,
        };
        for (i, k) in clocks.into_iter().enumerate() {
            out[i] = M::info().clocks[k].interval;
            q[i] = INTERVAL_UNCHANGED;
        }
        Status::Ok
    })
}

/// fmi3GetShiftDecimal: 0 (the first tick at the start time).
///
/// # Safety
/// C ABI.
pub unsafe fn get_shift_decimal<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n: usize,
    shifts: *mut f64,
) -> c_int {
    const F: &str = "fmi3GetShiftDecimal";
    with3::<M>(c, F, mask::INIT | mask::STEP | mask::EVENT, |inst| {
        let (Some(vr), Some(out)) = (slice(vr, n), slice_mut(shifts, n)) else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        match may_read_intervals(inst, F).and_then(|()| clocks_of(inst, view, F, vr)) {
            Ok(k) => {
                out[..k.len()].fill(0.0);
                Status::Ok
            }
            Err(s) => s,
        }
    })
}

/// fmi3EnterEventMode: from Step Mode, Co-Simulation instances made with eventModeUsed.
///
/// # Safety
/// C ABI.
pub unsafe fn enter_event_mode<M: Model>(c: Instance3) -> c_int {
    const F: &str = "fmi3EnterEventMode";
    with3::<M>(c, F, mask::STEP, |inst| {
        if !inst.event_mode_used {
            return inst.error(&format!("{F}: the instance was made with eventModeUsed = false"));
        }
        inst.state = State::EventMode;
        inst.event(F);
        Status::Ok
    })
}

/// fmi3EnterStepMode: from Event Mode.
///
/// # Safety
/// C ABI.
pub unsafe fn enter_step_mode<M: Model>(c: Instance3) -> c_int {
    const F: &str = "fmi3EnterStepMode";
    with3::<M>(c, F, mask::EVENT, |inst| {
        inst.state = State::StepComplete;
        inst.event(F);
        Status::Ok
    })
}

/// fmi3UpdateDiscreteStates: the partitions of the clocks set in this Event Mode ran when they
/// were set, and inputs act from the next step on: nothing left to update, no time event (the
/// clocks' ticks are in the modelDescription), no request to terminate.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn update_discrete_states<M: Model>(
    c: Instance3,
    need_update: *mut Boolean,
    terminate: *mut Boolean,
    nominals_changed: *mut Boolean,
    values_changed: *mut Boolean,
    next_defined: *mut Boolean,
    next_time: *mut f64,
) -> c_int {
    const F: &str = "fmi3UpdateDiscreteStates";
    with3::<M>(c, F, mask::EVENT, |inst| {
        let flags = [
            need_update,
            terminate,
            nominals_changed,
            values_changed,
            next_defined,
        ];
        if flags.iter().any(|p| p.is_null()) || next_time.is_null() {
            return inst.error(&format!("{F}: NULL output argument"));
        }
        for p in flags {
            *p = 0;
        }
        *next_time = 0.0;
        Status::Ok
    })
}
