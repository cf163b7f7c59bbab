//! MachineStructure's directional derivatives through its C ABI, as an importer calls them
//! (libloading): every entry of the state-space matrices A, B, C, D of each axis against the
//! mass-spring-damper form built here from the mode parameters the FMU reports, and the Jacobian
//! against the FMU's own behaviour (outputs = C x + D u, a short step = x + h (A x + B u)).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use libloading::Library;
use std::ffi::{c_char, c_int, c_uint, c_void, CString};

type Component = *mut c_void;
const OK: c_int = 0;
const ERROR: c_int = 3;

#[repr(C)]
struct Callbacks {
    logger: Option<unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char)>,
    allocate: *const c_void,
    free: *const c_void,
    step_finished: *const c_void,
    env: *mut c_void,
}

unsafe extern "C" fn logger(_: *mut c_void, _: *const c_char, _: c_int, _: *const c_char, _: *const c_char) {}

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
type FnReal = unsafe extern "C" fn(Component, *const c_uint, usize, *mut f64) -> c_int;
type FnDoStep = unsafe extern "C" fn(Component, f64, f64, c_int) -> c_int;
type FnDirectional = unsafe extern "C" fn(
    Component,
    *const c_uint,
    usize,
    *const c_uint,
    usize,
    *const f64,
    *mut f64,
) -> c_int;

/// The shared library cargo built with this test (the crate is a cdylib too), an instance of it
/// initialized, and the value references of the modelDescription.
struct Fmu {
    lib: Library,
    c: Component,
    vrs: std::collections::HashMap<String, c_uint>,
    _callbacks: Box<Callbacks>,
}

impl Fmu {
    fn new(coupling_mass: f64) -> Fmu {
        let exe = std::env::current_exe().unwrap();
        let lib =
            unsafe { Library::new(exe.with_file_name(libloading::library_filename("machine_structure"))) }
                .expect("the machine_structure cdylib beside the test");
        let xml = machine_structure::model_description();
        let guid = CString::new(xml.split("guid=\"").nth(1).unwrap().split('"').next().unwrap()).unwrap();
        let mut vrs = std::collections::HashMap::new();
        for part in xml.split("<ScalarVariable name=\"").skip(1) {
            let name = part.split('"').next().unwrap().to_string();
            let vr = part
                .split("valueReference=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap();
            vrs.insert(name, vr.parse().unwrap());
        }
        let callbacks = Box::new(Callbacks {
            logger: Some(logger),
            allocate: std::ptr::null(),
            free: std::ptr::null(),
            step_finished: std::ptr::null(),
            env: std::ptr::null_mut(),
        });
        let c = unsafe {
            let inst: libloading::Symbol<FnInstantiate> = lib.get(b"fmi2Instantiate").unwrap();
            let name = CString::new("ms").unwrap();
            inst(
                name.as_ptr(),
                1,
                guid.as_ptr(),
                std::ptr::null(),
                &*callbacks,
                0,
                0,
            )
        };
        assert!(!c.is_null());
        let fmu = Fmu {
            lib,
            c,
            vrs,
            _callbacks: callbacks,
        };
        unsafe {
            let setup: libloading::Symbol<FnSetup> = fmu.lib.get(b"fmi2SetupExperiment").unwrap();
            assert_eq!(setup(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(fmu.call("fmi2EnterInitializationMode"), OK);
            for a in ["x", "y", "z"] {
                fmu.set(&format!("{a}.couplingMass"), coupling_mass);
            }
            assert_eq!(fmu.call("fmi2ExitInitializationMode"), OK);
        }
        fmu
    }

    fn call(&self, name: &str) -> c_int {
        unsafe { self.lib.get::<FnC>(name.as_bytes()).unwrap()(self.c) }
    }

    fn set(&self, name: &str, x: f64) {
        let f = unsafe { self.lib.get::<FnReal>(b"fmi2SetReal").unwrap() };
        assert_eq!(
            unsafe { f(self.c, &self.vrs[name], 1, &x as *const f64 as *mut f64) },
            OK,
            "{name}"
        );
    }

    fn get(&self, name: &str) -> f64 {
        let f = unsafe { self.lib.get::<FnReal>(b"fmi2GetReal").unwrap() };
        let mut x = f64::NAN;
        assert_eq!(unsafe { f(self.c, &self.vrs[name], 1, &mut x) }, OK, "{name}");
        x
    }

    fn step(&self, t: f64, h: f64) {
        let f = unsafe { self.lib.get::<FnDoStep>(b"fmi2DoStep").unwrap() };
        assert_eq!(unsafe { f(self.c, t, h, 1) }, OK);
    }

    /// J · seed for `unknowns` by `knowns` (fmi2GetDirectionalDerivative): the status and dz.
    fn directional(&self, unknowns: &[&str], knowns: &[&str], seed: &[f64]) -> (c_int, Vec<f64>) {
        let f = unsafe {
            self.lib
                .get::<FnDirectional>(b"fmi2GetDirectionalDerivative")
                .unwrap()
        };
        let u: Vec<c_uint> = unknowns.iter().map(|n| self.vrs[*n]).collect();
        let k: Vec<c_uint> = knowns.iter().map(|n| self.vrs[*n]).collect();
        let mut dz = vec![f64::NAN; u.len()];
        let status = unsafe {
            f(
                self.c,
                u.as_ptr(),
                u.len(),
                k.as_ptr(),
                k.len(),
                seed.as_ptr(),
                dz.as_mut_ptr(),
            )
        };
        (status, dz)
    }

    /// The Jacobian column by column (unit seeds), as rows of unknowns.
    fn jacobian(&self, unknowns: &[&str], knowns: &[&str]) -> Vec<Vec<f64>> {
        let mut j = vec![vec![0.0; knowns.len()]; unknowns.len()];
        for col in 0..knowns.len() {
            let seed: Vec<f64> = (0..knowns.len()).map(|k| f64::from(u8::from(k == col))).collect();
            let (status, dz) = self.directional(unknowns, knowns, &seed);
            assert_eq!(status, OK);
            for (row, d) in j.iter_mut().zip(dz) {
                row[col] = d;
            }
        }
        j
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        let free = unsafe {
            self.lib
                .get::<unsafe extern "C" fn(Component)>(b"fmi2FreeInstance")
                .unwrap()
        };
        unsafe { free(self.c) };
    }
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale.max(1.0)
}

/// Knowns of axis `a`: driveForce, then q and v of mode 1 and 2; unknowns: the outputs, then the
/// state derivatives v (= der q) and a (= der v) of each mode.
fn names(a: &str) -> (Vec<String>, Vec<String>) {
    let knowns = ["driveForce", "mode1.q", "mode1.v", "mode2.q", "mode2.v"];
    let unknowns = [
        "deflection",
        "acceleration",
        "loadForce",
        "mode1.v",
        "mode1.a",
        "mode2.v",
        "mode2.a",
    ];
    let full = |l: &[&str]| l.iter().map(|n| format!("{a}.{n}")).collect();
    (full(&knowns), full(&unknowns))
}

/// [C D; A B] of one axis from the modes: per mode q̇ = v, v̇ = F/m − 2ζω v − ω² q (m q̈ + c q̇ + k q
/// = F with k = m ω², c = 2 ζ m ω); deflection = Σ q, acceleration = Σ v̇,
/// loadForce = −M Σ (v̇ − F/m).
fn expected(fmu: &Fmu, a: &str) -> Vec<Vec<f64>> {
    let mode = |k: usize, p: &str| fmu.get(&format!("{a}.mode{k}.{p}"));
    let big_m = fmu.get(&format!("{a}.couplingMass"));
    let mut rows = vec![vec![0.0; 5]; 7];
    for k in 1..=2 {
        let (m, zeta, w) = (
            mode(k, "mass"),
            mode(k, "damping"),
            2.0 * std::f64::consts::PI * mode(k, "frequency"),
        );
        let (stiff, damp) = (m * w * w, 2.0 * zeta * m * w);
        let (q, v) = (2 * k - 1, 2 * k);
        let dv = [1.0 / m, -stiff / m, -damp / m];
        rows[0][q] = 1.0;
        for (col, d) in [0, q, v].into_iter().zip(dv) {
            rows[1][col] += d;
            if col != 0 {
                rows[2][col] -= big_m * d;
            }
        }
        rows[1 + 2 * k][v] = 1.0;
        for (col, d) in [0, q, v].into_iter().zip(dv) {
            rows[2 + 2 * k][col] = d;
        }
    }
    rows
}

/// Drive every axis with its own force for a while, so that each mode's q and v are far from 0.
fn excite(fmu: &Fmu) -> f64 {
    let mut t = 0.0;
    for (n, f) in [(7, 900.0), (5, -400.0), (3, 1500.0)] {
        for (i, a) in ["x", "y", "z"].iter().enumerate() {
            fmu.set(&format!("{a}.driveForce"), f * (1.0 + i as f64 * 0.3));
        }
        for _ in 0..n {
            fmu.step(t, 1e-3);
            t += 1e-3;
        }
    }
    t
}

#[test]
fn the_jacobian_is_the_state_space_matrices_of_the_modes() {
    let fmu = Fmu::new(50.0);
    excite(&fmu);
    for a in ["x", "y", "z"] {
        let (knowns, unknowns) = names(a);
        let k: Vec<&str> = knowns.iter().map(String::as_str).collect();
        let u: Vec<&str> = unknowns.iter().map(String::as_str).collect();
        let got = fmu.jacobian(&u, &k);
        let want = expected(&fmu, a);
        for (r, (g, w)) in got.iter().zip(&want).enumerate() {
            for (c, (x, y)) in g.iter().zip(w).enumerate() {
                assert!(
                    close(*x, *y, y.abs()),
                    "{a}: ∂{}/∂{} = {x}, matrices give {y}",
                    u[r],
                    k[c]
                );
            }
        }
        // Another axis' knowns do not act on this axis.
        let other = if a == "x" { "y.driveForce" } else { "x.driveForce" };
        assert_eq!(fmu.jacobian(&u, &[other]).concat(), vec![0.0; u.len()]);
    }
}

#[test]
fn the_jacobian_gives_the_outputs_and_a_short_step() {
    let fmu = Fmu::new(50.0);
    let t = excite(&fmu);
    for a in ["x", "y", "z"] {
        let (knowns, unknowns) = names(a);
        let k: Vec<&str> = knowns.iter().map(String::as_str).collect();
        let u: Vec<&str> = unknowns.iter().map(String::as_str).collect();
        // The model is linear without offsets: every unknown is J · (u, x).
        let x: Vec<f64> = k.iter().map(|n| fmu.get(n)).collect();
        let (status, y) = fmu.directional(&u, &k, &x);
        assert_eq!(status, OK);
        for (name, y) in u.iter().zip(&y) {
            let value = fmu.get(name);
            assert!(
                (value - y).abs() <= 1e-9 * value.abs().max(1e-9),
                "{name} = {value}, J·x = {y}"
            );
        }
    }
    // A step of h with the force held: (x(t+h) − x(t))/h = A x + B u + O(h).
    let h = 1e-7;
    let before: Vec<Vec<f64>> = ["x", "y", "z"]
        .iter()
        .map(|a| names(a).0.iter().map(|n| fmu.get(n)).collect())
        .collect();
    let rates: Vec<Vec<f64>> = ["x", "y", "z"]
        .iter()
        .zip(&before)
        .map(|(a, x)| {
            let k = names(a).0;
            let k: Vec<&str> = k.iter().map(String::as_str).collect();
            let states = [
                format!("{a}.mode1.q"),
                format!("{a}.mode1.v"),
                format!("{a}.mode2.q"),
                format!("{a}.mode2.v"),
            ];
            let ders = [
                format!("{a}.mode1.v"),
                format!("{a}.mode1.a"),
                format!("{a}.mode2.v"),
                format!("{a}.mode2.a"),
            ];
            let d: Vec<&str> = ders.iter().map(String::as_str).collect();
            let (status, rate) = fmu.directional(&d, &k, x);
            assert_eq!(status, OK);
            assert_eq!(states.len(), rate.len());
            rate
        })
        .collect();
    fmu.step(t, h);
    for ((a, x), rate) in ["x", "y", "z"].iter().zip(&before).zip(&rates) {
        let after: Vec<f64> = names(a).0.iter().map(|n| fmu.get(n)).collect();
        for s in 0..4 {
            let fd = (after[s + 1] - x[s + 1]) / h;
            assert!(
                (fd - rate[s]).abs() <= 1e-3 * rate[s].abs().max(1e-6),
                "{a} state {s}: {fd} vs {}",
                rate[s]
            );
        }
    }
}

#[test]
fn directional_derivatives_of_parameters_are_refused() {
    let fmu = Fmu::new(0.0);
    let (status, _) = fmu.directional(&["x.acceleration"], &["x.mode1.mass"], &[1.0]);
    assert_eq!(status, ERROR, "a parameter is not a known");
    let fmu = Fmu::new(0.0);
    let (status, _) = fmu.directional(&["x.driveForce"], &["x.driveForce"], &[1.0]);
    assert_eq!(status, ERROR, "an input is not an unknown");
}

type FnInputDerivatives =
    unsafe extern "C" fn(Component, *const c_uint, usize, *const c_int, *const f64) -> c_int;

impl Fmu {
    fn set_derivative(&self, name: &str, order: c_int, x: f64) -> c_int {
        let f = unsafe {
            self.lib
                .get::<FnInputDerivatives>(b"fmi2SetRealInputDerivatives")
                .unwrap()
        };
        unsafe { f(self.c, &self.vrs[name], 1, &order, &x) }
    }
}

/// canInterpolateInputs: fmi2SetRealInputDerivatives ramps a drive force over the steps that
/// follow (first-order hold). From rest under F = r·t each mode follows the textbook ramp
/// response q = (r/k)·[t − 2ζ/ω + e^{−ζωt}(2ζ/ω·cos ω_d t + (2ζ² − 1)/ω_d·sin ω_d t)], in one step
/// or in steps whose value and slope the importer sets again each time (as fmpy does); setting the
/// value alone holds it again.
#[test]
fn a_drive_force_ramps_with_its_derivative() {
    let r = 4.0e4;
    let exact = |fmu: &Fmu, t: f64| -> f64 {
        (1..=2)
            .map(|k| {
                let mode = |p: &str| fmu.get(&format!("x.mode{k}.{p}"));
                let (m, zeta, w) = (
                    mode("mass"),
                    mode("damping"),
                    2.0 * std::f64::consts::PI * mode("frequency"),
                );
                let wd = w * (1.0 - zeta * zeta).sqrt();
                let free = 2.0 * zeta / w * (wd * t).cos() + (2.0 * zeta * zeta - 1.0) / wd * (wd * t).sin();
                r / (m * w * w) * (t - 2.0 * zeta / w + (-zeta * w * t).exp() * free)
            })
            .sum()
    };
    let one = Fmu::new(50.0);
    assert_eq!(one.set_derivative("x.driveForce", 1, r), OK);
    one.step(0.0, 0.02);
    let want = exact(&one, 0.02);
    let near = |x: f64| (x - want).abs() <= 1e-11 * want.abs();
    assert!(
        near(one.get("x.deflection")),
        "{} vs {want}",
        one.get("x.deflection")
    );
    assert_eq!(one.get("x.driveForce"), r * 0.02, "the input at the new time");
    let many = Fmu::new(50.0);
    for j in 0..20 {
        let t = j as f64 * 1e-3;
        many.set("x.driveForce", r * t);
        assert_eq!(many.set_derivative("x.driveForce", 1, r), OK);
        many.step(t, 1e-3);
    }
    assert!(
        near(many.get("x.deflection")),
        "{} vs {want}",
        many.get("x.deflection")
    );
    // The value alone holds the force (the slope set before it is dropped).
    let (held, ramped) = (Fmu::new(0.0), Fmu::new(0.0));
    assert_eq!(held.set_derivative("x.driveForce", 1, r), OK);
    held.set("x.driveForce", 100.0);
    ramped.set("x.driveForce", 100.0);
    held.step(0.0, 0.01);
    ramped.step(0.0, 0.01);
    assert_eq!(held.get("x.deflection"), ramped.get("x.deflection"));
    // Orders other than 1, outputs and non-finite slopes are refused.
    for (name, order, x) in [
        ("x.driveForce", 2, 1.0),
        ("x.loadForce", 1, 1.0),
        ("x.driveForce", 1, f64::NAN),
    ] {
        assert_eq!(
            Fmu::new(0.0).set_derivative(name, order, x),
            ERROR,
            "{name} order {order} = {x}"
        );
    }
}
