//! The documented range of every number a program may give (README "Program ranges"). Values
//! are checked where they are read, in the program's units, so the message names what was
//! written; anything outside is `FILE:LINE:COL: … out of range (…)`.

/// Largest |coordinate| and largest feed: the machine's ranges (config/ranges.rs).
pub use crate::config::ranges::{MAX_COORDINATE_M, MAX_FEED_MM_MIN};
pub const MAX_FEED_M_S: f64 = MAX_FEED_MM_MIN * 1e-3 / 60.0;
/// Longest move at its programmed feed (length / F, or 1/F minutes in G93): one day, as the
/// longest dwell. A slower move is refused before it starts instead of running for days.
pub const MAX_MOVE_TIME_S: f64 = 86_400.0;
/// Largest |R| of G10 L2 (degrees).
pub const MAX_ROTATION_DEG: f64 = 1e6;
/// Longest dwell G4 P: one day (s).
pub const MAX_DWELL_S: f64 = 86_400.0;
/// Most turns of a G2/G3 P word (P1 is the plain arc).
pub const MAX_TURNS: f64 = 10_000.0;

/// `value` in program units (metres per unit `unit`) as a length within ±MAX_COORDINATE_M.
pub fn length(letter: u8, value: f64, unit: f64) -> Result<f64, String> {
    let m = value * unit;
    if m.is_finite() && m.abs() <= MAX_COORDINATE_M {
        Ok(m)
    } else {
        let bound = MAX_COORDINATE_M / unit;
        Err(format!(
            "{}{value} out of range (|{}| ≤ {bound} {})",
            letter as char,
            letter as char,
            unit_name(unit)
        ))
    }
}

/// A feed F (program units per minute) in m/s: zero or any positive finite F (the caller caps
/// it at the machine's largest feed); the range only keeps the number finite. F0 is a setting
/// LinuxCNC takes (its planner tests write `F0` before `G95`); a feed move at F0 is refused.
pub fn feed(value: f64, unit: f64) -> Result<f64, String> {
    let v = value * unit / 60.0;
    if v >= 0.0 && v.is_finite() {
        Ok(v)
    } else if value < 0.0 {
        Err(format!("feed F{value} must not be negative"))
    } else {
        Err(format!("feed F{value} out of range (not a finite number)"))
    }
}

/// A G94 feed (m/s) as F in program units per minute, for messages.
pub fn feed_shown(v: f64, unit: f64) -> String {
    format!("{} {}/min", v * 60.0 / unit, unit_name(unit))
}

/// A G93 F (moves per minute, the move takes 1/F minutes): any positive finite F.
pub fn inverse_feed(value: f64) -> Result<(), String> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(format!(
            "inverse-time F{value} must be positive (G93: the move takes 1/F minutes)"
        ))
    }
}

/// A dwell G4 P (s): 0 ≤ P ≤ MAX_DWELL_S.
pub fn dwell(value: f64) -> Result<f64, String> {
    if value < 0.0 {
        Err("G4 P must not be negative".into())
    } else if value <= MAX_DWELL_S {
        Ok(value)
    } else {
        Err(format!("G4 P{value} out of range (0 ≤ P ≤ {MAX_DWELL_S} s)"))
    }
}

/// G2/G3 P: a whole number of turns 1 ≤ P ≤ MAX_TURNS; the extra full turns (P − 1).
pub fn turns(name: &str, value: f64) -> Result<u32, String> {
    if (1.0..=MAX_TURNS).contains(&value) && value.fract() == 0.0 {
        Ok(value as u32 - 1)
    } else {
        Err(format!(
            "{name} P{value} out of range (turns: a whole number from 1 to {MAX_TURNS})"
        ))
    }
}

/// G64 P or Q (program units) in metres: 0 ≤ value ≤ MAX_COORDINATE_M.
pub fn blend_tolerance(letter: u8, value: f64, unit: f64) -> Result<f64, String> {
    if value < 0.0 {
        return Err(format!("G64 {} must not be negative", letter as char));
    }
    length(letter, value, unit)
}

fn unit_name(unit: f64) -> &'static str {
    if unit > 1e-3 {
        "in"
    } else {
        "mm"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_are_inclusive_and_named_in_program_units() {
        assert_eq!(length(b'X', 1e5, 1e-3), Ok(100.0));
        let e = length(b'X', 100_000.001, 1e-3).unwrap_err();
        assert_eq!(e, "X100000.001 out of range (|X| ≤ 100000 mm)");
        let e = length(b'Y', f64::INFINITY, 25.4e-3).unwrap_err();
        assert!(e.contains("out of range") && e.contains(" in)"), "{e}");
        assert!(feed(1e6, 1e-3).is_ok() && feed(f64::MAX, 25.4e-3).is_ok());
        assert!(feed(f64::INFINITY, 1e-3).unwrap_err().contains("out of range"));
        assert!(feed(-1.0, 1e-3).unwrap_err().contains("negative") && feed(0.0, 1e-3) == Ok(0.0));
        assert_eq!(turns("G2", 1.0), Ok(0));
        assert_eq!(turns("G2", 10_000.0), Ok(9_999));
        assert!(turns("G2", 10_001.0).unwrap_err().contains("1 to 10000"));
        assert!(turns("G2", 1.5).is_err() && turns("G2", 0.0).is_err());
        assert!(dwell(86_400.0).is_ok() && dwell(86_401.0).is_err() && dwell(-1.0).is_err());
        assert!(blend_tolerance(b'Q', -0.1, 1e-3)
            .unwrap_err()
            .contains("negative"));
    }
}
