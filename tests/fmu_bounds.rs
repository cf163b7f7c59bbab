//! Every call returns in bounded time, through the C ABI: a step far beyond the program's motion
//! ends at rest at once (or, beyond the engine's time range, is refused with a message), and a
//! corrupted serialized state is refused with fmi2Error or, restored, runs with finite outputs.
//! No timed assertion: the work is bounded by construction (a few steps per case) and a watchdog
//! names a case that would hang instead of letting the suite wait.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[macro_use]
mod common;

use common::*;
use std::collections::BTreeMap;
use std::ffi::c_int;
use std::sync::atomic::{AtomicUsize, Ordering};

type FnRealStatus = unsafe extern "C" fn(Component, c_int, *mut f64) -> c_int;
const LAST_SUCCESSFUL_TIME: c_int = 2;
/// One encoder count of the default drive (1.2 mm lead, 10 000 counts), m.
const COUNT: f64 = 1.2e-3 / 10_000.0;

fn output(fmu: &Fmu, c: Component, name: &str) -> f64 {
    let i = fmu.outputs.iter().position(|o| o.0 == name).unwrap();
    fmu.outputs(c)[i]
}

fn time(fmu: &Fmu, c: Component) -> Option<f64> {
    let f = sym!(fmu, "fmi2GetRealStatus", FnRealStatus);
    let mut t = f64::NAN;
    (unsafe { f(c, LAST_SUCCESSFUL_TIME, &mut t) } == OK).then_some(t)
}

/// The program's end point, the command at rest and the drives at rest there (within an encoder
/// count: the integrator hunts between counts where the command is not a whole one).
fn at_rest_at_the_end(fmu: &Fmu, c: Component) {
    assert_eq!(output(fmu, c, "status.finished"), 1.0);
    for (axis, end) in ["x", "y", "z"].iter().zip([0.0, 0.0, 0.005]) {
        assert_eq!(output(fmu, c, &format!("{axis}.command.position")), end);
        assert_eq!(output(fmu, c, &format!("{axis}.command.velocity")), 0.0);
        let p = output(fmu, c, &format!("{axis}.position"));
        assert!((p - end).abs() <= COUNT, "{axis}.position {p}");
        assert!(output(fmu, c, &format!("{axis}.velocity")).abs() < 1e-6);
    }
}

#[test]
fn a_step_far_beyond_the_motion_ends_at_rest_at_once() {
    let fmu = Fmu::load();
    for servo in [true, false] {
        let c = fmu.instantiate("huge");
        assert_eq!(fmu.set_bool(c, "servo.enabled", servo), OK);
        assert_eq!(fmu.init(c, None), OK);
        assert_eq!(fmu.step(c, 0.0, 1e4), OK, "{}", fmu.last_log());
        assert_eq!(time(&fmu, c), Some(1e4));
        at_rest_at_the_end(&fmu, c);
        // And on from there, in ordinary steps.
        assert_eq!(fmu.step(c, 1e4, 1e-3), OK);
        at_rest_at_the_end(&fmu, c);
        fmu.free(c);
    }
    // Beyond the engine's time range (1e9 s): refused with the reason, nothing computed.
    for h in [1e300, 2e9] {
        let c = fmu.instantiate("beyond");
        assert_eq!(fmu.init(c, None), OK);
        assert_eq!(fmu.step(c, 0.0, h), ERROR);
        assert!(
            fmu.last_log().contains("beyond the engine's time range (1e9 s)"),
            "{}",
            fmu.last_log()
        );
        fmu.free(c);
    }
}

#[test]
fn a_long_rest_in_closed_form_is_where_stepping_gets() {
    // 100 s in one step against 100 000 steps of 1 ms, servo on: the drives that hold their
    // encoder count agree to rounding; z (5 mm is not a whole count) hunts between two counts
    // when stepped and rests between them in the closed form.
    let fmu = Fmu::load();
    let (a, b) = (fmu.instantiate("one"), fmu.instantiate("many"));
    assert_eq!(fmu.init(a, None), OK);
    assert_eq!(fmu.init(b, None), OK);
    assert_eq!(fmu.step(a, 0.0, 100.0), OK);
    for n in 0..100_000 {
        assert_eq!(fmu.step(b, n as f64 * 1e-3, 1e-3), OK);
    }
    for (axis, tolerance) in [("x", 1e-15), ("y", 1e-15), ("z", COUNT)] {
        let name = format!("{axis}.position");
        let (pa, pb) = (output(&fmu, a, &name), output(&fmu, b, &name));
        assert!(
            (pa - pb).abs() <= tolerance,
            "{name}: {pa} in one step, {pb} stepped"
        );
    }
    // A feed hold stopped mid-program rests too, and the release runs the program to its end.
    let c = fmu.instantiate("hold");
    assert_eq!(fmu.init(c, None), OK);
    assert_eq!(fmu.step(c, 0.0, 1.0), OK);
    assert_eq!(fmu.set_bool(c, "feedHold", true), OK);
    assert_eq!(fmu.step(c, 1.0, 1e4), OK);
    assert_eq!(output(&fmu, c, "status.finished"), 0.0);
    assert_eq!(output(&fmu, c, "path.feed"), 0.0);
    assert_eq!(fmu.set_bool(c, "feedHold", false), OK);
    assert_eq!(fmu.step(c, 1.0 + 1e4, 100.0), OK);
    at_rest_at_the_end(&fmu, c);
    for c in [a, b, c] {
        fmu.free(c);
    }
}

/// The kitchen-sink program without its tool words (the FMU has no tool table yet).
fn kitchen_sink() -> String {
    let text = include_str!("data/kitchen_sink.ngc");
    let tools = ["T1 M6", "G43 H1", "G41 D1", "G40"];
    text.lines()
        .filter(|l| !tools.contains(&l.trim()))
        .map(|l| format!("{l}\n"))
        .collect()
}

/// One corruption of `bytes`, as a flipped bit, a stray byte, a word or a double overwritten,
/// or a one-byte number grown into a five-byte one (postcard varint of 2³¹ − 1).
fn corrupt(rng: &mut Rng, bytes: &[u8]) -> (Vec<u8>, &'static str) {
    let mut b = bytes.to_vec();
    let n = b.len();
    let at = |rng: &mut Rng, width: usize| rng.below(n - width);
    let doubles = [
        1e300,
        -1.3e163,
        f64::NAN,
        f64::INFINITY,
        -1.0,
        0.0,
        5e-324,
        2147483647.0,
        1e12,
    ];
    let kind = match rng.below(6) {
        0 => {
            let i = at(rng, 0);
            b[i] ^= 1 << rng.below(8);
            "bit flip"
        }
        1 => {
            let i = at(rng, 0);
            b[i] = rng.next() as u8;
            "byte"
        }
        2 => {
            let i = at(rng, 4);
            b[i..i + 4].copy_from_slice(&0x7fff_ffffu32.to_le_bytes());
            "word 0x7fffffff"
        }
        3 => {
            let i = at(rng, 4);
            b[i..i + 4].copy_from_slice(&u32::MAX.to_le_bytes());
            "word 0xffffffff"
        }
        4 => {
            let i = at(rng, 8);
            let x = doubles[rng.below(doubles.len())];
            b[i..i + 8].copy_from_slice(&x.to_le_bytes());
            "double"
        }
        _ => {
            let i = at(rng, 1);
            b.splice(i..i + 1, [0xff, 0xff, 0xff, 0xff, 0x07]);
            "varint 2^31-1"
        }
    };
    (b, kind)
}

/// Aborts the test process, naming the case, if no case finishes for two minutes (a case takes
/// milliseconds): a hang is reported instead of stalling the suite.
fn watchdog(progress: &'static AtomicUsize) {
    std::thread::spawn(move || {
        let mut seen = usize::MAX;
        loop {
            std::thread::sleep(std::time::Duration::from_secs(120));
            let now = progress.load(Ordering::SeqCst);
            if now == seen {
                eprintln!("corrupted-state case {now} has not returned for 120 s");
                std::process::abort();
            }
            seen = now;
        }
    });
}

#[test]
fn corrupted_states_are_refused_or_run_with_finite_outputs() {
    static PROGRESS: AtomicUsize = AtomicUsize::new(0);
    watchdog(&PROGRESS);
    let seed: u64 = std::env::var("CNC_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_261_124);
    let cases: usize = std::env::var("CNC_STATE_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let mut rng = Rng(seed | 1);
    let fmu = Fmu::load();
    let sink = kitchen_sink();
    // A few states taken mid-program, servo on.
    let mut states = Vec::new();
    for (program, times) in [(None, [0.5, 2.5, 4.5]), (Some(sink.as_str()), [1.0, 6.0, 11.0])] {
        let c = fmu.instantiate("source");
        assert_eq!(fmu.init(c, program), OK, "{}", fmu.last_log());
        let mut n = 0u64;
        for t in times {
            while (n as f64) * 1e-3 < t {
                assert_eq!(fmu.step(c, n as f64 * 1e-3, 1e-3), OK);
                n += 1;
            }
            states.push((program, fmu.serialize(c), fmu.outputs(c)));
        }
        fmu.free(c);
    }
    let mut outcomes: BTreeMap<(&str, &str), usize> = BTreeMap::new();
    for (k, (program, state, outputs)) in states.iter().enumerate() {
        let c = fmu.instantiate("target");
        assert_eq!(fmu.init(c, *program), OK);
        // The state itself restores, with the outputs it was saved with.
        assert_eq!(fmu.restore(c, state), OK, "{}", fmu.last_log());
        assert_eq!(&fmu.outputs(c), outputs);
        for case in 0..cases {
            PROGRESS.fetch_add(1, Ordering::SeqCst);
            let (bytes, kind) = corrupt(&mut rng, state);
            let logged = fmu.log.lock().unwrap().len();
            let outcome = if fmu.restore(c, &bytes) == OK {
                run_a_few_steps(&fmu, c)
            } else {
                "refused"
            };
            let log = fmu.log.lock().unwrap();
            let said = log[logged..].iter().any(|l| !l.is_empty());
            assert!(
                outcome == "ran" || said,
                "state {k}, case {case} ({kind}): {outcome} without a message"
            );
            assert!(
                outcome != "failed",
                "state {k}, case {case} ({kind}): {:?}",
                &log[logged..]
            );
            *outcomes.entry((kind, outcome)).or_default() += 1;
        }
        fmu.free(c);
    }
    println!(
        "corrupted states (seed {seed}, {cases} per state, {} states):",
        states.len()
    );
    for ((kind, outcome), n) in &outcomes {
        println!("  {kind:>16}  {outcome:<28} {n}");
    }
    let total = |o: &str| {
        outcomes
            .iter()
            .filter(|((_, x), _)| *x == o)
            .map(|(_, n)| n)
            .sum::<usize>()
    };
    println!(
        "  refused {}, restored and ran {}, restored not stepping {}",
        total("refused"),
        total("ran"),
        total("restored, not stepping")
    );
}

/// Five steps of 1 ms from the restored time with every output finite; "restored, not
/// stepping" when the state restored is one where the slave does not step (a slave-state byte
/// changed: refused with a message at the step); "failed" otherwise.
fn run_a_few_steps(fmu: &Fmu, c: Component) -> &'static str {
    let Some(mut t) = time(fmu, c) else {
        return "restored, not stepping";
    };
    for _ in 0..5 {
        if fmu.step(c, t, 1e-3) != OK {
            let log = fmu.last_log();
            return if log.contains("not allowed in state") {
                "restored, not stepping"
            } else {
                "failed"
            };
        }
        t += 1e-3;
        if !fmu.outputs(c).iter().all(|x| x.is_finite()) {
            return "failed";
        }
    }
    "ran"
}
