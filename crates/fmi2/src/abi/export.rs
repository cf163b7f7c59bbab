//! `export_fmi2!(Model)`: every fmi2 function of the standard under its C name in a model's
//! cdylib, each a one-line forward to the generic function of this module's siblings.

/// Export every fmi2 function of the standard for model `$m` from this cdylib.
#[macro_export]
macro_rules! export_fmi2 {
    ($m:ty) => {
        mod __fmi2_exports {
            use std::ffi::{c_char, c_int};
            use $crate::abi::{
                self, Boolean, Call, CallbackFunctions, Component, FmuState, ValueReference as Vr,
            };
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

            $crate::__fmi2_forward! {
                fmi2SetDebugLogging(c: Component, on: Boolean, n: usize, cats: *const *const c_char) = set_debug_logging;
                fmi2SetupExperiment(c: Component, td: Boolean, tol: f64, t0: f64, sd: Boolean, t1: f64) = setup_experiment;
                fmi2EnterInitializationMode(c: Component) = enter_initialization_mode;
                fmi2ExitInitializationMode(c: Component) = exit_initialization_mode;
                fmi2Terminate(c: Component) = terminate;
                fmi2Reset(c: Component) = reset;
                fmi2GetReal(c: Component, vr: *const Vr, n: usize, v: *mut f64) = get_real;
                fmi2GetInteger(c: Component, vr: *const Vr, n: usize, v: *mut c_int) = get_integer;
                fmi2GetBoolean(c: Component, vr: *const Vr, n: usize, v: *mut Boolean) = get_boolean;
                fmi2GetString(c: Component, vr: *const Vr, n: usize, v: *mut *const c_char) = get_string;
                fmi2SetReal(c: Component, vr: *const Vr, n: usize, v: *const f64) = set_real;
                fmi2SetInteger(c: Component, vr: *const Vr, n: usize, v: *const c_int) = set_integer;
                fmi2SetBoolean(c: Component, vr: *const Vr, n: usize, v: *const Boolean) = set_boolean;
                fmi2SetString(c: Component, vr: *const Vr, n: usize, v: *const *const c_char) = set_string;
                fmi2GetFMUstate(c: Component, s: *mut FmuState) = get_fmu_state;
                fmi2SetFMUstate(c: Component, s: FmuState) = set_fmu_state;
                fmi2FreeFMUstate(c: Component, s: *mut FmuState) = free_fmu_state;
                fmi2SerializedFMUstateSize(c: Component, s: FmuState, size: *mut usize) = serialized_fmu_state_size;
                fmi2SerializeFMUstate(c: Component, s: FmuState, out: *mut u8, size: usize) = serialize_fmu_state;
                fmi2DeSerializeFMUstate(c: Component, b: *const u8, size: usize, s: *mut FmuState) = deserialize_fmu_state;
                fmi2DoStep(c: Component, t: f64, h: f64, no_prior: Boolean) = do_step;
                fmi2GetStatus(c: Component, kind: c_int, v: *mut c_int) = get_status;
                fmi2GetRealStatus(c: Component, kind: c_int, v: *mut f64) = get_real_status;
                fmi2GetIntegerStatus(c: Component, kind: c_int, v: *mut c_int) = get_integer_status;
                fmi2GetBooleanStatus(c: Component, kind: c_int, v: *mut Boolean) = get_boolean_status;
                fmi2GetStringStatus(c: Component, kind: c_int, v: *mut *const c_char) = get_string_status;
                // Refused with a log line unless the model declares the capability.
                fmi2GetDirectionalDerivative(c: Component, u: *const Vr, nu: usize, z: *const Vr, nz: usize,
                                             dv: *const f64, dz: *mut f64) = get_directional_derivative;
                fmi2SetRealInputDerivatives(c: Component, vr: *const Vr, n: usize, order: *const c_int,
                                            v: *const f64) = set_real_input_derivatives;
                fmi2GetRealOutputDerivatives(c: Component, vr: *const Vr, n: usize, order: *const c_int,
                                             v: *mut f64) = get_real_output_derivatives;
            }

            $crate::__fmi2_unsupported! {
                fmi2CancelStep(c: Component) = CancelStep;
            }
        }
    };
}

/// `name(args) = function;` → `#[no_mangle] fn name(args) -> fmi2Status { abi::function::<M>(args) }`.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi2_forward {
    ($($name:ident($($a:ident: $t:ty),*) = $f:ident;)*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $name($($a: $t),*) -> c_int {
                abi::$f::<M>($($a),*)
            }
        )*
    };
}

/// `name(c, ignored args) = Call;` → a function that logs and answers fmi2Error.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi2_unsupported {
    ($($name:ident(c: Component $(, $a:ident: $t:ty)*) = $call:ident;)*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $name(c: Component $(, $a: $t)*) -> c_int {
                abi::unsupported::<M>(c, Call::$call)
            }
        )*
    };
}
