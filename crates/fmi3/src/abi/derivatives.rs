//! fmi3GetOutputDerivatives, fmi3GetDirectionalDerivative and fmi3GetAdjointDerivative: the checks
//! and the model's answers of the FMI 2 functions (fmi2::abi::derivatives), on serialized arrays.

use super::{elements, mask, var, with3, Instance3, ValueReference};
use crate::View;
use fmi2::abi::{jacobian_of, output_derivative_of, slice, slice_mut, unknown_derivatives};
use fmi2::instance::Status;
use fmi2::Model;
use std::ffi::c_int;

/// Derivatives of continuous outputs: `orders[k]` of `vr[k]`, every element of an array.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get_output_derivatives<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    orders: *const i32,
    values: *mut f64,
    n_values: usize,
) -> c_int {
    const F: &str = "fmi3GetOutputDerivatives";
    with3::<M>(c, F, mask::DERIVATIVES, |inst| {
        let (Some(vr), Some(orders), Some(out)) =
            (slice(vr, n_vr), slice(orders, n_vr), slice_mut(values, n_values))
        else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        let (mut k, mut unknown) = (0, Vec::new());
        for (&r, &order) in vr.iter().zip(orders) {
            let v = match var(inst, view, F, r) {
                Ok(v) => v,
                Err(s) => return s,
            };
            if k + v.size() > n_values {
                return inst.error(&format!(
                    "{F}: nValues = {n_values} is too small for the variables"
                ));
            }
            if v.elements.is_empty() {
                return inst.error(&format!("{F}: '{}' is not an output", v.name));
            }
            for &i in &v.elements {
                out[k] = match output_derivative_of(inst, F, i, i64::from(order)) {
                    Ok(Some(d)) => d,
                    Ok(None) => {
                        unknown.push(format!("{} (order {order})", M::info().variables[i].name));
                        0.0
                    }
                    Err(s) => return s,
                };
                k += 1;
            }
        }
        if k != n_values {
            return inst.error(&format!(
                "{F}: nValues = {n_values}, the variables hold {k} values"
            ));
        }
        unknown_derivatives(inst, F, &unknown)
    })
}

/// The Jacobian of the serialized unknowns by the serialized knowns, with the lengths of seed
/// and sensitivity checked (`adjoint`: seed by unknowns, sensitivity by knowns).
#[allow(clippy::too_many_arguments)]
unsafe fn partials<M: Model>(
    view: &'static View,
    f: &'static str,
    adjoint: bool,
    c: Instance3,
    unknowns: *const ValueReference,
    n_unknowns: usize,
    knowns: *const ValueReference,
    n_knowns: usize,
    seed: *const f64,
    n_seed: usize,
    sensitivity: *mut f64,
    n_sensitivity: usize,
) -> c_int {
    with3::<M>(c, f, mask::PARTIALS, |inst| {
        let (Some(u), Some(k)) = (slice(unknowns, n_unknowns), slice(knowns, n_knowns)) else {
            return inst.error(&format!("{f}: NULL array with a length > 0"));
        };
        let (Some(seed), Some(out)) = (slice(seed, n_seed), slice_mut(sensitivity, n_sensitivity)) else {
            return inst.error(&format!("{f}: NULL array with a length > 0"));
        };
        let (u, k) = match elements(inst, view, f, u).and_then(|u| elements(inst, view, f, k).map(|k| (u, k)))
        {
            Ok(x) => x,
            Err(s) => return s,
        };
        let (n_in, n_out) = if adjoint {
            (u.len(), k.len())
        } else {
            (k.len(), u.len())
        };
        if (seed.len(), out.len()) != (n_in, n_out) {
            return inst.error(&format!(
                "{f}: nSeed = {}, nSensitivity = {}; the variables need {n_in} and {n_out}",
                seed.len(),
                out.len()
            ));
        }
        let j = match jacobian_of(inst, f, &u, &k) {
            Ok(j) => j,
            Err(s) => return s,
        };
        if adjoint {
            for (col, o) in out.iter_mut().enumerate() {
                *o = j.iter().zip(seed).map(|(row, s)| row[col] * s).sum();
            }
        } else {
            for (row, o) in j.iter().zip(out.iter_mut()) {
                *o = row.iter().zip(seed).map(|(a, b)| a * b).sum();
            }
        }
        Status::Ok
    })
}

/// sensitivity = J · seed.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get_directional_derivative<M: Model>(
    view: &'static View,
    c: Instance3,
    unknowns: *const ValueReference,
    n_unknowns: usize,
    knowns: *const ValueReference,
    n_knowns: usize,
    seed: *const f64,
    n_seed: usize,
    sensitivity: *mut f64,
    n_sensitivity: usize,
) -> c_int {
    let f = "fmi3GetDirectionalDerivative";
    partials::<M>(
        view,
        f,
        false,
        c,
        unknowns,
        n_unknowns,
        knowns,
        n_knowns,
        seed,
        n_seed,
        sensitivity,
        n_sensitivity,
    )
}

/// sensitivityᵀ = seedᵀ · J.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get_adjoint_derivative<M: Model>(
    view: &'static View,
    c: Instance3,
    unknowns: *const ValueReference,
    n_unknowns: usize,
    knowns: *const ValueReference,
    n_knowns: usize,
    seed: *const f64,
    n_seed: usize,
    sensitivity: *mut f64,
    n_sensitivity: usize,
) -> c_int {
    let f = "fmi3GetAdjointDerivative";
    partials::<M>(
        view,
        f,
        true,
        c,
        unknowns,
        n_unknowns,
        knowns,
        n_knowns,
        seed,
        n_seed,
        sensitivity,
        n_sensitivity,
    )
}
