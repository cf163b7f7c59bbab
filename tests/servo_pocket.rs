//! Issue 4's acceptance: on the seed-003 pocket at the default machine, the S-curve gives a smaller
//! peak following error and motor torque than the trapezoid.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use cnc_motion::feed::ProfileKind;
use std::sync::Arc;

fn peaks(kind: ProfileKind) -> (f64, f64) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpus/seed003_pocket_compensated.ngc"
    );
    let text = std::fs::read_to_string(path).expect("corpus file");
    let machine = Machine {
        profile: kind,
        ..Machine::default()
    };
    let mut e = Engine::new(Arc::from(text), "pocket.ngc", &machine)
        .unwrap()
        .with_servo(true);
    let (mut fe, mut torque) = (0.0f64, 0.0f64);
    while !e.finished() {
        e.step().unwrap();
        for s in e.axes() {
            fe = fe.max(s.following_error.abs());
            torque = torque.max(s.motor_torque.abs());
        }
    }
    // Let the drives settle after the last tick.
    for _ in 0..200 {
        e.step().unwrap();
    }
    for (i, s) in e.axes().iter().enumerate() {
        assert!(
            (s.position - e.tick().p[i]).abs() < 2e-6,
            "axis {i} settles on the end point"
        );
    }
    (fe, torque)
}

#[test]
fn scurve_beats_trapezoid_on_the_pocket() {
    let (fe_s, tq_s) = peaks(ProfileKind::Scurve7);
    let (fe_t, tq_t) = peaks(ProfileKind::Trapezoid);
    println!(
        "following error {:.4} vs {:.4} mm, torque {:.3} vs {:.3} N·m",
        fe_s * 1e3,
        fe_t * 1e3,
        tq_s,
        tq_t
    );
    assert!(fe_s < fe_t, "following error: S-curve {fe_s} vs trapezoid {fe_t}");
    assert!(tq_s < tq_t, "torque: S-curve {tq_s} vs trapezoid {tq_t}");
}
