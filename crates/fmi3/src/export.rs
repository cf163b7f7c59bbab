//! `export_fmi3!(Model)`: every fmi3 function of the standard under its C name in a model's
//! cdylib (beside the fmi2 ones of `fmi2::export_fmi2!`), each a one-line forward to the generic
//! functions of [`crate::abi`] with the model's [`crate::View`], built once.

/// Export every fmi3 function of the standard for model `$m` from this cdylib.
#[macro_export]
macro_rules! export_fmi3 {
    ($m:ty) => {
        mod __fmi3_exports {
            use std::ffi::{c_char, c_int, c_void};
            use $crate::abi::{self, values, Boolean, FmuState, Instance3 as I, ValueReference as Vr};
            type M = $m;
            type Log = Option<$crate::__LogMessageFn>;

            fn view() -> &'static $crate::View {
                static VIEW: std::sync::OnceLock<$crate::View> = std::sync::OnceLock::new();
                VIEW.get_or_init($crate::View::of::<M>)
            }

            #[no_mangle]
            pub extern "C" fn fmi3GetVersion() -> *const c_char {
                abi::VERSION.as_ptr()
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
                name: *const c_char,
                token: *const c_char,
                resources: *const c_char,
                visible: Boolean,
                logging_on: Boolean,
                event_mode_used: Boolean,
                early_return_allowed: Boolean,
                required: *const Vr,
                n_required: usize,
                env: *mut c_void,
                log: Log,
                intermediate_update: *const c_void,
            ) -> I {
                abi::instantiate_co_simulation::<M>(
                    view(), name, token, resources, visible, logging_on, event_mode_used,
                    early_return_allowed, required, n_required, env, log, intermediate_update,
                )
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateModelExchange(
                _name: *const c_char,
                _token: *const c_char,
                _resources: *const c_char,
                _visible: Boolean,
                _logging_on: Boolean,
                env: *mut c_void,
                log: Log,
            ) -> I {
                abi::refuse_interface("fmi3InstantiateModelExchange", env, log)
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
                name: *const c_char,
                token: *const c_char,
                resources: *const c_char,
                visible: Boolean,
                logging_on: Boolean,
                env: *mut c_void,
                log: Log,
                _clock_update: *const c_void,
                _lock: *const c_void,
                _unlock: *const c_void,
            ) -> I {
                abi::instantiate_scheduled_execution::<M>(view(), name, token, resources, visible, logging_on, env, log)
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3FreeInstance(c: I) {
                $crate::fmi2::abi::free_instance::<M>(c)
            }

            $crate::__fmi3_forward! {
                fmi3SetDebugLogging(c: I, on: Boolean, n: usize, cats: *const *const c_char) = set_debug_logging;
                fmi3EnterInitializationMode(c: I, td: Boolean, tol: f64, t0: f64, sd: Boolean, t1: f64) = enter_initialization_mode;
                fmi3ExitInitializationMode(c: I) = exit_initialization_mode;
                fmi3Terminate(c: I) = terminate;
                fmi3Reset(c: I) = reset;
                fmi3GetFMUState(c: I, s: *mut FmuState) = get_fmu_state;
                fmi3SetFMUState(c: I, s: FmuState) = set_fmu_state;
                fmi3FreeFMUState(c: I, s: *mut FmuState) = free_fmu_state;
                fmi3SerializedFMUStateSize(c: I, s: FmuState, size: *mut usize) = serialized_fmu_state_size;
                fmi3SerializeFMUState(c: I, s: FmuState, out: *mut u8, size: usize) = serialize_fmu_state;
                fmi3DeserializeFMUState(c: I, b: *const u8, size: usize, s: *mut FmuState) = deserialize_fmu_state;
                fmi3DoStep(c: I, t: f64, h: f64, np: Boolean, ev: *mut Boolean, term: *mut Boolean,
                           early: *mut Boolean, last: *mut f64) = do_step;
                fmi3EnterEventMode(c: I) = enter_event_mode;
                fmi3EnterStepMode(c: I) = enter_step_mode;
                fmi3UpdateDiscreteStates(c: I, a: *mut Boolean, b: *mut Boolean, x: *mut Boolean,
                                         d: *mut Boolean, e: *mut Boolean, t: *mut f64) = update_discrete_states;
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3ActivateModelPartition(c: I, clock: Vr, t: f64) -> c_int {
                abi::activate_model_partition::<M>(view(), c, clock, t)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetClock(c: I, vr: *const Vr, n: usize, v: *const Boolean) -> c_int {
                abi::set_clock::<M>(view(), c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetClock(c: I, vr: *const Vr, n: usize, _v: *mut Boolean) -> c_int {
                abi::get_clock::<M>(view(), c, vr, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetIntervalDecimal(c: I, vr: *const Vr, n: usize, i: *mut f64, q: *mut c_int) -> c_int {
                abi::get_interval_decimal::<M>(view(), c, vr, n, i, q)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetShiftDecimal(c: I, vr: *const Vr, n: usize, s: *mut f64) -> c_int {
                abi::get_shift_decimal::<M>(view(), c, vr, n, s)
            }

            $crate::__fmi3_values! {
                fmi3GetFloat64 / fmi3SetFloat64: f64 = values::FLOAT64;
                fmi3GetInt32 / fmi3SetInt32: i32 = values::INT32;
                fmi3GetUInt64 / fmi3SetUInt64: u64 = values::UINT64;
                fmi3GetInt64 / fmi3SetInt64: i64 = values::INT64;
                fmi3GetBoolean / fmi3SetBoolean: Boolean = values::BOOLEAN;
                fmi3GetFloat32 / fmi3SetFloat32: f32 = values::none();
                fmi3GetInt8 / fmi3SetInt8: i8 = values::none();
                fmi3GetUInt8 / fmi3SetUInt8: u8 = values::none();
                fmi3GetInt16 / fmi3SetInt16: i16 = values::none();
                fmi3GetUInt16 / fmi3SetUInt16: u16 = values::none();
                fmi3GetUInt32 / fmi3SetUInt32: u32 = values::none();
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetString(c: I, vr: *const Vr, n: usize, v: *mut *const c_char, nv: usize) -> c_int {
                values::get_string::<M>(view(), c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetString(c: I, vr: *const Vr, n: usize, v: *const *const c_char, nv: usize) -> c_int {
                values::set_string::<M>(view(), c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetOutputDerivatives(
                c: I, vr: *const Vr, n: usize, orders: *const i32, v: *mut f64, nv: usize,
            ) -> c_int {
                abi::get_output_derivatives::<M>(view(), c, vr, n, orders, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
                c: I, u: *const Vr, nu: usize, k: *const Vr, nk: usize, seed: *const f64, ns: usize,
                sens: *mut f64, nsens: usize,
            ) -> c_int {
                abi::get_directional_derivative::<M>(view(), c, u, nu, k, nk, seed, ns, sens, nsens)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetAdjointDerivative(
                c: I, u: *const Vr, nu: usize, k: *const Vr, nk: usize, seed: *const f64, ns: usize,
                sens: *mut f64, nsens: usize,
            ) -> c_int {
                abi::get_adjoint_derivative::<M>(view(), c, u, nu, k, nk, seed, ns, sens, nsens)
            }

            const CONSTANT: &str = "its clocks are constant: the interval and shift are the modelDescription's";
            const NO_FRACTIONS: &str = "supportsFraction = false: use the Decimal functions";
            const CS_ONLY: &str = "Co-Simulation and Scheduled Execution only";
            $crate::__fmi3_unsupported! {
                fmi3EvaluateDiscreteStates(c: I) = "providesEvaluateDiscreteStates = false";
                fmi3EnterConfigurationMode(c: I) = "no structural parameters";
                fmi3ExitConfigurationMode(c: I) = "no structural parameters";
                fmi3GetNumberOfVariableDependencies(c: I, _vr: Vr, _n: *mut usize) = "providesPerElementDependencies = false";
                fmi3GetVariableDependencies(c: I, _d: Vr, _ed: *mut usize, _i: *mut Vr, _ei: *mut usize,
                                            _k: *mut c_int, _n: usize) = "providesPerElementDependencies = false";
                fmi3GetBinary(c: I, _vr: *const Vr, _n: usize, _s: *mut usize, _v: *mut *const u8, _nv: usize) = "no Binary variables";
                fmi3SetBinary(c: I, _vr: *const Vr, _n: usize, _s: *const usize, _v: *const *const u8, _nv: usize) = "no Binary variables";
                fmi3GetIntervalFraction(c: I, _vr: *const Vr, _n: usize, _i: *mut u64, _r: *mut u64, _q: *mut c_int) = NO_FRACTIONS;
                fmi3GetShiftFraction(c: I, _vr: *const Vr, _n: usize, _s: *mut u64, _r: *mut u64) = NO_FRACTIONS;
                fmi3SetIntervalDecimal(c: I, _vr: *const Vr, _n: usize, _i: *const f64) = CONSTANT;
                fmi3SetIntervalFraction(c: I, _vr: *const Vr, _n: usize, _i: *const u64, _r: *const u64) = CONSTANT;
                fmi3SetShiftDecimal(c: I, _vr: *const Vr, _n: usize, _s: *const f64) = CONSTANT;
                fmi3SetShiftFraction(c: I, _vr: *const Vr, _n: usize, _s: *const u64, _r: *const u64) = CONSTANT;
                fmi3EnterContinuousTimeMode(c: I) = CS_ONLY;
                fmi3CompletedIntegratorStep(c: I, _np: Boolean, _e: *mut Boolean, _t: *mut Boolean) = CS_ONLY;
                fmi3SetTime(c: I, _t: f64) = CS_ONLY;
                fmi3SetContinuousStates(c: I, _x: *const f64, _n: usize) = CS_ONLY;
                fmi3GetContinuousStateDerivatives(c: I, _x: *mut f64, _n: usize) = CS_ONLY;
                fmi3GetEventIndicators(c: I, _x: *mut f64, _n: usize) = CS_ONLY;
                fmi3GetContinuousStates(c: I, _x: *mut f64, _n: usize) = CS_ONLY;
                fmi3GetNominalsOfContinuousStates(c: I, _x: *mut f64, _n: usize) = CS_ONLY;
                fmi3GetNumberOfEventIndicators(c: I, _n: *mut usize) = CS_ONLY;
                fmi3GetNumberOfContinuousStates(c: I, _n: *mut usize) = CS_ONLY;
            }
        }
    };
}

/// fmi3LogMessageCallback (for the macro's users).
#[doc(hidden)]
pub type __LogMessageFn = fmi2::instance::LogMessageFn;

/// `name(args) = function;` → `#[no_mangle] fn name(args) -> fmi3Status { abi::function::<M>(args) }`.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_forward {
    ($($name:ident($($a:ident: $t:ty),*) = $f:ident;)*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $name($($a: $t),*) -> c_int {
                abi::$f::<M>($($a),*)
            }
        )*
    };
}

/// `get / set: C type = family;` → fmi3Get… and fmi3Set… of one C element type.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_values {
    ($($get:ident / $set:ident: $t:ty = $family:expr;)*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $get(c: I, vr: *const Vr, n: usize, v: *mut $t, nv: usize) -> c_int {
                values::get::<M, $t>(view(), stringify!($get), $family, c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn $set(c: I, vr: *const Vr, n: usize, v: *const $t, nv: usize) -> c_int {
                values::set::<M, $t>(view(), stringify!($set), $family, c, vr, n, v, nv)
            }
        )*
    };
}

/// `name(c, ignored args) = why;` → a function that logs and answers fmi3Error.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_unsupported {
    ($($name:ident(c: I $(, $a:ident: $t:ty)*) = $why:expr;)*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $name(c: I $(, $a: $t)*) -> c_int {
                abi::unsupported::<M>(c, stringify!($name), $why)
            }
        )*
    };
}
