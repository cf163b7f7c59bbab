//! fmi2Get*/fmi2Set*: arrays of value references, read and written through the model's table.

use super::{opt_str, slice, slice_mut, with, Boolean, Call, Component, ValueReference};
use crate::instance::Status;
use crate::{Model, Type, Value};
use std::ffi::{c_char, c_int, CString};

macro_rules! getter {
    ($fn:ident, $call:expr, $t:ty, $family:expr, $pat:pat => $val:expr) => {
        /// # Safety
        /// C ABI.
        pub unsafe fn $fn<M: Model>(
            c: Component,
            vr: *const ValueReference,
            n: usize,
            out: *mut $t,
        ) -> c_int {
            with::<M>(c, $call, |inst| {
                let name = $call.name();
                let (Some(vr), Some(out)) = (slice(vr, n), slice_mut(out, n)) else {
                    return inst.error(&format!("{name}: NULL array with nvr > 0"));
                };
                // One lookup and one model read per variable (outputs are computed once per
                // step by the model: this loop is the whole cost of reading them). Value
                // references are 1…n in table order; anything else takes `lookup`'s way.
                let vars = &M::info().variables;
                for (r, o) in vr.iter().zip(out.iter_mut()) {
                    let i = (*r as usize).wrapping_sub(1);
                    let i = match vars.get(i) {
                        Some(v) if v.value_reference == *r && v.kind.family() == $family => i,
                        _ => match inst.lookup(name, *r, $family) {
                            Ok(i) => i,
                            Err(s) => return s,
                        },
                    };
                    match inst.model.get(i) {
                        $pat => *o = $val,
                        _ => return inst.error(&format!("{name}: model returned another type")),
                    }
                }
                Status::Ok
            })
        }
    };
}

getter!(get_real, Call::GetReal, f64, Type::Real, Value::Real(x) => x);
getter!(get_integer, Call::GetInteger, c_int, Type::Integer, Value::Integer(x) => x);
getter!(get_boolean, Call::GetBoolean, Boolean, Type::Boolean, Value::Boolean(x) => c_int::from(x));

/// # Safety
/// C ABI. The strings stay valid until the next fmi2GetString on this instance.
pub unsafe fn get_string<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    out: *mut *const c_char,
) -> c_int {
    with::<M>(c, Call::GetString, |inst| {
        let (Some(vr), Some(out)) = (slice(vr, n), slice_mut(out, n)) else {
            return inst.error("fmi2GetString: NULL array with nvr > 0");
        };
        inst.strings.clear();
        for r in vr {
            match inst.get("fmi2GetString", *r, Type::String) {
                Ok(Value::String(s)) => inst
                    .strings
                    .push(CString::new(s.replace('\0', "")).unwrap_or_default()),
                Ok(_) => return inst.error("fmi2GetString: model returned another type"),
                Err(s) => return s,
            }
        }
        for (o, s) in out.iter_mut().zip(&inst.strings) {
            *o = s.as_ptr();
        }
        Status::Ok
    })
}

macro_rules! setter {
    ($fn:ident, $call:expr, $t:ty, $family:expr, |$x:ident| $val:expr) => {
        /// # Safety
        /// C ABI.
        pub unsafe fn $fn<M: Model>(
            c: Component,
            vr: *const ValueReference,
            n: usize,
            values: *const $t,
        ) -> c_int {
            with::<M>(c, $call, |inst| {
                let name = $call.name();
                let (Some(vr), Some(values)) = (slice(vr, n), slice(values, n)) else {
                    return inst.error(&format!("{name}: NULL array with nvr > 0"));
                };
                for (r, &$x) in vr.iter().zip(values) {
                    if let Err(s) = inst.set(name, *r, $family, $val) {
                        return s;
                    }
                }
                Status::Ok
            })
        }
    };
}

setter!(set_real, Call::SetReal, f64, Type::Real, |x| Value::Real(x));
setter!(set_integer, Call::SetInteger, c_int, Type::Integer, |x| {
    Value::Integer(x)
});
setter!(set_boolean, Call::SetBoolean, Boolean, Type::Boolean, |x| {
    Value::Boolean(x != 0)
});

/// # Safety
/// C ABI.
pub unsafe fn set_string<M: Model>(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    values: *const *const c_char,
) -> c_int {
    with::<M>(c, Call::SetString, |inst| {
        let (Some(vr), Some(values)) = (slice(vr, n), slice(values, n)) else {
            return inst.error("fmi2SetString: NULL array with nvr > 0");
        };
        for (r, &p) in vr.iter().zip(values) {
            let Some(s) = opt_str(p) else {
                return inst.error(&format!("fmi2SetString: NULL or non-UTF-8 string for vr {r}"));
            };
            if let Err(st) = inst.set("fmi2SetString", *r, Type::String, Value::String(s.to_string())) {
                return st;
            }
        }
        Status::Ok
    })
}
