//! Numbered and named parameters (`#1`, `#<name>`) and expressions `[...]` (LinuxCNC G-code
//! reference, "Parameters" and "Expressions": binary operators `**`, `* / MOD`, `+ -`,
//! `EQ NE GT GE LT LE`, `AND OR XOR` in that precedence, left to right; functions ABS ACOS ASIN
//! ATAN[y]/[x] COS EXP FIX FUP ROUND LN SIN SQRT TAN EXISTS, angles in degrees). Memory is
//! bounded: numbered parameters 1 … MAX_NUMBERED, at most MAX_NAMED names.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub const MAX_NUMBERED: usize = 5602;
pub const MAX_NAMED: usize = 10_000;
/// Deepest nesting of `[` brackets and `#` indirections: 64 levels are read, a 65th is an error.
pub const MAX_DEPTH: usize = 64;

/// Function names (ACOS before COS is not needed: names are matched at the cursor).
pub const FUNCTIONS: [&str; 14] = [
    "ABS", "ACOS", "ASIN", "ATAN", "COS", "EXISTS", "EXP", "FIX", "FUP", "ROUND", "LN", "SIN", "SQRT", "TAN",
];

/// The parameter store.
/// Only the parameters set are stored (a saved FMU state stays small).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Params {
    numbered: BTreeMap<usize, f64>,
    named: BTreeMap<String, f64>,
}

/// A parameter to set after the line is read (RS274NGC: settings take effect after the line).
#[derive(Clone, Debug, PartialEq)]
pub enum Key {
    Number(usize),
    Name(String),
}

impl Params {
    /// Apply the settings of a line, in order.
    pub fn set(&mut self, sets: &mut Vec<(Key, f64, usize)>) -> Result<(), (usize, String)> {
        for (key, v, col) in sets.drain(..) {
            match key {
                Key::Number(n) => {
                    self.numbered.insert(n, v);
                }
                Key::Name(s) => {
                    if self.named.len() >= MAX_NAMED && !self.named.contains_key(&s) {
                        return Err((col, format!("more than {MAX_NAMED} named parameters")));
                    }
                    self.named.insert(s, v);
                }
            }
        }
        Ok(())
    }
}

/// Parameters local to a call level (LinuxCNC "O Codes", "Subroutines"): #1 … #30 and the named
/// ones not starting with `_`, saved at a call and given back at its return.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Locals {
    numbered: Vec<(usize, f64)>,
    named: Vec<(String, f64)>,
}

/// Numbered parameters local to a call level: #1 … LOCAL_NUMBERED.
pub const LOCAL_NUMBERED: usize = 30;

impl Params {
    /// Enter a subroutine: the caller's locals are saved (returned), the arguments become #1,
    /// #2, … #N (#N+1 … #30 keep the caller's values), named locals start unset, and
    /// `#<_value>`, `#<_value_returned>` are cleared.
    pub fn enter_call(&mut self, args: &[f64]) -> Locals {
        let numbered = (1..=LOCAL_NUMBERED)
            .filter_map(|n| self.numbered.get(&n).map(|&v| (n, v)))
            .collect();
        let local: Vec<String> = self
            .named
            .keys()
            .filter(|k| !k.starts_with('_'))
            .cloned()
            .collect();
        let named = local
            .into_iter()
            .filter_map(|k| self.named.remove(&k).map(|v| (k, v)))
            .collect();
        for (i, &v) in args.iter().enumerate() {
            self.numbered.insert(i + 1, v);
        }
        self.set_named("_value", 0.0);
        self.set_named("_value_returned", 0.0);
        Locals { numbered, named }
    }

    /// Leave a subroutine: its locals are dropped, the caller's given back.
    pub fn leave_call(&mut self, saved: Locals) {
        for n in 1..=LOCAL_NUMBERED {
            self.numbered.remove(&n);
        }
        self.named.retain(|k, _| k.starts_with('_'));
        self.numbered.extend(saved.numbered);
        self.named.extend(saved.named);
    }

    /// Set a global named parameter at once (`_value` of a return).
    pub fn set_named(&mut self, name: &str, v: f64) {
        match self.named.get_mut(name) {
            Some(x) => *x = v,
            None => {
                self.named.insert(name.to_string(), v);
            }
        }
    }

    /// A named parameter's value, if set.
    pub fn named(&self, name: &str) -> Option<f64> {
        self.named.get(name).copied()
    }
}

/// A cursor over one line's bytes for values and expressions.
pub struct Expr<'a> {
    pub b: &'a [u8],
    pub i: usize,
    pub params: &'a Params,
    depth: usize,
}

type R<T> = Result<T, (usize, String)>;

impl<'a> Expr<'a> {
    pub fn new(b: &'a [u8], i: usize, params: &'a Params) -> Expr<'a> {
        Expr {
            b,
            i,
            params,
            depth: 0,
        }
    }

    fn skip(&mut self) {
        while self.i < self.b.len() && (self.b[self.i] == b' ' || self.b[self.i] == b'\t') {
            self.i += 1;
        }
    }

    /// The next non-blank byte as written.
    pub fn peek_byte(&mut self) -> Option<u8> {
        self.skip();
        self.b.get(self.i).copied()
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip();
        self.b.get(self.i).map(u8::to_ascii_uppercase)
    }

    fn starts(&mut self, word: &str) -> bool {
        self.skip();
        let w = word.as_bytes();
        self.b.len() >= self.i + w.len() && self.b[self.i..self.i + w.len()].eq_ignore_ascii_case(w)
    }

    fn expect(&mut self, c: u8, what: &str) -> R<()> {
        if self.peek() == Some(c) {
            self.i += 1;
            Ok(())
        } else {
            Err((self.i, format!("expected {what}")))
        }
    }

    /// A parameter reference after `#`: `#5`, `#<name>`, `##1`, `#[1+2]`.
    pub fn key(&mut self) -> R<Key> {
        let at = self.i;
        self.skip();
        if self.peek() == Some(b'<') {
            self.i += 1;
            let start = self.i;
            let end = self.b[start..]
                .iter()
                .position(|&c| c == b'>')
                .ok_or((at, "named parameter without '>'".to_string()))?;
            let name: String = String::from_utf8_lossy(&self.b[start..start + end])
                .chars()
                .filter(|c| !c.is_whitespace())
                .flat_map(char::to_lowercase)
                .collect();
            self.i = start + end + 1;
            if name.is_empty() {
                return Err((at, "empty parameter name".into()));
            }
            return Ok(Key::Name(name));
        }
        let v = self.primary()?;
        if v.fract() != 0.0 || v < 1.0 || v > MAX_NUMBERED as f64 {
            return Err((at, format!("parameter #{v} out of range (1 … {MAX_NUMBERED})")));
        }
        Ok(Key::Number(v as usize))
    }

    fn get(&self, key: &Key, at: usize) -> R<f64> {
        match key {
            Key::Number(n) => Ok(self.params.numbered.get(n).copied().unwrap_or(0.0)),
            Key::Name(s) => self
                .params
                .named
                .get(s)
                .copied()
                .ok_or((at, format!("parameter #<{s}> is not defined"))),
        }
    }

    /// One more level of `[` or `#` nesting, at most MAX_DEPTH.
    fn enter(&mut self, at: usize) -> R<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err((at, format!("expression nested deeper than {MAX_DEPTH}")));
        }
        Ok(())
    }

    /// A real value: number, `[expression]`, `#parameter`, function, with unary signs (read
    /// in a loop: any number of them nest nothing).
    pub fn primary(&mut self) -> R<f64> {
        let mut negate = false;
        loop {
            match self.peek() {
                Some(b'-') => negate = !negate,
                Some(b'+') => {}
                _ => break,
            }
            self.i += 1;
        }
        let at = self.i;
        let v = match self.peek() {
            Some(b'[') => {
                self.enter(at)?;
                self.i += 1;
                let v = self.expression(0)?;
                self.expect(b']', "']'")?;
                self.depth -= 1;
                v
            }
            Some(b'#') => {
                self.enter(at)?;
                self.i += 1;
                let key = self.key()?;
                self.depth -= 1;
                self.get(&key, at)?
            }
            Some(c) if c.is_ascii_alphabetic() => self.function()?,
            _ => {
                let (v, next) = super::words::number(self.b, self.i).map_err(|m| (at, m))?;
                self.i = next;
                v
            }
        };
        let v = if negate { -v } else { v };
        if v.is_finite() {
            Ok(v)
        } else {
            Err((at, "expression out of range (not a finite number)".into()))
        }
    }

    fn function(&mut self) -> R<f64> {
        let at = self.i;
        let Some(name) = FUNCTIONS.iter().find(|n| self.starts(n)) else {
            return Err((at, "unknown function or word in an expression".into()));
        };
        self.i += name.len();
        if *name == "EXISTS" {
            self.expect(b'[', "'[' after EXISTS")?;
            self.expect(b'#', "a parameter in EXISTS")?;
            let key = self.key()?;
            self.expect(b']', "']'")?;
            return Ok(if self.get(&key, at).is_ok() { 1.0 } else { 0.0 });
        }
        if self.peek() != Some(b'[') {
            return Err((self.i, format!("{name} needs [argument]")));
        }
        let x = self.primary()?;
        let d = std::f64::consts::PI / 180.0;
        let v = match *name {
            "ABS" => x.abs(),
            "ACOS" => x.acos() / d,
            "ASIN" => x.asin() / d,
            "ATAN" => {
                self.expect(b'/', "'/' in ATAN[y]/[x]")?;
                let y = self.primary()?;
                x.atan2(y) / d
            }
            "COS" => (x * d).cos(),
            "EXP" => x.exp(),
            "FIX" => x.floor(),
            "FUP" => x.ceil(),
            "ROUND" => x.round(),
            "LN" => x.ln(),
            "SIN" => (x * d).sin(),
            "SQRT" => x.sqrt(),
            _ => (x * d).tan(),
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err((at, format!("{name} of {x} is not a finite number")))
        }
    }

    /// Binary operators from precedence level `level` (0 lowest) up, left to right.
    pub fn expression(&mut self, level: usize) -> R<f64> {
        const LEVELS: [&[&str]; 5] = [
            &["AND", "OR", "XOR"],
            &["EQ", "NE", "GT", "GE", "LT", "LE"],
            &["+", "-"],
            &["*", "/", "MOD"],
            &["**"],
        ];
        if level == LEVELS.len() {
            return self.primary();
        }
        let mut v = self.expression(level + 1)?;
        loop {
            let at = self.i;
            // `*` must not take the first half of `**`.
            let Some(op) = LEVELS[level]
                .iter()
                .find(|op| self.starts(op) && !(**op == "*" && self.starts("**")))
            else {
                return Ok(v);
            };
            self.i += op.len();
            let w = self.expression(level + 1)?;
            let t = |c: bool| if c { 1.0 } else { 0.0 };
            v = match *op {
                "AND" => t(v != 0.0 && w != 0.0),
                "OR" => t(v != 0.0 || w != 0.0),
                "XOR" => t((v != 0.0) != (w != 0.0)),
                "EQ" => t(v == w),
                "NE" => t(v != w),
                "GT" => t(v > w),
                "GE" => t(v >= w),
                "LT" => t(v < w),
                "LE" => t(v <= w),
                "+" => v + w,
                "-" => v - w,
                "*" => v * w,
                "/" if w == 0.0 => return Err((at, "division by zero".into())),
                "/" => v / w,
                "MOD" if w == 0.0 => return Err((at, "MOD by zero".into())),
                "MOD" => v.rem_euclid(w.abs()),
                _ => v.powf(w),
            };
            if !v.is_finite() {
                return Err((at, "expression out of range (not a finite number)".into()));
            }
        }
    }
}
