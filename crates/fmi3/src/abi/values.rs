//! fmi3Get*/fmi3Set*: value references of scalars and arrays, the values serialized (an array's
//! elements in order) and counted against nValues, read and written through the model's table
//! with the checks of FMI 2 (types, the rules per state, declared ranges).

use super::{mask, var, with3, Boolean, Instance3, ValueReference};
use crate::view::Kind;
use crate::View;
use fmi2::abi::{opt_str, slice, slice_mut};
use fmi2::instance::{Instance, Status};
use fmi2::{Model, Value};
use std::ffi::{c_char, c_int, CString};

/// How one C element type maps onto the variables: the kinds it reads and writes.
pub struct Family<T> {
    pub kinds: &'static [Kind],
    /// The value of a variable of one of `kinds` as a C element.
    pub get: fn(Value) -> Option<T>,
    /// A C element as a value, or why it is refused (checked before the declared range).
    pub set: fn(T) -> Result<Value, String>,
}

pub const FLOAT64: Family<f64> = Family {
    kinds: &[Kind::Float64],
    get: |v| match v {
        Value::Real(x) => Some(x),
        _ => None,
    },
    set: |x| Ok(Value::Real(x)),
};

pub const INT32: Family<i32> = Family {
    kinds: &[Kind::Int32],
    get: |v| match v {
        Value::Integer(n) => Some(n),
        _ => None,
    },
    set: |n| Ok(Value::Integer(n)),
};

/// UInt64 variables hold what FMI 2 declares as Integers with min ≥ 0 (within i32).
pub const UINT64: Family<u64> = Family {
    kinds: &[Kind::UInt64],
    get: |v| match v {
        Value::Integer(n) => u64::try_from(n).ok(),
        _ => None,
    },
    set: |n| {
        i32::try_from(n)
            .map(Value::Integer)
            .map_err(|_| format!("{n} out of range (above {})", i32::MAX))
    },
};

/// Enumerations are read and written as Int64 (FMI 3.0 §2.4.7.5).
pub const INT64: Family<i64> = Family {
    // Any Enumeration (`kind_matches`).
    kinds: &[Kind::Enumeration(0)],
    get: |v| match v {
        Value::Integer(n) => Some(i64::from(n)),
        _ => None,
    },
    set: |n| {
        i32::try_from(n)
            .map(Value::Integer)
            .map_err(|_| format!("{n} is not an item of the enumeration"))
    },
};

pub const BOOLEAN: Family<Boolean> = Family {
    kinds: &[Kind::Boolean],
    get: |v| match v {
        Value::Boolean(b) => Some(Boolean::from(b)),
        _ => None,
    },
    set: |b| Ok(Value::Boolean(b != 0)),
};

/// The C types no variable of these FMUs has (Float32, Int8, UInt8, Int16, UInt16, UInt32):
/// every value reference is refused with its variable's type.
pub fn none<T>() -> Family<T> {
    Family {
        kinds: &[],
        get: |_| None,
        set: |_| Err(String::new()),
    }
}

fn kind_matches(kinds: &[Kind], k: Kind) -> bool {
    match k {
        Kind::Enumeration(_) => kinds.iter().any(|x| matches!(x, Kind::Enumeration(_))),
        k => kinds.contains(&k),
    }
}

/// The variables of `vrs` checked against the function's type, and the number of values they
/// hold; `time` is a Float64 of one value.
fn checked<'a, M: Model, T>(
    inst: &Instance<M>,
    view: &'a View,
    f: &str,
    family: &Family<T>,
    vrs: &[ValueReference],
    n_values: usize,
) -> Result<Vec<&'a crate::Var>, Status> {
    let mut vars = Vec::with_capacity(vrs.len());
    let mut count = 0;
    for &vr in vrs {
        let v = var(inst, view, f, vr)?;
        if !kind_matches(family.kinds, v.kind) {
            return Err(inst.error(&format!(
                "{f}: variable '{}' (vr {vr}) is of type {}",
                v.name,
                v.kind.name()
            )));
        }
        count += v.size();
        vars.push(v);
    }
    if count != n_values {
        return Err(inst.error(&format!(
            "{f}: nValues = {n_values}, the {} variables hold {count} values",
            vrs.len()
        )));
    }
    Ok(vars)
}

/// fmi3Get{Float64, Int32, UInt64, Int64, Boolean, …}.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get<M: Model, T: Copy>(
    view: &'static View,
    f: &'static str,
    family: Family<T>,
    c: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    values: *mut T,
    n_values: usize,
) -> c_int {
    with3::<M>(c, f, mask::GET, |inst| {
        let (Some(vr), Some(out)) = (slice(vr, n_vr), slice_mut(values, n_values)) else {
            return inst.error(&format!("{f}: NULL array with a length > 0"));
        };
        let vars = match checked(inst, view, f, &family, vr, n_values) {
            Ok(v) => v,
            Err(s) => return s,
        };
        let mut k = 0;
        for v in vars {
            if v.elements.is_empty() {
                // The independent variable: the instance's time.
                match (family.get)(Value::Real(inst.time)) {
                    Some(x) => out[k] = x,
                    None => return inst.error(&format!("{f}: 'time' is a Float64")),
                }
                k += 1;
            }
            for &i in &v.elements {
                match (family.get)(inst.model.get(i)) {
                    Some(x) => out[k] = x,
                    None => return inst.error(&format!("{f}: '{}' has a value out of its type", v.name)),
                }
                k += 1;
            }
        }
        Status::Ok
    })
}

/// fmi3Set{Float64, Int32, UInt64, Int64, Boolean, …}.
///
/// # Safety
/// C ABI.
#[allow(clippy::too_many_arguments)]
pub unsafe fn set<M: Model, T: Copy>(
    view: &'static View,
    f: &'static str,
    family: Family<T>,
    c: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    values: *const T,
    n_values: usize,
) -> c_int {
    with3::<M>(c, f, mask::SET, |inst| {
        let (Some(vr), Some(input)) = (slice(vr, n_vr), slice(values, n_values)) else {
            return inst.error(&format!("{f}: NULL array with a length > 0"));
        };
        let vars = match checked(inst, view, f, &family, vr, n_values) {
            Ok(v) => v,
            Err(s) => return s,
        };
        let mut k = 0;
        for v in vars {
            if v.elements.is_empty() {
                return inst.error(&format!("{f}: 'time' cannot be set"));
            }
            for &i in &v.elements {
                let value = match (family.set)(input[k]) {
                    Ok(x) => x,
                    Err(e) => return inst.error(&format!("{f}: '{}' = {e}", v.name)),
                };
                if let Err(s) = inst.set_at(f, i, value) {
                    return s;
                }
                k += 1;
            }
        }
        Status::Ok
    })
}

/// fmi3GetString: the strings stay valid until the next fmi3GetString on this instance.
///
/// # Safety
/// C ABI.
pub unsafe fn get_string<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    values: *mut *const c_char,
    n_values: usize,
) -> c_int {
    const F: &str = "fmi3GetString";
    let family: Family<()> = Family {
        kinds: &[Kind::String],
        get: |_| None,
        set: |_| Err(String::new()),
    };
    with3::<M>(c, F, mask::GET, |inst| {
        let (Some(vr), Some(out)) = (slice(vr, n_vr), slice_mut(values, n_values)) else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        let vars = match checked(inst, view, F, &family, vr, n_values) {
            Ok(v) => v,
            Err(s) => return s,
        };
        inst.strings.clear();
        for v in vars {
            for &i in &v.elements {
                let Value::String(s) = inst.model.get(i) else {
                    return inst.error(&format!("{F}: model returned another type"));
                };
                inst.strings
                    .push(CString::new(s.replace('\0', "")).unwrap_or_default());
            }
        }
        for (o, s) in out.iter_mut().zip(&inst.strings) {
            *o = s.as_ptr();
        }
        Status::Ok
    })
}

/// # Safety
/// C ABI.
pub unsafe fn set_string<M: Model>(
    view: &'static View,
    c: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    values: *const *const c_char,
    n_values: usize,
) -> c_int {
    const F: &str = "fmi3SetString";
    let family: Family<()> = Family {
        kinds: &[Kind::String],
        get: |_| None,
        set: |_| Err(String::new()),
    };
    with3::<M>(c, F, mask::SET, |inst| {
        let (Some(vr), Some(input)) = (slice(vr, n_vr), slice(values, n_values)) else {
            return inst.error(&format!("{F}: NULL array with a length > 0"));
        };
        let vars = match checked(inst, view, F, &family, vr, n_values) {
            Ok(v) => v,
            Err(s) => return s,
        };
        let mut k = 0;
        for v in vars {
            for &i in &v.elements {
                let Some(s) = opt_str(input[k]) else {
                    return inst.error(&format!("{F}: NULL or non-UTF-8 string for '{}'", v.name));
                };
                if let Err(st) = inst.set_at(F, i, Value::String(s.to_string())) {
                    return st;
                }
                k += 1;
            }
        }
        Status::Ok
    })
}
