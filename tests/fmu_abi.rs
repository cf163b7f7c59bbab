//! The built CncMotion shared library driven through its C ABI, as an importer does it (libloading):
//! a full run of the default program, and every kind of bad call answered with fmi2Error.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[macro_use]
mod common;

use common::*;
use std::ffi::{c_int, c_uint, CString};

#[test]
fn full_run_of_the_default_program_equals_the_engine() {
    let fmu = Fmu::load();
    let c = fmu.instantiate("run");
    assert!(!c.is_null());
    assert_eq!(fmu.init(c, None), OK);
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let get_bool = sym!(fmu, "fmi2GetBoolean", FnGetBool);
    let finished_vr = fmu.vr("status.finished");
    // The same program and machine through the library: outputs must be identical.
    let text = include_str!("../resources/default.ngc");
    let machine = cnc_motion::config::Machine::default();
    let mut engine = cnc_motion::engine::Engine::new(text, "default.ngc", &machine)
        .unwrap()
        .with_servo(true);
    let mut t = 0.0;
    let mut done: c_int = 0;
    let mut n = 0;
    while done == 0 {
        assert_eq!(unsafe { step(c, t, 1e-3, 1) }, OK);
        engine.advance(1e-3).unwrap();
        t = (n + 1) as f64 * 1e-3;
        n += 1;
        assert_eq!(fmu.real(c, "x.command.position"), engine.tick().p[0]);
        assert_eq!(fmu.real(c, "y.position"), engine.axes()[1].position);
        assert_eq!(unsafe { get_bool(c, &finished_vr, 1, &mut done) }, OK);
        assert!(n < 100_000);
    }
    let end = [
        fmu.real(c, "x.command.position"),
        fmu.real(c, "y.command.position"),
        fmu.real(c, "z.command.position"),
    ];
    assert_eq!(end, [0.0, 0.0, 0.005], "the program's last point");
    assert_eq!(fmu.call("fmi2Terminate", c), OK);
    fmu.free(c);
}

/// Each refused call answers fmi2Error with a log line and leaves the instance in the terminal
/// Error state (FMI 2.0 §2.1.3, as the Reference-FMUs): set, doStep and terminate are then
/// refused, get still answers, and fmi2Reset brings it back.
#[test]
fn bad_calls_return_errors_with_a_log_line() {
    let fmu = Fmu::load();
    let c = fmu.instantiate("bad");
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let get = sym!(fmu, "fmi2GetReal", FnGetReal);
    let set = sym!(fmu, "fmi2SetReal", FnSetReal);
    let refused_after_error = |want: &str| {
        assert!(fmu.log.lock().unwrap().iter().any(|l| l.contains(want)), "{want}");
        let mut v = 0.0;
        let vr = fmu.vr("feedOverride");
        assert_eq!(unsafe { get(c, &vr, 1, &mut v) }, OK);
        assert_eq!(unsafe { set(c, &vr, 1, &0.5) }, ERROR);
        assert!(
            fmu.last_log().contains("not allowed in state Error"),
            "{}",
            fmu.last_log()
        );
        assert_eq!(unsafe { step(c, 0.0, 1e-3, 1) }, ERROR);
        assert_eq!(fmu.call("fmi2Terminate", c), ERROR);
        assert_eq!(fmu.call("fmi2Reset", c), OK);
        assert_eq!(fmu.init(c, None), OK);
    };
    // Wrong state: a step before initialization.
    assert_eq!(unsafe { step(c, 0.0, 1e-3, 1) }, ERROR);
    assert!(fmu
        .last_log()
        .contains("fmi2DoStep: not allowed in state Instantiated"));
    assert_eq!(fmu.call("fmi2Reset", c), OK);
    assert_eq!(fmu.init(c, None), OK);
    // Unknown value reference.
    let bad_vr: c_uint = 999_999;
    let mut v = 0.0;
    assert_eq!(unsafe { get(c, &bad_vr, 1, &mut v) }, ERROR);
    refused_after_error("unknown value reference 999999");
    // Wrong type: a Boolean read as Real.
    let vr = fmu.vr("status.finished");
    assert_eq!(unsafe { get(c, &vr, 1, &mut v) }, ERROR);
    refused_after_error("is of type Boolean");
    // NULL arrays with n > 0.
    assert_eq!(unsafe { get(c, std::ptr::null(), 2, &mut v) }, ERROR);
    refused_after_error("NULL array");
    // A fixed parameter after initialization.
    let vr = fmu.vr("x.maxJerk");
    assert_eq!(unsafe { set(c, &vr, 1, &1.0) }, ERROR);
    refused_after_error("cannot be set in state StepComplete");
    // An input is fine; a value out of its range is not.
    let vr = fmu.vr("feedOverride");
    assert_eq!(unsafe { set(c, &vr, 1, &0.5) }, OK);
    assert_eq!(unsafe { set(c, &vr, 1, &3.0) }, ERROR);
    refused_after_error("'feedOverride' = 3 out of range (0 … 2)");
    // doStep off the slave's time, NaN time, a negative step.
    assert_eq!(unsafe { step(c, 0.5, 1e-3, 1) }, ERROR);
    refused_after_error("is not the slave's time");
    assert_eq!(unsafe { step(c, f64::NAN, 1e-3, 1) }, ERROR);
    refused_after_error("currentCommunicationPoint must be finite");
    assert_eq!(unsafe { step(c, 0.0, -1.0, 1) }, ERROR);
    refused_after_error("communicationStepSize must be > 0");
    // Float drift of the master's time far below the tolerance (1 µs) is accepted.
    let mut t = 0.0;
    for _ in 0..1000 {
        assert_eq!(unsafe { step(c, t + 1e-12, 1e-3, 1) }, OK);
        t += 1e-3;
    }
    // NULL instance.
    assert_eq!(unsafe { step(std::ptr::null_mut(), 0.0, 1e-3, 1) }, ERROR);
    fmu.free(c);
    // Wrong GUID: no instance, a log line.
    let f = sym!(fmu, "fmi2Instantiate", FnInstantiate);
    let name = CString::new("x").unwrap();
    let guid = CString::new("{not-this}").unwrap();
    let inst = unsafe {
        f(
            name.as_ptr(),
            1,
            guid.as_ptr(),
            std::ptr::null(),
            &*fmu.callbacks,
            0,
            0,
        )
    };
    assert!(inst.is_null());
    assert!(fmu.last_log().contains("GUID"));
}

#[test]
fn bad_programs_fail_initialization_with_their_place() {
    let fmu = Fmu::load();
    for (program, want) in [
        (
            "G21 G90\nG1 X1 F100\nG41 D1 X2\n",
            "program:3:5: D1: tool 1 is not in the machine's tool table ([tool.1])",
        ),
        ("G1 X1 F100\nG1 X2 Y$\n", "program:2:7: Y: a number is missing"),
        (
            "G21 G0 X10 Y0\nG3 X0 Y10.5 I-10 J0 F100\n",
            "program:2:1: G3: end point is 0.5000 mm off the circle",
        ),
    ] {
        let c = fmu.instantiate("prog");
        assert_eq!(fmu.init(c, Some(program)), ERROR);
        assert!(fmu.last_log().starts_with(want), "{} vs {want}", fmu.last_log());
        // Reset brings the instance back; a good program then runs.
        assert_eq!(fmu.call("fmi2Reset", c), OK);
        assert_eq!(fmu.init(c, Some("G21 G1 X1 F600\nM30\n")), OK);
        fmu.free(c);
    }
}

/// Issue 11 through the C ABI: each extreme parameter is refused with a logged "out of range"
/// (at fmi2SetReal or fmi2ExitInitializationMode), fast; none reaches a hanging fmi2DoStep.
#[test]
fn extreme_parameters_are_refused_through_the_c_abi() {
    let fmu = Fmu::load();
    let set = sym!(fmu, "fmi2SetReal", FnSetReal);
    for (name, value) in [
        ("x.servo.screwLead", 1e200),
        ("x.servo.tableMass", 5e-324),
        ("y.servo.currentTimeConstant", 5e-324),
        ("z.servo.axialStiffness", 1e308),
        ("x.servo.axialDamping", 1e308),
        ("x.servo.velocityGain", 1e308),
        ("x.servo.encoderCounts", 5e-324),
        ("x.servo.servoRate", 1e12),
        ("machine.interpolationPeriod", 1e-12),
        ("machine.interpolationPeriod", 1.7976931348623157e308),
        ("x.maxAcceleration", 1e-308),
    ] {
        let start = std::time::Instant::now();
        let c = fmu.instantiate("extreme");
        let vr = fmu.vr(name);
        let status = match unsafe { set(c, &vr, 1, &value) } {
            OK => fmu.init(c, None),
            refused => refused,
        };
        assert_eq!(status, ERROR, "{name} = {value}");
        // encoderCounts is an Integer now: a Real is refused for its type.
        let log = fmu.last_log();
        assert!(
            log.contains("out of range") || log.contains("is of type Integer"),
            "{name}: {log}"
        );
        assert!(start.elapsed().as_secs_f64() < 2.0, "{name}");
        fmu.free(c);
    }
    let c = fmu.instantiate("load");
    assert_eq!(fmu.init(c, None), OK);
    let vr = fmu.vr("x.loadForce");
    assert_eq!(unsafe { set(c, &vr, 1, &1e308) }, ERROR);
    assert!(
        fmu.last_log()
            .contains("'x.loadForce' = 1e308 out of range (-10000000 … 10000000)"),
        "{}",
        fmu.last_log()
    );
    fmu.free(c);
}

/// Run `text` through the FMU's `program` string and the library's engine side by side, 1 ms
/// steps until the FMU says finished: the command position on `axis` equal at every tick.
/// Returns the instance (still to be freed) and the lowest position seen on that axis.
fn run_beside_the_engine(fmu: &Fmu, name: &str, text: &str, axis: usize) -> (Component, f64) {
    let c = fmu.instantiate(name);
    assert_eq!(fmu.init(c, Some(text)), OK, "{}", fmu.last_log());
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let get_bool = sym!(fmu, "fmi2GetBoolean", FnGetBool);
    let finished_vr = fmu.vr("status.finished");
    let machine = cnc_motion::config::Machine::default();
    let mut engine = cnc_motion::engine::Engine::new(text, "program", &machine)
        .unwrap()
        .with_servo(true);
    let position = format!("{}.command.position", ["x", "y", "z"][axis]);
    let (mut n, mut done, mut lowest) = (0, 0, 0.0_f64);
    while done == 0 {
        assert_eq!(unsafe { step(c, n as f64 * 1e-3, 1e-3, 1) }, OK);
        engine.advance(1e-3).unwrap();
        n += 1;
        let p = fmu.real(c, &position);
        assert_eq!(p, engine.tick().p[axis]);
        lowest = lowest.min(p);
        assert_eq!(unsafe { get_bool(c, &finished_vr, 1, &mut done) }, OK);
        assert!(n < 200_000);
    }
    (c, lowest)
}

/// Issue 14 through the FMU's `program` string: cutter compensation with the radius in the word
/// (LinuxCNC "G41.1, G42.1"), work offset G10 L2 (LinuxCNC "G10 L2"), G92 and block delete run
/// through the C ABI exactly as through the library, and the tool centre leaves the contour by
/// the radius (2 mm right of the first edge, y = −2 mm).
#[test]
fn compensated_program_through_the_program_string_equals_the_engine() {
    let text = "G21 G90 G17 F3000\nG10 L2 P1 X1\n/G0 X50\nG0 X-1 Y0\nG42.1 D4 G1 X9 Y0\nX29\n\
                G3 X39 Y10 R10\nG1 Y30\nX9\nG40 X-1 Y-1\nG92 X0 Y0\nG0 X1\nM2\n";
    let fmu = Fmu::load();
    let (c, y_min) = run_beside_the_engine(&fmu, "comp", text, 1);
    // Within the default G64 path tolerance (0.01 mm) of the blended corners.
    assert!(
        (y_min + 0.002).abs() < 1e-5,
        "tool centre 2 mm right of y = 0: {y_min}"
    );
    // After G92 X0 at machine X0 (program X−1 + G10 offset 1), X1 is machine X1.
    let x = fmu.real(c, "x.command.position");
    assert!((x - 0.001).abs() < 1e-12, "{x}");
    fmu.free(c);
}

/// Issue 14's other words through the FMU's `program` string, tick for tick equal to the
/// library: parameters and expressions (LinuxCNC "Parameters", "Expressions"), G43.1 / G49,
/// G54…G59.3 with G10 L20, G53, G81 / G83 with G98 / G99 / G80, G28, M1, block delete.
#[test]
fn new_words_through_the_program_string_equal_the_engine() {
    let text = "G21 G90 G17\n#<depth> = 2\n#1 = [#<depth> * 2]\nG10 L20 P2 X0 Y0 Z0\nG55 G43.1 Z1\n\
                /G0 X99\nG0 X[#1 + 1] Y SIN[90]\nG81 G98 X5 Y5 Z-#<depth> R1 F600\nX8\nG80\nM1\n\
                G83 G99 X10 Y10 Z-3 R1 Q1\nG80 G49\nG53 G0 Z5\nG28\nM2\n";
    let fmu = Fmu::load();
    let (c, z_min) = run_beside_the_engine(&fmu, "words", text, 2);
    // G43.1 Z1 lifts every programmed Z by 1 mm: G83's bottom Z−3 is machine Z−2.
    assert!((z_min + 0.002).abs() < 1e-9, "{z_min}");
    let end = ["x", "y", "z"].map(|a| fmu.real(c, &format!("{a}.command.position")));
    assert_eq!(end, [0.0, 0.0, 0.0], "G28 ends at the home position");
    fmu.free(c);
}

/// O-word control flow (LinuxCNC "O Codes") and G93 through the FMU's `program` string, tick for
/// tick equal to the library: a subroutine with arguments called from a while loop (the
/// "Looping" sawtooth made of calls), a repeat, an inverse-time move; the end is the known corner.
#[test]
fn o_words_through_the_program_string_equal_the_engine() {
    let text = "G21 G90 F3000\no<tooth> sub\nG1 X0\nG1 Y#1 X1\no<tooth> endsub\n#1 = 0\n\
                o101 while [#1 LT 5]\no<tooth> call [#1 / 10]\n#1 = [#1 + 1]\no101 endwhile\n\
                o102 repeat [2]\nG91 G1 Y0.5\no102 endrepeat\nG90\nG93 G1 X2 F60\nG94 G1 X1 F3000\nM2\n";
    let fmu = Fmu::load();
    let (c, _) = run_beside_the_engine(&fmu, "owords", text, 1);
    // Last tooth at Y 0.4, then two G91 steps of 0.5, out to X2 (G93) and back: (1, 1.4).
    let end = ["x", "y"].map(|a| fmu.real(c, &format!("{a}.command.position")));
    assert!(
        (end[0] - 1e-3).abs() < 1e-12 && (end[1] - 1.4e-3).abs() < 1e-12,
        "{end:?}"
    );
    fmu.free(c);
}
