//! µs per fmi2DoStep of 1 ms through the C ABI of the built library (servo on), no Python.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use criterion::{criterion_group, criterion_main, Criterion};
use libloading::{Library, Symbol};
use std::ffi::{c_char, c_int, c_void, CString};

type Component = *mut c_void;
#[repr(C)]
struct Callbacks {
    logger: *const c_void,
    allocate: *const c_void,
    free: *const c_void,
    step_finished: *const c_void,
    env: *mut c_void,
}
type FnInstantiate = unsafe extern "C" fn(
    *const c_char,
    c_int,
    *const c_char,
    *const c_char,
    *const Callbacks,
    c_int,
    c_int,
) -> Component;
type FnC = unsafe extern "C" fn(Component) -> c_int;
type FnSetup = unsafe extern "C" fn(Component, c_int, f64, f64, c_int, f64) -> c_int;
type FnDoStep = unsafe extern "C" fn(Component, f64, f64, c_int) -> c_int;

fn bench(c: &mut Criterion) {
    let exe = std::env::current_exe().unwrap();
    let lib =
        unsafe { Library::new(exe.parent().unwrap().parent().unwrap().join("libcnc_motion.so")) }.unwrap();
    let xml = cnc_motion::fmu::model_description();
    let guid = CString::new(xml.split("guid=\"").nth(1).unwrap().split('"').next().unwrap()).unwrap();
    let cb = Callbacks {
        logger: std::ptr::null(),
        allocate: std::ptr::null(),
        free: std::ptr::null(),
        step_finished: std::ptr::null(),
        env: std::ptr::null_mut(),
    };
    let uri = CString::new(format!("file://{}/resources", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let name = CString::new("bench").unwrap();
    unsafe {
        let inst: Symbol<FnInstantiate> = lib.get(b"fmi2Instantiate").unwrap();
        let setup: Symbol<FnSetup> = lib.get(b"fmi2SetupExperiment").unwrap();
        let enter: Symbol<FnC> = lib.get(b"fmi2EnterInitializationMode").unwrap();
        let exit: Symbol<FnC> = lib.get(b"fmi2ExitInitializationMode").unwrap();
        let reset: Symbol<FnC> = lib.get(b"fmi2Reset").unwrap();
        let step: Symbol<FnDoStep> = lib.get(b"fmi2DoStep").unwrap();
        let comp = inst(name.as_ptr(), 1, guid.as_ptr(), uri.as_ptr(), &cb, 0, 0);
        let start = |comp: Component| {
            setup(comp, 0, 0.0, 0.0, 0, 0.0);
            enter(comp);
            exit(comp);
        };
        start(comp);
        let mut t = 0.0;
        let mut n = 0u64;
        c.bench_function("fmu/doStep_1ms_servo", |b| {
            b.iter(|| {
                // The default program runs ~6 s; start it again before it ends.
                if n == 5000 {
                    reset(comp);
                    start(comp);
                    t = 0.0;
                    n = 0;
                }
                let s = step(comp, t, 1e-3, 1);
                n += 1;
                t = n as f64 * 1e-3;
                s
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
