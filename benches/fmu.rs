//! The FMU through the C ABI of the built library, as an importer drives it (no Python), never
//! reset:
//!
//! - `sustained`: a program that moves for 98 minutes (benches/data/one_hour.ngc), servo on,
//!   h = T = 1 ms, t = n·h. Every fmi2DoStep of the first minute and of the 60th is timed; the
//!   median of each simulated second is printed (min / median / max over the minute's 60). Then
//!   criterion measures fmi2DoStep on from the 61st minute (`fmu/doStep_1ms_servo_after_1h`).
//! - `outputs`: all 34 outputs read after a step (one fmi2GetReal for the 32 Reals, one
//!   fmi2GetInteger, one fmi2GetBoolean), servo on and off (`fmu/outputs_34_servo_{on,off}`).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[macro_use]
#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use criterion::{criterion_group, criterion_main, Criterion};
use std::ffi::{c_int, c_uint};
use std::hint::black_box;
use std::time::{Duration, Instant};

const PROGRAM: &str = include_str!("data/one_hour.ngc");
const H: f64 = 1e-3;

/// An instance of `program` (servo on or off), initialized.
fn running(fmu: &Fmu, program: &str, servo: bool) -> Component {
    let c = fmu.instantiate("bench");
    assert_eq!(fmu.set_bool(c, "servo.enabled", servo), OK);
    assert_eq!(fmu.init(c, Some(program)), OK, "{}", fmu.last_log());
    c
}

/// Steps n … n + 1000·seconds, each timed when `timed`; the median of each second (µs).
fn seconds(fmu: &Fmu, c: Component, n: &mut u64, seconds: u64, timed: bool) -> Vec<f64> {
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let mut medians = Vec::new();
    let mut times = Vec::with_capacity(1000);
    for _ in 0..seconds {
        times.clear();
        for _ in 0..1000 {
            let t = *n as f64 * H;
            let start = timed.then(Instant::now);
            let status = unsafe { step(c, t, H, 1) };
            if let Some(s) = start {
                times.push(s.elapsed().as_secs_f64() * 1e6);
            }
            assert_eq!(status, OK);
            *n += 1;
        }
        if timed {
            times.sort_by(f64::total_cmp);
            medians.push(times[times.len() / 2]);
        }
    }
    medians
}

fn summary(label: &str, medians: &[f64]) {
    let mut m = medians.to_vec();
    m.sort_by(f64::total_cmp);
    println!(
        "fmu/sustained {label}: per-second median of fmi2DoStep {:.3} µs (min {:.3}, max {:.3} over {} s)",
        m[m.len() / 2],
        m[0],
        m[m.len() - 1],
        m.len()
    );
}

fn sustained(c: &mut Criterion) {
    let fmu = Fmu::load();
    let step = sym!(fmu, "fmi2DoStep", FnDoStep);
    let finished = fmu.outputs.iter().position(|o| o.0 == "status.finished").unwrap();
    // Set up on the first call (criterion calls the routine again for each sample), so that a
    // filter on the other benchmarks skips the hour.
    let mut hour: Option<(Component, u64)> = None;
    let mut group = c.benchmark_group("fmu");
    // About 20 simulated minutes: the program still moves throughout.
    group
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    group.bench_function("doStep_1ms_servo_after_1h", |b| {
        let (inst, n) = hour.get_or_insert_with(|| {
            let inst = running(&fmu, PROGRAM, true);
            let mut n = 0u64;
            let first = seconds(&fmu, inst, &mut n, 60, true);
            seconds(&fmu, inst, &mut n, 58 * 60, false);
            let last = seconds(&fmu, inst, &mut n, 60, true);
            summary("minute 1 ", &first);
            summary("minute 60", &last);
            assert_eq!(fmu.outputs(inst)[finished], 0.0, "still moving after an hour");
            (inst, n)
        });
        b.iter(|| {
            let s = unsafe { step(*inst, *n as f64 * H, H, 1) };
            *n += 1;
            s
        })
    });
    group.finish();
    if let Some((inst, _)) = hour {
        assert_eq!(
            fmu.outputs(inst)[finished],
            0.0,
            "still moving after the measurement"
        );
        fmu.free(inst);
    }
}

fn outputs(c: &mut Criterion) {
    let fmu = Fmu::load();
    let get_real = sym!(fmu, "fmi2GetReal", FnGetReal);
    let get_int = sym!(fmu, "fmi2GetInteger", FnGetInt);
    let get_bool = sym!(fmu, "fmi2GetBoolean", FnGetBool);
    let of =
        |kind: &str| -> Vec<c_uint> { fmu.outputs.iter().filter(|o| o.2 == kind).map(|o| o.1).collect() };
    let (reals, ints, bools) = (of("Real"), of("Integer"), of("Boolean"));
    assert_eq!(reals.len() + ints.len() + bools.len(), 34);
    for servo in [true, false] {
        let inst = running(&fmu, PROGRAM, servo);
        let mut n = 0;
        seconds(&fmu, inst, &mut n, 2, false);
        let (mut r, mut i, mut b) = (
            vec![0.0; reals.len()],
            vec![0 as c_int; ints.len()],
            vec![0; bools.len()],
        );
        let name = format!("fmu/outputs_34_servo_{}", if servo { "on" } else { "off" });
        c.bench_function(&name, |bench| {
            bench.iter(|| unsafe {
                get_real(inst, reals.as_ptr(), reals.len(), r.as_mut_ptr());
                get_int(inst, ints.as_ptr(), ints.len(), i.as_mut_ptr());
                get_bool(inst, bools.as_ptr(), bools.len(), b.as_mut_ptr());
                black_box(r[0] + f64::from(i[0] + b[0]))
            })
        });
        fmu.free(inst);
    }
}

criterion_group!(benches, sustained, outputs);
criterion_main!(benches);
