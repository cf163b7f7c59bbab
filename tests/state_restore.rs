//! Engine states (fmi2GetFMUstate / serialization) round trip: a state saved anywhere in a
//! program — every corner mode and feed law, servo on and off, under feed override and hold, at
//! ticks and between them — passes the restore checks, and the restored engine runs on tick for
//! tick, bit for bit, as the one it was saved from. (That states no run produces are refused is
//! tested in src/engine/state.rs and, through the C ABI, in tests/fmu_bounds.rs.)
#![allow(unused_crate_dependencies)]

use cnc_motion::config::{CornerMode, Machine};
use cnc_motion::engine::Engine;
use cnc_motion::feed::ProfileKind;

const KITCHEN_SINK: &str = include_str!("data/kitchen_sink.ngc");
const TOOLS: &str = "[tool.1]\nradius_mm = 2\nlength_mm = 10\n";

fn machine(corner: CornerMode, profile: ProfileKind) -> Machine {
    let mut m = Machine::from_toml(TOOLS, "tools.toml").unwrap();
    m.corner = corner;
    m.profile = profile;
    m
}

/// Run `text` with override and hold changes, saving every `every` steps; each saved state is
/// restored into a fresh engine and both run 20 ticks side by side. Returns the states saved.
fn round_trips(text: &str, m: &Machine, servo: bool, every: u64) -> Vec<Vec<u8>> {
    let mut a = Engine::new(text, "p.ngc", m).unwrap().with_servo(servo);
    let mut saved = Vec::new();
    for k in 0u64.. {
        // Inputs as an importer sets them between steps.
        match k % 3000 {
            700 => a.set_feed_override(0.4),
            1300 => a.set_feed_hold(true),
            1900 => a.set_feed_hold(false),
            2400 => a.set_feed_override(1.0),
            _ => {}
        }
        // Mostly whole ticks, sometimes a communication point between ticks.
        let h = if k % 7 == 3 { 0.37e-3 } else { 1e-3 };
        a.advance(h).unwrap();
        if k % every == every / 2 {
            let bytes = a.save_state();
            let mut b = Engine::new(text, "p.ngc", m).unwrap();
            if let Err(e) = b.restore_state(&bytes) {
                panic!("state at step {k} (t = {} s) refused: {e}", a.time());
            }
            // The outputs as they were, before any step.
            assert_eq!(
                (a.tick(), a.axes(), a.contour_error()),
                (b.tick(), b.axes(), b.contour_error())
            );
            let mut a2 = a.clone();
            for _ in 0..20 {
                a2.advance(1e-3).unwrap();
                b.advance(1e-3).unwrap();
                assert_eq!(a2.tick(), b.tick(), "after the state of step {k}");
                assert_eq!(a2.axes(), b.axes(), "after the state of step {k}");
            }
            saved.push(bytes);
        }
        // On a little after the end: the drives settling at rest.
        if a.finish_time().is_some_and(|t| a.time() > t + 0.5) {
            break;
        }
        assert!(
            k < 200_000,
            "the program ends: t = {} s, line {}, {:?}",
            a.time(),
            a.tick().line,
            a.tick()
        );
    }
    saved
}

#[test]
fn states_taken_anywhere_in_every_corner_mode_are_accepted_and_run_on_identically() {
    // The servo on where the path stage keeps the most state (smooth chains, transitions).
    for corner in CornerMode::ALL {
        let servo = matches!(corner, CornerMode::Smooth | CornerMode::Polynomial);
        let n = round_trips(KITCHEN_SINK, &machine(corner, ProfileKind::Scurve7), servo, 307).len();
        assert!(n > 40, "{corner:?}: {n} states");
    }
}

#[test]
fn states_taken_anywhere_with_every_feed_law_are_accepted_and_run_on_identically() {
    for profile in ProfileKind::ALL {
        round_trips(KITCHEN_SINK, &machine(CornerMode::Smooth, profile), false, 997);
    }
    let default = include_str!("../resources/default.ngc");
    round_trips(default, &Machine::default(), true, 193);
}
