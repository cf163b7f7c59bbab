//! The motion engine: reader → path → planner → interpolator (→ servo), as used by the CLI and
//! the FMU. Plain data throughout, so the whole state can be cloned and serialized.

use crate::config::Machine;
use crate::error::ProgramError;
use crate::gcode::{Motion, ProgramSource, Reader};
use crate::interp::{Interpolator, Tick};
use crate::path::{PathBlock, PathBuilder};
use crate::plan::{FeedControl, Planned, Planner, Replan};
use crate::servo::{AxisCommand, AxisState, ServoAxis};
use crate::tolerance::PERIOD_SLACK;
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Version of the serialized engine state (fmi2 FMU state); bump on any layout change.
// 3: reader NC state (tools, offsets, compensation, parameters); 4: O-word flow, G93, inch setup;
// 5: override and hold in the plan stage; 6: the smooth mode's held sub-tolerance moves;
// 7: reader: motion modes G5…, `%`, splines, work rotations, queued blocks kept, cycle words;
// 8: seed 004's transition in time (no arc-length table), chains' source-line marks;
// 9: speed bands on path blocks and the banded S-curve profile.
const STATE_VERSION: u32 = 9;
/// Blocks read at most per tick for the read-ahead, and the planned segments it aims to hold.
const READ_AHEAD_PER_TICK: usize = 1;
const QUEUE_TARGET: usize = 8;

/// Runs one program on one machine.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Engine {
    machine: Machine,
    #[serde(skip)]
    program: ProgramSource,
    reader: Reader,
    builder: PathBuilder,
    planner: Planner,
    queue: VecDeque<Planned>,
    #[serde(skip)]
    segments: Vec<PathBlock>,
    interp: Interpolator,
    program_done: bool,
    tick: Tick,
    /// Number of interpolation ticks done (tick n is at n·T).
    ticks: u64,
    time: f64,
    /// Feed override and hold (plan stage).
    control: FeedControl,
    /// The three drives when the servo model is on, and the time they have reached.
    drives: Option<Vec<ServoAxis>>,
    servo_time: f64,
    load_force: Vec3,
    motion_blocks: u64,
    /// Time of the tick at which all motion was done (s).
    finish_time: Option<f64>,
}

impl Engine {
    /// Checks the whole program first (streaming, nothing kept), so that a bad program fails here
    /// with `file:line:col: message`, before any motion.
    pub fn new(
        program: impl Into<ProgramSource>,
        file: &str,
        machine: &Machine,
    ) -> Result<Engine, ProgramError> {
        let program = program.into();
        let start = [0.0; 3];
        let reader = Reader::new(program.clone(), file, start).with_machine(machine);
        crate::gcode::validate_with(reader.clone())?;
        let interp = Interpolator::new(start);
        let tick = interp.sample(0.0, false);
        let mut engine = Engine {
            machine: machine.clone(),
            reader,
            program,
            builder: PathBuilder::new(machine),
            planner: Planner::new(machine.profile, machine.lookahead_blocks),
            queue: VecDeque::new(),
            segments: Vec::new(),
            interp,
            program_done: false,
            tick,
            ticks: 0,
            time: 0.0,
            control: FeedControl::new(machine),
            drives: None,
            servo_time: 0.0,
            load_force: [0.0; 3],
            motion_blocks: 0,
            finish_time: None,
        };
        // Read ahead before the first tick, as an NC does before cycle start.
        engine.refill()?;
        Ok(engine)
    }

    /// Switch the servo-axis model on (the FMU always does; the CLI with `--servo`).
    pub fn with_servo(mut self, on: bool) -> Engine {
        self.drives = on.then(|| {
            (0..3)
                .map(|i| ServoAxis::new(self.machine.servo[i], self.tick.p[i]))
                .collect()
        });
        self.servo_time = self.time;
        self
    }

    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    pub fn program(&self) -> &ProgramSource {
        &self.program
    }

    /// Internal time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The latest interpolator output (held between ticks).
    pub fn tick(&self) -> &Tick {
        &self.tick
    }

    /// Bytes of the program the reader has read (ahead of the motion by the look-ahead; an
    /// O-word loop takes it back): progress through a program file.
    pub fn program_offset(&self) -> usize {
        self.reader.offset()
    }

    /// Motion blocks (G0/G1/G2/G3) read so far.
    pub fn motion_blocks(&self) -> u64 {
        self.motion_blocks
    }

    /// Exact path time of the motion (sum of the planned block durations, dwells included) once
    /// finished; the running path time before that.
    pub fn motion_time(&self) -> f64 {
        self.interp.path_time()
    }

    /// Time of the first tick with all motion done.
    pub fn finish_time(&self) -> Option<f64> {
        self.finish_time
    }

    /// Actual axis states after the drives (equal to the command when the servo is off).
    pub fn axes(&self) -> [AxisState; 3] {
        if let Some(d) = &self.drives {
            return [d[0].state(), d[1].state(), d[2].state()];
        }
        let mut out = [AxisState::default(); 3];
        for (i, o) in out.iter_mut().enumerate() {
            o.position = self.tick.p[i];
            o.velocity = self.tick.v[i];
        }
        out
    }

    /// Distance of the actual tool point from the programmed path (m), measured from the tangent
    /// line at the commanded point.
    pub fn contour_error(&self) -> f64 {
        let axes = self.axes();
        let e: Vec3 = std::array::from_fn(|i| axes[i].position - self.tick.p[i]);
        let u = self.tick.tangent;
        let along = crate::path::dot(e, u);
        let normal = crate::path::sub(e, crate::path::scale(u, along));
        crate::path::norm(normal)
    }

    /// The block being executed and the path time left in it (s), None between blocks.
    pub fn executing(&self) -> Option<(&PathBlock, f64)> {
        self.interp.current().map(|(p, left)| (&p.block, left))
    }

    pub fn finished(&self) -> bool {
        self.tick.finished
    }

    /// Feed override factor (0…2). The path is re-planned from the next point where its
    /// acceleration is zero (a cruise phase or a block end) with the feeds scaled: a speed change
    /// by the feed law itself, so jerk-limited and within every limit. 0 acts as a feed hold.
    pub fn set_feed_override(&mut self, k: f64) {
        let current = self.interp.current().map(|(p, _)| p);
        self.control
            .set_override(k, current, &mut self.queue, &mut self.planner);
    }

    /// Feed hold: decelerate to standstill on the path within the limits (planned from the next
    /// point of zero acceleration); release resumes from there.
    pub fn set_feed_hold(&mut self, hold: bool) {
        let current = self.interp.current().map(|(p, _)| p);
        self.control
            .set_hold(hold, current, &mut self.queue, &mut self.planner);
    }

    /// External force on each axis' table from a structure model (N).
    pub fn set_load_force(&mut self, force: Vec3) {
        self.load_force = force;
    }

    /// Advance one interpolation period.
    pub fn step(&mut self) -> Result<&Tick, ProgramError> {
        let t = (self.ticks + 1) as f64 * self.machine.interpolation_period;
        self.advance(t - self.time)?;
        Ok(&self.tick)
    }

    /// Advance the time by h > 0: interpolator ticks at every multiple of the period (zero-order
    /// hold between), servo sub-stepped continuously.
    pub fn advance(&mut self, h: f64) -> Result<(), ProgramError> {
        let period = self.machine.interpolation_period;
        let t_end = self.time + h.max(0.0);
        // A tick within a billionth of a period of the end belongs to this step (rounding of t).
        let slack = PERIOD_SLACK * period;
        loop {
            let t_tick = (self.ticks + 1) as f64 * period;
            if t_tick > t_end + slack {
                break;
            }
            let t = t_tick.min(t_end);
            self.servo_to(t);
            self.time = t;
            self.ticks += 1;
            self.interpolate(t_tick)?;
        }
        self.servo_to(t_end);
        self.time = t_end;
        Ok(())
    }

    /// Drives from their time to t with the current command held (zero-order hold).
    fn servo_to(&mut self, t: f64) {
        let Some(drives) = self.drives.as_mut() else {
            return;
        };
        let dt = t - self.servo_time;
        // A remainder of rounding size (a communication point a hair past a tick) is not a step:
        // it would start a servo period on the new command and make the result depend on how the
        // importer sums its time.
        if dt <= PERIOD_SLACK * self.machine.interpolation_period {
            return;
        }
        for (i, d) in drives.iter_mut().enumerate() {
            let cmd = AxisCommand {
                position: self.tick.p[i],
                velocity: self.tick.v[i],
                acceleration: self.tick.a[i],
            };
            d.step(&cmd, self.load_force[i], dt);
        }
        self.servo_time = t;
    }

    /// One interpolation tick at time `t`.
    fn interpolate(&mut self, t: f64) -> Result<(), ProgramError> {
        let period = self.machine.interpolation_period;
        if self.control.pending() {
            let here = self.interp.here();
            let replan = self.control.replan(here, &mut self.queue, &mut self.planner);
            if replan == (Replan::Done { cut: true }) {
                self.interp.end_here();
            }
        }
        // Keep a few planned segments ahead, reading at most a few blocks per tick, so that no
        // single tick pays for a whole look-ahead window.
        let hold_applied = self.control.hold_applied();
        if !hold_applied {
            for _ in 0..READ_AHEAD_PER_TICK {
                if self.queue.len() >= QUEUE_TARGET || !self.pull()? {
                    break;
                }
            }
        }
        let mut dt = period;
        loop {
            dt = self.interp.advance(dt, &mut self.queue);
            if dt <= 0.0 || hold_applied || !self.refill()? {
                break;
            }
        }
        if self.interp.idle() && self.queue.is_empty() && !hold_applied {
            self.refill()?;
        }
        let finished = self.interp.idle()
            && self.queue.is_empty()
            && self.program_done
            && self.planner.pending() == 0
            && self.control.held() == 0;
        let tick = self.interp.sample(t, finished);
        if finished && self.finish_time.is_none() {
            self.finish_time = Some(t);
        }
        self.tick = tick;
        Ok(())
    }

    /// Read, build and plan until a planned segment is queued or the program ends.
    /// Returns whether the queue holds a segment.
    fn refill(&mut self) -> Result<bool, ProgramError> {
        while self.queue.is_empty() {
            if !self.pull()? {
                break;
            }
        }
        Ok(!self.queue.is_empty())
    }

    /// Read one block (or, after the program end, release one planned segment).
    /// Returns false when nothing more will come.
    fn pull(&mut self) -> Result<bool, ProgramError> {
        if self.program_done {
            return Ok(self.planner.emit_one(&mut self.queue));
        }
        {
            match self.reader.next_block()? {
                Some(block) => {
                    if matches!(
                        block.motion,
                        Motion::Rapid { .. } | Motion::Linear { .. } | Motion::Arc { .. }
                    ) {
                        self.motion_blocks += 1;
                    }
                    self.builder.push(&block, &mut self.segments);
                }
                None => {
                    self.builder.finish(&mut self.segments);
                    self.program_done = true;
                }
            }
            for segment in self.segments.drain(..) {
                self.planner.push(segment, &mut self.queue);
            }
        }
        Ok(true)
    }

    /// Serialize the whole state (not the program text) for fmi2GetFMUstate / serialization.
    pub fn save_state(&self) -> Vec<u8> {
        let mut out = STATE_VERSION.to_le_bytes().to_vec();
        // Plain data only, so this cannot fail; an empty body would be refused by restore_state.
        out.extend(bincode::serialize(self).unwrap_or_default());
        out
    }

    /// Restore a state written by `save_state` for the same program and machine.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        if bytes.len() < 4 {
            return Err(format!("engine state too short: {} bytes", bytes.len()));
        }
        let version = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        if version != STATE_VERSION {
            return Err(format!(
                "engine state version {version}, expected {STATE_VERSION}"
            ));
        }
        let mut restored: Engine =
            bincode::deserialize(&bytes[4..]).map_err(|e| format!("engine state: {e}"))?;
        if restored.machine != self.machine {
            return Err("engine state was saved for another machine configuration".into());
        }
        restored.program = self.program.clone();
        restored.reader.attach_text(self.program.clone());
        *self = restored;
        Ok(())
    }
}
