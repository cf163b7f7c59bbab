//! Issue 20: RS274NGC as LinuxCNC runs it. Each test follows a section of LinuxCNC's
//! documentation (2.9, "G-code" / "Overview" / "O Codes", and the NIST RS274NGC v3 report
//! where LinuxCNC follows it) and asserts the end position the documentation gives or its
//! text implies (hand-computed in the comments), or the located error it names.
#![allow(unused_crate_dependencies)]

mod reading;

use cnc_motion::config::Machine;
use cnc_motion::gcode::{validate, Motion};
use reading::{blocks, blocks_with, end_of, ends, ends_in, error};

fn last(text: &str) -> [f64; 3] {
    *ends(text).last().expect("a move")
}

/// "G10 L2 Set Coordinate System": R is the rotation of the XY axes about Z. The case:
/// P1 at X10 Y0 rotated 90°, so program X5 Y0 is machine (10, 5) — where LinuxCNC ends.
#[test]
fn g10_l2_r_rotates_the_coordinate_system() {
    assert_eq!(
        last("G10 L2 P1 X10 Y0 R90\nG54 G1 X5 Y0 F600\n"),
        [10.0, 5.0, 0.0]
    );
    // Offsets, G92 and tool length compose as LinuxCNC's canonical layer composes them:
    // machine = R·(program + G92) + work offset + tool length (Z). Hand-computed:
    let text = "G10 L2 P1 X10 Y20 R90\nG54 G0 X0 Y0\n\
                G92 X1 Y0\n\
                G1 X3 Y0 F600\n\
                G43.1 Z5\nG0 Z1\n\
                G91 G1 X1\n\
                G10 L20 P1 X0 Y0\nG90 G1 X0 Y0\nX1\n";
    let want = [
        [10.0, 20.0, 0.0], // R90·(0, 0) + (10, 20)
        [10.0, 22.0, 0.0], // G92 = (−1, 0): R90·(3 − 1, 0) + (10, 20)
        [10.0, 22.0, 6.0], // Z1 + tool length 5
        [10.0, 23.0, 6.0], // G91 X1 along the rotated X: machine +Y
        [10.0, 23.0, 6.0], // G10 L20: here reads X0 Y0, offset (10, 24)
        [10.0, 24.0, 6.0], // R90·(1 − 1, 0) + (10, 24)
    ];
    assert_eq!(ends(text), want);
    // An arc's centre offset rotates with the axes: G3 half circle about program (0, 1).
    let b = blocks("G10 L2 P1 R90\nG1 X0 Y0 F600\nG3 X0 Y2 I0 J1\n");
    let Motion::Arc { to, center, .. } = b[1].motion else {
        panic!("{b:?}")
    };
    assert_eq!(
        (to.map(|v| v * 1e3), center.map(|v| v * 1e3)),
        ([-2.0, 0.0, 0.0], [-1.0, 0.0, 0.0])
    );
    // LinuxCNC refuses R in G10 L20; G18/G19 arcs turn with the system
    // (tests/gcode_linuxcnc_samples.rs).
    assert_eq!(
        error("G10 L20 P1 X0 R30\n"),
        "t.ngc:1:15: R (rotation) is not allowed in G10 L20, only in L2"
    );
    assert!(matches!(
        blocks("G10 L2 P1 R30\nG18 G2 X1 Z0 I0.5 K0 F100\n")[0].motion,
        Motion::Arc {
            plane: cnc_motion::geometry::Plane::Turned { yz: false, .. },
            ..
        }
    ));
}

/// "Polar Coordinates": `G1 @1^90` is `G1 Y1`; the documentation's spiral (G91 @ and ^ both
/// add) and square (G91 ^ only) programs, end points as its figures show them.
#[test]
fn polar_coordinates_as_documented() {
    assert_eq!(last("F100 G1 @1^90\n"), [0.0, 1.0, 0.0]);
    let spiral = ends("F100 G1 @.5 ^90\nG91 @.5 ^90\n@.5 ^90\n@.5 ^90\n@.5 ^90\nG90 G0 X0 Y0 M2\n");
    let want = [
        [0.0, 0.5],
        [-1.0, 0.0],
        [0.0, -1.5],
        [2.0, 0.0],
        [0.0, 2.5],
        [0.0, 0.0],
    ];
    for (p, w) in spiral.iter().zip(want) {
        assert!(
            (p[0] - w[0]).abs() < 1e-9 && (p[1] - w[1]).abs() < 1e-9,
            "{spiral:?}"
        );
    }
    let square = ends("F100 G1 @.5 ^90\nG91 ^90\n^90\n^90\n^90\nG90 G0 X0 Y0 M2\n");
    let want = [
        [0.0, 0.5],
        [-0.5, 0.0],
        [0.0, -0.5],
        [0.5, 0.0],
        [0.0, 0.5],
        [0.0, 0.0],
    ];
    for (p, w) in square.iter().zip(want) {
        assert!(
            (p[0] - w[0]).abs() < 1e-9 && (p[1] - w[1]).abs() < 1e-9,
            "{square:?}"
        );
    }
    // "It is an error if: an incremental move is started at the origin; a mix of polar and X or
    // Y words are used."
    assert!(error("G91 G1 @1 F100\n").starts_with("t.ngc:1:8: G91 polar move from the XY origin"));
    assert!(error("G1 @1 ^0 X1 F100\n").starts_with("t.ngc:1:10: polar coordinates (@ ^) and X or Y"));
}

/// Overview, "File Requirements": a program whose first non-blank line is `%` ends at the
/// second `%` (LinuxCNC ends at X1, the X5 after it is not read); an opening `%` without a
/// closing one is an error, as in LinuxCNC ("File ended with no percent sign").
#[test]
fn percent_lines_demarcate_the_program() {
    assert_eq!(last("%\nG1 X1 F600\n%\nG1 X5\n"), [1.0, 0.0, 0.0]);
    assert_eq!(
        last("\n  %  \nG1 X1 F600\n%\nthis is not read\n"),
        [1.0, 0.0, 0.0]
    );
    assert_eq!(
        error("%\nG1 X1 F600\n"),
        "t.ngc:1:1: the program opens with '%' but has no closing '%' line (LinuxCNC \"File Requirements\")"
    );
    assert!(error("G1 X1 F600\n%\n").starts_with("t.ngc:2:1: '%' alone on a line ends a program only"));
    // A subroutine after the closing `%` is not part of the program.
    assert!(error("%\no1 call\n%\no1 sub\no1 endsub\n").contains("the program has no o1 sub"));
}

/// "O Codes", "Conditional" (one `else`, after the `elseif`s) and "Subroutines" (a sub ends at
/// its `endsub`): located errors where LinuxCNC's program would be malformed.
#[test]
fn o_word_constructs_are_checked() {
    let e = error("#1=1\no1 if [#1]\nG1 X1 F100\no1 else\nG1 X2\no1 else\nG1 X3\no1 endif\n");
    assert_eq!(e, "t.ngc:6:1: a second o1 else in one o1 if");
    let e = error("#1=0\no1 if [#1]\nG1 X1 F100\no1 else\nG1 X2 F100\no1 else\no1 endif\n");
    assert_eq!(e, "t.ngc:6:1: a second o1 else in one o1 if");
    let e = error("#1=1\no1 if [#1]\nG1 X1 F100\no1 else\no1 elseif [1]\no1 endif\n");
    assert_eq!(
        e,
        "t.ngc:5:1: o1 elseif after o1 else (the else branch comes last)"
    );
    let e = error("#1=0\no1 if [#1]\no1 else\nG1 X2 F100\no1 elseif [1]\no1 endif\n");
    assert_eq!(
        e,
        "t.ngc:5:1: o1 elseif after o1 else (the else branch comes last)"
    );
    // A called sub without its endsub (uncalled it was already an error).
    assert_eq!(
        error("o3 call\nM2\no3 sub\nG1 X1 F100\n"),
        "t.ngc:3:1: o3 sub without o3 endsub"
    );
    // A well-formed chain still runs its branch.
    assert_eq!(
        last("#1=0\no1 if [#1]\nG1 X1 F100\no1 elseif [1]\nG1 X2 F100\no1 else\nG1 X3 F100\no1 endif\n"),
        [2.0, 0.0, 0.0]
    );
}

/// "G53 Move in Machine Coordinates": only with G0/G1, not with cutter compensation (LinuxCNC
/// "Cannot use G53 with cutter radius comp"), not in G91 (NIST RS274NGC v3 §3.5.3 "it is an
/// error if G53 is used in incremental distance mode"). `G53 G0 X1` in G55 ends at machine X1.
#[test]
fn g53_rules() {
    let toml = "[work_offset.g55]\nx_mm = 100\n";
    let m = Machine::from_toml(toml, "m.toml").unwrap();
    let b = blocks_with("G55 G53 G0 X1\n", &m).unwrap();
    assert_eq!(end_of(&b[0]).map(|p| p[0] * 1e3), Some(1.0));
    assert_eq!(
        error("G91 G53 G1 X1 F100\n"),
        "t.ngc:1:5: G53 in G91: machine coordinates are absolute (NIST RS274NGC v3, \"G53\")"
    );
    assert_eq!(
        error("G53 G2 X1 I1 F100\n"),
        "t.ngc:1:1: G53 needs a G0 or G1 move on its line (LinuxCNC \"G53\")"
    );
    assert_eq!(
        error("G53\n"),
        "t.ngc:1:1: G53 needs a G0 or G1 move on its line (LinuxCNC \"G53\")"
    );
    let e = error("G41.1 D1 G1 X5 F100\nG53 G1 X10\n");
    assert_eq!(
        e,
        "t.ngc:2:5: G53 with cutter compensation on (LinuxCNC: cannot use G53 with cutter radius comp)"
    );
}

/// Overview, "Order of Execution" (dwell is step 14, motion step 24) and "Modal Groups" (G4 is
/// group 0, legal with motion): `G1 X1 F600 G4 P0.5` dwells, then moves, ending at X1; the
/// documentation's own "Eight Holes" line `G1 F10 X0 G4 P0.1` runs.
#[test]
fn group_zero_codes_run_before_the_motion() {
    let b = blocks("G1 X1 F600 G4 P0.5\n");
    assert_eq!(b[0].motion, Motion::Dwell { seconds: 0.5 });
    assert_eq!(end_of(&b[1]).map(|p| p[0] * 1e3), Some(1.0));
    let b = blocks("G90 G0 X0 Y0 Z0\nG1 F10 X0 G4 P0.1\n");
    assert!(b.iter().any(|b| b.motion == Motion::Dwell { seconds: 0.1 }));
    // Axis words with a modal G1 and G4 on the line: dwell, then the move.
    let b = blocks("G1 X1 F100\nG4 P1 X2\n");
    assert_eq!(
        (b[1].motion, end_of(&b[2]).map(|p| p[0] * 1e3)),
        (Motion::Dwell { seconds: 1.0 }, Some(2.0))
    );
    // Dwell, move, then the stop (steps 14, 24, 25), whatever the order on the line.
    let b = blocks("M0 G1 X1 F100 G4 P1\n");
    assert_eq!(b.len(), 3);
    assert_eq!(b[0].motion, Motion::Dwell { seconds: 1.0 });
    assert!(matches!(b[2].motion, Motion::Stop(_)));
    // "It is an error to put a G-code from group 1 and a G-code from group 0 on the same line if
    // both of them use axis words"; LinuxCNC also refuses G4 with G2/G3 (both use P).
    assert_eq!(
        error("G1 G92 X0\n"),
        "t.ngc:1:1: G1 and G92 on one line: both use the axis words (LinuxCNC \"Modal Groups\")"
    );
    assert_eq!(
        error("G2 X1 I0.5 F100 G4 P1\n"),
        "t.ngc:1:17: G4 and G2/G3 on one line: both use P (LinuxCNC \"G4\")"
    );
    assert_eq!(
        error("G4 P1 G10 L2 P1 X0\n"),
        "t.ngc:1:7: two words of the same modal group on one line"
    );
    // F (step 4) is read before G20 (step 16): F10 here is 10 mm/min, X1 one inch.
    let b = blocks("G20 G1 X1 F10\n");
    assert!((b[0].feed - 10.0 * 1e-3 / 60.0).abs() < 1e-15, "{}", b[0].feed);
    assert!((end_of(&b[0]).unwrap()[0] - 25.4e-3).abs() < 1e-15);
    // G28.1 (step 23) stores the point before the line's move (step 24): G28 comes back to X1.
    assert_eq!(
        ends("G1 X1 F100\nG28.1 X5\nG28\n"),
        vec![[1.0, 0.0, 0.0], [5.0, 0.0, 0.0], [5.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    );
    // A modal G1 is suspended by G92 on a line: the axis words are G92's (no move).
    assert_eq!(
        ends("G1 X1 F100\nG92 X0\nX1\n"),
        vec![[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
    );
}

/// "G81 Drilling Cycle", "Repeat Cycle": in G90, L3 drills three times at the same place
/// (LinuxCNC); in G91 the holes step by X Y (Example 2, documented moves, in inches).
#[test]
fn canned_cycle_repeats() {
    let b = blocks("G0 Z10\nG81 X5 Y0 Z-2 R1 L3 F100\n");
    let feeds: Vec<_> = b
        .iter()
        .filter(|b| matches!(b.motion, Motion::Linear { .. }))
        .collect();
    assert_eq!(feeds.len(), 3);
    assert!(feeds
        .iter()
        .all(|b| end_of(b).map(|p| p.map(|v| (v * 1e6).round() / 1e3)) == Some([5.0, 0.0, -2.0])));
    assert_eq!(last("G0 Z10\nG81 X5 Y0 Z-2 R1 L3 F100\n"), [5.0, 0.0, 10.0]);
    // Example 2: from X1 Y2 Z3, `G91 G98 G81 X4 Y5 Z-0.6 R1.8 L3`.
    let m = ends_in("G20 G0 X1 Y2 Z3\nG91 G98 G81 X4 Y5 Z-0.6 R1.8 L3 F10\n", 25.4);
    let want = [
        [1.0, 2.0, 3.0],
        [1.0, 2.0, 4.8],
        [5.0, 7.0, 4.8],
        [5.0, 7.0, 4.2],
        [5.0, 7.0, 4.8],
        [9.0, 12.0, 4.8],
        [9.0, 12.0, 4.2],
        [9.0, 12.0, 4.8],
        [13.0, 17.0, 4.8],
        [13.0, 17.0, 4.2],
        [13.0, 17.0, 4.8],
    ];
    assert_eq!(m.len(), want.len(), "{m:?}");
    for (p, w) in m.iter().zip(want) {
        assert!(p.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-9), "{m:?}");
    }
    // "Twelve Holes in a Square": 12 feed moves, at the perimeter of the square 0…4 × 0…3.
    let text = "N1000 G90 G0 X0 Y0 Z0\nN1010 G1 F50 X0 G4 P0.1\nN1020 G91 G81 X1 Y0 Z-0.5 R1 L4\n\
                N1030 X0 Y1 R0 L3\nN1040 X-1 Y0 L3\nN1050 X0 Y-1 L2\nN1060 G80\nN1070 G90 G0 X0\nN1080 Y0\nN1090 Z0\nN1100 M2\n";
    let want = [
        [1.0, 0.0],
        [2.0, 0.0],
        [3.0, 0.0],
        [4.0, 0.0],
        [4.0, 1.0],
        [4.0, 2.0],
        [4.0, 3.0],
        [3.0, 3.0],
        [2.0, 3.0],
        [1.0, 3.0],
        [1.0, 2.0],
        [1.0, 1.0],
    ];
    // The drilling feeds (N1010's G1 X0 aside).
    let drilled: Vec<[f64; 2]> = blocks(text)
        .iter()
        .filter(|b| b.line > 2 && matches!(b.motion, Motion::Linear { .. }))
        .filter_map(end_of)
        .map(|p| [(p[0] * 1e6).round() / 1e3, (p[1] * 1e6).round() / 1e3])
        .collect();
    assert_eq!(drilled, want);
    assert_eq!(last(text), [0.0, 0.0, 0.0]);
    assert_eq!(
        error("G81 X1 Z-1 R1 L0 F100\n"),
        "t.ngc:1:15: G81 L0: zero repeats (L ≥ 1)"
    );
}

/// "G83 Peck Drilling": the README bounds a hole to 10 000 pecks; 10 mm in Q0.001 is exactly
/// that, though 10 / 0.001 is 10000.000000000002 in binary (tolerance 1e-9 of the count).
#[test]
fn exactly_ten_thousand_pecks() {
    let b = blocks("G0 Z5\nG83 X0 Y0 R1 Z-9 Q0.001 F100\n");
    let feeds: Vec<_> = b
        .iter()
        .filter(|b| matches!(b.motion, Motion::Linear { .. }))
        .collect();
    assert_eq!(feeds.len(), 10_000);
    assert_eq!(
        end_of(feeds[9_999]).map(|p| (p[2] * 1e9).round() / 1e6),
        Some(-9.0)
    );
    assert_eq!(last("G0 Z5\nG73 X0 Y0 R1 Z-9 Q0.001 F100\n"), [0.0, 0.0, 5.0]);
    assert_eq!(
        error("G0 Z5\nG83 X0 Y0 R1 Z-9.0001 Q0.001 F100\n"),
        "t.ngc:2:1: G83: more than 10000 pecks"
    );
}

/// "Expressions": the README's bound is "nesting deeper than 64": 64 nested brackets are read.
#[test]
fn sixty_four_nested_brackets() {
    let nested = |n: usize| format!("G1 F100 X{}1{}\n", "[".repeat(n), "]".repeat(n));
    assert_eq!(last(&nested(64)), [1.0, 0.0, 0.0]);
    assert_eq!(
        error(&nested(65)),
        "t.ngc:1:74: X: expression nested deeper than 64"
    );
    // Signs nest nothing: a long run of them is one value.
    assert_eq!(
        last(&format!("G1 F100 X[{}1]\n", "-".repeat(1000))),
        [1.0, 0.0, 0.0]
    );
}

/// "F: Set Feed Rate": NCs take any F and run at most at the machine's largest feed
/// (LinuxCNC's sample 3D_Chips.ngc programs F2250000; its test programs F100000 in G20).
#[test]
fn feed_above_the_machine_maximum_is_capped() {
    let m = Machine::default();
    for text in ["G21 G1 X1 F2250000\n", "G20 G1 X1 F100000\n"] {
        let b = blocks(text);
        assert_eq!(b[0].feed, m.max_feed, "{text}");
    }
    assert_eq!(last("G20 G1 X1 F100000\n")[0], 25.4);
    // F0 is a setting (LinuxCNC's planner tests write it before G95); a feed move at F0 is not.
    assert_eq!(
        error("G1 X1 F0\n"),
        "t.ngc:1:1: G1 with a zero feed rate (F0, or F never set)"
    );
    assert_eq!(last("F0\nG0 X2\nG1 X3 F10\n"), [3.0, 0.0, 0.0]);
}

/// Messages and limits from the issue: each with its place and what is meant.
#[test]
fn messages_say_what_is_meant() {
    // G93 F1e-9: the move takes 1e9 min, refused at once (it ran the whole --max-time).
    let start = std::time::Instant::now();
    let e = error("G93 G1 X1 F0.000000001\n");
    assert!(
        e.starts_with("t.ngc:1:11: G93 F0.000000001: the move takes 1/F = "),
        "{e}"
    );
    assert!(
        e.ends_with(" min: longer than the longest move (86400 s, one day)") && !e.contains("mm/min"),
        "{e}"
    );
    assert!(start.elapsed().as_secs() < 5);
    // The same in G94: 100 mm at F1e-6 mm/min, and a drilling cycle's feed.
    assert!(error("G1 X100 F0.000001\n").contains("longer than the longest move"));
    assert!(error("G81 X0 Y0 Z-10 R1 F0.000001\n").contains("longer than the longest move"));
    // R alone in G81 mode is not an arc word (LinuxCNC: "R word with no g code that uses it").
    assert_eq!(
        error("G81 X1 Y1 Z-1 R1 F100\nR0.5\n"),
        "t.ngc:2:1: R with no G code that uses it: G2/G3, or a drilling cycle with X, Y or Z on the line"
    );
    // Arc radius equal to the tool radius (LinuxCNC: "Tool radius not less than arc radius").
    let e = error("G0 X-5 Y0\nG41.1 D2 G1 X0 Y0 F100\nG3 X2 Y0 I1 J0\nG40 G1 X5\n");
    assert_eq!(
        e,
        "t.ngc:3:1: arc radius 1.0000 mm is equal to the tool radius 1.0000 mm on the tool's side: the tool cannot follow it (gouge)"
    );
}

/// The issue's `G93 G1 X1 F0.000000001` through the CLI: exit 2 with the place, at once.
#[test]
fn cli_refuses_a_move_longer_than_a_day() {
    let dir = std::env::temp_dir().join(format!("cnc-g93-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("slow.ngc");
    std::fs::write(&path, "G93 G1 X1 F0.000000001\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cnc-motion"))
        .args(["run", path.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(":1:11: G93 F0.000000001"), "{err}");
    // A G93 move of 100 min stopped by --max-time: the message names the path feed, not F.
    std::fs::write(&path, "G93 G1 X1 F0.01\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cnc-motion"))
        .args(["run", path.to_str().unwrap(), "--max-time", "0.5"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("feed too low: 0.01 mm/min along the path") && !err.contains("F0.01 mm/min"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        validate("G93 G1 X1 F0.001\n", "t.ngc").is_ok(),
        "1000 min is under a day"
    );
    // A program file's path quoted in an error is cut, not echoed whole.
    let long = std::path::Path::new("/").join("x".repeat(100_000));
    let e = cnc_motion::gcode::source::read_program_file(&long, "p.ngc").unwrap_err();
    assert!(e.len() < 3000 && e.contains("characters cut"), "{}", e.len());
}

/// "G41.1, G42.1" (LinuxCNC "Cutter Compensation"): tolerances are lengths, so a 1 µm tool runs
/// the path that 0, 0.5 µm and 0.1 mm tools run (it reported a "concave corner … gouge": the
/// previous join left the tool 0.9 nm before the arc's start, an angle tolerance of 1e-9 rad
/// allowed 3e-12 m). Every radius ends at the G40 move's point, (23.6538, 12.1471).
#[test]
fn compensation_tolerances_scale_with_the_tool() {
    let path = |d: &str| {
        format!(
            "G21 G17 F1000\nG0 X-5 Y0\nG41.1 D{d} G1 X0 Y0\nG1 X7.5294 Y0.0057\nG3 X9.9662 Y1.2281 I0.0003 J3.0393\n\
             G1 X13.5372 Y6.0299\nG2 X21.1149 Y7.8397 I4.8714 J-3.6279\nG40 G1 X23.6538 Y12.1471\nM30\n"
        )
    };
    for d in ["0", "0.001", "0.002", "0.2"] {
        let end = last(&path(d));
        assert!(
            (end[0] - 23.6538).abs() < 1e-9 && (end[1] - 12.1471).abs() < 1e-9,
            "D{d}: {end:?}"
        );
    }
}

/// Machine-file messages: an integer key refuses 4.5; an inch file's errors quote the inch
/// values it wrote; a 10 MB string is cut with an ellipsis.
#[test]
fn machine_file_messages() {
    let e = Machine::from_toml("[servo.x]\nencoder_counts = 4.5\n", "m.toml").unwrap_err();
    assert_eq!(
        e.to_string(),
        "m.toml:2:18: servo.x.encoder_counts = 4.5: must be a whole number"
    );
    let e = Machine::from_toml("units = \"inch\"\nmax_feed_mm_min = 400000\n", "m.toml").unwrap_err();
    assert!(
        e.to_string().starts_with(
            "m.toml:2:19: max_feed_mm_min = 400000 out of range (0.0393700787402 … 39370.0787402 in/min;"
        ),
        "{e}"
    );
    let e = Machine::from_toml("units = \"inch\"\n[tool.1]\nradius_mm = 50\n", "m.toml").unwrap_err();
    assert!(
        e.to_string()
            .ends_with("tool.1.radius_mm = 50 out of range (0 … 39.3700787402 in)"),
        "{e}"
    );
    let long = "x".repeat(10_000_000);
    let e = Machine::from_toml(&format!("profile = \"{long}\"\n"), "m.toml").unwrap_err();
    let m = e.to_string();
    assert!(
        m.len() < 1000 && m.contains("… (10000000 characters)"),
        "{}",
        &m[..m.len().min(300)]
    );
}
