//! The motion engine: reader → path → planner → interpolator (→ servo), as used by the CLI and
//! the FMU. Plain data throughout, so the whole state can be cloned and serialized.

use crate::config::Machine;
use crate::error::ProgramError;
use crate::gcode::{Motion, Reader};
use crate::interp::{Interpolator, Tick};
use crate::path::{PathBlock, PathBuilder};
use crate::plan::{Planned, Planner};
use crate::servo::{AxisCommand, AxisState, ServoAxis};
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use std::sync::Arc;

/// Version of the serialized engine state (fmi2 FMU state); bump on any layout change.
const STATE_VERSION: u32 = 1;
/// Blocks read at most per tick for the read-ahead, and the planned segments it aims to hold.
const READ_AHEAD_PER_TICK: usize = 4;
const QUEUE_TARGET: usize = 8;

/// Feed-override tracker: the time-scaling factor k = dσ/dt (σ the planned path time) follows
/// its target with bounded k̇ and k̈, so an override or a hold changes the speed jerk-limited:
/// ṡ = s'k, s̈ = s''k² + s'k̇, s⃛ = s'''k³ + 3s''kk̇ + s'k̈.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct TimeScale {
    k: f64,
    k_dot: f64,
    k_ddot: f64,
    k_dot_max: f64,
    k_ddot_max: f64,
}

impl TimeScale {
    fn new(machine: &Machine) -> TimeScale {
        // Half the slowest axis' acceleration and jerk at the machine's top feed, so the override
        // transient adds at most that much to a planned motion.
        let a = machine
            .axes
            .iter()
            .map(|x| x.max_acceleration)
            .fold(f64::INFINITY, f64::min);
        let j = machine
            .axes
            .iter()
            .map(|x| x.max_jerk)
            .fold(f64::INFINITY, f64::min);
        let v_ref = machine.max_feed.max(1e-9);
        TimeScale {
            k: 1.0,
            k_dot: 0.0,
            k_ddot: 0.0,
            k_dot_max: 0.5 * a / v_ref,
            k_ddot_max: 0.5 * j / v_ref,
        }
    }

    /// Advance by one period T toward `target`; returns the path time elapsed, ∫k dt.
    fn step(&mut self, target: f64, period: f64) -> f64 {
        let k_old = self.k;
        let e = target - self.k;
        let (jd, am) = (self.k_ddot_max, self.k_dot_max);
        if e.abs() < 1e-12 && self.k_dot.abs() < 1e-12 {
            self.k = target;
            self.k_dot = 0.0;
            self.k_ddot = 0.0;
            return period * 0.5 * (k_old + self.k);
        }
        // Distance the rate needs to come back to zero at full k̈: k̇²/(2 k̈_max).
        let stopping = self.k_dot * self.k_dot / (2.0 * jd) + self.k_dot.abs() * period;
        let toward = self.k_dot * e > 0.0;
        let k_ddot = if toward && e.abs() <= stopping {
            -self.k_dot.signum() * jd
        } else {
            e.signum() * jd
        };
        let mut k_dot = (self.k_dot + k_ddot * period).clamp(-am, am);
        let mut k = self.k + 0.5 * (self.k_dot + k_dot) * period;
        // Land on the target instead of overshooting it.
        if (target - k) * e <= 0.0 {
            k = target;
            k_dot = 0.0;
        }
        self.k_ddot = (k_dot - self.k_dot) / period;
        self.k_dot = k_dot;
        self.k = k.clamp(0.0, 1.0);
        period * 0.5 * (k_old + self.k)
    }
}

/// Runs one program on one machine.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Engine {
    machine: Machine,
    #[serde(skip)]
    program: Arc<str>,
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
    scale: TimeScale,
    servo: bool,
    /// The three drives when the servo model is on, and the time they have reached.
    drives: Option<Vec<ServoAxis>>,
    servo_time: f64,
    feed_override: f64,
    feed_hold: bool,
    load_force: Vec3,
    motion_blocks: u64,
    /// Time of the tick at which all motion was done (s).
    finish_time: Option<f64>,
}

impl Engine {
    /// Checks the whole program first (streaming, nothing kept), so that a bad program fails here
    /// with `file:line:col: message`, before any motion.
    pub fn new(program: Arc<str>, file: &str, machine: &Machine) -> Result<Engine, ProgramError> {
        crate::gcode::validate(program.clone(), file)?;
        let start = [0.0; 3];
        let interp = Interpolator::new(start);
        let tick = interp.sample(0.0, false);
        let mut engine = Engine {
            machine: machine.clone(),
            reader: Reader::new(program.clone(), file, start),
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
            scale: TimeScale::new(machine),
            servo: false,
            drives: None,
            servo_time: 0.0,
            feed_override: 1.0,
            feed_hold: false,
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
        self.servo = on;
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

    pub fn program(&self) -> &Arc<str> {
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

    pub fn finished(&self) -> bool {
        self.tick.finished
    }

    /// Feed override factor (0…2), applied with jerk-limited speed changes: below 1 by time
    /// scaling of the planned motion, above 1 by planning the blocks read from now on faster.
    pub fn set_feed_override(&mut self, k: f64) {
        let k = if k.is_finite() { k.clamp(0.0, 2.0) } else { 1.0 };
        self.feed_override = k;
        self.planner.set_feed_scale(k.max(1.0));
    }

    /// Feed hold: decelerate to standstill on the path within the limits; release resumes.
    pub fn set_feed_hold(&mut self, hold: bool) {
        self.feed_hold = hold;
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
        let slack = 1e-9 * period;
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
        if dt <= 1e-9 * self.machine.interpolation_period {
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
        let target = if self.feed_hold {
            0.0
        } else {
            self.feed_override.min(1.0)
        };
        let mut dt = self.scale.step(target, period);
        // Keep a few planned segments ahead, reading at most a few blocks per tick, so that no
        // single tick pays for a whole look-ahead window.
        for _ in 0..READ_AHEAD_PER_TICK {
            if self.queue.len() >= QUEUE_TARGET || !self.pull()? {
                break;
            }
        }
        loop {
            dt = self.interp.advance(dt, &mut self.queue);
            if dt <= 0.0 || !self.refill()? {
                break;
            }
        }
        if self.interp.idle() && self.queue.is_empty() {
            self.refill()?;
        }
        let finished = self.interp.idle() && self.queue.is_empty() && self.program_done;
        let mut tick = self.interp.sample(t, finished);
        // Time scaling by the override (chain rule in k = dσ/dt).
        let TimeScale { k, k_dot, k_ddot, .. } = self.scale;
        for i in 0..3 {
            let (v, a, j) = (tick.v[i], tick.a[i], tick.j[i]);
            tick.v[i] = v * k;
            tick.a[i] = a * k * k + v * k_dot;
            tick.j[i] = j * k * k * k + 3.0 * a * k * k_dot + v * k_ddot;
        }
        let (v, a, j) = (tick.feed, tick.path_acceleration, tick.path_jerk);
        tick.feed = v * k;
        tick.path_acceleration = a * k * k + v * k_dot;
        tick.path_jerk = j * k * k * k + 3.0 * a * k * k_dot + v * k_ddot;
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
        out.extend(serde_json::to_vec(self).unwrap_or_default());
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
            serde_json::from_slice(&bytes[4..]).map_err(|e| format!("engine state: {e}"))?;
        if restored.machine != self.machine {
            return Err("engine state was saved for another machine configuration".into());
        }
        restored.program = self.program.clone();
        restored.reader.attach_text(self.program.clone());
        *self = restored;
        Ok(())
    }
}
