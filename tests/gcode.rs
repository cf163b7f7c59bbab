//! The G-code reader: every supported word, each refusal with its place, streaming.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::gcode::{validate, Block, Motion, PathMode, Reader, StopKind};
use cnc_motion::geometry::Plane;
use proptest::prelude::*;
use std::sync::Arc;

fn blocks(text: &str) -> Vec<Block> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().unwrap_or_else(|e| panic!("{e}")) {
        out.push(b);
    }
    out
}

fn error(text: &str) -> String {
    validate(Arc::from(text), "t.ngc").unwrap_err().to_string()
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
}

#[test]
fn lines_units_distance_modes_and_feed() {
    let b = blocks("%\nN10 G21 G90 G0 X10 Y5 (rapid)\nG1 Z-1 F600 ; plunge\nX20\nG91 X1 Y1\nG20 G90 X1\n%\n");
    assert_eq!(b.len(), 5);
    assert!(matches!(b[0].motion, Motion::Rapid { to } if close(to, [0.01, 0.005, 0.0])));
    assert_eq!(b[0].line, 2);
    assert!(matches!(b[1].motion, Motion::Linear { to } if close(to, [0.01, 0.005, -0.001])));
    assert!((b[1].feed - 0.01).abs() < 1e-15, "600 mm/min = 0.01 m/s");
    // Modal G1 on a line with axis words only.
    assert!(matches!(b[2].motion, Motion::Linear { to } if close(to, [0.02, 0.005, -0.001])));
    assert!(matches!(b[3].motion, Motion::Linear { to } if close(to, [0.021, 0.006, -0.001])));
    assert_eq!(b[3].from, [0.02, 0.005, -0.001]);
    // G20: inches, and the feed stays what it was (it was given in mm/min).
    assert!(matches!(b[4].motion, Motion::Linear { to } if close(to, [0.0254, 0.006, -0.001])));
}

#[test]
fn arcs_ijk_r_full_circle_helix_and_planes() {
    // Quarter circle, radius 10, centre (0, 0): I/J relative and R give the same centre.
    let ij = blocks("G21 G17 G90 G0 X10 Y0\nG3 X0 Y10 I-10 J0 F1000\n");
    let r = blocks("G21 G17 G90 G0 X10 Y0\nG3 X0 Y10 R10 F1000\n");
    let abs = blocks("G21 G17 G90 G90.1 G0 X10 Y0\nG3 X0 Y10 I0 J0 F1000\n");
    for b in [&ij[1], &r[1], &abs[1]] {
        match b.motion {
            Motion::Arc {
                center,
                clockwise,
                plane,
                turns,
                ..
            } => {
                assert!(close(center, [0.0, 0.0, 0.0]), "{center:?}");
                assert!(!clockwise && plane == Plane::XY && turns == 0);
            }
            _ => panic!("arc expected"),
        }
    }
    // R < 0: the long way round, centre on the other side of the chord.
    let long = blocks("G21 G0 X10 Y0\nG3 X0 Y10 R-10 F1000\n");
    assert!(matches!(long[1].motion, Motion::Arc { center, .. } if close(center, [0.01, 0.01, 0.0])));
    // Full circle with P2 (two turns) and a helix (Z moves).
    let full = blocks("G21 G0 X10 Y0\nG2 X10 Y0 Z-2 I-10 P2 F1000\n");
    assert!(
        matches!(full[1].motion, Motion::Arc { to, turns: 1, clockwise: true, .. } if close(to, [0.01, 0.0, -0.002]))
    );
    // G18 takes I/K, G19 J/K.
    let xz = blocks("G21 G18 G0 X10 Z0\nG2 X0 Z10 I-10 K0 F1000\n");
    assert!(matches!(xz[1].motion, Motion::Arc { plane: Plane::XZ, center, .. } if close(center, [0.0; 3])));
    let yz = blocks("G21 G19 G0 Y10 Z0\nG2 Y0 Z10 J-10 K0 F1000\n");
    assert!(matches!(yz[1].motion, Motion::Arc { plane: Plane::YZ, center, .. } if close(center, [0.0; 3])));
}

#[test]
fn path_modes_dwell_and_stops() {
    let b = blocks("G21 G61 G1 X1 F100\nG64 P0.02 Q0.01 X2\nG64 X3\nG4 P0.5\nM0\nX4 M30\nX5\n");
    assert_eq!(b[0].path_mode, PathMode::ExactStop);
    assert_eq!(
        b[1].path_mode,
        PathMode::Blend {
            tolerance: Some(0.02e-3),
            q: Some(0.01e-3)
        }
    );
    assert_eq!(
        b[2].path_mode,
        PathMode::Blend {
            tolerance: None,
            q: None
        }
    );
    assert_eq!(b[3].motion, Motion::Dwell { seconds: 0.5 });
    assert_eq!(b[4].motion, Motion::Stop(StopKind::Pause));
    assert!(matches!(b[5].motion, Motion::Linear { .. }));
    assert_eq!(b[6].motion, Motion::Stop(StopKind::End));
    assert_eq!(b.len(), 7, "nothing after M30");
}

#[test]
fn words_that_do_not_move_are_accepted() {
    let b = blocks("G17 G21 G40 G49 G54 G80 G94 G97 S12000 M3 T1 M6\nM8 G1 X1 F100\nM9 M5\nX2\n");
    assert_eq!(b.len(), 2);
    assert!(matches!(b[1].motion, Motion::Linear { .. }));
}

#[test]
fn refusals_name_the_place() {
    let cases = [
        (
            "G1 X1 F100\nG41 D1 X2\n",
            "t.ngc:2:5: D1: tool 1 is not in the machine's tool table ([tool.1])",
        ),
        (
            "G42 X2\n",
            "t.ngc:1:5: axis words without a motion mode (G0, G1, G2, G3, G5, G5.1, G5.2, G73, G81…G83)",
        ),
        (
            "G1 F100\nG33 Z-1 K1\n",
            "t.ngc:2:1: unsupported G33 (spindle-synchronised motion: this model has no spindle position to follow)",
        ),
        (
            "G10 L5 P1 X0\n",
            "t.ngc:1:5: unsupported G10 L5 (L1, L2, L10, L20 are)",
        ),
        (
            "G5 X1 Y1 I1 J0 F100\n",
            "t.ngc:1:1: G5 needs both P and Q (the end's control offset)",
        ),
        ("G95 G1 X1 F1\n", "t.ngc:1:1: unsupported G95 (feed per revolution)"),
        (
            "O100 sub\n",
            "t.ngc:1:1: o100 sub without o100 endsub",
        ),
        (
            "G1 X#<a> F100\n",
            "t.ngc:1:5: X: parameter #<a> is not defined",
        ),
        (
            "G1 X[1+2 F100\n",
            "t.ngc:1:10: X: expected ']'",
        ),
        ("G1 X1\n", "t.ngc:1:1: G1 with a zero feed rate (F0, or F never set)"),
        (
            "X1\n",
            "t.ngc:1:1: axis words without a motion mode (G0, G1, G2, G3, G5, G5.1, G5.2, G73, G81…G83)",
        ),
        (
            "G0 G1 X1\n",
            "t.ngc:1:4: two words of the same modal group on one line",
        ),
        (
            "G1 A10 F100\n",
            "t.ngc:1:4: unsupported axis word A (only X, Y, Z are machine axes)",
        ),
        ("G1 X F100\n", "t.ngc:1:4: X: a number is missing"),
        (
            "G2 X10 Y0 F100\n",
            "t.ngc:1:1: G2 needs a centre (I/J) or a radius (R)",
        ),
        ("G4\n", "t.ngc:1:1: G4 needs P (dwell time in seconds)"),
        ("M98 P100\n", "t.ngc:1:1: unsupported M98"),
        ("G1 X1 F0\n", "t.ngc:1:1: G1 with a zero feed rate (F0, or F never set)"),
        ("G1 X1 F-1\n", "t.ngc:1:7: feed F-1 must not be negative"),
        (
            "G2 X10 Y0 R4 F100\n",
            "t.ngc:1:11: G2: R4 is smaller than half the chord (5.0000 mm)",
        ),
    ];
    for (text, want) in cases {
        assert_eq!(error(text), want, "{text:?}");
    }
    // An end point 0.5 mm off the circle of radius 10 (limits 0.002 mm and 0.1 %).
    let e = error("G21 G0 X10 Y0\nG3 X0 Y10.5 I-10 J0 F100\n");
    assert!(
        e.starts_with("t.ngc:2:1: G3: end point is 0.5000 mm off the circle"),
        "{e}"
    );
    // Within tolerance: accepted, centre moved onto the bisector so both ends are on the circle.
    let b = blocks("G21 G0 X10 Y0\nG3 X0 Y10.001 I-10 J0 F100\n");
    if let Motion::Arc { center, to, .. } = b[1].motion {
        let r1 = (0.01 - center[0]).hypot(center[1]);
        let r2 = (to[0] - center[0]).hypot(to[1] - center[1]);
        assert!((r1 - r2).abs() < 1e-15);
    } else {
        panic!("arc expected");
    }
}

#[test]
fn corpus_programs_read_to_the_end() {
    let corpus = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus");
    for name in ["pessoles_linear.ngc", "seed003_pocket_compensated.ngc"] {
        let text = std::fs::read_to_string(format!("{corpus}/{name}")).unwrap();
        let n = validate(Arc::from(text), name).unwrap_or_else(|e| panic!("{e}"));
        assert!(n > 5, "{name}: {n} blocks");
    }
}

#[test]
fn streams_a_million_lines() {
    // 1 M lines through the reader: only the cursor and the modal state are kept.
    let n = if cfg!(debug_assertions) {
        200_000
    } else {
        1_000_000
    };
    let mut text = String::with_capacity(n * 20);
    text.push_str("G21 G90 G1 F3000\n");
    for i in 0..n {
        text.push_str(&format!("X{}.{:03} Y{}\n", i / 1000, i % 1000, i % 7));
    }
    let count = validate(Arc::from(text), "big.ngc").unwrap();
    assert_eq!(count as usize, n);
}

proptest! {
    #[test]
    fn garbage_never_panics(line in "[ -~]{0,40}") {
        let _ = validate(Arc::from(format!("G21 F100\n{line}\n")), "fuzz.ngc");
    }

    #[test]
    fn valid_line_programs_never_fail(points in prop::collection::vec((-500i32..500, -500i32..500, -50i32..50), 1..30)) {
        let mut text = String::from("G21 G90 G64 F1500\n");
        for (x, y, z) in &points {
            text.push_str(&format!("G1 X{}.{} Y{} Z{}\n", x / 10, (x % 10).abs(), y, z));
        }
        prop_assert_eq!(validate(Arc::from(text), "p.ngc").unwrap() as usize, points.len());
    }
}
