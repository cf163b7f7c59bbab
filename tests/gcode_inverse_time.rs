//! G93 inverse-time feed (LinuxCNC "G93, G94, G95"; RS274NGC 3.5.19): each G1/G2/G3 carries F,
//! the move takes 1/F minutes, so its feed is length × F per minute; a move without F is a
//! located error; G94 returns to units per minute and needs a new F.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use cnc_motion::gcode::{validate, Block, Motion, Reader};
use std::f64::consts::PI;
use std::sync::Arc;

/// Motion time (s) of a program run through the whole engine.
fn motion_time(text: &str, machine: &Machine) -> f64 {
    let mut e = Engine::new(text, "t.ngc", machine).unwrap_or_else(|e| panic!("{e}"));
    let mut n = 0;
    while !e.finished() {
        e.step().unwrap();
        n += 1;
        assert!(n < 1_000_000);
    }
    e.motion_time()
}

/// Feeds (mm/min) of the feed moves of a program.
fn feeds(text: &str) -> Vec<f64> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().unwrap_or_else(|e| panic!("{e}")) {
        if let Block {
            motion: Motion::Linear { .. } | Motion::Arc { .. },
            feed,
            ..
        } = b
        {
            out.push(feed * 60e3);
        }
    }
    out
}

fn error(text: &str) -> String {
    validate(Arc::from(text), "t.ngc").unwrap_err().to_string()
}

/// A fast machine: acceleration and jerk so high that a single move's ramps take well under a
/// millisecond, so the move's time is its length over the feed.
fn fast_machine() -> Machine {
    let mut toml = String::from("max_feed_mm_min = 100000\ncorner = \"exact_stop\"\n");
    for a in ["x", "y", "z"] {
        toml += &format!(
            "[axis.{a}]\nmax_velocity_mm_min = 100000\nmax_acceleration_mm_s2 = 1000000\nmax_jerk_mm_s3 = 1000000000\n"
        );
    }
    Machine::from_toml(&toml, "m.toml").unwrap()
}

/// A single line and a single half circle each take 1/F minutes (plus ramps of well under
/// 10 ms), and equal the same moves in G94 at feed = length × F.
#[test]
fn a_move_takes_one_over_f_minutes() {
    let m = fast_machine();
    // 100 mm at F12: 5 s (1200 mm/min).
    let t = motion_time("G93 G1 X100 F12\nM2\n", &m);
    assert!((t - 5.0).abs() < 0.01, "{t}");
    let t94 = motion_time("G94 G1 X100 F1200\nM2\n", &m);
    assert!((t - t94).abs() < 1e-9, "{t} {t94}");
    // Half circle of radius 10 mm (10π mm) at F30: 2 s.
    let t = motion_time("G93 G3 X0 Y20 I0 J10 F30\nM2\n", &m);
    assert!((t - 2.0).abs() < 0.01, "{t}");
    let t94 = motion_time(&format!("G3 X0 Y20 I0 J10 F{}\nM2\n", 10.0 * PI * 30.0), &m);
    assert!((t - t94).abs() < 1e-9, "{t} {t94}");
    // Two moves with their own F: 1 s + 0.5 s in exact stop.
    let t = motion_time("G61 G93 G1 X50 F60\nY20 F120\nM2\n", &m);
    assert!((t - 1.5).abs() < 0.02, "{t}");
}

/// The feed of each block is its length × F: lines, a helix with an extra turn (P2: 1.5 turns
/// of radius 5 mm and 3 mm down), a full circle; G0 stays rapid; G94 then needs F again.
#[test]
fn feeds_are_length_times_f() {
    let f = feeds("G93\nG1 X-3 Y-4 F2\nG1 X0 Y0 F2\nG2 X10 Y0 I5 J0 Z-3 P2 F1\nG3 X10 Y0 I-5 J0 F0.5\nG0 X0\nG94 G1 X1 F100\nM2\n");
    let helix = (5.0 * 3.0 * PI).hypot(3.0);
    let want = [10.0, 10.0, helix, 5.0 * PI, 100.0];
    assert_eq!(f.len(), 5);
    for (a, b) in f.iter().zip(want) {
        assert!((a - b).abs() < 1e-9 * b, "{a} {b}");
    }
}

/// Located errors.
#[test]
fn inverse_time_errors() {
    assert_eq!(
        error("G93\nG1 X1\n"),
        "t.ngc:2:1: G1 in G93 needs F on its line (inverse time: the move takes 1/F minutes)"
    );
    assert_eq!(
        error("G93 G1 X1 F1\nX2\n"),
        "t.ngc:2:1: G1 in G93 needs F on its line (inverse time: the move takes 1/F minutes)"
    );
    assert_eq!(
        error("G1 X1 F100\nG93 G1 X2 F1\nG94 G1 X3\n"),
        "t.ngc:3:5: G1 with a zero feed rate (F0, or F never set)"
    );
    assert!(error("G93 G1 X1 F0\n").starts_with("t.ngc:1:11: inverse-time F0 must be positive"));
    assert_eq!(
        error("G93 G81 X1 Y1 Z-1 R1 F1\n"),
        "t.ngc:1:5: G81: drilling cycles are not defined in G93 (inverse time); use G94"
    );
    assert_eq!(
        error("G93 G94\n"),
        "t.ngc:1:5: two words of the same modal group on one line"
    );
}
