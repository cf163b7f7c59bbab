//! CncMotion's output derivatives through its C ABI, as a co-simulation master reads them
//! (fmi2GetRealOutputDerivatives after every step of one interpolation period T), over whole
//! programs (lines, arcs, corners): against finite differences and the Taylor expansion of the
//! outputs themselves, with the error bounds that a jerk limit J gives; and the refusals.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[macro_use]
mod common;

use common::*;
use std::ffi::{c_int, c_uint};

type FnOutputDerivatives =
    unsafe extern "C" fn(Component, *const c_uint, usize, *const c_int, *mut f64) -> c_int;

const WARNING: c_int = 1;
const T: f64 = 1e-3;
const ARCS: &str = "G21 G90 G17 G64\nG0 X0 Y0 Z0\nG1 X10 F3000\nG2 X20 Y0 I5 J0\nG3 X30 Y0 I5\nG1 X30 Y10 Z-2\nG1 X0 Y0 Z0\nM30\n";
const OUTPUTS: [&str; 4] = ["position", "velocity", "acceleration", "jerk"];

/// One axis' command after each step of T until the program is finished: per tick the outputs
/// p, v, a, j and the derivatives d[n][k] = order k+1 of output n (n + k + 1 ≤ 3).
struct Run {
    value: Vec<[f64; 4]>,
    derivative: Vec<[[f64; 3]; 3]>,
}

fn run(fmu: &Fmu, program: Option<&str>, axis: &str) -> Run {
    let c = fmu.instantiate("derivatives");
    assert_eq!(fmu.init(c, program), OK);
    let get = sym!(fmu, "fmi2GetRealOutputDerivatives", FnOutputDerivatives);
    let get_bool = sym!(fmu, "fmi2GetBoolean", FnGetBool);
    let name = |n: usize| format!("{axis}.command.{}", OUTPUTS[n]);
    // Every (output, order) the FMU knows, in one call.
    let requests: Vec<(usize, usize)> = (0..3).flat_map(|n| (1..=3 - n).map(move |k| (n, k))).collect();
    let vrs: Vec<c_uint> = requests.iter().map(|&(n, _)| fmu.vr(&name(n))).collect();
    let orders: Vec<c_int> = requests.iter().map(|&(_, k)| k as c_int).collect();
    let (finished, mut done) = (fmu.vr("status.finished"), 0);
    let mut r = Run {
        value: Vec::new(),
        derivative: Vec::new(),
    };
    while done == 0 {
        r.value.push(std::array::from_fn(|n| fmu.real(c, &name(n))));
        let mut d = vec![f64::NAN; vrs.len()];
        assert_eq!(
            unsafe { get(c, vrs.as_ptr(), vrs.len(), orders.as_ptr(), d.as_mut_ptr()) },
            OK
        );
        let mut tick = [[f64::NAN; 3]; 3];
        for (&(n, k), x) in requests.iter().zip(d) {
            tick[n][k - 1] = x;
        }
        r.derivative.push(tick);
        assert_eq!(fmu.step(c, (r.value.len() - 1) as f64 * T, T), OK);
        assert_eq!(unsafe { get_bool(c, &finished, 1, &mut done) }, OK);
        assert!(r.value.len() < 100_000);
    }
    fmu.free(c);
    r
}

/// The bounds, for every axis of the default program and a program with arcs: with |j| ≤ J,
/// |central difference of p − ṗ| ≤ J T²/6, of v − v̇ ≤ J T/2, of a − ȧ ≤ 2J, and the Taylor
/// polynomial of p of degree 3 misses p(t + T) by ≤ 2J T³/6. Each higher order is exactly the
/// next output (what the importer reads as that output).
#[test]
fn derivatives_match_the_outputs_within_the_jerk_bounds() {
    let fmu = Fmu::load();
    let machine = cnc_motion::config::Machine::default();
    for program in [None, Some(ARCS)] {
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            let jerk = machine.axes[i].max_jerk;
            let r = run(&fmu, program, axis);
            let bounds = [jerk * T * T / 6.0, jerk * T / 2.0, 2.0 * jerk];
            let mut worst = [0.0f64; 4];
            for k in 1..r.value.len() - 1 {
                let (p, d) = (&r.value, &r.derivative[k]);
                for n in 0..3 {
                    let central = (p[k + 1][n] - p[k - 1][n]) / (2.0 * T);
                    let e = (central - d[n][0]).abs();
                    assert!(
                        e <= bounds[n] + 1e-12,
                        "{axis}.{} tick {k}: {central} vs {}",
                        OUTPUTS[n],
                        d[n][0]
                    );
                    worst[n] = worst[n].max(e / bounds[n]);
                    for order in 1..=3 - n {
                        assert_eq!(
                            d[n][order - 1],
                            p[k][n + order],
                            "{axis} order {order} of {}",
                            OUTPUTS[n]
                        );
                    }
                }
                let taylor = p[k][0] + d[0][0] * T + d[0][1] * T * T / 2.0 + d[0][2] * T.powi(3) / 6.0;
                let e = (p[k + 1][0] - taylor).abs();
                let bound = 2.0 * jerk * T.powi(3) / 6.0;
                assert!(e <= bound + 1e-12, "{axis} tick {k}: Taylor misses by {e}");
                worst[3] = worst[3].max(e / bound);
            }
            // The bounds are reached (the tests can fail): the motion uses its jerk.
            if program.is_none() && *axis != "z" {
                assert!(worst[0] > 0.5 && worst[1] > 0.25, "{axis}: {worst:?}");
            }
            eprintln!("{axis}: worst error / bound (ṗ, v̇, ȧ, Taylor) = {worst:.3?}");
        }
    }
}

/// Orders outside 1 … maxOutputDerivativeOrder and non-outputs are fmi2Error; derivatives the
/// model does not know (the drives', jerk's) come back as 0 with fmi2Warning.
#[test]
fn unknown_derivatives_warn_and_bad_requests_are_errors() {
    let fmu = Fmu::load();
    let get = sym!(fmu, "fmi2GetRealOutputDerivatives", FnOutputDerivatives);
    let ask = |name: &str, order: c_int| {
        let c = fmu.instantiate("bad");
        assert_eq!(fmu.init(c, None), OK);
        assert_eq!(fmu.step(c, 0.0, 0.05), OK);
        let (vr, mut d) = (fmu.vr(name), f64::NAN);
        let status = unsafe { get(c, &vr, 1, &order, &mut d) };
        fmu.free(c);
        (status, d)
    };
    assert_eq!(ask("x.command.position", 4).0, ERROR);
    assert_eq!(ask("x.command.position", 0).0, ERROR);
    assert_eq!(ask("feedOverride", 1).0, ERROR);
    assert_eq!(ask("x.driveForce", 1), (WARNING, 0.0));
    assert_eq!(ask("x.command.jerk", 1), (WARNING, 0.0));
    assert_eq!(ask("z.command.position", 1).0, OK);
}

/// CncMotion declares no directional derivatives and refuses them.
#[test]
fn directional_derivatives_are_refused() {
    type FnDirectional = unsafe extern "C" fn(
        Component,
        *const c_uint,
        usize,
        *const c_uint,
        usize,
        *const f64,
        *mut f64,
    ) -> c_int;
    let fmu = Fmu::load();
    let c = fmu.instantiate("dd");
    assert_eq!(fmu.init(c, None), OK);
    let f = sym!(fmu, "fmi2GetDirectionalDerivative", FnDirectional);
    let (u, k, seed, mut out) = (fmu.vr("x.position"), fmu.vr("feedOverride"), 1.0, 0.0);
    assert_eq!(unsafe { f(c, &u, 1, &k, 1, &seed, &mut out) }, ERROR);
    assert!(
        fmu.last_log().contains("no directional derivatives"),
        "{}",
        fmu.last_log()
    );
    fmu.free(c);
}
