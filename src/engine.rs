//! The motion engine: reader → path → planner → interpolator (→ servo), as used by the CLI and
//! the FMU. Plain data throughout, so the whole state can be cloned and serialized.
//! PLACEHOLDER implementation: the public API below is the contract the CLI and the FMU use.

use crate::config::Machine;
use crate::error::ProgramError;
use crate::interp::Tick;
use crate::servo::AxisState;
use crate::Vec3;
use std::sync::Arc;

/// Runs one program on one machine.
#[derive(Clone, Debug)]
pub struct Engine {
    machine: Machine,
    program: Arc<str>,
    tick: Tick,
    time: f64,
    servo: bool,
    feed_override: f64,
    feed_hold: bool,
    load_force: Vec3,
}

impl Engine {
    /// Checks the whole program first (streaming, nothing kept), so that a bad program fails here
    /// with `file:line:col: message`, before any motion.
    pub fn new(program: Arc<str>, file: &str, machine: &Machine) -> Result<Engine, ProgramError> {
        crate::gcode::validate(program.clone(), file)?;
        Ok(Engine {
            machine: machine.clone(),
            program,
            tick: Tick::default(),
            time: 0.0,
            servo: false,
            feed_override: 1.0,
            feed_hold: false,
            load_force: [0.0; 3],
        })
    }

    /// Switch the servo-axis model on (the FMU always does; the CLI with `--servo`).
    pub fn with_servo(mut self, on: bool) -> Engine {
        self.servo = on;
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

    /// Actual axis states after the drives (equal to the command when the servo is off).
    pub fn axes(&self) -> [AxisState; 3] {
        let mut out = [AxisState::default(); 3];
        for (i, o) in out.iter_mut().enumerate() {
            o.position = self.tick.p[i];
            o.velocity = self.tick.v[i];
        }
        out
    }

    /// Distance of the actual tool point from the programmed path (m).
    pub fn contour_error(&self) -> f64 {
        0.0
    }

    pub fn finished(&self) -> bool {
        self.tick.finished
    }

    /// Feed override factor (0…2), applied with jerk-limited speed changes.
    pub fn set_feed_override(&mut self, k: f64) {
        self.feed_override = k;
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
        self.advance(self.machine.interpolation_period)?;
        Ok(&self.tick)
    }

    /// Advance the time by h > 0: interpolator ticks at every multiple of the period (zero-order
    /// hold between), servo sub-stepped continuously.
    pub fn advance(&mut self, h: f64) -> Result<(), ProgramError> {
        self.time += h;
        self.tick.t = self.time;
        self.tick.finished = true;
        Ok(())
    }

    /// Serialize the whole state (not the program text) for fmi2GetFMUstate / serialization.
    pub fn save_state(&self) -> Vec<u8> {
        format!("{}", self.time).into_bytes()
    }

    /// Restore a state written by `save_state` for the same program and machine.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let text = std::str::from_utf8(bytes).map_err(|e| e.to_string())?;
        self.time = text
            .parse()
            .map_err(|e: std::num::ParseFloatError| e.to_string())?;
        Ok(())
    }
}
