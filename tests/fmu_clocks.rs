//! CncMotion's FMI 3 clock `tick` through its C ABI, as an importer drives it (libloading):
//! Scheduled Execution (fmi3ActivateModelPartition at every tick, or every fifth) gives every
//! output bit for bit as Co-Simulation (fmi3DoStep of the same length) on the whole default
//! program; Co-Simulation with Event Mode (fmi3SetClock at ticks) too; and the refusals the
//! standard asks for (off-grid, repeated or decreasing activations, the wrong interface's calls,
//! a period the clock does not have), each an fmi3Error with a log line.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

mod common;

use cnc_motion::fmu::CncMotionFmu;
use libloading::{Library, Symbol};
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::sync::Mutex;

type I = *mut c_void;
type Vr = u32;
const OK: c_int = 0;
const ERROR: c_int = 3;
const T: f64 = 1e-3;

type Log = Mutex<Vec<String>>;

unsafe extern "C" fn logger(env: *mut c_void, _status: c_int, _cat: *const c_char, msg: *const c_char) {
    let text = CStr::from_ptr(msg).to_string_lossy().into_owned();
    (*(env as *const Log)).lock().unwrap().push(text);
}

type Logger = unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char);
type FnCs = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    u8,
    u8,
    u8,
    u8,
    *const Vr,
    usize,
    *mut c_void,
    Option<Logger>,
    *const c_void,
) -> I;
type FnSe = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    u8,
    u8,
    *mut c_void,
    Option<Logger>,
    *const c_void,
    *const c_void,
    *const c_void,
) -> I;
type FnC = unsafe extern "C" fn(I) -> c_int;
type FnEnterInit = unsafe extern "C" fn(I, u8, f64, f64, u8, f64) -> c_int;
type FnDoStep = unsafe extern "C" fn(I, f64, f64, u8, *mut u8, *mut u8, *mut u8, *mut f64) -> c_int;
type FnActivate = unsafe extern "C" fn(I, Vr, f64) -> c_int;
type FnGetF64 = unsafe extern "C" fn(I, *const Vr, usize, *mut f64, usize) -> c_int;
type FnSetF64 = unsafe extern "C" fn(I, *const Vr, usize, *const f64, usize) -> c_int;
type FnClock = unsafe extern "C" fn(I, *const Vr, usize, *const u8) -> c_int;
type FnInterval = unsafe extern "C" fn(I, *const Vr, usize, *mut f64, *mut c_int) -> c_int;
type FnUpdate = unsafe extern "C" fn(I, *mut u8, *mut u8, *mut u8, *mut u8, *mut u8, *mut f64) -> c_int;
type FnFree = unsafe extern "C" fn(I);

/// The repository's resources folder (the default program), as FMI 3 passes it: a native path
/// with a trailing separator.
fn c_resources() -> CString {
    CString::new(concat!(env!("CARGO_MANIFEST_DIR"), "/resources/")).unwrap()
}

struct Fmu {
    lib: Library,
    token: CString,
    view: fmi3::View,
    log: Box<Log>,
}

impl Fmu {
    fn load() -> Fmu {
        let lib = unsafe { Library::new(common::library_path()) }.expect("the CncMotion library");
        let view = fmi3::View::of::<CncMotionFmu>();
        Fmu {
            lib,
            token: CString::new(view.token.clone()).unwrap(),
            view,
            log: Box::new(Mutex::new(Vec::new())),
        }
    }

    fn sym<F>(&self, name: &str) -> Symbol<'_, F> {
        unsafe { self.lib.get(name.as_bytes()) }.expect(name)
    }

    fn vr(&self, name: &str) -> Vr {
        self.view.vars[self.view.index_of(name).expect(name)].value_reference
    }

    fn env(&self) -> *mut c_void {
        &*self.log as *const Log as *mut c_void
    }

    fn last_log(&self) -> String {
        self.log.lock().unwrap().last().cloned().unwrap_or_default()
    }

    /// A Co-Simulation instance (with Event Mode if asked) or a Scheduled Execution one.
    fn instantiate(&self, scheduled: bool, event_mode: bool) -> I {
        let name = c"clocks";
        let res = c_resources();
        unsafe {
            if scheduled {
                let f = self.sym::<FnSe>("fmi3InstantiateScheduledExecution");
                let null = std::ptr::null();
                f(
                    name.as_ptr(),
                    self.token.as_ptr(),
                    res.as_ptr(),
                    0,
                    0,
                    self.env(),
                    Some(logger),
                    null,
                    null,
                    null,
                )
            } else {
                let f = self.sym::<FnCs>("fmi3InstantiateCoSimulation");
                let (n, m) = (std::ptr::null(), u8::from(event_mode));
                f(
                    name.as_ptr(),
                    self.token.as_ptr(),
                    res.as_ptr(),
                    0,
                    0,
                    m,
                    0,
                    n,
                    0,
                    self.env(),
                    Some(logger),
                    std::ptr::null(),
                )
            }
        }
    }

    /// Instantiated, initialized at t = 0 with `period` (the default when None).
    fn start(&self, scheduled: bool, event_mode: bool, period: Option<f64>) -> (I, c_int) {
        let c = self.instantiate(scheduled, event_mode);
        assert!(!c.is_null(), "{}", self.last_log());
        unsafe {
            assert_eq!(
                self.sym::<FnEnterInit>("fmi3EnterInitializationMode")(c, 0, 0.0, 0.0, 0, 0.0),
                OK
            );
            if let Some(p) = period {
                assert_eq!(self.set(c, "machine.interpolationPeriod", p), OK);
            }
            (c, self.sym::<FnC>("fmi3ExitInitializationMode")(c))
        }
    }

    fn set(&self, c: I, name: &str, x: f64) -> c_int {
        let vr = self.vr(name);
        unsafe { self.sym::<FnSetF64>("fmi3SetFloat64")(c, &vr, 1, &x, 1) }
    }

    /// Every Float64 output, serialized (arrays element by element), after the time.
    fn outputs(&self, c: I) -> Vec<f64> {
        let vars = self
            .view
            .vars
            .iter()
            .filter(|v| v.causality == fmi2::Causality::Output);
        let vrs: Vec<Vr> = vars
            .clone()
            .filter(|v| v.kind == fmi3::Kind::Float64)
            .map(|v| v.value_reference)
            .collect();
        let n: usize = vars
            .filter(|v| v.kind == fmi3::Kind::Float64)
            .map(|v| v.size())
            .sum();
        let mut out = vec![f64::NAN; n + 1];
        let vrs = [&[0][..], &vrs].concat();
        let get = self.sym::<FnGetF64>("fmi3GetFloat64");
        assert_eq!(
            unsafe { get(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), n + 1) },
            OK
        );
        out
    }

    fn finished(&self, c: I) -> bool {
        let vr = self.vr("status.finished");
        let mut b = 0u8;
        let get =
            self.sym::<unsafe extern "C" fn(I, *const Vr, usize, *mut u8, usize) -> c_int>("fmi3GetBoolean");
        assert_eq!(unsafe { get(c, &vr, 1, &mut b, 1) }, OK);
        b != 0
    }

    fn step(&self, c: I, t: f64, h: f64) -> c_int {
        let (mut a, mut b, mut e, mut last) = (0u8, 0u8, 0u8, 0.0);
        unsafe { self.sym::<FnDoStep>("fmi3DoStep")(c, t, h, 1, &mut a, &mut b, &mut e, &mut last) }
    }

    fn activate(&self, c: I, t: f64) -> c_int {
        unsafe { self.sym::<FnActivate>("fmi3ActivateModelPartition")(c, self.vr("tick"), t) }
    }

    fn call(&self, c: I, name: &str) -> c_int {
        unsafe { self.sym::<FnC>(name)(c) }
    }

    fn free(&self, c: I) {
        unsafe { self.sym::<FnFree>("fmi3FreeInstance")(c) }
    }
}

/// Co-Simulation in steps of `every` ticks beside Scheduled Execution activated at the same
/// ticks: every output the same after each, until the program is finished.
fn scheduled_equals_co_simulation(every: u32) -> usize {
    let fmu = Fmu::load();
    let (se, s) = fmu.start(true, false, None);
    assert_eq!(s, OK, "{}", fmu.last_log());
    let (cs, s) = fmu.start(false, false, None);
    assert_eq!(s, OK);
    assert_eq!(fmu.activate(se, 0.0), OK, "the first tick is at the start time");
    assert_eq!(fmu.outputs(se), fmu.outputs(cs));
    let (mut k, h) = (0u32, f64::from(every) * T);
    while !fmu.finished(cs) {
        assert_eq!(fmu.step(cs, f64::from(k) * T, h), OK);
        k += every;
        let t = f64::from(k) * T;
        assert_eq!(fmu.activate(se, t), OK, "{}", fmu.last_log());
        let (a, b) = (fmu.outputs(se), fmu.outputs(cs));
        // The time is the importer's: the activation time, or the sum of the steps.
        assert_eq!(a[0], t);
        assert_eq!(a[1..], b[1..], "tick {k}");
        assert!(k < 100_000);
    }
    assert!(fmu.finished(se));
    fmu.free(se);
    fmu.free(cs);
    k as usize
}

#[test]
fn scheduled_execution_gives_the_co_simulation_outputs_bit_for_bit() {
    let ticks = scheduled_equals_co_simulation(1);
    assert!(ticks > 1000, "the default program runs {ticks} ticks");
    scheduled_equals_co_simulation(5);
}

#[test]
fn activations_off_the_grid_repeated_or_back_in_time_are_refused() {
    let fmu = Fmu::load();
    let cases: [(&[f64], &str); 4] = [
        (&[0.0005], "is not one of its ticks"),
        (&[0.001, 0.001], "already activated at 0.001"),
        (&[0.002, 0.001], "activation times must increase"),
        (&[-0.001], "is not one of its ticks"),
    ];
    for (times, message) in cases {
        let (c, _) = fmu.start(true, false, None);
        let (last, first) = times.split_last().unwrap();
        for &t in first {
            assert_eq!(fmu.activate(c, t), OK);
        }
        assert_eq!(fmu.activate(c, *last), ERROR, "{times:?}");
        assert!(fmu.last_log().contains(message), "{}", fmu.last_log());
        fmu.free(c);
    }
    // Within the time tolerance of doStep, a master's rounded time is the tick.
    let (c, _) = fmu.start(true, false, None);
    assert_eq!(fmu.activate(c, 0.1 + 1e-12), OK);
    fmu.free(c);
}

#[test]
fn each_interface_refuses_the_others_calls() {
    let fmu = Fmu::load();
    let (se, _) = fmu.start(true, false, None);
    assert_eq!(fmu.step(se, 0.0, T), ERROR);
    assert!(fmu.last_log().contains("advances by fmi3ActivateModelPartition"));
    fmu.free(se);
    let (cs, _) = fmu.start(false, false, None);
    assert_eq!(fmu.activate(cs, T), ERROR);
    assert!(fmu.last_log().contains("only for Scheduled Execution"));
    fmu.free(cs);
    let (cs, _) = fmu.start(false, false, None);
    assert_eq!(fmu.call(cs, "fmi3EnterEventMode"), ERROR);
    assert!(fmu.last_log().contains("eventModeUsed = false"));
    fmu.free(cs);
    // A value reference that is not a clock.
    let (se, _) = fmu.start(true, false, None);
    let f = fmu.sym::<FnActivate>("fmi3ActivateModelPartition");
    assert_eq!(unsafe { f(se, fmu.vr("feedOverride"), 0.0) }, ERROR);
    assert!(fmu.last_log().contains("'feedOverride' is not a clock"));
    fmu.free(se);
}

#[test]
fn the_interval_is_the_declared_constant_and_the_period_must_keep_it() {
    let fmu = Fmu::load();
    let (se, _) = fmu.start(true, false, None);
    let tick = fmu.vr("tick");
    let (mut interval, mut qualifier, mut shift) = (0.0, -1, -1.0);
    unsafe {
        assert_eq!(
            fmu.sym::<FnInterval>("fmi3GetIntervalDecimal")(se, &tick, 1, &mut interval, &mut qualifier),
            OK
        );
        let shift_of =
            fmu.sym::<unsafe extern "C" fn(I, *const Vr, usize, *mut f64) -> c_int>("fmi3GetShiftDecimal");
        assert_eq!(shift_of(se, &tick, 1, &mut shift), OK);
        let set = fmu
            .sym::<unsafe extern "C" fn(I, *const Vr, usize, *const f64) -> c_int>("fmi3SetIntervalDecimal");
        assert_eq!(set(se, &tick, 1, &0.002), ERROR);
    }
    // fmi3IntervalUnchanged: the only qualifier of a constant clock.
    assert_eq!((interval, qualifier, shift), (T, 1, 0.0));
    fmu.free(se);
    for (scheduled, event_mode) in [(true, false), (false, true)] {
        let (c, status) = fmu.start(scheduled, event_mode, Some(0.002));
        assert_eq!(status, ERROR);
        assert!(
            fmu.last_log().contains("machine.interpolationPeriod is 0.002 s"),
            "{}",
            fmu.last_log()
        );
        fmu.free(c);
    }
    // Without clocks in use, another period is fine.
    let (c, status) = fmu.start(false, false, Some(0.002));
    assert_eq!(status, OK);
    fmu.free(c);
}

/// Co-Simulation with Event Mode: initialization ends in Event Mode, the clock is set at each
/// tick in an Event Mode of its own, and the outputs are those of plain Co-Simulation.
#[test]
fn event_mode_with_the_clock_set_at_ticks_gives_the_co_simulation_outputs() {
    let fmu = Fmu::load();
    let (em, s) = fmu.start(false, true, None);
    assert_eq!(s, OK, "{}", fmu.last_log());
    let (cs, _) = fmu.start(false, false, None);
    let tick = fmu.vr("tick");
    let set_clock = fmu.sym::<FnClock>("fmi3SetClock");
    let update = fmu.sym::<FnUpdate>("fmi3UpdateDiscreteStates");
    assert_eq!(fmu.step(em, 0.0, T), ERROR, "in Event Mode after initialization");
    fmu.free(em);
    let (em, _) = fmu.start(false, true, None);
    let mut flags = [9u8; 5];
    let mut next = f64::NAN;
    for k in 0..600u32 {
        unsafe {
            assert_eq!(set_clock(em, &tick, 1, &1), OK, "{}", fmu.last_log());
            let [a, b, c, d, e] = &mut flags;
            assert_eq!(update(em, a, b, c, d, e, &mut next), OK);
        }
        assert_eq!(flags, [0; 5], "nothing to update, no time event, no termination");
        assert_eq!(fmu.call(em, "fmi3EnterStepMode"), OK);
        assert_eq!(
            fmu.outputs(em),
            fmu.outputs(cs),
            "tick {k} (time included: both sum h)"
        );
        let t = f64::from(k) * T;
        assert_eq!(fmu.step(em, t, T), OK);
        assert_eq!(fmu.step(cs, t, T), OK);
        assert_eq!(fmu.call(em, "fmi3EnterEventMode"), OK);
    }
    // Once per time; and only at ticks.
    assert_eq!(unsafe { set_clock(em, &tick, 1, &1) }, OK);
    assert_eq!(unsafe { set_clock(em, &tick, 1, &1) }, ERROR);
    assert!(fmu.last_log().contains("already activated"));
    fmu.free(em);
    let (em, _) = fmu.start(false, true, None);
    assert_eq!(fmu.call(em, "fmi3EnterStepMode"), OK);
    assert_eq!(fmu.step(em, 0.0, 0.0005), OK);
    assert_eq!(fmu.call(em, "fmi3EnterEventMode"), OK);
    assert_eq!(unsafe { set_clock(em, &tick, 1, &1) }, ERROR);
    assert!(fmu.last_log().contains("not one of its ticks"));
    fmu.free(em);
    fmu.free(cs);
}

type FnState = unsafe extern "C" fn(I, *mut *mut c_void) -> c_int;
type FnSize = unsafe extern "C" fn(I, *mut c_void, *mut usize) -> c_int;
type FnSerialize = unsafe extern "C" fn(I, *mut c_void, *mut u8, usize) -> c_int;
type FnDeserialize = unsafe extern "C" fn(I, *const u8, usize, *mut *mut c_void) -> c_int;

/// An FMU state saved in Event Mode restores Event Mode in an instance with Event Mode, and is
/// refused by one without.
#[test]
fn a_state_saved_in_event_mode_needs_an_instance_with_event_mode() {
    let fmu = Fmu::load();
    let (em, _) = fmu.start(false, true, None);
    let mut state = std::ptr::null_mut();
    let mut size = 0usize;
    let bytes = unsafe {
        assert_eq!(fmu.sym::<FnState>("fmi3GetFMUState")(em, &mut state), OK);
        assert_eq!(
            fmu.sym::<FnSize>("fmi3SerializedFMUStateSize")(em, state, &mut size),
            OK
        );
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmu.sym::<FnSerialize>("fmi3SerializeFMUState")(em, state, bytes.as_mut_ptr(), size),
            OK
        );
        assert_eq!(fmu.sym::<FnState>("fmi3FreeFMUState")(em, &mut state), OK);
        bytes
    };
    let deserialize = fmu.sym::<FnDeserialize>("fmi3DeserializeFMUState");
    let (cs, _) = fmu.start(false, false, None);
    assert_eq!(
        unsafe { deserialize(cs, bytes.as_ptr(), bytes.len(), &mut state) },
        ERROR
    );
    assert!(
        fmu.last_log().contains("saved in Event Mode"),
        "{}",
        fmu.last_log()
    );
    fmu.free(cs);
    // Into the instance itself after a step: back in Event Mode at t = 0.
    assert_eq!(fmu.call(em, "fmi3EnterStepMode"), OK);
    assert_eq!(fmu.step(em, 0.0, T), OK);
    unsafe {
        assert_eq!(deserialize(em, bytes.as_ptr(), bytes.len(), &mut state), OK);
        assert_eq!(
            fmu.sym::<unsafe extern "C" fn(I, *mut c_void) -> c_int>("fmi3SetFMUState")(em, state),
            OK
        );
        assert_eq!(fmu.sym::<FnState>("fmi3FreeFMUState")(em, &mut state), OK);
    }
    assert_eq!(fmu.step(em, 0.0, T), ERROR, "in Event Mode");
    fmu.free(em);
    let (em, _) = fmu.start(false, true, None);
    unsafe {
        assert_eq!(deserialize(em, bytes.as_ptr(), bytes.len(), &mut state), OK);
        assert_eq!(
            fmu.sym::<unsafe extern "C" fn(I, *mut c_void) -> c_int>("fmi3SetFMUState")(em, state),
            OK
        );
    }
    assert_eq!(fmu.call(em, "fmi3EnterStepMode"), OK);
    assert_eq!(fmu.step(em, 0.0, T), OK);
    fmu.free(em);
}
