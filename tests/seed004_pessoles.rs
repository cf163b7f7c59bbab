//! Seed 004 §4: Pessoles' linear path on the DMU 50 eVo / Siemens 840D at F5000 in the seed-004
//! corner model (`polynomial`), against the paper: its model gives 4237 ms from the first to the
//! last point (the machine measured 4232 ms), and Table 2 lists the model's feeds in the seven
//! transitions (72, 222, 135, 148, 150, 158, 91 mm/min; measured 71, 256, 150, 193, 161, 196,
//! 126). Table 1's jerk of 60 m/s³ "on passage of a discontinuity in curvature" does not act on
//! this path: its corners are tangent discontinuities, passed by the curvature-continuous quintic
//! at the axis jerk (eq. 54).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use std::sync::Arc;

const MODEL_MS: f64 = 4237.0;
const MEASURED_MS: f64 = 4232.0;
const TABLE2_MODEL_MM_MIN: [f64; 7] = [72.0, 222.0, 135.0, 148.0, 150.0, 158.0, 91.0];
const TABLE2_MEASURED_MM_MIN: [f64; 7] = [71.0, 256.0, 150.0, 193.0, 161.0, 196.0, 126.0];

fn machine(file: &str) -> Machine {
    let toml = std::fs::read_to_string(file).expect("machine file");
    Machine::from_toml(&toml, file).expect("valid machine")
}

/// Exact path time of a program (s) and the lowest feed of each drop below 1000 mm/min after
/// line 4 (the transitions).
fn run(text: &str, machine: &Machine) -> (f64, Vec<f64>) {
    let mut e = Engine::new(Arc::from(text), "pessoles_linear.ngc", machine).unwrap();
    let mut feeds: Vec<f64> = Vec::new();
    let mut prev = f64::INFINITY;
    let mut falling = false;
    while !e.finished() {
        let t = *e.step().unwrap();
        let f = t.feed * 60e3;
        if t.line >= 5 {
            if f > prev + 1e-9 && falling && prev < 1000.0 {
                feeds.push(prev);
            }
            falling = f < prev - 1e-9 || (falling && (f - prev).abs() <= 1e-9);
        }
        prev = f;
    }
    (e.motion_time(), feeds)
}

/// Time from the first programmed point to the last (ms), as the difference of two exact path
/// times, and the transition feeds (mm/min). The measurement and the paper's model start at rest
/// at the first point: the corpus program (kept verbatim) gets G61 on its rapid of line 4, so
/// the path stops there, and G64 back on the first feed move.
fn pessoles(machine_file: &str) -> (f64, Vec<f64>) {
    let verbatim = std::fs::read_to_string("corpus/pessoles_linear.ngc").expect("corpus");
    let text = verbatim
        .replacen("\nG0 X50 Y0 Z100\n", "\nG61 G0 X50 Y0 Z100\n", 1)
        .replacen("\nG1 X40 Y10 Z95 F5000\n", "\nG64 G1 X40 Y10 Z95 F5000\n", 1);
    assert_eq!(
        text.matches("G61 G0").count() + text.matches("G64 G1").count(),
        2,
        "{text}"
    );
    let m = machine(machine_file);
    let (whole, feeds) = run(&text, &m);
    let rapid: String = text.lines().take(4).map(|l| format!("{l}\n")).collect();
    let (to_first_point, _) = run(&format!("{rapid}M2\n"), &m);
    ((whole - to_first_point) * 1e3, feeds)
}

fn rms(feeds: &[f64], table: &[f64; 7]) -> f64 {
    let sum: f64 = feeds.iter().zip(table).map(|(a, b)| (a - b).powi(2)).sum();
    (sum / 7.0).sqrt()
}

#[test]
fn the_papers_model_to_a_tenth_of_a_percent() {
    let (ms, feeds) = pessoles("corpus/dmu50_840d.toml");
    let err = (ms - MODEL_MS) / MODEL_MS;
    println!(
        "seed-004 mode: {ms:.1} ms ({:+.3} % of the model's {MODEL_MS}, {:+.2} % of the measured \
         {MEASURED_MS}); transition feeds {feeds:.1?} mm/min, RMS {:.1} against the measured",
        err * 100.0,
        (ms - MEASURED_MS) / MEASURED_MS * 100.0,
        rms(&feeds, &TABLE2_MEASURED_MM_MIN)
    );
    assert!(err.abs() < 1e-3, "{ms} ms");
    assert_eq!(feeds.len(), 7, "{feeds:?}");
    // The model's transition feeds: the lowest speed in the transition, V_In·|v − u|/2 at Q,
    // sampled at the 2 ms ticks (so up to ~1 mm/min above it). Corner 3 is the exception: the
    // paper prints 135, which is what a Euclidean |OQ| = tol gives there (135.1); eq. 30's axis
    // tolerance, which reproduces the other six, gives 145.5.
    for (k, (ours, paper)) in feeds.iter().zip(TABLE2_MODEL_MM_MIN).enumerate() {
        if k != 2 {
            assert!(
                (ours - paper).abs() <= 1.5,
                "transition {}: {ours} vs {paper}",
                k + 1
            );
        }
    }
    assert!((feeds[2] - 145.5).abs() <= 1.5, "{}", feeds[2]);
}

#[test]
fn the_curvature_jerk_does_not_act_on_corners() {
    // Table 1's J_c (examples/machines/dmu50_840d_jc60.toml) is for curvature discontinuities
    // (eq. 10, the circular mode's arcs); Pessoles' linear path has none: the same run.
    let (ms, feeds) = pessoles("examples/machines/dmu50_840d_jc60.toml");
    let (ms_axes, feeds_axes) = pessoles("corpus/dmu50_840d.toml");
    assert_eq!(ms, ms_axes);
    assert_eq!(feeds, feeds_axes);
    assert!(((ms - MEASURED_MS) / MEASURED_MS).abs() < 2e-3, "{ms} ms");
}
