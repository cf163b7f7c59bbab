//! The built CncMotion shared library loaded as an importer loads it (libloading): the fmi2
//! functions, value references read from the modelDescription, and a logger that keeps the
//! messages. Shared by the C-ABI test files (`mod common;`).
#![allow(dead_code)]

use libloading::{Library, Symbol};
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::path::PathBuf;
use std::sync::Mutex;

pub type Component = *mut c_void;
pub const OK: c_int = 0;
pub const ERROR: c_int = 3;

#[repr(C)]
pub struct Callbacks {
    // Declared without the C varargs, as fmpy's ctypes logger is: the FMU passes the finished
    // message and no arguments, which is ABI-compatible on the platforms we build for.
    logger: Option<unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char)>,
    allocate: *const c_void,
    free: *const c_void,
    step_finished: *const c_void,
    env: *mut c_void,
}

/// The messages of one test's instances (the logger's environment pointer).
pub type Log = Mutex<Vec<String>>;

pub unsafe extern "C" fn logger(
    env: *mut c_void,
    _name: *const c_char,
    _status: c_int,
    _cat: *const c_char,
    msg: *const c_char,
) {
    let text = CStr::from_ptr(msg).to_string_lossy().replace("%%", "%");
    (*(env as *const Log)).lock().unwrap().push(text);
}

/// The CncMotion shared library the tests load: `CNC_MOTION_LIB` when set (e.g. the binary of a
/// packaged FMU), else the one cargo built for this test run. The library target is a cdylib too,
/// so cargo compiles the shared library together with the rlib the tests link
/// (target/<profile>/deps/libcnc_motion.so, beside this test's executable): never stale, never
/// built inside a test, and with `cargo test --release` the very build `make build` made.
pub fn library_path() -> PathBuf {
    if let Some(path) = std::env::var_os("CNC_MOTION_LIB") {
        return PathBuf::from(path);
    }
    let exe = std::env::current_exe().expect("the test executable's path");
    let lib = exe.with_file_name(libloading::library_filename("cnc_motion"));
    assert!(
        lib.exists(),
        "{} missing: run the tests through cargo (`cargo test`, which builds the library with \
         them) or set CNC_MOTION_LIB to a built libcnc_motion.so",
        lib.display()
    );
    lib
}

pub struct Fmu {
    pub lib: Library,
    pub guid: CString,
    pub callbacks: Box<Callbacks>,
    pub log: Box<Log>,
    pub vrs: std::collections::HashMap<String, c_uint>,
}

#[macro_export]
macro_rules! sym {
    ($fmu:expr, $name:literal, $t:ty) => {{
        let (lib, name): (&libloading::Library, &str) = (&$fmu.lib, $name);
        let s: libloading::Symbol<$t> = unsafe { lib.get(name.as_bytes()) }.expect(name);
        s
    }};
}

pub type FnInstantiate = unsafe extern "C" fn(
    *const c_char,
    c_int,
    *const c_char,
    *const c_char,
    *const Callbacks,
    c_int,
    c_int,
) -> Component;
pub type FnC = unsafe extern "C" fn(Component) -> c_int;
pub type FnSetup = unsafe extern "C" fn(Component, c_int, f64, f64, c_int, f64) -> c_int;
pub type FnGetReal = unsafe extern "C" fn(Component, *const c_uint, usize, *mut f64) -> c_int;
pub type FnSetReal = unsafe extern "C" fn(Component, *const c_uint, usize, *const f64) -> c_int;
pub type FnGetBool = unsafe extern "C" fn(Component, *const c_uint, usize, *mut c_int) -> c_int;
pub type FnSetString = unsafe extern "C" fn(Component, *const c_uint, usize, *const *const c_char) -> c_int;
pub type FnDoStep = unsafe extern "C" fn(Component, f64, f64, c_int) -> c_int;
pub type FnFree = unsafe extern "C" fn(Component);

impl Fmu {
    pub fn load() -> Fmu {
        let lib = unsafe { Library::new(library_path()) }
            .unwrap_or_else(|e| panic!("loading {}: {e}", library_path().display()));
        let xml = cnc_motion::fmu::model_description();
        let guid = xml
            .split("guid=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .to_string();
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        let callbacks = Box::new(Callbacks {
            logger: Some(logger),
            allocate: std::ptr::null(),
            free: std::ptr::null(),
            step_finished: std::ptr::null(),
            env: &*log as *const Log as *mut c_void,
        });
        // Value references from the modelDescription, as an importer reads them.
        let mut vrs = std::collections::HashMap::new();
        for part in xml.split("<ScalarVariable name=\"").skip(1) {
            let name = part.split('"').next().unwrap().to_string();
            let vr = part
                .split("valueReference=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            vrs.insert(name, vr);
        }
        Fmu {
            lib,
            guid: CString::new(guid).unwrap(),
            callbacks,
            log,
            vrs,
        }
    }

    pub fn vr(&self, name: &str) -> c_uint {
        self.vrs[name]
    }

    pub fn last_log(&self) -> String {
        self.log.lock().unwrap().last().cloned().unwrap_or_default()
    }

    pub fn instantiate(&self, name: &str) -> Component {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/resources");
        self.instantiate_in(name, std::path::Path::new(dir))
    }

    /// An instance whose resources folder is `dir`.
    pub fn instantiate_in(&self, name: &str, dir: &std::path::Path) -> Component {
        let f = sym!(self, "fmi2Instantiate", FnInstantiate);
        let n = CString::new(name).unwrap();
        let uri = CString::new(format!("file://{}", dir.display())).unwrap();
        unsafe {
            f(
                n.as_ptr(),
                1,
                self.guid.as_ptr(),
                uri.as_ptr(),
                &*self.callbacks,
                0,
                1,
            )
        }
    }

    pub fn call(&self, name: &str, c: Component) -> c_int {
        let f: Symbol<FnC> = unsafe { self.lib.get(name.as_bytes()) }.unwrap();
        unsafe { f(c) }
    }

    pub fn init(&self, c: Component, program: Option<&str>) -> c_int {
        let setup = sym!(self, "fmi2SetupExperiment", FnSetup);
        assert_eq!(unsafe { setup(c, 0, 0.0, 0.0, 0, 0.0) }, OK);
        if let Some(p) = program {
            let set = sym!(self, "fmi2SetString", FnSetString);
            let text = CString::new(p).unwrap();
            let vr = self.vr("program");
            assert_eq!(unsafe { set(c, &vr, 1, &text.as_ptr()) }, OK);
        }
        assert_eq!(self.call("fmi2EnterInitializationMode", c), OK);
        self.call("fmi2ExitInitializationMode", c)
    }

    pub fn real(&self, c: Component, name: &str) -> f64 {
        let get = sym!(self, "fmi2GetReal", FnGetReal);
        let vr = self.vr(name);
        let mut v = f64::NAN;
        assert_eq!(unsafe { get(c, &vr, 1, &mut v) }, OK);
        v
    }

    pub fn free(&self, c: Component) {
        let f = sym!(self, "fmi2FreeInstance", FnFree);
        unsafe { f(c) };
    }
}
