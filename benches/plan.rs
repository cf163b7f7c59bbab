//! Planning throughput: blocks per second of reader → path → look-ahead plan for a 100 000-segment
//! micro-segment program (0.05–0.2 mm segments on a wavy curve, as CAM output for free-form parts).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::config::Machine;
use cnc_motion::gcode::Reader;
use cnc_motion::path::PathBuilder;
use cnc_motion::plan::{Planned, Planner};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::collections::VecDeque;
use std::fmt::Write;
use std::sync::Arc;

pub fn micro_segments(n: usize) -> String {
    let mut text = String::with_capacity(n * 32);
    text.push_str("G21 G90 G64 F3000\n");
    let (mut x, mut y) = (0.0f64, 0.0f64);
    for i in 0..n {
        let step = 0.05 + 0.15 * ((i as f64 * 0.37).sin() * 0.5 + 0.5);
        let heading = 0.6 * (i as f64 * 0.01).sin();
        x += step * heading.cos();
        y += step * heading.sin();
        writeln!(text, "G1 X{x:.4} Y{y:.4}").unwrap();
    }
    text.push_str("M30\n");
    text
}

fn plan_program(text: &Arc<str>, machine: &Machine) -> usize {
    let mut reader = Reader::new(text.clone(), "bench.ngc", [0.0; 3]);
    let mut builder = PathBuilder::new(machine);
    let mut planner = Planner::new(machine.profile, machine.lookahead_blocks);
    let mut segments = Vec::new();
    let mut queue: VecDeque<Planned> = VecDeque::new();
    let mut planned = 0;
    while let Some(block) = reader.next_block().expect("valid program") {
        builder.push(&block, &mut segments);
        for s in segments.drain(..) {
            planner.push(s, &mut queue);
        }
        planned += queue.len();
        queue.clear();
    }
    builder.finish(&mut segments);
    for s in segments.drain(..) {
        planner.push(s, &mut queue);
    }
    planner.finish(&mut queue);
    planned + queue.len()
}

/// The segments of the program (reader and path stages), built once.
fn segments(text: &Arc<str>, machine: &Machine) -> Vec<cnc_motion::path::PathBlock> {
    let mut reader = Reader::new(text.clone(), "bench.ngc", [0.0; 3]);
    let mut builder = PathBuilder::new(machine);
    let mut out = Vec::new();
    while let Some(block) = reader.next_block().expect("valid program") {
        builder.push(&block, &mut out);
    }
    builder.finish(&mut out);
    out
}

fn bench(c: &mut Criterion) {
    let n = 100_000;
    let text: Arc<str> = Arc::from(micro_segments(n));
    let machine = Machine::default();
    let mut g = c.benchmark_group("plan");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n as u64));
    // The look-ahead alone (backward and forward passes, one feed profile per segment).
    let segs = segments(&text, &machine);
    g.bench_function("lookahead_only_micro_segments_100k", |b| {
        b.iter(|| {
            let mut planner = Planner::new(machine.profile, machine.lookahead_blocks);
            let mut queue: VecDeque<Planned> = VecDeque::new();
            let mut planned = 0;
            for s in &segs {
                planner.push(s.clone(), &mut queue);
                planned += queue.len();
                queue.clear();
            }
            planner.finish(&mut queue);
            planned + queue.len()
        })
    });
    // Reader, path (smooth mode: spans fitted over the micro-segments, chains) and look-ahead.
    g.bench_function("read_path_plan_micro_segments_100k", |b| {
        b.iter(|| plan_program(&text, &machine))
    });
    let exact = Machine {
        corner: cnc_motion::config::CornerMode::ExactStop,
        ..Machine::default()
    };
    g.bench_function("read_path_plan_exact_stop_100k", |b| {
        b.iter(|| plan_program(&text, &exact))
    });
    let polynomial = Machine {
        corner: cnc_motion::config::CornerMode::Polynomial,
        ..Machine::default()
    };
    g.bench_function("read_path_plan_polynomial_100k", |b| {
        b.iter(|| plan_program(&text, &polynomial))
    });
    // The whole pipeline: reader → path → look-ahead → feed → interpolated ticks (no CSV).
    g.bench_function("whole_pipeline_to_ticks_100k", |b| {
        b.iter(|| {
            let mut e = cnc_motion::engine::Engine::new(text.clone(), "bench.ngc", &machine).unwrap();
            let mut ticks = 0u64;
            while !e.finished() {
                e.step().unwrap();
                ticks += 1;
            }
            ticks
        })
    });
    g.finish();
    // One smooth-mode corner transition (a zig-zag of 5 mm lines: a corner at every vertex).
    let corners = 10_000;
    let mut zig = String::from("G21 G90 G64 F3000\n");
    for i in 0..corners {
        let y = if i % 2 == 0 { 1.0 } else { 0.0 };
        writeln!(zig, "G1 X{:.4} Y{y:.4}", 5.0 * (i + 1) as f64).unwrap();
    }
    zig.push_str("M30\n");
    let zig: Arc<str> = Arc::from(zig);
    let mut g = c.benchmark_group("transition");
    g.sample_size(10);
    g.throughput(Throughput::Elements(corners as u64));
    g.bench_function("smooth_corner_read_path_plan", |b| {
        b.iter(|| plan_program(&zig, &machine))
    });
    g.bench_function("exact_stop_read_path_plan", |b| {
        b.iter(|| plan_program(&zig, &exact))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
