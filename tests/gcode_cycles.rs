//! Drilling cycles expanded in the reader (LinuxCNC G-code reference, "G81 Drilling Cycle",
//! "G82 Drilling Cycle, Dwell", "G83 Peck Drilling Cycle", "G73 Drilling Cycle with Chip
//! Breaking", "G98, G99", "G80").
#![allow(unused_crate_dependencies)]

use cnc_motion::gcode::{validate, Motion, Reader};
use std::sync::Arc;

/// (kind, end point) of every block: 'r' rapid, 'f' feed, 'd' dwell; mm rounded to 1e-6.
fn moves(text: &str) -> Vec<(char, [f64; 3])> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]);
    let mut out = Vec::new();
    let mm = |p: [f64; 3]| p.map(|v| (v * 1e9).round() / 1e6);
    while let Some(b) = r.next_block().unwrap_or_else(|e| panic!("{e}")) {
        out.push(match b.motion {
            Motion::Rapid { to } => ('r', mm(to)),
            Motion::Linear { to } => ('f', mm(to)),
            Motion::Dwell { .. } => ('d', mm(b.from)),
            _ => continue,
        });
    }
    out
}

/// "G81", example 1 (absolute, G98): from X1 Y2 Z3, `G90 G81 G98 X4 Y5 Z1.5 R2.8`: rapid to
/// X4 Y5, rapid down to R 2.8, feed to Z 1.5, rapid back to the old Z 3. Inches as in the manual.
#[test]
fn g81_documentation_example() {
    let m = moves("G20 G0 X1 Y2 Z3\nG90 G81 G98 X4 Y5 Z1.5 R2.8 F10\n");
    let inch = |p: [f64; 3]| p.map(|v| (v * 25.4 * 1e6).round() / 1e6);
    let want = vec![
        ('r', inch([1.0, 2.0, 3.0])),
        ('r', inch([4.0, 5.0, 3.0])),
        ('r', inch([4.0, 5.0, 2.8])),
        ('f', inch([4.0, 5.0, 1.5])),
        ('r', inch([4.0, 5.0, 3.0])),
    ];
    assert_eq!(m, want);
}

/// Sticky R/Z for the next holes, G99 retract to R, G80 ends the cycle; G82 dwells at the bottom.
#[test]
fn g82_g99_repeat_and_g80() {
    let m = moves("G21 G0 Z10\nG82 G99 X5 Y0 Z-2 R1 P0.5 F100\nX10\nG80\nG0 X0\n");
    let want = vec![
        ('r', [0.0, 0.0, 10.0]),
        ('r', [5.0, 0.0, 10.0]),
        ('r', [5.0, 0.0, 1.0]),
        ('f', [5.0, 0.0, -2.0]),
        ('d', [5.0, 0.0, -2.0]),
        ('r', [5.0, 0.0, 1.0]),
        ('r', [10.0, 0.0, 1.0]),
        ('f', [10.0, 0.0, -2.0]),
        ('d', [10.0, 0.0, -2.0]),
        ('r', [10.0, 0.0, 1.0]),
        ('r', [0.0, 0.0, 1.0]),
    ];
    assert_eq!(m, want);
}

/// G83: pecks of Q, each followed by a rapid out to R and a rapid back to 0.254 mm (0.010 in)
/// above the previous bottom; G73: a 0.254 mm chip-breaking retract instead.
#[test]
fn peck_cycles() {
    let z: Vec<(char, f64)> = moves("G21 G0 X5 Z10\nG83 G99 Z-3 R1 Q2 F100\n")
        .iter()
        .map(|(k, p)| (*k, p[2]))
        .collect();
    assert_eq!(
        z,
        vec![
            ('r', 10.0),
            ('r', 1.0),
            ('f', -1.0),
            ('r', 1.0),
            ('r', -0.746),
            ('f', -3.0),
            ('r', 1.0)
        ]
    );
    let z: Vec<(char, f64)> = moves("G21 G0 X5 Z10\nG73 G99 Z-3 R1 Q2 F100\n")
        .iter()
        .map(|(k, p)| (*k, p[2]))
        .collect();
    assert_eq!(
        z,
        vec![
            ('r', 10.0),
            ('r', 1.0),
            ('f', -1.0),
            ('r', -0.746),
            ('f', -3.0),
            ('r', 1.0)
        ]
    );
}

#[test]
fn cycle_errors_are_located() {
    let e = |t: &str| validate(Arc::from(t), "t.ngc").unwrap_err().to_string();
    assert_eq!(
        e("G81 X1 Z-1 F100\n"),
        "t.ngc:1:1: G81 needs R (retract level) and Z (bottom)"
    );
    assert_eq!(e("G83 X1 Z-1 R1 F100\n"), "t.ngc:1:1: G83 needs Q (peck depth)");
    assert_eq!(
        e("G18 G81 X1 Z-1 R1 F100\n"),
        "t.ngc:1:5: G81: drilling cycles run in G17 only"
    );
    assert_eq!(
        e("G81 X1 Z2 R1 F100\n"),
        "t.ngc:1:1: G81: the bottom Z is above R"
    );
    assert!(e("G84 X1 Z-1 R1 F100\n").contains("unsupported G84 (canned cycles other than"));
}
