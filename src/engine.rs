//! The motion engine: reader → path → planner → interpolator (→ servo), as used by the CLI and
//! the FMU. Plain data throughout, so the whole state can be cloned and serialized.
//!
//! Time is counted in whole interpolation ticks plus the fraction of a period past the last one:
//! a communication point within [`SAME_INSTANT_S`] of a tick is that tick, however the importer
//! formed its time, so every tick is seen at h = T and the drives always step whole ticks of
//! exactly T (the same sub-steps, bit for bit, after an hour as after a second).

mod outputs;
mod state;

pub use crate::valid::MAX_TIME_S;
pub use outputs::Outputs;

use crate::config::Machine;
use crate::error::ProgramError;
use crate::gcode::{Motion, ProgramSource, Reader};
use crate::interp::{Interpolator, Tick};
use crate::path::{PathBlock, PathBuilder};
use crate::plan::{FeedControl, Planned, Planner, Replan};
use crate::servo::{AxisCommand, AxisState, ServoAxis};
use crate::tolerance::SAME_INSTANT_S;
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Blocks read at most per tick for the read-ahead, and the planned segments it aims to hold.
const READ_AHEAD_PER_TICK: usize = 1;
const QUEUE_TARGET: usize = 8;
/// Ticks stepped before drives that could not take a rest in closed form are asked again.
const REST_RETRY: u64 = 64;
/// Fewest ticks at rest worth the closed form (shorter rests are stepped: the same result as
/// with any other step size, to rounding, and cheaper).
const REST_MIN_TICKS: u64 = 1000;
/// Ticks one `advance` steps one by one at most (motion, and drives settling after it; ≈ 5–10 s
/// of computing): a longer step is refused when it gets there. Ticks at rest with the drives
/// still cost nothing (closed form).
pub const MAX_STEPPED_TICKS: u64 = 10_000_000;

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
    /// Time past tick `ticks`, in periods (0 ≤ phase < 1): a communication point between ticks.
    phase: f64,
    /// Feed override and hold (plan stage).
    control: FeedControl,
    /// The three drives when the servo model is on (at the engine's time).
    drives: Option<Vec<ServoAxis>>,
    load_force: Vec3,
    motion_blocks: u64,
    /// The tick at which all motion was done.
    finish_tick: Option<u64>,
    /// What the outputs read, computed once per step.
    #[serde(skip)]
    outputs: Outputs,
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
            phase: 0.0,
            control: FeedControl::new(machine),
            drives: None,
            load_force: [0.0; 3],
            motion_blocks: 0,
            finish_tick: None,
            outputs: Outputs::default(),
        };
        // Read ahead before the first tick, as an NC does before cycle start.
        engine.refill()?;
        engine.refresh_outputs();
        Ok(engine)
    }

    /// Switch the servo-axis model on (the FMU always does; the CLI with `--servo`).
    pub fn with_servo(mut self, on: bool) -> Engine {
        self.drives = on.then(|| {
            (0..3)
                .map(|i| ServoAxis::new(self.machine.servo[i], self.tick.p[i]))
                .collect()
        });
        self.refresh_outputs();
        self
    }

    /// Whether the drives are simulated.
    pub fn servo(&self) -> bool {
        self.drives.is_some()
    }

    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    pub fn program(&self) -> &ProgramSource {
        &self.program
    }

    /// Internal time (s): n·T at tick n.
    pub fn time(&self) -> f64 {
        self.time_of(self.ticks, self.phase)
    }

    /// Interpolation ticks done.
    pub fn ticks(&self) -> u64 {
        self.ticks
    }

    fn time_of(&self, ticks: u64, phase: f64) -> f64 {
        let t = ticks as f64 * self.machine.interpolation_period;
        if phase == 0.0 {
            t
        } else {
            t + phase * self.machine.interpolation_period
        }
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
        self.finish_tick.map(|n| self.time_of(n, 0.0))
    }

    /// Actual axis states after the drives (equal to the command when the servo is off).
    pub fn axes(&self) -> [AxisState; 3] {
        self.outputs().axes
    }

    /// Distance of the actual tool point from the programmed path (m), measured from the tangent
    /// line at the commanded point.
    pub fn contour_error(&self) -> f64 {
        self.outputs().contour_error
    }

    /// Everything the outputs read, as of the end of the last step: kept once per step with the
    /// drives on; without them a view of the command, made when asked (a caller that does not
    /// read them, the CLI without `--servo`, pays nothing per tick).
    pub fn outputs(&self) -> Outputs {
        match self.drives {
            Some(_) => self.outputs,
            None => Outputs::of(&self.tick, None),
        }
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

    /// Advance one interpolation period: `run_to(ticks + 1, 0)` without its loop (one tick is
    /// never a rest worth the closed form, nor too many ticks).
    pub fn step(&mut self) -> Result<&Tick, ProgramError> {
        self.next_tick()?;
        self.refresh_outputs();
        Ok(&self.tick)
    }

    /// Advance the time by h ≥ 0: interpolator ticks at every multiple of the period (zero-order
    /// hold between), drives sub-stepped continuously. An end within [`SAME_INSTANT_S`] of a
    /// tick is that tick.
    pub fn advance(&mut self, h: f64) -> Result<(), ProgramError> {
        let period = self.machine.interpolation_period;
        let end = self.phase + h.max(0.0) / period;
        if self.time() + h > MAX_TIME_S || h.is_nan() {
            return Err(self.error(format!(
                "a step of {h} s from t = {} s ends beyond the engine's time range ({MAX_TIME_S:e} s)",
                self.time()
            )));
        }
        let whole = end.round();
        let (ticks, phase) = if (end - whole).abs() * period <= SAME_INSTANT_S {
            (whole, 0.0)
        } else {
            (end.floor(), end - end.floor())
        };
        self.run_to(self.ticks + ticks as u64, phase)
    }

    /// Run to tick `ticks` plus `phase` periods.
    fn run_to(&mut self, ticks: u64, phase: f64) -> Result<(), ProgramError> {
        let (mut stepped, mut next_rest) = (0u64, 0u64);
        while self.ticks < ticks {
            // At rest for good, for long: the rest of the step at once, once the drives are still
            // (tried again REST_RETRY ticks after a drive could not take it).
            if stepped >= next_rest && ticks - self.ticks >= REST_MIN_TICKS && self.quiescent() {
                if self.rest_to(ticks) {
                    break;
                }
                next_rest = stepped + REST_RETRY;
            }
            if stepped == MAX_STEPPED_TICKS {
                self.refresh_outputs();
                return Err(self.error(format!(
                    "a step of more than {MAX_STEPPED_TICKS} ticks with motion or drives not at rest \
                     (stopped at t = {} s): take shorter steps",
                    self.time()
                )));
            }
            stepped += 1;
            self.next_tick()?;
        }
        if phase > self.phase {
            self.drives_to(phase);
            self.phase = phase;
        }
        self.refresh_outputs();
        Ok(())
    }

    /// The drives to the next tick, and the interpolator at it.
    #[inline]
    fn next_tick(&mut self) -> Result<(), ProgramError> {
        self.drives_to(1.0);
        self.ticks += 1;
        self.phase = 0.0;
        self.interpolate(self.time())
    }

    /// An error at the line being executed.
    fn error(&self, message: String) -> ProgramError {
        ProgramError::new(self.reader.file(), self.tick.line.max(1), 1, message)
    }

    /// Nothing will move the command before the inputs change: the program is finished, or a
    /// hold has brought the path to rest.
    fn quiescent(&self) -> bool {
        self.interp.idle()
            && self.queue.is_empty()
            && !self.control.pending()
            && (self.tick.finished || self.control.hold_applied())
    }

    /// With the command at rest for good: to tick `ticks` at once if the drives are still (their
    /// closed form at rest; the ticks only move the clock). False, with nothing changed, if not.
    fn rest_to(&mut self, ticks: u64) -> bool {
        let n = ticks - self.ticks;
        let still = self.drives.iter().flatten().all(ServoAxis::still);
        if self.phase != 0.0 || !still {
            return false;
        }
        if let Some(drives) = &self.drives {
            let period = self.machine.interpolation_period;
            let mut next = drives.clone();
            for (i, d) in next.iter_mut().enumerate() {
                if !d.rest(&self.command(i), self.load_force[i], n, period) {
                    return false;
                }
            }
            self.drives = Some(next);
        }
        self.ticks = ticks;
        self.tick.t = self.time();
        true
    }

    /// The command of axis `i` (held between ticks).
    fn command(&self, i: usize) -> AxisCommand {
        AxisCommand {
            position: self.tick.p[i],
            velocity: self.tick.v[i],
            acceleration: self.tick.a[i],
        }
    }

    /// Drives from the engine's time to `phase` periods past tick `ticks` (1: the next tick),
    /// the current command held (zero-order hold).
    #[inline]
    fn drives_to(&mut self, phase: f64) {
        // Without the drives (the CLI's default) every tick only asks.
        if self.drives.is_some() {
            self.step_drives(phase);
        }
    }

    #[inline(never)]
    fn step_drives(&mut self, phase: f64) {
        // (1 − 0)·T is T exactly: whole ticks are always the same step.
        let dt = (phase - self.phase) * self.machine.interpolation_period;
        let commands: [AxisCommand; 3] = std::array::from_fn(|i| self.command(i));
        if let Some(drives) = self.drives.as_mut() {
            for (i, d) in drives.iter_mut().enumerate() {
                d.step(&commands[i], self.load_force[i], dt);
            }
        }
    }

    fn refresh_outputs(&mut self) {
        if let Some(drives) = self.drives.as_deref() {
            self.outputs = Outputs::of(&self.tick, Some(drives));
        }
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
        self.interp.sample_into(t, finished, &mut self.tick);
        if finished && self.finish_tick.is_none() {
            self.finish_tick = Some(self.ticks);
        }
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
}
