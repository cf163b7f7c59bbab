//! FMU states of an FMI 3 instance: the FMI 2 functions' work (fmi2::abi::state) under the FMI 3
//! names; serialized states carry the instantiation token, so an FMI 2 state is refused here.

use super::{mask, with3, FmuState, Instance3};
use fmi2::abi::{deserialize_of, free_state_of, get_state_of, serialize_of, set_state_of, state_size_of};
use fmi2::Model;
use std::ffi::c_int;

/// # Safety
/// C ABI.
pub unsafe fn get_fmu_state<M: Model>(c: Instance3, state: *mut FmuState) -> c_int {
    let f = "fmi3GetFMUState";
    with3::<M>(c, f, mask::ANY, |inst| get_state_of(inst, f, state))
}

/// # Safety
/// C ABI.
pub unsafe fn set_fmu_state<M: Model>(c: Instance3, state: FmuState) -> c_int {
    let f = "fmi3SetFMUState";
    with3::<M>(c, f, mask::ANY, |inst| set_state_of(inst, f, state))
}

/// # Safety
/// C ABI.
pub unsafe fn free_fmu_state<M: Model>(c: Instance3, state: *mut FmuState) -> c_int {
    let f = "fmi3FreeFMUState";
    with3::<M>(c, f, mask::ANY, |inst| free_state_of(inst, f, state))
}

/// # Safety
/// C ABI.
pub unsafe fn serialized_fmu_state_size<M: Model>(c: Instance3, state: FmuState, size: *mut usize) -> c_int {
    let f = "fmi3SerializedFMUStateSize";
    with3::<M>(c, f, mask::ANY, |inst| state_size_of(inst, f, state, size))
}

/// # Safety
/// C ABI.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: Instance3,
    state: FmuState,
    out: *mut u8,
    size: usize,
) -> c_int {
    let f = "fmi3SerializeFMUState";
    with3::<M>(c, f, mask::ANY, |inst| serialize_of(inst, f, state, out, size))
}

/// # Safety
/// C ABI.
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: Instance3,
    bytes: *const u8,
    size: usize,
    state: *mut FmuState,
) -> c_int {
    let f = "fmi3DeserializeFMUState";
    with3::<M>(c, f, mask::ANY, |inst| {
        deserialize_of(inst, f, bytes, size, state)
    })
}
