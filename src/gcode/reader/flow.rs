//! O-word control flow (LinuxCNC G-code reference, "O Codes"): subroutines with arguments and
//! local parameters, `if/elseif/else/endif`, `while/endwhile`, `do/while`, `repeat/endrepeat`,
//! `break`, `continue`, `return`. Memory stays bounded: the reader keeps the places (byte
//! offset, line) of the subroutines and of the open constructs, and moves its cursor there —
//! a loop re-reads its body from the program, a call jumps to the body of the subroutine; a
//! branch not taken is skipped by scanning forward for the matching O-word. Every jump back
//! counts against the machine's `max_loop_iterations`; calls nest at most MAX_CALL_DEPTH deep.

use super::files::Found;
use super::Reader;
use crate::error::ProgramError;
use crate::gcode::oword::{self, Head, Keyword};
use crate::gcode::params::Locals;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Deepest nesting of subroutine calls, recursion included (LinuxCNC "O Codes",
/// "Subroutines": "The maximum subroutine nesting level is 10").
pub const MAX_CALL_DEPTH: usize = 10;
/// Most constructs open at once (over all call levels).
pub const MAX_OPEN: usize = 1024;
/// Most subroutines a program defines.
pub const MAX_SUBS: usize = 10_000;

/// A line of the program or of a subroutine file: the source (0 the program, k the k-th
/// subroutine file, `files.rs`), its byte offset there and its number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Place {
    pub src: u32,
    pub offset: usize,
    pub line: u32,
}

impl Default for Place {
    /// The first line of the program.
    fn default() -> Self {
        Place {
            src: 0,
            offset: 0,
            line: 1,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
enum Kind {
    If,
    While,
    Do,
    Repeat,
}

/// An open construct: where it started (the `while` line, the line after `do`/`repeat`).
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Open {
    label: String,
    kind: Kind,
    at: Place,
    /// Passes of a `repeat` still to run.
    left: u64,
    /// An `if` whose `else` branch is running.
    in_else: bool,
}

/// A subroutine call: where to go back, the caller's locals, the open constructs below it.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Frame {
    label: String,
    back: Place,
    locals: Locals,
    open: usize,
}

/// The control-flow state of the reader.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Flow {
    /// Subroutines seen: label → the line after `sub`.
    subs: BTreeMap<String, Place>,
    open: Vec<Open>,
    calls: Vec<Frame>,
    /// Jumps back (loop passes) so far.
    iterations: u64,
}

impl Flow {
    /// A restored state: every saved place a line start of the program (`place_ok`), the
    /// bounds on subroutines, open constructs, call depth and loop passes.
    pub(super) fn check_state(
        &self,
        place_ok: &dyn Fn(Place) -> bool,
        max_iterations: u64,
    ) -> Result<(), String> {
        use crate::valid::at_most;
        at_most("subroutines", self.subs.len() as u64, MAX_SUBS as u64)?;
        at_most("open O-word constructs", self.open.len() as u64, MAX_OPEN as u64)?;
        at_most("call depth", self.calls.len() as u64, MAX_CALL_DEPTH as u64)?;
        at_most("loop passes", self.iterations, max_iterations)?;
        let places = self.subs.values().chain(self.open.iter().map(|o| &o.at));
        if !places
            .chain(self.calls.iter().map(|f| &f.back))
            .all(|&p| place_ok(p))
        {
            return Err("an O-word place is not a line start of the program".into());
        }
        for o in &self.open {
            at_most("repeat passes left", o.left, max_iterations)?;
        }
        let mut below = 0;
        for f in &self.calls {
            if f.open < below || f.open > self.open.len() {
                return Err("a call level's open constructs are out of order".into());
            }
            below = f.open;
            f.locals.check_state()?;
        }
        Ok(())
    }

    pub(super) fn sub_count(&self) -> usize {
        self.subs.len()
    }

    /// Remember subroutine `label`, its body starting at `body`.
    pub(super) fn add_sub(&mut self, label: &str, body: Place) {
        self.subs.insert(label.to_string(), body);
    }

    /// Byte offset in the program of the outermost call into a subroutine file (progress
    /// through the program while a file's sub runs).
    pub(super) fn program_offset(&self) -> Option<usize> {
        self.calls.iter().find(|f| f.back.src == 0).map(|f| f.back.offset)
    }

    /// The constructs open in the current call level.
    fn level(&self) -> &[Open] {
        &self.open[self.calls.last().map_or(0, |f| f.open)..]
    }

    fn top_is(&self, label: &str, kind: Kind) -> bool {
        self.level()
            .last()
            .is_some_and(|o| o.label == label && o.kind == kind)
    }

    fn name(kind: Kind) -> &'static str {
        match kind {
            Kind::If => "if",
            Kind::While => "while",
            Kind::Do => "do",
            Kind::Repeat => "repeat",
        }
    }
}

impl Reader {
    /// Execute the O-word line at `here` (`next` is the line after it); may set `self.jump`.
    pub(super) fn o_word(
        &mut self,
        here: Place,
        next: Place,
        text: &str,
        head: Head,
    ) -> Result<(), ProgramError> {
        let line = here.line;
        match head.keyword {
            Keyword::Sub => self.define_sub(here, next, &head),
            Keyword::EndSub | Keyword::Return => {
                let value = self.arguments(line, text, &head, 0, 1)?;
                self.return_from(line, &head, value.first().copied())
            }
            Keyword::Call => {
                let args = self.arguments(line, text, &head, 0, oword::MAX_ARGS)?;
                self.call(line, next, &head, &args)
            }
            Keyword::If => {
                let c = self.arguments(line, text, &head, 1, 1)?[0];
                self.push(line, &head, Kind::If, here, 0)?;
                if c == 0.0 {
                    self.next_branch(line, next, &head)?;
                }
                Ok(())
            }
            Keyword::ElseIf | Keyword::Else => {
                // The branch before it ran: go past the endif.
                self.expect_top(line, &head, Kind::If)?;
                let in_else = self.flow.open.last().is_some_and(|o| o.in_else);
                self.after_else(line, &head, in_else)?;
                let end = self.past_endif(line, next, &head)?;
                self.flow.open.pop();
                self.jump = Some(end);
                Ok(())
            }
            Keyword::EndIf => {
                self.expect_top(line, &head, Kind::If)?;
                self.flow.open.pop();
                Ok(())
            }
            Keyword::While => self.while_line(here, next, text, &head),
            Keyword::EndWhile => {
                self.expect_top(line, &head, Kind::While)?;
                let at = self.flow.open.last().map_or(here, |o| o.at);
                self.iterate(line)?;
                self.jump = Some(at);
                Ok(())
            }
            Keyword::Do => {
                self.arguments(line, text, &head, 0, 0)?;
                self.push(line, &head, Kind::Do, next, 0)
            }
            Keyword::Repeat => self.repeat(line, next, text, &head),
            Keyword::EndRepeat => {
                self.expect_top(line, &head, Kind::Repeat)?;
                let Some(top) = self.flow.open.last_mut() else {
                    return Ok(());
                };
                top.left = top.left.saturating_sub(1);
                if top.left == 0 {
                    self.flow.open.pop();
                    return Ok(());
                }
                let at = top.at;
                self.iterate(line)?;
                self.jump = Some(at);
                Ok(())
            }
            Keyword::Break | Keyword::Continue => self.leave_pass(line, next, &head),
            // A program number heads a program; later it would start an M98/M99 subprogram.
            // Refused by `head_run` before it gets here.
            Keyword::Unknown => Err(self.error(line, head.col, "unknown O-word keyword")),
            Keyword::Number if self.motion.is_none() => Ok(()),
            Keyword::Number => {
                let l = head.shown();
                let msg =
                    format!("unsupported Fanuc-style subprogram {l} (… M99); write {l} sub … {l} endsub");
                Err(self.error(line, head.col, msg))
            }
        }
    }

    /// The bracketed arguments of an executed O-word line, between `min` and `max` of them.
    fn arguments(
        &self,
        line: u32,
        text: &str,
        head: &Head,
        min: usize,
        max: usize,
    ) -> Result<Vec<f64>, ProgramError> {
        let args =
            oword::args(text, head, &self.params).map_err(|(c, m)| self.error(line, c as u32 + 1, m))?;
        if args.len() < min || args.len() > max {
            let what = match (min, max) {
                (0, 0) => "takes no [expression]".to_string(),
                (1, 1) => "needs one [expression]".to_string(),
                _ => format!("takes {min} to {max} [expressions]"),
            };
            let msg = format!("{} {} {what}", head.shown(), head.keyword.name());
            return Err(self.error(line, head.col, msg));
        }
        Ok(args)
    }

    fn push(&mut self, line: u32, head: &Head, kind: Kind, at: Place, left: u64) -> Result<(), ProgramError> {
        if self.flow.open.len() >= MAX_OPEN {
            return Err(self.error(
                line,
                head.col,
                format!("more than {MAX_OPEN} O-word constructs open"),
            ));
        }
        self.flow.open.push(Open {
            label: head.label.clone(),
            kind,
            at,
            left,
            in_else: false,
        });
        Ok(())
    }

    fn expect_top(&self, line: u32, head: &Head, kind: Kind) -> Result<(), ProgramError> {
        if self.flow.top_is(&head.label, kind) {
            return Ok(());
        }
        let l = head.shown();
        let kw = head.keyword.name();
        let open = match self.flow.level().last() {
            Some(o) => format!(
                " (open: {} {} of line {})",
                oword::shown(&o.label),
                Flow::name(o.kind),
                o.at.line
            ),
            None => String::new(),
        };
        let msg = format!("{l} {kw} without a matching {l} {}{open}", Flow::name(kind));
        Err(self.error(line, head.col, msg))
    }

    /// Count one jump back against the machine's limit.
    fn iterate(&mut self, line: u32) -> Result<(), ProgramError> {
        self.flow.iterations += 1;
        let limit = self.nc.max_loop_iterations;
        if self.flow.iterations > limit {
            let msg = format!("more than {limit} loop iterations (machine key max_loop_iterations)");
            return Err(self.error(line, 1, msg));
        }
        Ok(())
    }

    /// `oN sub`: remember the body, skip to after `oN endsub`.
    fn define_sub(&mut self, here: Place, next: Place, head: &Head) -> Result<(), ProgramError> {
        match self.flow.subs.get(&head.label) {
            Some(p) if p.line != next.line => {
                let msg = format!(
                    "{} sub defined twice (first at line {})",
                    head.shown(),
                    p.line - 1
                );
                return Err(self.error(here.line, head.col, msg));
            }
            Some(_) => {}
            None if self.flow.subs.len() >= MAX_SUBS => {
                let msg = format!("more than {MAX_SUBS} subroutines");
                return Err(self.error(here.line, head.col, msg));
            }
            None => {
                self.flow.subs.insert(head.label.clone(), next);
            }
        }
        let end = self.find(here.line, next, head, &[Keyword::EndSub], "endsub")?;
        self.jump = Some(end.next);
        Ok(())
    }

    /// `oN call [args]`: save the caller's locals, set #1 … from the arguments, run the body.
    fn call(&mut self, line: u32, next: Place, head: &Head, args: &[f64]) -> Result<(), ProgramError> {
        if self.flow.calls.len() >= MAX_CALL_DEPTH {
            let msg = format!("{} call: calls nested deeper than {MAX_CALL_DEPTH}", head.shown());
            return Err(self.error(line, head.col, msg));
        }
        let body = match self.flow.subs.get(&head.label) {
            Some(p) => *p,
            None => self.find_sub(line, head)?,
        };
        let locals = self.params.enter_call(args);
        self.flow.calls.push(Frame {
            label: head.label.clone(),
            back: next,
            locals,
            open: self.flow.open.len(),
        });
        self.jump = Some(body);
        Ok(())
    }

    /// `oN endsub [value]` / `oN return [value]`: back to the caller, `#<_value>` set (0 without
    /// a value, as LinuxCNC's `read_o`). Whatever its label, it returns from the call running:
    /// LinuxCNC's `convert_control_functions` leaves the current call level on any `return` or
    /// `endsub` (its sample retval.ngc returns from `o1000` with `o1010 return` inside
    /// `o1010 if`).
    fn return_from(&mut self, line: u32, head: &Head, value: Option<f64>) -> Result<(), ProgramError> {
        let Some(frame) = self.flow.calls.pop() else {
            let kw = head.keyword.name();
            let msg = format!(
                "{} {kw} outside a call of {} (no {} call is running)",
                head.shown(),
                head.shown(),
                head.shown()
            );
            return Err(self.error(line, head.col, msg));
        };
        self.params.leave_call(frame.locals);
        self.flow.open.truncate(frame.open);
        self.params.set_named("_value", value.unwrap_or(0.0));
        self.params
            .set_named("_value_returned", if value.is_some() { 1.0 } else { 0.0 });
        self.jump = Some(frame.back);
        Ok(())
    }

    /// An `else` or `elseif` met while the `else` branch of its `if` runs: a second `else`, or an
    /// `elseif` after the `else` (LinuxCNC "O Codes", "Conditional": one `else`, last).
    fn after_else(&self, line: u32, head: &Head, in_else: bool) -> Result<(), ProgramError> {
        if !in_else {
            return Ok(());
        }
        let l = head.shown();
        let msg = match head.keyword {
            Keyword::Else => format!("a second {l} else in one {l} if"),
            _ => format!("{l} elseif after {l} else (the else branch comes last)"),
        };
        Err(self.error(line, head.col, msg))
    }

    /// The line after the `endif` of the `if` whose branch just ran, the rest of its chain
    /// checked on the way: at most one `else`, no `elseif` after it.
    fn past_endif(&mut self, line: u32, from: Place, head: &Head) -> Result<Place, ProgramError> {
        let mut seen_else = head.keyword == Keyword::Else;
        let mut from = from;
        loop {
            let keys = [Keyword::ElseIf, Keyword::Else, Keyword::EndIf];
            let found = self.find(line, from, head, &keys, "endif")?;
            if found.head.keyword == Keyword::EndIf {
                return Ok(found.next);
            }
            self.after_else(found.here.line, &found.head, seen_else)?;
            seen_else |= found.head.keyword == Keyword::Else;
            from = found.next;
        }
    }

    /// A false `if`/`elseif`: on to the next branch whose condition holds, the `else`, or past
    /// the `endif`.
    fn next_branch(&mut self, line: u32, from: Place, head: &Head) -> Result<(), ProgramError> {
        let mut from = from;
        loop {
            let keys = [Keyword::ElseIf, Keyword::Else, Keyword::EndIf];
            let found = self.find(line, from, head, &keys, "endif")?;
            let here = found.here.line;
            match found.head.keyword {
                Keyword::ElseIf => {
                    let c = self.arguments(here, &found.text, &found.head, 1, 1)?[0];
                    if c != 0.0 {
                        self.jump = Some(found.next);
                        return Ok(());
                    }
                    from = found.next;
                }
                Keyword::Else => {
                    if let Some(top) = self.flow.open.last_mut() {
                        top.in_else = true;
                    }
                    self.jump = Some(found.next);
                    return Ok(());
                }
                _ => {
                    self.flow.open.pop();
                    self.jump = Some(found.next);
                    return Ok(());
                }
            }
        }
    }

    /// `oN while [c]`: the end of a `do` loop, or the head of a `while` loop.
    fn while_line(&mut self, here: Place, next: Place, text: &str, head: &Head) -> Result<(), ProgramError> {
        let line = here.line;
        let c = self.arguments(line, text, head, 1, 1)?[0];
        if self.flow.top_is(&head.label, Kind::Do) {
            if c != 0.0 {
                let at = self.flow.open.last().map_or(next, |o| o.at);
                self.iterate(line)?;
                self.jump = Some(at);
            } else {
                self.flow.open.pop();
            }
            return Ok(());
        }
        // Back from its endwhile the loop is already open.
        if !self.flow.top_is(&head.label, Kind::While) {
            self.push(line, head, Kind::While, here, 0)?;
        }
        if c == 0.0 {
            let end = self.find(line, next, head, &[Keyword::EndWhile], "endwhile")?;
            self.flow.open.pop();
            self.jump = Some(end.next);
        }
        Ok(())
    }

    /// `oN repeat [count]`: run the body count times (0: skip it).
    fn repeat(&mut self, line: u32, next: Place, text: &str, head: &Head) -> Result<(), ProgramError> {
        let n = self.arguments(line, text, head, 1, 1)?[0];
        let limit = self.nc.max_loop_iterations;
        if n < 0.0 || n.fract() != 0.0 || n > limit as f64 {
            let msg = format!(
                "{} repeat [{n}]: count out of range (a whole number 0 … {limit}, machine key max_loop_iterations)",
                head.shown()
            );
            return Err(self.error(line, head.col, msg));
        }
        if n == 0.0 {
            let end = self.find(line, next, head, &[Keyword::EndRepeat], "endrepeat")?;
            self.jump = Some(end.next);
            return Ok(());
        }
        self.push(line, head, Kind::Repeat, next, n as u64)
    }

    /// `oN break` (past the end of loop oN) / `oN continue` (to its end line, which loops).
    fn leave_pass(&mut self, line: u32, next: Place, head: &Head) -> Result<(), ProgramError> {
        let kw = if head.keyword == Keyword::Break {
            "break"
        } else {
            "continue"
        };
        let level = self.flow.level();
        let Some(k) = level
            .iter()
            .rposition(|o| o.label == head.label && o.kind != Kind::If)
        else {
            let msg = format!(
                "{} {kw} outside a loop {} (while, do, repeat)",
                head.shown(),
                head.shown()
            );
            return Err(self.error(line, head.col, msg));
        };
        let kind = level[k].kind;
        let cut = self.flow.open.len() - (level.len() - k);
        let (end, name) = match kind {
            Kind::While => (Keyword::EndWhile, "endwhile"),
            Kind::Do => (Keyword::While, "while"),
            _ => (Keyword::EndRepeat, "endrepeat"),
        };
        let found = self.find(line, next, head, &[end], name)?;
        if head.keyword == Keyword::Break {
            self.flow.open.truncate(cut);
            self.jump = Some(found.next);
        } else {
            self.flow.open.truncate(cut + 1);
            self.jump = Some(found.here);
        }
        Ok(())
    }

    /// `scan`, with a located error naming the missing end when there is none.
    pub(super) fn find(
        &mut self,
        line: u32,
        from: Place,
        head: &Head,
        keys: &[Keyword],
        end: &str,
    ) -> Result<Found, ProgramError> {
        match self.scan(from, &head.label, keys)? {
            Some(f) => Ok(f),
            None => {
                let kw = head.keyword.name();
                let msg = format!("{l} {kw} without {l} {end}", l = head.shown());
                Err(self.error_in(from.src, line, head.col, msg))
            }
        }
    }

    /// At the end of the program: no construct may be left open.
    pub(super) fn check_flow_closed(&self) -> Result<(), ProgramError> {
        if let Some(o) = self.flow.open.last() {
            let l = oword::shown(&o.label);
            let line = match o.kind {
                Kind::If | Kind::While => o.at.line,
                Kind::Do | Kind::Repeat => o.at.line.saturating_sub(1),
            };
            let msg = format!(
                "{l} {} is not closed before the end of the program",
                Flow::name(o.kind)
            );
            return Err(self.error(line.max(1), 1, msg));
        }
        Ok(())
    }
}
