//! Interpolation cost: ns per tick (reader, path, plan and interpolation amortised over a program,
//! as the FMU runs it), and the worst single tick measured over a whole run.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use criterion::{criterion_group, criterion_main, Criterion};
use std::fmt::Write;
use std::sync::Arc;
use std::time::Instant;

fn program() -> String {
    let mut text = String::from("G21 G90 G64 F4000\n");
    for i in 0..400 {
        let x = (i % 20) as f64 * 2.0;
        let y = (i / 20) as f64 * 1.5 + if i % 2 == 0 { 0.0 } else { 0.7 };
        writeln!(text, "G1 X{x:.3} Y{y:.3}").unwrap();
    }
    text.push_str("M30\n");
    text
}

fn bench(c: &mut Criterion) {
    let text: Arc<str> = Arc::from(program());
    let machine = Machine::default();
    let fresh = Engine::new(text.clone(), "bench.ngc", &machine).unwrap();
    c.bench_function("interp/tick", |b| {
        let mut e = fresh.clone();
        b.iter(|| {
            if e.finished() {
                e = fresh.clone();
            }
            *e.step().unwrap()
        })
    });
    let servo = Engine::new(
        Arc::from(cnc_motion::fmu::DEFAULT_PROGRAM),
        "default.ngc",
        &machine,
    )
    .unwrap()
    .with_servo(true);
    c.bench_function("interp/tick_with_servo_default_program", |b| {
        let mut e = servo.clone();
        b.iter(|| {
            if e.finished() {
                e = servo.clone();
            }
            *e.step().unwrap()
        })
    });
    c.bench_function("interp/advance_1ms_with_servo_default_program", |b| {
        let mut e = servo.clone();
        b.iter(|| {
            if e.finished() {
                e = servo.clone();
            }
            e.advance(1e-3).unwrap();
            e.tick().p[0]
        })
    });
    {
        use fmi2::Model;
        let mut m = cnc_motion::fmu::CncMotionFmu::new(None);
        m.0.program = cnc_motion::fmu::DEFAULT_PROGRAM.to_string();
        m.exit_initialization().unwrap();
        let fresh = m.clone();
        let mut n = 0;
        c.bench_function("interp/model_do_step_1ms", |b| {
            b.iter(|| {
                n += 1;
                if n % 5000 == 0 {
                    m = fresh.clone();
                }
                m.do_step(1e-3).unwrap();
            })
        });
    }
    // Worst tick of whole runs, reported once (criterion measures means, not maxima), with the
    // noise floor of this machine: the same timing around a fixed 200 ns of arithmetic.
    let mut times = Vec::new();
    for _ in 0..5 {
        let mut e = fresh.clone();
        while !e.finished() {
            let t0 = Instant::now();
            e.step().unwrap();
            times.push(t0.elapsed().as_secs_f64());
        }
    }
    let mut floor = Vec::with_capacity(times.len());
    let mut x = 1.0f64;
    for _ in 0..times.len() {
        let t0 = Instant::now();
        for _ in 0..100 {
            x = std::hint::black_box(x * 1.000001 + 1e-9);
        }
        floor.push(t0.elapsed().as_secs_f64());
    }
    let stats = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let q = |p: f64| v[((v.len() - 1) as f64 * p) as usize] * 1e6;
        (
            q(0.5),
            q(0.999),
            q(0.9999),
            v[v.len() - 1] * 1e6,
            v.iter().filter(|&&t| t > 20e-6).count(),
        )
    };
    let (m, p3, p4, worst, over) = stats(&mut times);
    println!(
        "interp/worst_tick: median {m:.2} µs, p99.9 {p3:.2} µs, p99.99 {p4:.2} µs, max {worst:.2} µs, \
         {over} of {} ticks over 20 µs",
        times.len()
    );
    let (m, p3, p4, worst, over) = stats(&mut floor);
    println!(
        "interp/noise_floor (fixed work): median {m:.2} µs, p99.9 {p3:.2} µs, p99.99 {p4:.2} µs, max {worst:.2} µs, \
         {over} over 20 µs"
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
