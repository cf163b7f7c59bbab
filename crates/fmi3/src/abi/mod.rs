//! The fmi3 C functions, generic over the model, on the same instance and state machine as fmi2
//! ([`fmi2::abi::guard`]): [`lifecycle`] (instantiate … doStep … free), [`values`] (get/set of
//! every FMI 3 type, arrays serialized element by element), [`derivatives`] (output, directional
//! and adjoint derivatives), [`state`] (FMU states), [`clocks`] (Event Mode, clock activation in
//! Co-Simulation and Scheduled Execution, intervals) and the calls this FMU refuses
//! ([`unsupported`]). The `#[no_mangle]` symbols are in [`crate::export_fmi3!`].
//!
//! As the Modelica Reference-FMUs: every function checks the instance's state against its mask
//! ([`mask`]); a call in a wrong state, a bad value reference, a refused value, a wrong
//! communication point or a step past the stop time answers fmi3Error with a log line and moves
//! the instance to Terminated (FMI 3.0 §2.3.1), where values, output and partial derivatives can
//! still be read and fmi3Reset or an FMU state brings it back; a panic is fmi3Fatal for good.

pub mod clocks;
pub mod derivatives;
pub mod lifecycle;
pub mod state;
pub mod values;

pub use clocks::*;
pub use derivatives::*;
pub use lifecycle::*;
pub use state::*;
pub use values::*;

use crate::View;
use fmi2::instance::{Instance, State, Status};
use fmi2::Model;
use std::ffi::{c_int, c_void, CStr};

pub type Instance3 = *mut c_void;
pub type FmuState = *mut c_void;
pub type ValueReference = u32;
/// fmi3Boolean is C's `bool`: read as a byte (any non-zero byte is true), written as 0 or 1.
pub type Boolean = u8;

pub static VERSION: &CStr = c"3.0";

/// Bit masks of the states of an FMI 3 instance: Instantiated, Initialization Mode, Step Mode
/// (`State::StepComplete`; Clock Activation Mode of a Scheduled Execution instance), Event Mode
/// (Co-Simulation with eventModeUsed), Terminated (also after an error).
pub mod mask {
    use fmi2::instance::State;
    pub const INSTANTIATED: u16 = 1 << State::Instantiated as u16;
    pub const INIT: u16 = 1 << State::InitializationMode as u16;
    pub const STEP: u16 = 1 << State::StepComplete as u16;
    pub const EVENT: u16 = 1 << State::EventMode as u16;
    pub const TERMINATED: u16 = 1 << State::Terminated as u16;
    pub const ANY: u16 = INSTANTIATED | INIT | STEP | EVENT | TERMINATED;
    /// fmi3Get{VariableType}: Initialization Mode, Step Mode, Event Mode, Terminated (FMI 3.0
    /// §2.3).
    pub const GET: u16 = INIT | STEP | EVENT | TERMINATED;
    /// fmi3Set{VariableType}: Instantiated, Initialization Mode, Step Mode, Event Mode (the
    /// variables each state allows: `Instance::set_at`).
    pub const SET: u16 = INSTANTIATED | INIT | STEP | EVENT;
    /// Output derivatives: at communication points (Step Mode) and after the end.
    pub const DERIVATIVES: u16 = STEP | TERMINATED;
    /// Directional and adjoint derivatives: also in Event Mode (the Jacobian at that instant;
    /// not in Initialization Mode).
    pub const PARTIALS: u16 = STEP | EVENT | TERMINATED;
    /// fmi3Terminate: from Step Mode (Clock Activation Mode) or Event Mode.
    pub const RUNNING: u16 = STEP | EVENT;
}

/// Run `f` on the instance if its state is in `allowed` (the fmi2 state machine; an fmi3Error
/// moves the instance to Terminated).
///
/// # Safety
/// `c` is NULL or an instance of `M` from fmi3InstantiateCoSimulation.
pub unsafe fn with3<M: Model>(
    c: Instance3,
    name: &str,
    allowed: u16,
    f: impl FnOnce(&mut Instance<M>) -> Status,
) -> c_int {
    fmi2::abi::guard(c, name, allowed, State::Terminated, "fmi3FreeInstance", f)
}

/// A function this FMU does not provide (Model Exchange, structural parameters, binary values,
/// per-element dependencies, fractional clock intervals, …): log and refuse.
///
/// # Safety
/// C ABI.
pub unsafe fn unsupported<M: Model>(c: Instance3, name: &str, why: &str) -> c_int {
    with3::<M>(c, name, mask::ANY, |inst| {
        inst.error(&format!("{name} is not supported by this FMU ({why})"))
    })
}

/// The variable of `vr`, or an error naming `f`.
pub(crate) fn var<'a, M: Model>(
    inst: &Instance<M>,
    view: &'a View,
    f: &str,
    vr: ValueReference,
) -> Result<&'a crate::Var, Status> {
    view.get(vr)
        .ok_or_else(|| inst.error(&format!("{f}: unknown value reference {vr}")))
}

/// The table indices of the values of `vrs`, serialized (an array's elements in order).
pub(crate) fn elements<M: Model>(
    inst: &Instance<M>,
    view: &View,
    f: &str,
    vrs: &[ValueReference],
) -> Result<Vec<usize>, Status> {
    let mut out = Vec::new();
    for &vr in vrs {
        let v = var(inst, view, f, vr)?;
        if v.elements.is_empty() {
            return Err(inst.error(&format!("{f}: '{}' has no derivatives", v.name)));
        }
        out.extend_from_slice(&v.elements);
    }
    Ok(out)
}
