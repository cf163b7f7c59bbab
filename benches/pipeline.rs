//! Whole-pipeline throughput on CAM-like programs (issue 22): `cnc-motion run FILE --json` as a
//! user runs it (reader → path → look-ahead → feed → ticks, with the CLI's per-tick checks and
//! maxima; no CSV), on 100 000 and 1 000 000 lines of benches/common/cam_like.rs, in the default
//! corner mode and in exact stop. Throughput in blocks; the ticks per block are printed once.
//! `CAM_SIZES=100000` (comma-separated) picks the sizes; `CAM_BASELINE_BIN=/path/to/cnc-motion`
//! adds that binary's runs to each group (before/after in one run: build the old commit's CLI,
//! copy it aside).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[allow(dead_code)]
mod common {
    pub mod cam_like;
}

use cnc_motion::config::{CornerMode, Machine};
use cnc_motion::engine::Engine;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Duration;

const SEED: u64 = 1;

/// The programs, written once into the target directory (a 1 M-line program is 32 MB).
fn program_file(moves: usize) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join(format!("cam_like_{moves}_{SEED}.ngc"));
    if !path.exists() {
        let text = common::cam_like::program(moves, SEED);
        std::fs::write(&path, text).expect("writing the program");
    }
    path
}

fn machine_file(corner: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cam_like_{corner}.toml"));
    std::fs::write(&path, format!("corner = \"{corner}\"\n")).expect("writing the machine");
    path
}

/// One CLI run; the summary's ticks and motion blocks.
fn run_cli(bin: &Path, program: &Path, machine: &Path) -> (u64, u64) {
    let out = Command::new(bin)
        .arg("run")
        .arg(program)
        .arg("--machine")
        .arg(machine)
        .arg("--json")
        .output()
        .expect("running cnc-motion");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON summary");
    let count = |key: &str| summary[key].as_u64().expect("a count");
    (count("ticks"), count("motion_blocks"))
}

fn sizes() -> Vec<usize> {
    std::env::var("CAM_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|n| n.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![100_000, 1_000_000])
}

/// This build's CLI, and the baseline's when given.
fn binaries() -> Vec<(&'static str, PathBuf)> {
    let mut bins = vec![("", PathBuf::from(env!("CARGO_BIN_EXE_cnc-motion")))];
    if let Some(old) = std::env::var_os("CAM_BASELINE_BIN") {
        bins.push(("_baseline", PathBuf::from(old)));
    }
    bins
}

fn bench(c: &mut Criterion) {
    let bins = binaries();
    for moves in sizes() {
        let program = program_file(moves);
        let mut g = c.benchmark_group(format!("cam_like_{moves}"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(100));
        g.measurement_time(Duration::from_secs(if moves > 200_000 { 60 } else { 10 }));
        for corner in ["smooth", "exact_stop"] {
            let machine = machine_file(corner);
            let (ticks, blocks) = run_cli(&bins[0].1, &program, &machine);
            eprintln!(
                "cam_like {moves} lines, {corner}: {blocks} blocks, {ticks} ticks ({:.1} a block)",
                ticks as f64 / blocks as f64
            );
            g.throughput(Throughput::Elements(blocks));
            for (suffix, bin) in &bins {
                g.bench_function(format!("cli_run_{corner}{suffix}"), |b| {
                    b.iter(|| run_cli(bin, &program, &machine))
                });
            }
        }
        g.finish();
    }
    // The library alone (no CLI checks or maxima), in process: what the FMU's loop costs.
    let moves = 100_000;
    let text: Arc<str> = Arc::from(common::cam_like::program(moves, SEED));
    let mut g = c.benchmark_group("cam_like_engine");
    g.sample_size(10);
    g.throughput(Throughput::Elements(moves as u64));
    for corner in [CornerMode::Smooth, CornerMode::ExactStop] {
        let machine = Machine {
            corner,
            ..Machine::default()
        };
        g.bench_function(format!("engine_steps_{moves}_{}", corner.name()), |b| {
            b.iter(|| {
                let mut e = Engine::new(text.clone(), "cam.ngc", &machine).expect("valid");
                while !e.finished() {
                    e.step().expect("runs");
                }
                e.ticks()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
