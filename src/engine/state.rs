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
// 7: postcard instead of bincode; time as whole ticks and a phase, no servo clock.
const STATE_VERSION: u32 = 7;

/// Fields whose numbers may be more than finite and moderate (see `valid::numbers`): the
/// planner's "not computed yet" and "no junction limit", a quintic's power coefficients.
const WIDER: &[(&str, Wider)] = &[
    ("junction_prev", Wider::Marker),
    ("v_in_lim", Wider::Marker),
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
        restored
            .check_state(self.program.text())
            .map_err(|e| format!("engine state: {e}"))?;
        restored.program = self.program.clone();
        restored.reader.attach_text(self.program.clone());
        *self = restored;
        Ok(())
    }
}

impl Engine {
    /// Every field of a restored state (its `program` not yet attached; `text` is the program
    /// it is restored for): the numbers (`valid::numbers`), the clock, each stage's own
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
