//! FMU states (get/set/free, serialize) and the status inquiries fmi2Get*Status.

use super::{slice, with, Boolean, Call, Component, FmuState};
use crate::instance::{Instance, Snapshot, State, Status};
use crate::Model;
use std::ffi::{c_char, c_int};

/// fmi2StatusKind.
pub const DO_STEP_STATUS: c_int = 0;
pub const PENDING_STATUS: c_int = 1;
pub const LAST_SUCCESSFUL_TIME: c_int = 2;
pub const TERMINATED: c_int = 3;

/// Store `snap` in the importer's state `*state` if it is one of ours, else in a new one.
unsafe fn hand_out<M: Model>(inst: &mut Instance<M>, state: *mut FmuState, snap: Snapshot<M>) {
    if !(*state).is_null() && inst.snapshots.contains(&(*state as usize)) {
        *(*state as *mut Snapshot<M>) = snap;
    } else {
        let p = Box::into_raw(Box::new(snap)) as usize;
        inst.snapshots.push(p);
        *state = p as FmuState;
    }
}

/// The snapshot behind an FMU state of this instance.
unsafe fn ours<'a, M: Model>(inst: &Instance<M>, state: FmuState) -> Option<&'a Snapshot<M>> {
    (!state.is_null() && inst.snapshots.contains(&(state as usize))).then(|| &*(state as *const Snapshot<M>))
}

// The FMU-state functions of both versions on an instance (`f`: the C name, for messages).

/// fmi2GetFMUstate / fmi3GetFMUState.
///
/// # Safety
/// `state` is NULL or the importer's FMU-state pointer.
pub unsafe fn get_state_of<M: Model>(inst: &mut Instance<M>, f: &str, state: *mut FmuState) -> Status {
    if state.is_null() {
        return inst.error(&format!("{f}: FMUstate pointer is NULL"));
    }
    let snap = inst.snapshot();
    hand_out(inst, state, snap);
    Status::Ok
}

/// fmi2SetFMUstate / fmi3SetFMUState.
///
/// # Safety
/// `state` is any pointer the importer passes.
pub unsafe fn set_state_of<M: Model>(inst: &mut Instance<M>, f: &str, state: FmuState) -> Status {
    match ours(inst, state) {
        Some(snap) => {
            inst.restore(snap);
            Status::Ok
        }
        None => inst.error(&format!("{f}: not an FMU state of this instance")),
    }
}

/// fmi2FreeFMUstate / fmi3FreeFMUState.
///
/// # Safety
/// `state` is NULL or the importer's FMU-state pointer.
pub unsafe fn free_state_of<M: Model>(inst: &mut Instance<M>, f: &str, state: *mut FmuState) -> Status {
    if state.is_null() || (*state).is_null() {
        return Status::Ok;
    }
    let p = *state as usize;
    let Some(k) = inst.snapshots.iter().position(|&q| q == p) else {
        return inst.error(&format!("{f}: not an FMU state of this instance"));
    };
    inst.snapshots.swap_remove(k);
    drop(Box::from_raw(p as *mut Snapshot<M>));
    *state = std::ptr::null_mut();
    Status::Ok
}

/// fmi2SerializedFMUstateSize / fmi3SerializedFMUStateSize.
///
/// # Safety
/// `size` is NULL or writable.
pub unsafe fn state_size_of<M: Model>(
    inst: &mut Instance<M>,
    f: &str,
    state: FmuState,
    size: *mut usize,
) -> Status {
    match ours(inst, state) {
        Some(snap) if !size.is_null() => {
            *size = inst.serialize(snap).len();
            Status::Ok
        }
        _ => inst.error(&format!("{f}: bad FMU state or NULL size")),
    }
}

/// fmi2SerializeFMUstate / fmi3SerializeFMUState.
///
/// # Safety
/// `out` is NULL or `size` writable bytes.
pub unsafe fn serialize_of<M: Model>(
    inst: &mut Instance<M>,
    f: &str,
    state: FmuState,
    out: *mut u8,
    size: usize,
) -> Status {
    let Some(snap) = ours(inst, state).filter(|_| !out.is_null()) else {
        return inst.error(&format!("{f}: bad FMU state or NULL buffer"));
    };
    let bytes = inst.serialize(snap);
    if bytes.len() != size {
        return inst.error(&format!("{f}: size {size}, the state needs {}", bytes.len()));
    }
    std::ptr::copy_nonoverlapping(bytes.as_ptr(), out, size);
    Status::Ok
}

/// fmi2DeSerializeFMUstate / fmi3DeserializeFMUState.
///
/// # Safety
/// `bytes` is NULL or `size` readable bytes; `state` NULL or the importer's FMU-state pointer.
pub unsafe fn deserialize_of<M: Model>(
    inst: &mut Instance<M>,
    f: &str,
    bytes: *const u8,
    size: usize,
    state: *mut FmuState,
) -> Status {
    let (Some(bytes), false) = (slice(bytes, size), state.is_null()) else {
        return inst.error(&format!("{f}: NULL argument"));
    };
    match inst.deserialize(bytes) {
        Ok(snap) => {
            hand_out(inst, state, snap);
            Status::Ok
        }
        Err(e) => inst.error(&format!("{f}: {e}")),
    }
}

/// # Safety
/// C ABI.
pub unsafe fn get_fmu_state<M: Model>(c: Component, state: *mut FmuState) -> c_int {
    with::<M>(c, Call::GetFmuState, |inst| {
        get_state_of(inst, "fmi2GetFMUstate", state)
    })
}

/// # Safety
/// C ABI.
pub unsafe fn set_fmu_state<M: Model>(c: Component, state: FmuState) -> c_int {
    with::<M>(c, Call::SetFmuState, |inst| {
        set_state_of(inst, "fmi2SetFMUstate", state)
    })
}

/// # Safety
/// C ABI.
pub unsafe fn free_fmu_state<M: Model>(c: Component, state: *mut FmuState) -> c_int {
    with::<M>(c, Call::FreeFmuState, |inst| {
        free_state_of(inst, "fmi2FreeFMUstate", state)
    })
}

/// # Safety
/// C ABI.
pub unsafe fn serialized_fmu_state_size<M: Model>(c: Component, state: FmuState, size: *mut usize) -> c_int {
    with::<M>(c, Call::SerializedFmuStateSize, |inst| {
        state_size_of(inst, "fmi2SerializedFMUstateSize", state, size)
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
    with::<M>(c, Call::SerializeFmuState, |inst| {
        serialize_of(inst, "fmi2SerializeFMUstate", state, out, size)
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
    with::<M>(c, Call::DeserializeFmuState, |inst| {
        deserialize_of(inst, "fmi2DeSerializeFMUstate", bytes, size, state)
    })
}

/// fmi2GetStatus: fmi2DoStepStatus is the status of the last fmi2DoStep (steps are synchronous,
/// never Pending); other kinds are not available (fmi2Discard).
///
/// # Safety
/// C ABI.
pub unsafe fn get_status<M: Model>(c: Component, kind: c_int, out: *mut c_int) -> c_int {
    with::<M>(c, Call::GetStatus, |inst| {
        if out.is_null() {
            return inst.error("fmi2GetStatus: NULL value");
        }
        if kind != DO_STEP_STATUS {
            return Status::Discard;
        }
        *out = inst.last_step as c_int;
        Status::Ok
    })
}

/// fmi2GetRealStatus: fmi2LastSuccessfulTime is the time the last successful step reached.
///
/// # Safety
/// C ABI.
pub unsafe fn get_real_status<M: Model>(c: Component, kind: c_int, out: *mut f64) -> c_int {
    with::<M>(c, Call::GetRealStatus, |inst| {
        if out.is_null() {
            return inst.error("fmi2GetRealStatus: NULL value");
        }
        if kind != LAST_SUCCESSFUL_TIME {
            return Status::Discard;
        }
        *out = inst.time;
        Status::Ok
    })
}

/// fmi2GetBooleanStatus: fmi2Terminated is true once the simulation cannot go on (after
/// fmi2Terminate or an fmi2Error).
///
/// # Safety
/// C ABI.
pub unsafe fn get_boolean_status<M: Model>(c: Component, kind: c_int, out: *mut Boolean) -> c_int {
    with::<M>(c, Call::GetBooleanStatus, |inst| {
        if out.is_null() {
            return inst.error("fmi2GetBooleanStatus: NULL value");
        }
        if kind != TERMINATED {
            return Status::Discard;
        }
        *out = Boolean::from(matches!(inst.state, State::Terminated | State::Error));
        Status::Ok
    })
}

/// fmi2GetIntegerStatus: no integer status kinds exist for Co-Simulation (fmi2Discard).
///
/// # Safety
/// C ABI.
pub unsafe fn get_integer_status<M: Model>(c: Component, _kind: c_int, out: *mut c_int) -> c_int {
    with::<M>(c, Call::GetIntegerStatus, |inst| {
        if out.is_null() {
            return inst.error("fmi2GetIntegerStatus: NULL value");
        }
        Status::Discard
    })
}

/// fmi2GetStringStatus: fmi2PendingStatus only exists while a step is pending, which never
/// happens here (fmi2Discard).
///
/// # Safety
/// C ABI.
pub unsafe fn get_string_status<M: Model>(c: Component, _kind: c_int, out: *mut *const c_char) -> c_int {
    with::<M>(c, Call::GetStringStatus, |inst| {
        if out.is_null() {
            return inst.error("fmi2GetStringStatus: NULL value");
        }
        Status::Discard
    })
}
