//! The coupling aids: output derivatives (fmi2GetRealOutputDerivatives), input derivatives
//! (fmi2SetRealInputDerivatives, `canInterpolateInputs`) and directional derivatives
//! (fmi2GetDirectionalDerivative), each refused with a log line where the model does not declare
//! the capability. The checks on an instance are shared with FMI 3 (crates/fmi3).

use super::{slice, slice_mut, with, Call, Component, ValueReference};
use crate::instance::{Instance, Status};
use crate::{Causality, Model, Type, Variability};
use std::ffi::c_int;

/// Derivative `order` of output `i` (table index): a Real output and 1 ≤ order ≤
/// maxOutputDerivativeOrder, else an error naming `f`; None where the model does not know it.
pub fn output_derivative_of<M: Model>(
    inst: &Instance<M>,
    f: &str,
    i: usize,
    order: i64,
) -> Result<Option<f64>, Status> {
    let info = M::info();
    let (v, max) = (&info.variables[i], info.capabilities.max_output_derivative_order);
    if max == 0 {
        return Err(inst.error(&format!("{f}: this FMU provides no output derivatives")));
    }
    if v.causality != Causality::Output || v.kind != Type::Real {
        return Err(inst.error(&format!("{f}: '{}' is not a Real output", v.name)));
    }
    if !(1..=i64::from(max)).contains(&order) {
        return Err(inst.error(&format!(
            "{f}: order {order} of '{}' is not 1 … {max} (maxOutputDerivativeOrder)",
            v.name
        )));
    }
    Ok(inst.model.output_derivative(i, order as u32))
}

/// The answer of an output-derivative call that met derivatives the model does not know (`unknown`:
/// "name (order k)"): they were returned as 0, and the call answers a Warning that names them.
pub fn unknown_derivatives<M: Model>(inst: &Instance<M>, f: &str, unknown: &[String]) -> Status {
    if unknown.is_empty() {
        return Status::Ok;
    }
    let list = unknown.join(", ");
    inst.log(
        Status::Warning,
        1,
        &format!("{f}: not known, returned as 0: {list}"),
    );
    Status::Warning
}

/// Set derivative `order` of continuous Real input `i` (FMI 2 only: FMI 3 has no input
/// derivatives).
pub fn set_input_derivative_of<M: Model>(
    inst: &mut Instance<M>,
    f: &str,
    i: usize,
    order: i64,
    value: f64,
) -> Result<(), Status> {
    let info = M::info();
    let (v, max) = (&info.variables[i], info.capabilities.max_input_derivative_order);
    if max == 0 {
        return Err(inst.error(&format!("{f}: this FMU cannot interpolate inputs")));
    }
    let continuous = v.causality == Causality::Input && v.variability == Variability::Continuous;
    if !continuous || v.kind != Type::Real {
        return Err(inst.error(&format!("{f}: '{}' is not a continuous Real input", v.name)));
    }
    if !(1..=i64::from(max)).contains(&order) {
        return Err(inst.error(&format!("{f}: order {order} of '{}' is not 1 … {max}", v.name)));
    }
    if !value.is_finite() {
        return Err(inst.error(&format!(
            "{f}: derivative of '{}' = {value} is not finite",
            v.name
        )));
    }
    inst.model
        .set_input_derivative(i, order as u32, value)
        .map_err(|e| inst.error(&format!("{f}: '{}': {e}", v.name)))
}

/// The Jacobian J[i][j] = ∂unknowns[i]/∂knowns[j] (table indices), after checking that each
/// unknown is an output or a state derivative and each known a continuous input or a state.
pub fn jacobian_of<M: Model>(
    inst: &Instance<M>,
    f: &str,
    unknowns: &[usize],
    knowns: &[usize],
) -> Result<Vec<Vec<f64>>, Status> {
    let info = M::info();
    if !info.capabilities.provides_directional_derivative {
        return Err(inst.error(&format!("{f}: this FMU provides no directional derivatives")));
    }
    if let Some(&u) = unknowns.iter().find(|&&u| !info.is_unknown(u)) {
        let name = &info.variables[u].name;
        return Err(inst.error(&format!(
            "{f}: '{name}' is neither an output nor a state derivative"
        )));
    }
    if let Some(&k) = knowns.iter().find(|&&k| !info.is_known(k)) {
        let name = &info.variables[k].name;
        return Err(inst.error(&format!(
            "{f}: '{name}' is neither a continuous input nor a state"
        )));
    }
    Ok(unknowns
        .iter()
        .map(|&u| {
            knowns
                .iter()
                .map(|&k| inst.model.partial_derivative(u, k))
                .collect()
        })
        .collect())
}

/// Table indices of Real value references (errors logged by the lookup).
fn indices<M: Model>(inst: &Instance<M>, f: &str, vrs: &[ValueReference]) -> Result<Vec<usize>, Status> {
    vrs.iter().map(|&r| inst.lookup(f, r, Type::Real)).collect()
}

/// # Safety
/// C ABI.
pub unsafe fn get_real_output_derivatives<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    order: *const c_int,
    value: *mut f64,
) -> c_int {
    with::<M>(c, Call::GetRealOutputDerivatives, |inst| {
        let f = "fmi2GetRealOutputDerivatives";
        let (Some(vr), Some(order), Some(value)) = (slice(vr, n), slice(order, n), slice_mut(value, n))
        else {
            return inst.error(&format!("{f}: NULL array with nvr > 0"));
        };
        let idx = match indices(inst, f, vr) {
            Ok(i) => i,
            Err(s) => return s,
        };
        let mut unknown = Vec::new();
        for ((&i, &k), out) in idx.iter().zip(order).zip(value.iter_mut()) {
            *out = match output_derivative_of(inst, f, i, i64::from(k)) {
                Ok(Some(d)) => d,
                Ok(None) => {
                    unknown.push(format!("{} (order {k})", M::info().variables[i].name));
                    0.0
                }
                Err(s) => return s,
            };
        }
        unknown_derivatives(inst, f, &unknown)
    })
}

/// # Safety
/// C ABI.
pub unsafe fn set_real_input_derivatives<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    order: *const c_int,
    value: *const f64,
) -> c_int {
    with::<M>(c, Call::SetRealInputDerivatives, |inst| {
        let f = "fmi2SetRealInputDerivatives";
        let (Some(vr), Some(order), Some(value)) = (slice(vr, n), slice(order, n), slice(value, n)) else {
            return inst.error(&format!("{f}: NULL array with nvr > 0"));
        };
        let idx = match indices(inst, f, vr) {
            Ok(i) => i,
            Err(s) => return s,
        };
        for ((&i, &k), &x) in idx.iter().zip(order).zip(value) {
            if let Err(s) = set_input_derivative_of(inst, f, i, i64::from(k), x) {
                return s;
            }
        }
        Status::Ok
    })
}

/// dvUnknown = J · dvKnown with J = ∂unknowns/∂knowns at the communication point.
///
/// # Safety
/// C ABI.
pub unsafe fn get_directional_derivative<M: Model>(
    c: Component,
    unknown: *const ValueReference,
    n_unknown: usize,
    known: *const ValueReference,
    n_known: usize,
    dv_known: *const f64,
    dv_unknown: *mut f64,
) -> c_int {
    with::<M>(c, Call::GetDirectionalDerivative, |inst| {
        let f = "fmi2GetDirectionalDerivative";
        let (Some(u), Some(k)) = (slice(unknown, n_unknown), slice(known, n_known)) else {
            return inst.error(&format!("{f}: NULL array with a length > 0"));
        };
        let (Some(seed), Some(out)) = (slice(dv_known, n_known), slice_mut(dv_unknown, n_unknown)) else {
            return inst.error(&format!("{f}: NULL array with a length > 0"));
        };
        let j = match indices(inst, f, u)
            .and_then(|u| indices(inst, f, k).map(|k| (u, k)))
            .and_then(|(u, k)| jacobian_of(inst, f, &u, &k))
        {
            Ok(j) => j,
            Err(s) => return s,
        };
        for (row, o) in j.iter().zip(out.iter_mut()) {
            *o = row.iter().zip(seed).map(|(a, b)| a * b).sum();
        }
        Status::Ok
    })
}
