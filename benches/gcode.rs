//! Reader throughput (blocks per second) for the same 20 000 moves written out line by line and
//! produced by O-word control flow (a `while` loop calling a subroutine with arguments, LinuxCNC
//! "O Codes"), from memory and from a file: the cost of re-reading loop bodies and of calls.
//! And the cost of G5 splines turned into arcs (LinuxCNC "G5 Cubic Spline").

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::gcode::{ProgramSource, Reader};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::fmt::Write;
use std::sync::Arc;

const TEETH: usize = 10_000;

/// The "Looping" sawtooth of the LinuxCNC documentation, unrolled.
fn unrolled() -> String {
    let mut text = String::from("G21 G90 F3000\n");
    for k in 0..TEETH {
        writeln!(text, "G1 X0\nG1 Y{} X1", k as f64 / 10.0).unwrap();
    }
    text + "M2\n"
}

/// The same teeth by a while loop calling a subroutine.
fn looped() -> String {
    format!(
        "G21 G90 F3000\no<tooth> sub\n  G1 X0\n  G1 Y#1 X1\no<tooth> endsub\n#<k> = 0\n\
         o101 while [#<k> LT {TEETH}]\n  o<tooth> call [#<k> / 10]\n  #<k> = [#<k> + 1]\no101 endwhile\nM2\n"
    )
}

const SPLINES: usize = 1000;

/// 1000 chained G5 cubics, 2 mm wide S-shaped steps continuing each other (I J left out).
fn splines() -> String {
    let mut text = String::from("G21 G90 G17 F3000\nG5 I0 J3 P0 Q-3 X2 Y0\n");
    for k in 1..SPLINES {
        writeln!(text, "G5 P0 Q-3 X{} Y0", 2 * (k + 1)).unwrap();
    }
    text + "M2\n"
}

fn count(mut r: Reader) -> usize {
    let mut n = 0;
    while r.next_block().expect("valid program").is_some() {
        n += 1;
    }
    n
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("gcode");
    g.throughput(Throughput::Elements(2 * TEETH as u64));
    g.sample_size(20);
    let flat: Arc<str> = Arc::from(unrolled());
    let looped_text: Arc<str> = Arc::from(looped());
    g.bench_function("read_unrolled_20k_moves", |b| {
        b.iter(|| count(Reader::new(flat.clone(), "b.ngc", [0.0; 3])))
    });
    g.bench_function("read_oword_loop_20k_moves", |b| {
        b.iter(|| count(Reader::new(looped_text.clone(), "b.ngc", [0.0; 3])))
    });
    let path = std::env::temp_dir().join(format!("bench_oword_{}.ngc", std::process::id()));
    std::fs::write(&path, &*looped_text).expect("temp file");
    g.bench_function("read_oword_loop_20k_moves_from_file", |b| {
        b.iter(|| count(Reader::new(ProgramSource::File(path.clone()), "b.ngc", [0.0; 3])))
    });
    g.finish();
    let _ = std::fs::remove_file(&path);
    let text: Arc<str> = Arc::from(splines());
    let arcs = count(Reader::new(text.clone(), "b.ngc", [0.0; 3]));
    eprintln!("gcode/read_g5_1k: {arcs} blocks for {SPLINES} splines");
    let mut g = c.benchmark_group("gcode");
    g.throughput(Throughput::Elements(SPLINES as u64));
    g.sample_size(10);
    g.bench_function("read_g5_1k", |b| {
        b.iter(|| count(Reader::new(text.clone(), "b.ngc", [0.0; 3])))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
