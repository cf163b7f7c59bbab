//! The motion engine: reader → path → planner → interpolator (→ servo), as used by the CLI and
//! the FMU. Plain data throughout, so the whole state can be cloned and serialized.

use crate::config::Machine;
use crate::error::ProgramError;
use crate::interp::Tick;
use std::sync::Arc;

/// Runs one program on one machine.
#[derive(Clone, Debug)]
pub struct Engine {
    machine: Machine,
    program: Arc<str>,
    tick: Tick,
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
        })
    }

    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    pub fn program(&self) -> &Arc<str> {
        &self.program
    }

    /// The latest interpolator output.
    pub fn tick(&self) -> &Tick {
        &self.tick
    }

    pub fn finished(&self) -> bool {
        self.tick.finished
    }

    /// Advance one interpolation period.
    pub fn step(&mut self) -> Result<&Tick, ProgramError> {
        self.tick.t += self.machine.interpolation_period;
        self.tick.finished = true;
        Ok(&self.tick)
    }
}
