//! A restored reader (FMU state) is checked before it reads a line: its cursor and every saved
//! place of the O-word flow are line starts of the program with their right numbers, its modal
//! words are ones the reader sets, its NC state within the machine-file ranges.

use super::flow::Place;
use super::Reader;
use crate::config::Machine;
use crate::gcode::check::MAX_COORDINATE_M;
use crate::valid::{at_most, point, within, MAX_POSITION_M, MAX_SPEED_M_S};

/// Byte offset of the start of every line (and of the end): `starts[n − 1]` is line n's.
fn line_starts(text: &str) -> Vec<usize> {
    let mut starts = vec![0];
    starts.extend(
        text.bytes()
            .enumerate()
            .filter(|&(_, b)| b == b'\n')
            .map(|(i, _)| i + 1),
    );
    if starts.last() != Some(&text.len()) {
        starts.push(text.len());
    }
    starts
}

impl Reader {
    /// `text`: the program the state is restored for (None: a file, read as a stream).
    pub fn check_state(&self, text: Option<&str>, machine: &Machine) -> Result<(), String> {
        let starts = text.map(line_starts);
        // The program's places against its text; a subroutine file's (streamed) by number.
        let files = self.subfile_count() as u64;
        let place_ok = |p: Place| match (&starts, p.src) {
            (Some(s), 0) => p.line >= 1 && s.get(p.line as usize - 1) == Some(&p.offset),
            _ => p.line >= 1 && u64::from(p.src) <= files,
        };
        if !place_ok(Place {
            src: self.src,
            offset: self.offset,
            line: self.line,
        }) {
            return Err(format!(
                "reader at byte {} is not the start of line {}",
                self.offset, self.line
            ));
        }
        if self.nc.subroutine_path != machine.nc.subroutine_path {
            return Err("reader: the machine's subroutine_path changed".into());
        }
        self.check_subfiles()?;
        if self.arc_tolerance != machine.arc_radius_tolerance
            || self.nc.max_loop_iterations != machine.nc.max_loop_iterations
            || self.max_feed != machine.max_feed
            || self.chord_tolerance != machine.chord_tolerance.min(machine.path_tolerance)
        {
            return Err(
                "reader: the machine's arc tolerance, loop bound, feed or chord tolerance changed".into(),
            );
        }
        if self.unit != 1e-3 && self.unit != 25.4e-3 {
            return Err(format!("reader: unit {} m is neither mm nor inch", self.unit));
        }
        point("reader position", self.position, MAX_POSITION_M)?;
        point("G92 offset", self.g92, MAX_POSITION_M)?;
        within("reader feed", self.feed, 0.0, MAX_SPEED_M_S)?;
        if let Some(super::modal::Mode::Cycle(m)) = self.motion {
            if ![73, 81, 82, 83].contains(&m) {
                return Err(format!("reader: modal cycle G{m} is not one the reader runs"));
            }
        }
        // A line expands to at most a cycle's or a spline's blocks.
        let most = super::cycles::MAX_CYCLE_BLOCKS as u64 + super::spline::MAX_SPLINE_PIECES as u64;
        at_most("queued blocks", self.pending.len() as u64, most)?;
        self.spline.check_state()?;
        at_most("work system", self.work as u64, 8)?;
        if let crate::gcode::PathMode::Blend { tolerance, q } = self.path_mode {
            for x in tolerance.into_iter().chain(q) {
                within("G64 P/Q", x, 0.0, MAX_COORDINATE_M)?;
            }
        }
        self.nc.check_state()?;
        let max_tool = u64::from(crate::config::nc::MAX_TOOL);
        at_most("tool T", u64::from(self.tool.selected), max_tool)?;
        at_most("tool M6", u64::from(self.tool.loaded), max_tool)?;
        at_most("tool D", self.tool.d.map_or(0, u64::from), max_tool)?;
        within(
            "tool length offset",
            self.tool.length,
            -MAX_POSITION_M,
            MAX_POSITION_M,
        )?;
        self.comp.check_state()?;
        self.cycle.check_state()?;
        self.params.check_state()?;
        self.flow.check_state(&place_ok, self.nc.max_loop_iterations)
    }
}
