//! Parameters through the C ABI as importers set them (issue 18): every start value written, in any
//! order; relations between parameters checked only at fmi2ExitInitializationMode; `machineFile`
//! read by the CLI's loader, combined with the parameters by one rule (a parameter whose value
//! differs from its declared start value overrides the file), whatever the order of the calls; and
//! seed 003's pocket with its machine file, tick for tick as the command line runs it.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[macro_use]
mod common;

use cnc_motion::fmu::CncMotionFmu;
use common::*;
use fmi2::{Causality, Model, Type, Value};
use proptest::prelude::*;
use std::ffi::{c_int, CString};

type FnSetInt = unsafe extern "C" fn(Component, *const u32, usize, *const c_int) -> c_int;
type FnSetBool = FnSetInt;

/// Set one variable through the C ABI by its type; the status.
fn set(fmu: &Fmu, c: Component, name: &str, value: &Value) -> c_int {
    let vr = fmu.vr(name);
    match value {
        Value::Real(x) => {
            let f = sym!(fmu, "fmi2SetReal", FnSetReal);
            unsafe { f(c, &vr, 1, x) }
        }
        Value::Integer(n) => {
            let f = sym!(fmu, "fmi2SetInteger", FnSetInt);
            unsafe { f(c, &vr, 1, n) }
        }
        Value::Boolean(b) => {
            let f = sym!(fmu, "fmi2SetBoolean", FnSetBool);
            unsafe { f(c, &vr, 1, &c_int::from(*b)) }
        }
        Value::String(s) => {
            let f = sym!(fmu, "fmi2SetString", FnSetString);
            let text = CString::new(s.as_str()).unwrap();
            unsafe { f(c, &vr, 1, &text.as_ptr()) }
        }
    }
}

/// Every parameter with its declared start value, in value-reference order (as fmpy and most
/// importers write them before initialization).
fn start_values() -> Vec<(String, Value)> {
    let info = CncMotionFmu::info();
    let starts = fmi2::start_values::<CncMotionFmu>();
    info.variables
        .iter()
        .zip(starts)
        .filter(|(v, _)| v.causality == Causality::Parameter)
        .map(|(v, s)| (v.name.clone(), s.expect("parameters have a start value")))
        .collect()
}

fn enter_init(fmu: &Fmu, c: Component) {
    let setup = sym!(fmu, "fmi2SetupExperiment", FnSetup);
    assert_eq!(unsafe { setup(c, 0, 0.0, 0.0, 0, 0.0) }, OK);
    assert_eq!(fmu.call("fmi2EnterInitializationMode", c), OK);
}

/// Instantiate, write `values` in the given order, initialize: the status of
/// fmi2ExitInitializationMode (every set must succeed).
fn initialize_with(fmu: &Fmu, name: &str, values: &[(String, Value)]) -> (Component, c_int) {
    let c = fmu.instantiate(name);
    for (n, v) in values {
        assert_eq!(set(fmu, c, n, v), OK, "{n} = {v:?}: {}", fmu.last_log());
    }
    enter_init(fmu, c);
    (c, fmu.call("fmi2ExitInitializationMode", c))
}

/// A valid parameter set whose relations do not hold part-way for some orders: rated torques
/// above the default peak (1.9 N·m) with peaks above them, and other values off their starts.
fn valid_set() -> Vec<(String, Value)> {
    let changes = [
        ("x.servo.ratedTorque", 3.0),
        ("x.servo.peakTorque", 9.0),
        ("y.servo.peakTorque", 0.5),
        ("y.servo.ratedTorque", 0.4),
        ("z.servo.ratedTorque", 2.5),
        ("z.servo.peakTorque", 2.5),
        ("machine.interpolationPeriod", 0.002),
        ("machine.maxPathAcceleration", 1.5),
        ("machine.maxTransitionJerk", 40.0),
        ("x.maxJerk", 30.0),
        ("z.servo.servoRate", 4000.0),
    ];
    let mut set = start_values();
    for (name, x) in changes {
        let at = set.iter().position(|(n, _)| n == name).expect(name);
        set[at].1 = Value::Real(x);
    }
    set.push((
        "program".into(),
        Value::String("G21 G1 X2 Y1 F1200\nM30\n".into()),
    ));
    set
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Any order of a valid set initializes, and every value reads back as written.
    #[test]
    fn a_valid_parameter_set_initializes_in_any_order(order in Just(valid_set()).prop_shuffle()) {
        let fmu = Fmu::load();
        let (c, status) = initialize_with(&fmu, "order", &order);
        prop_assert_eq!(status, OK, "{}", fmu.last_log());
        for (name, value) in &order {
            if let Value::Real(x) = value {
                prop_assert_eq!(fmu.real(c, name), *x, "{}", name);
            }
        }
        fmu.free(c);
    }
}

#[test]
fn a_broken_relation_is_refused_at_initialization_naming_both_parameters() {
    let fmu = Fmu::load();
    let c = fmu.instantiate("relation");
    // Each value is within its own range: accepted when set.
    assert_eq!(set(&fmu, c, "y.servo.peakTorque", &Value::Real(2.0)), OK);
    assert_eq!(set(&fmu, c, "y.servo.ratedTorque", &Value::Real(3.0)), OK);
    enter_init(&fmu, c);
    assert_eq!(fmu.call("fmi2ExitInitializationMode", c), ERROR);
    let log = fmu.last_log();
    assert!(
        log.contains("y.servo.peakTorque") && log.contains("y.servo.ratedTorque"),
        "{log}"
    );
    fmu.free(c);
    // A value outside its own range (0 < x < min where 0 means none) is refused when set.
    let c = fmu.instantiate("own");
    assert_eq!(set(&fmu, c, "machine.maxPathJerk", &Value::Real(1e-5)), ERROR);
    assert!(
        fmu.last_log().contains("out of range (0 or 0.01 … 1000000)"),
        "{}",
        fmu.last_log()
    );
    fmu.free(c);
}

/// A machine file in a temporary resources folder of its own (relative `machineFile`).
fn resources_with(name: &str, files: &[(&str, &str)]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("cnc-fmu-params-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (f, text) in files {
        std::fs::write(dir.join(f), text).unwrap();
    }
    dir
}

const MACHINE_FILE: &str =
    "max_feed_mm_min = 3000\nprofile = \"quintic\"\n[axis.x]\nmax_jerk_mm_s3 = 30000\n\
                            [servo.x]\nrated_torque_n_m = 3\npeak_torque_n_m = 9\n[tool.1]\nradius_mm = 2\n";

/// The rule, in both orders (file first, file last) and with every start value written: keys of
/// the file hold unless a parameter differs from its start value; the tool table comes from the file.
#[test]
fn machine_file_and_parameters_combine_the_same_in_both_orders() {
    let dir = resources_with("orders", &[("mill.toml", MACHINE_FILE)]);
    let fmu = Fmu::load();
    let file = ("machineFile".to_string(), Value::String("mill.toml".into()));
    let program = "G21 G90 G41 D1 G1 X10 Y0 F6000\nG40 X20\nM30\n";
    // Every other parameter at its start value, as importers write them.
    let mut params: Vec<_> = start_values()
        .into_iter()
        .filter(|(n, _)| n != "machineFile")
        .collect();
    params.push(("program".into(), Value::String(program.into())));
    params.push(("y.maxJerk".into(), Value::Real(20.0))); // differs from its start: overrides
    let first: Vec<_> = std::iter::once(file.clone()).chain(params.clone()).collect();
    let last: Vec<_> = params.into_iter().chain(std::iter::once(file)).collect();
    let mut seen = Vec::new();
    for (label, values) in [("file first", first), ("file last", last)] {
        let c = fmu.instantiate_in(label, &dir);
        for (n, v) in &values {
            assert_eq!(set(&fmu, c, n, v), OK, "{label}: {n}: {}", fmu.last_log());
        }
        enter_init(&fmu, c);
        assert_eq!(
            fmu.call("fmi2ExitInitializationMode", c),
            OK,
            "{label}: {}",
            fmu.last_log()
        );
        let read = [
            "machine.maxFeed",
            "x.maxJerk",
            "y.maxJerk",
            "x.servo.ratedTorque",
            "x.servo.peakTorque",
        ]
        .map(|n| fmu.real(c, n));
        // From the file (mm/min, mm/s³ → SI), the parameter that differs, the file's drive.
        assert_eq!(read, [0.05, 30.0, 20.0, 3.0, 9.0], "{label}");
        seen.push(read);
        fmu.free(c);
    }
    assert_eq!(seen[0], seen[1]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// Seed 003's pocket (`T1 D1 M06`, `G54`, `G41`) needs the tool table of its machine file: the FMU
/// reads the file with the CLI's loader and runs it tick for tick as the command line's engine
/// does (`cnc-motion run corpus/seed003_pocket.txt --machine examples/machines/seed003_pocket.toml`).
#[test]
fn seed003_pocket_with_its_machine_file_runs_tick_for_tick_as_the_cli() {
    let root = env!("CARGO_MANIFEST_DIR");
    let program = format!("{root}/corpus/seed003_pocket.txt");
    let machine_path = format!("{root}/examples/machines/seed003_pocket.toml");
    let fmu = Fmu::load();
    let uri = format!("file://{machine_path}");
    let values = [
        ("machineFile".to_string(), Value::String(uri)),
        ("programFile".to_string(), Value::String(program.clone())),
    ];
    let (c, status) = initialize_with(&fmu, "pocket", &values);
    assert_eq!(status, OK, "{}", fmu.last_log());
    // The command line: its loader, its streaming program source.
    let text = std::fs::read_to_string(&machine_path).unwrap();
    let machine = cnc_motion::config::Machine::from_toml(&text, &machine_path).unwrap();
    let source = cnc_motion::gcode::ProgramSource::File(program.clone().into());
    let mut engine = cnc_motion::engine::Engine::new(source, &program, &machine)
        .unwrap()
        .with_servo(true);
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let get_bool = sym!(fmu, "fmi2GetBoolean", FnGetBool);
    let finished = fmu.vr("status.finished");
    let (mut n, mut done) = (0u32, 0);
    while done == 0 {
        assert_eq!(
            unsafe { step(c, f64::from(n) * 1e-3, 1e-3, 1) },
            OK,
            "{}",
            fmu.last_log()
        );
        engine.advance(1e-3).unwrap();
        n += 1;
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            assert_eq!(
                fmu.real(c, &format!("{axis}.command.position")),
                engine.tick().p[i]
            );
            assert_eq!(
                fmu.real(c, &format!("{axis}.position")),
                engine.axes()[i].position
            );
        }
        assert_eq!(unsafe { get_bool(c, &finished, 1, &mut done) }, OK);
        assert!(n < 100_000);
    }
    assert!(engine.finished());
    // The program's last point: G40 X5 Y60, then G0 Z50 (mm).
    let end = ["x", "y", "z"].map(|a| fmu.real(c, &format!("{a}.command.position")));
    assert!(
        (end[0] - 0.005).abs() < 1e-12 && (end[1] - 0.060).abs() < 1e-12 && (end[2] - 0.050).abs() < 1e-12,
        "{end:?}"
    );
    fmu.free(c);
    // Without the machine file the pocket is refused, located (the tool table is missing).
    let (c, status) = initialize_with(&fmu, "no-file", &values[1..]);
    assert_eq!(status, ERROR);
    assert!(
        fmu.last_log()
            .contains("seed003_pocket.txt:5:5: D1: tool 1 is not in the machine's tool table"),
        "{}",
        fmu.last_log()
    );
    fmu.free(c);
}

/// A machine file that is missing or wrong fails initialization with its place, like the CLI.
#[test]
fn bad_machine_files_are_refused_at_initialization_with_their_place() {
    let dir = resources_with("bad", &[("bad.toml", "[axis.x]\nmax_jerk_mm_s3 = -1\n")]);
    let fmu = Fmu::load();
    for (file, want) in [
        (
            "bad.toml",
            "bad.toml:2:18: axis.x.max_jerk_mm_s3 = -1 out of range",
        ),
        ("missing.toml", "missing.toml: "),
        ("file:relative.toml", "file:relative.toml: resource location"),
    ] {
        let c = fmu.instantiate_in("bad", &dir);
        assert_eq!(set(&fmu, c, "machineFile", &Value::String(file.into())), OK);
        enter_init(&fmu, c);
        assert_eq!(fmu.call("fmi2ExitInitializationMode", c), ERROR, "{file}");
        assert!(fmu.last_log().contains(want), "{file}: {}", fmu.last_log());
        fmu.free(c);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn types_of_the_drive_parameters_come_from_the_servo_table() {
    let info = CncMotionFmu::info();
    let kind = |n: &str| info.variables.iter().find(|v| v.name == n).unwrap().kind;
    assert_eq!(kind("x.servo.encoderCounts"), Type::Integer);
    assert_eq!(kind("y.servo.linearScale"), Type::Boolean);
    assert_eq!(kind("z.servo.kv"), Type::Real);
}

/// The machine a machine file made is part of the FMU state: a serialized state restores into an
/// instance that never saw the file (no `machineFile` set, the file not read again) and runs on
/// with the file's tool table, tick for tick as the original.
#[test]
fn a_serialized_state_keeps_the_machine_of_its_machine_file() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut a = <CncMotionFmu as Model>::new(None);
    a.0.machine_file = format!("{root}/examples/machines/seed003_pocket.toml");
    a.0.program_file = format!("{root}/corpus/seed003_pocket.txt");
    a.exit_initialization().unwrap();
    for _ in 0..1500 {
        a.do_step(1e-3).unwrap();
    }
    let bytes = a.serialize();
    let mut b = <CncMotionFmu as Model>::new(None);
    b.deserialize(&bytes).unwrap();
    assert_eq!(b.0.machine.nc.tools.len(), 1);
    for _ in 0..2000 {
        a.do_step(1e-3).unwrap();
        b.do_step(1e-3).unwrap();
        let (ea, eb) = (a.0.engine.as_ref().unwrap(), b.0.engine.as_ref().unwrap());
        assert_eq!(ea.tick().p, eb.tick().p);
        assert_eq!(ea.axes(), eb.axes());
    }
}

/// Step an initialized instance to the end of its program; the command position (mm).
fn run_to_end(fmu: &Fmu, c: Component) -> [f64; 3] {
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let get_bool = sym!(fmu, "fmi2GetBoolean", FnGetBool);
    let finished = fmu.vr("status.finished");
    let (mut n, mut done) = (0u32, 0);
    while done == 0 {
        assert_eq!(
            unsafe { step(c, f64::from(n) * 1e-2, 1e-2, 1) },
            OK,
            "{}",
            fmu.last_log()
        );
        assert_eq!(unsafe { get_bool(c, &finished, 1, &mut done) }, OK);
        n += 1;
        assert!(n < 100_000);
    }
    ["x", "y", "z"].map(|a| 1e3 * fmu.real(c, &format!("{a}.command.position")))
}

/// Initialize `c`, step it to the end of its program and free it; the end position (mm).
fn initialized_run(fmu: &Fmu, c: Component) -> [f64; 3] {
    enter_init(fmu, c);
    assert_eq!(
        fmu.call("fmi2ExitInitializationMode", c),
        OK,
        "{}",
        fmu.last_log()
    );
    let end = run_to_end(fmu, c);
    fmu.free(c);
    end
}

/// Subroutine files in the FMU as in the CLI (LinuxCNC "O Codes", "Calling Files"):
/// `programFile` searches its own directory, an inline `program` only the machine file's
/// `subroutine_path`, which is relative to the machine file (resolved like `machineFile`).
#[test]
fn subroutine_files_from_program_file_and_machine_file() {
    let dir = resources_with("subs", &[]);
    for (f, text) in [
        ("progs/main.ngc", "G21 F3000\no<Beside> call [4]\nM2\n"),
        ("progs/beside.ngc", "o<beside> sub\nG1 X#1 Y1\no<beside> endsub\n"),
        ("cfg/m.toml", "subroutine_path = [\"../lib\"]\n"),
        ("lib/far.ngc", "o<far> sub\nG1 X2 Y3\no<far> endsub\n"),
    ] {
        std::fs::create_dir_all(dir.join(f).parent().unwrap()).unwrap();
        std::fs::write(dir.join(f), text).unwrap();
    }
    let fmu = Fmu::load();
    let c = fmu.instantiate_in("beside", &dir);
    assert_eq!(
        set(&fmu, c, "programFile", &Value::String("progs/main.ngc".into())),
        OK
    );
    let end = initialized_run(&fmu, c);
    assert!(
        (end[0] - 4.0).abs() < 1e-9 && (end[1] - 1.0).abs() < 1e-9,
        "{end:?}"
    );
    let c = fmu.instantiate_in("far", &dir);
    let program = Value::String("G21 F3000\no<far> call\nM2\n".into());
    assert_eq!(set(&fmu, c, "program", &program), OK);
    assert_eq!(
        set(&fmu, c, "machineFile", &Value::String("cfg/m.toml".into())),
        OK
    );
    let end = initialized_run(&fmu, c);
    assert!(
        (end[0] - 2.0).abs() < 1e-9 && (end[1] - 3.0).abs() < 1e-9,
        "{end:?}"
    );
    // Without the machine file the inline program has nowhere to look.
    let c = fmu.instantiate_in("none", &dir);
    assert_eq!(set(&fmu, c, "program", &program), OK);
    enter_init(&fmu, c);
    assert_eq!(fmu.call("fmi2ExitInitializationMode", c), ERROR);
    assert!(
        fmu.last_log()
            .contains("program:2:1: o<far> call: the program has no o<far> sub"),
        "{}",
        fmu.last_log()
    );
    fmu.free(c);
    std::fs::remove_dir_all(dir).unwrap();
}
