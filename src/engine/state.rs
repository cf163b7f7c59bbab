//! The engine's state for fmi2GetFMUstate/serialization: postcard (a maintained, compact serde
//! format whose reads are bounded by the input: no length field makes it allocate more than the
//! bytes it is given), behind a version, and checked field by field when it comes back — a
//! restored state is refused with a message unless every counter, index and value is one the
//! engine can have produced.

use super::{Engine, MAX_TIME_S};
use crate::valid::Wider;
use crate::valid::{at_most, within};

/// Version of the serialized engine state (fmi2 FMU state); bump on any layout change.
// 3: reader NC state (tools, offsets, compensation, parameters); 4: O-word flow, G93, inch setup;
// 5: override and hold in the plan stage; 6: the smooth mode's held sub-tolerance moves;
// 7: reader: motion modes G5…, `%`, splines, work rotations, queued blocks kept, cycle words;
// 8: seed 004's transition in time (no arc-length table), chains' source-line marks;
// 9: postcard instead of bincode; time as whole ticks and a phase, no servo clock;
// 10: speed bands on path blocks and the banded S-curve profile; 11: a window segment's stop
// limit NaN until needed; 12: the reader's subroutine files (a source on every place), the
// centre of a held G41/G42 entry arc; 13: a smooth span keeps the moves it stands for; 14: and
// the bound on its speed where it begins, and the planner's pass-through entry limits; 15: the
// smooth span waiting for the next before its junction; 16: a smooth chain's bound cells, none
// until it closes where its pieces' were not needed before; 17: the length of the tiny moves
// a smooth move took.
const STATE_VERSION: u32 = 17;

/// Fields whose numbers may be more than finite and moderate (see `valid::numbers`): the
/// planner's "not computed yet" and "no junction limit", a quintic's power coefficients.
const WIDER: &[(&str, Wider)] = &[
    ("junction_prev", Wider::Marker),
    ("v_in_lim", Wider::Marker),
    ("v_in_pass", Wider::Marker),
    ("v_in_stop", Wider::Marker),
    ("Hermite.c", Wider::Finite),
];

impl Engine {
    /// Serialize the whole state (not the program text) for fmi2GetFMUstate / serialization.
    pub fn save_state(&self) -> Vec<u8> {
        let mut out = STATE_VERSION.to_le_bytes().to_vec();
        // Plain data only, so this cannot fail; an empty body would be refused by restore_state.
        out.extend(postcard::to_stdvec(self).unwrap_or_default());
        out
    }

    /// Restore a state written by `save_state` for the same program and machine.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let Some((version, body)) = bytes.split_first_chunk::<4>() else {
            return Err(format!("engine state too short: {} bytes", bytes.len()));
        };
        let version = u32::from_le_bytes(*version);
        if version != STATE_VERSION {
            return Err(format!(
                "engine state version {version}, expected {STATE_VERSION}"
            ));
        }
        let (mut restored, rest): (Engine, &[u8]) =
            postcard::take_from_bytes(body).map_err(|e| format!("engine state: {e}"))?;
        if !rest.is_empty() {
            return Err(format!("engine state: {} bytes after its end", rest.len()));
        }
        if restored.machine != self.machine {
            return Err("engine state was saved for another machine configuration".into());
        }
        // The program attached first: the reader checks its subroutine files where it finds them.
        restored.program = self.program.clone();
        restored.reader.attach_text(self.program.clone());
        restored
            .check_state(self.program.text())
            .map_err(|e| format!("engine state: {e}"))?;
        restored.refresh_outputs();
        *self = restored;
        Ok(())
    }
}

impl Engine {
    /// Every field of a restored state (`text` is the program it is restored for): the numbers (`valid::numbers`), the clock, each stage's own
    /// counters, indices and relations, and the outputs it holds as the interpolator and the
    /// drives give them.
    fn check_state(&mut self, text: Option<&str>) -> Result<(), String> {
        crate::valid::numbers(self, WIDER)?;
        let m = &self.machine;
        at_most("ticks", self.ticks, (MAX_TIME_S / m.interpolation_period) as u64)?;
        within("phase", self.phase, 0.0, 1.0 - f64::EPSILON)?;
        at_most("finish tick", self.finish_tick.unwrap_or(0), self.ticks)?;
        at_most("motion blocks", self.motion_blocks, 1 << 53)?;
        for f in self.load_force {
            crate::config::ranges::check_load_force(f)?;
        }
        m.nc.check_state()?;
        self.reader.check_state(text, m)?;
        self.builder.check_state(m)?;
        self.planner.check_state(m)?;
        self.control.check_state(m)?;
        self.interp.check_state(m.profile)?;
        self.queue.iter().try_for_each(|p| p.check_state(m.profile))?;
        if let Some(d) = &self.drives {
            if d.len() != 3 {
                return Err(format!("{} drives", d.len()));
            }
            for (d, p) in d.iter().zip(&m.servo) {
                d.check_state(p)?;
            }
        }
        // The command held is the interpolator's at the last tick; finished is when it says so.
        let finished = self.interp.idle()
            && self.queue.is_empty()
            && self.program_done
            && self.planner.pending() == 0
            && self.control.held() == 0;
        let tick = self
            .interp
            .sample(self.time_of(self.ticks, 0.0), self.tick.finished);
        let claimed = self.tick.finished;
        if tick != self.tick || claimed != self.finish_tick.is_some() || (claimed && !finished) {
            return Err("the outputs held are not the interpolator's".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Machine;
    use serde::{de::DeserializeOwned, Serialize};
    use serde_json::{json, Value};

    const SINK: &str = include_str!("../../tests/data/kitchen_sink.ngc");

    fn machine() -> Machine {
        Machine::from_toml("[tool.1]\nradius_mm = 2\nlength_mm = 10\n", "tools.toml").unwrap()
    }

    /// The kitchen-sink program after `seconds`, servo on.
    fn running(seconds: f64) -> Engine {
        let mut e = Engine::new(SINK, "sink.ngc", &machine())
            .unwrap()
            .with_servo(true);
        e.advance(seconds).unwrap();
        e
    }

    /// The message a state changed by `change` is refused with.
    fn refused(e: &Engine, change: impl FnOnce(&mut Engine)) -> String {
        let mut bad = e.clone();
        change(&mut bad);
        let mut fresh = Engine::new(SINK, "sink.ngc", &machine()).unwrap();
        assert_eq!(
            fresh.clone().restore_state(&e.save_state()),
            Ok(()),
            "the unchanged state"
        );
        fresh.restore_state(&bad.save_state()).unwrap_err()
    }

    /// `part` with the value at JSON `pointer` replaced (parts without NaN markers).
    fn set<T: Serialize + DeserializeOwned>(part: &mut T, pointer: &str, value: Value) {
        let mut v = serde_json::to_value(&*part).unwrap();
        *v.pointer_mut(pointer).unwrap_or_else(|| panic!("{pointer}")) = value;
        *part = serde_json::from_value(v).unwrap();
    }

    type Change = Box<dyn FnOnce(&mut Engine)>;

    fn drive(e: &mut Engine) -> &mut crate::servo::ServoAxis {
        &mut e.drives.as_mut().unwrap()[0]
    }

    #[test]
    fn counters_indices_and_magnitudes_no_run_produces_are_refused() {
        let e = running(6.0);
        let big = json!(2_147_483_647u64);
        let cases: Vec<(&str, Change)> = vec![
            ("not the interpolator's", Box::new(|e| e.ticks = 2_147_483_647)),
            (
                "ticks = 18446744073709551615 out of range",
                Box::new(|e| e.ticks = u64::MAX),
            ),
            ("phase", Box::new(|e| e.phase = 1.5)),
            ("finish tick", Box::new(|e| e.finish_tick = Some(e.ticks + 10))),
            (
                "not the start of line",
                Box::new(|e| {
                    let next = json!(e.reader.offset() + 1);
                    set(&mut e.reader, "/offset", next)
                }),
            ),
            (
                "not the start of line",
                Box::new(move |e| set(&mut e.reader, "/line", big)),
            ),
            (
                "work system = 1000",
                Box::new(|e| set(&mut e.reader, "/work", json!(1000))),
            ),
            (
                "loop passes",
                Box::new(|e| set(&mut e.reader, "/flow/iterations", json!(2e9 as u64))),
            ),
            (
                "peck depth",
                Box::new(|e| set(&mut e.reader, "/cycle/q", json!(-1.0))),
            ),
            ("servo phase", Box::new(|e| set(drive(e), "/phase", json!(1.0)))),
            (
                "drives.x.x = -1.3e163 out of range",
                Box::new(|e| set(drive(e), "/x/x", json!(-1.3e163))),
            ),
            (
                "torque command",
                Box::new(|e| set(drive(e), "/torque_ref", json!(100.0))),
            ),
            (
                "time in block",
                Box::new(|e| set(&mut e.interp, "/current/tau", json!(1e6))),
            ),
            (
                "another machine",
                Box::new(|e| e.machine.interpolation_period = 1e-300),
            ),
            ("load_force", Box::new(|e| e.load_force[2] = 1e300)),
        ];
        for (want, change) in cases {
            let message = refused(&e, change);
            assert!(message.contains(want), "{want}: {message}");
        }
        // A window larger than the look-ahead would read the whole program at once.
        let mut done = running(6.0);
        done.advance(20.0).unwrap();
        assert!(done.finished());
        let message = refused(&done, |e| {
            set(&mut e.planner, "/capacity", json!(2_147_483_647u64))
        });
        assert!(message.contains("another law or look-ahead"), "{message}");
    }

    /// Every numeric field of the stages' states (JSON leaves), one at a time, set to a value
    /// from a list of extremes: refused with a message, or the engine runs on for 5 ticks with
    /// finite outputs (or stops with a located program error), never a panic. Seeded by
    /// CNC_FUZZ_SEED; CNC_STATE_FUZZ_CASES cases (default 1500).
    #[test]
    fn any_field_set_to_an_extreme_is_refused_or_runs_on() {
        let env = |k: &str, d: u64| std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d);
        let mut x = env("CNC_FUZZ_SEED", 20_261_124) | 1;
        let mut rng = move |n: usize| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % n as u64) as usize
        };
        let extremes = [
            json!(2_147_483_647u64),
            json!(u64::MAX),
            json!(-1),
            json!(0),
            json!(1e300),
            json!(-1.3e163),
            json!(1e-300),
            json!(2.5),
        ];
        let states = [running(0.7), running(3.3), running(6.0), running(9.5)];
        let (mut refused_n, mut ran, mut located, mut skipped) = (0, 0, 0, 0);
        for case in 0..env("CNC_STATE_FUZZ_CASES", 1500) {
            let mut e = states[rng(states.len())].clone();
            let part = rng(7);
            let mut tree = match part {
                0 => serde_json::to_value(&e.reader),
                1 => serde_json::to_value(&e.builder),
                2 => serde_json::to_value(&e.interp),
                3 => serde_json::to_value(&e.queue),
                4 => serde_json::to_value(&e.planner),
                5 => serde_json::to_value(&e.control),
                _ => serde_json::to_value(&e.drives),
            }
            .unwrap();
            let leaves = numbers_in(&tree, String::new());
            if leaves.is_empty() {
                skipped += 1;
                continue;
            }
            let at = &leaves[rng(leaves.len())];
            *tree.pointer_mut(at).unwrap() = extremes[rng(extremes.len())].clone();
            let back = match part {
                0 => serde_json::from_value(tree).map(|v| e.reader = v),
                1 => serde_json::from_value(tree).map(|v| e.builder = v),
                2 => serde_json::from_value(tree).map(|v| e.interp = v),
                3 => serde_json::from_value(tree).map(|v| e.queue = v),
                4 => serde_json::from_value(tree).map(|v| e.planner = v),
                5 => serde_json::from_value(tree).map(|v| e.control = v),
                _ => serde_json::from_value(tree).map(|v| e.drives = v),
            };
            if back.is_err() {
                skipped += 1; // not of the field's type, or a NaN marker elsewhere in the part
                continue;
            }
            let mut fresh = Engine::new(SINK, "sink.ngc", &machine()).unwrap();
            match fresh.restore_state(&e.save_state()) {
                Err(m) => {
                    assert!(!m.is_empty());
                    refused_n += 1;
                }
                Ok(()) => {
                    let mut outcome = "ran";
                    for _ in 0..env("CNC_STATE_FUZZ_STEPS", 5) {
                        if let Err(err) = fresh.advance(1e-3) {
                            assert!(err.line >= 1, "case {case} ({part}{at}): {err}");
                            outcome = "located";
                            break;
                        }
                        let ok = fresh.check_outputs();
                        assert!(ok.is_ok(), "case {case} ({part}{at}): {ok:?}");
                    }
                    if outcome == "ran" {
                        ran += 1;
                    } else {
                        located += 1;
                    }
                }
            }
        }
        println!("fields set to extremes: refused {refused_n}, ran {ran}, located error {located}, not representable {skipped}");
        assert!(refused_n > 100 && ran > 100);
    }

    /// JSON pointers of every number in `v`.
    fn numbers_in(v: &Value, at: String) -> Vec<String> {
        match v {
            Value::Number(_) => vec![at],
            Value::Array(a) => a
                .iter()
                .enumerate()
                .flat_map(|(i, x)| numbers_in(x, format!("{at}/{i}")))
                .collect(),
            Value::Object(o) => o
                .iter()
                .flat_map(|(k, x)| numbers_in(x, format!("{at}/{k}")))
                .collect(),
            _ => Vec::new(),
        }
    }
}
