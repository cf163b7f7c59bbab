//! `export_fmi2!(Model)`: every fmi2 function of the standard under its C name in a model's cdylib.

/// Export every fmi2 function of the standard for model `$m` from this cdylib.
#[macro_export]
macro_rules! export_fmi2 {
    ($m:ty) => {
        mod __fmi2_exports {
            use super::*;
            use std::ffi::{c_char, c_int};
            use $crate::abi::{self, Boolean, Call, CallbackFunctions, Component, FmuState, ValueReference};
            type M = $m;

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                abi::TYPES_PLATFORM.as_ptr()
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                abi::VERSION.as_ptr()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Component,
                on: Boolean,
                n: usize,
                cats: *const *const c_char,
            ) -> c_int {
                abi::set_debug_logging::<M>(c, on, n, cats)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: *const c_char,
                kind: c_int,
                guid: *const c_char,
                resources: *const c_char,
                functions: *const CallbackFunctions,
                visible: Boolean,
                logging_on: Boolean,
            ) -> Component {
                abi::instantiate::<M>(name, kind, guid, resources, functions, visible, logging_on)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
                abi::free_instance::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Component,
                td: Boolean,
                tol: f64,
                start: f64,
                sd: Boolean,
                stop: f64,
            ) -> c_int {
                abi::setup_experiment::<M>(c, td, tol, start, sd, stop)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> c_int {
                abi::enter_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> c_int {
                abi::exit_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Terminate(c: Component) -> c_int {
                abi::terminate::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Reset(c: Component) -> c_int {
                abi::reset::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut f64,
            ) -> c_int {
                abi::get_real::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut c_int,
            ) -> c_int {
                abi::get_integer::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut Boolean,
            ) -> c_int {
                abi::get_boolean::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *mut *const c_char,
            ) -> c_int {
                abi::get_string::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const f64,
            ) -> c_int {
                abi::set_real::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const c_int,
            ) -> c_int {
                abi::set_integer::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const Boolean,
            ) -> c_int {
                abi::set_boolean::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(
                c: Component,
                vr: *const ValueReference,
                n: usize,
                v: *const *const c_char,
            ) -> c_int {
                abi::set_string::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, s: *mut FmuState) -> c_int {
                abi::get_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, s: FmuState) -> c_int {
                abi::set_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, s: *mut FmuState) -> c_int {
                abi::free_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Component,
                s: FmuState,
                size: *mut usize,
            ) -> c_int {
                abi::serialized_fmu_state_size::<M>(c, s, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Component,
                s: FmuState,
                out: *mut u8,
                size: usize,
            ) -> c_int {
                abi::serialize_fmu_state::<M>(c, s, out, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Component,
                b: *const u8,
                size: usize,
                s: *mut FmuState,
            ) -> c_int {
                abi::deserialize_fmu_state::<M>(c, b, size, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Component,
                _u: *const ValueReference,
                _nu: usize,
                _z: *const ValueReference,
                _nz: usize,
                _dv: *const f64,
                _dz: *mut f64,
            ) -> c_int {
                abi::unsupported::<M>(c, Call::GetDirectionalDerivative)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const c_int,
                _v: *const f64,
            ) -> c_int {
                abi::unsupported::<M>(c, Call::SetRealInputDerivatives)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Component,
                _vr: *const ValueReference,
                _n: usize,
                _order: *const c_int,
                _v: *mut f64,
            ) -> c_int {
                abi::unsupported::<M>(c, Call::GetRealOutputDerivatives)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DoStep(c: Component, t: f64, h: f64, no_prior: Boolean) -> c_int {
                abi::do_step::<M>(c, t, h, no_prior)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> c_int {
                abi::unsupported::<M>(c, Call::CancelStep)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStatus(c: Component, kind: c_int, v: *mut c_int) -> c_int {
                abi::get_status::<M>(c, kind, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, v: *mut f64) -> c_int {
                abi::get_real_status::<M>(c, kind, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(c: Component, kind: c_int, v: *mut c_int) -> c_int {
                abi::get_integer_status::<M>(c, kind, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Component,
                kind: c_int,
                v: *mut Boolean,
            ) -> c_int {
                abi::get_boolean_status::<M>(c, kind, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Component,
                kind: c_int,
                v: *mut *const c_char,
            ) -> c_int {
                abi::get_string_status::<M>(c, kind, v)
            }
        }
    };
}
