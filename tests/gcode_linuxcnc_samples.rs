//! Issue 20, the side-by-side run: programs LinuxCNC 2.9 runs (its sample programs in
//! /usr/share/linuxcnc/ncfiles and its planner tests) that the reader refused. Each test follows
//! the section of LinuxCNC's documentation ("O Codes", "G-code", "Cutter Compensation") or, where
//! it is silent, what LinuxCNC's interpreter does (named), and asserts the end position LinuxCNC
//! reaches (hand-computed in the comments) or the located error.
#![allow(unused_crate_dependencies)]

mod reading;

use cnc_motion::config::Machine;
use cnc_motion::gcode::{Block, Motion};
use reading::{blocks, blocks_with, end_of, ends, error};

/// "O Codes", "Subroutines" (O- Return: "returns to the calling code, just as though O- endsub
/// was encountered") and "Subroutine return values": LinuxCNC's retval.ngc, `o1010 return
/// [123*[#1]]` inside `o1010 if` within `o1000 sub`, returns from the o1000 call (LinuxCNC's
/// interpreter leaves the running call on any return or endsub, whatever its label). The
/// values it prints, 4712, 246 and 0, are the X of the moves here.
#[test]
fn return_with_another_label_leaves_the_running_sub() {
    let retval = "o1000 sub\no1010 if [#1 GT 0]\no1010    return [123*[#1]]\no1010 endif\n\n\
                  o1020 if [#1 LT 0]\no1020    return\no1020 endif\n\no1000 endsub [4712]\n\n\
                  o1000 call [0]\nG1 F100 X#<_value>\no1000 call [2]\nG1 X#<_value> Y#<_value_returned>\n\
                  o1000 call [-1]\nG1 X#<_value> Y#<_value_returned>\nm2\n";
    assert_eq!(
        ends(retval),
        vec![[4712.0, 0.0, 0.0], [246.0, 1.0, 0.0], [0.0, 0.0, 0.0]]
    );
    // A return with no call running is still LinuxCNC's "not in a subroutine definition".
    assert_eq!(
        error("o1010 return\n"),
        "t.ngc:1:1: o1010 return outside a call of o1010 (no o1010 call is running)"
    );
}

/// LinuxCNC's `read_g` (the documentation's "Modal Groups" says two words of one group are an
/// error and is silent on G80): a G80 beside another motion code is dropped, in either order,
/// and a second G80 too. Its planner tests start `G90 G17 G40 G80 G00 G20`; two other motion
/// codes stay an error.
#[test]
fn g80_beside_a_motion_code_is_dropped() {
    let inch = 25.4;
    assert_eq!(
        ends("G90 G17 G40 G80 G00 G20\nG0 X1 Y0 Z0\n"),
        vec![[inch, 0.0, 0.0]]
    );
    assert_eq!(ends("G1 G80 X2 F100\n"), vec![[2.0, 0.0, 0.0]]);
    // G80 then a cycle: the cycle runs (drill to Z-1, back to the initial Z5 in G98).
    let drill = ends("G0 Z5\nG98 G80 G81 X1 Z-1 R2 F100\n");
    assert_eq!(drill[drill.len() - 2..], [[1.0, 0.0, -1.0], [1.0, 0.0, 5.0]]);
    assert_eq!(ends("G80 G80\nG0 X3\n"), vec![[3.0, 0.0, 0.0]]);
    // G80 alone still cancels the modal motion: axis words then need a motion code.
    let e = error("G1 X1 F100\nG80\nX2\n");
    assert!(e.starts_with("t.ngc:3:1: "), "{e}");
    assert_eq!(
        error("G0 G80 G1 X1\n"),
        "t.ngc:1:8: two words of the same modal group on one line"
    );
}

/// "O Codes": the keywords are words of their own; LinuxCNC's `read_o` takes the first keyword
/// the word starts with and refuses what follows ("Unexpected character after O-word"): its
/// sample nestedcall.ngc (`O<g20sub> callsub`) stops there in LinuxCNC 2.9 (run with rs274),
/// and so does the reader, at the column of `sub`.
#[test]
fn callsub_is_call_followed_by_an_error() {
    let e = error("G21\nO<g20sub> callsub\n");
    assert_eq!(
        e,
        "t.ngc:2:15: o<g20sub>: unexpected 'sub' after 'call' (LinuxCNC reads the keyword call and \
         refuses the rest: \"Unexpected character after O-word\")"
    );
    // In a branch not taken the line is skipped, as LinuxCNC checks the rest only when it
    // runs; so is a word that is no keyword at all (LinuxCNC's O_none).
    assert_eq!(
        ends("o1 if [0]\no1 goto\no1 endif\nG0 X1\n"),
        vec![[1.0, 0.0, 0.0]]
    );
    assert_eq!(
        ends("o1 if [0]\nO<g20sub> callsub\no1 endif\nG0 X1\n"),
        vec![[1.0, 0.0, 0.0]]
    );
}

/// The machine of LinuxCNC's side-by-side run: tool 4 of radius 3.175 mm (1/8 in).
fn tool4() -> Machine {
    Machine::from_toml("[tool.4]\nradius_mm = 3.175\n", "m.toml").unwrap()
}

/// "Cutter Compensation", "Programming Entry Moves" ("Any move that is long enough to perform
/// the compensation will work as the entry move. The minimum length is the cutter radius"):
/// LinuxCNC's comp311_2.ngc enters G41 on a G3 arc. LinuxCNC's `convert_arc_comp1` runs the
/// tool from where it is to the offset of the programmed end, (2, 3 + 1/8), on an arc whose
/// centre lies on the radial line there: (2, y) with 1 + (4 − y)² = (y − 3.125)², y = 7.234375
/// / 1.75 = 4.1339… . The rest is the contour's offset, 1/8 in out, every element tangent to
/// the next. LinuxCNC 2.9 (rs274, this tool) prints ARC_FEED(2.0000, 3.1250, 2.0000, 4.1339,
/// 1), ARC_FEED(3.1250, 2.0000, …), STRAIGHT_FEED(3.1250, -1.0000), ARC_FEED(2.0000, -2.1250,
/// …), STRAIGHT_FEED(-2.0000, -2.1250), ARC_FEED(-2.6750, -0.1000, …), STRAIGHT_FEED(1.3250,
/// 2.9000), ARC_FEED(2.0000, 3.1250, …): the closed forms below, in inches.
#[test]
fn g41_entry_on_an_arc_as_linuxcnc_comp311_2() {
    let text = "g20 f60\nt4 m6\ng0 z1\ng0 x1 y4\ng1 z0\ng41\ng3 x2 y3 i1\ng2 x3 y2 j-1\ng1 y-1\n\
                g2 x2 y-2 i-1\ng1 x-2\ng2 x-2.6 y-0.2 j1\ng1 x1.4 y2.8\ng2 x2 y3 i.6 j-.8\ng40\nm2\n";
    let b = blocks_with(text, &tool4()).unwrap();
    let inch = |p: [f64; 3]| p.map(|v| v / 25.4e-3);
    let moves: Vec<&Block> = b.iter().filter(|b| end_of(b).is_some()).skip(3).collect();
    let r = 0.125;
    let want: [([f64; 2], Option<[f64; 2]>); 8] = [
        ([2.0, 3.0 + r], Some([2.0, 7.234375 / 1.75])),
        ([3.0 + r, 2.0], Some([2.0, 2.0])),
        ([3.0 + r, -1.0], None),
        ([2.0, -2.0 - r], Some([2.0, -1.0])),
        ([-2.0, -2.0 - r], None),
        // (−2, −1) + 1.125·(−0.6, 0.8): the radius to (−2.6, −0.2), outwards.
        ([-2.0 - 1.125 * 0.6, -1.0 + 1.125 * 0.8], Some([-2.0, -1.0])),
        // (1.4, 2.8) + 0.125·(−0.6, 0.8), the line's left normal.
        ([1.4 - r * 0.6, 2.8 + r * 0.8], None),
        ([2.0, 3.0 + r], Some([2.0, 2.0])),
    ];
    for (k, (m, (end, center))) in moves.iter().zip(want).enumerate() {
        let got = inch(end_of(m).unwrap());
        assert!(
            (got[0] - end[0]).abs() < 1e-12 && (got[1] - end[1]).abs() < 1e-12,
            "move {k}: end {got:?}, LinuxCNC {end:?}"
        );
        match (m.motion, center) {
            (Motion::Arc { center: c, .. }, Some(want)) => {
                let c = inch(c);
                assert!(
                    (c[0] - want[0]).abs() < 1e-12 && (c[1] - want[1]).abs() < 1e-12,
                    "move {k}: centre {c:?}, LinuxCNC {want:?}"
                );
            }
            (Motion::Linear { .. }, None) => {}
            (motion, _) => panic!("move {k}: {motion:?}"),
        }
    }
    // The G40 move: nothing after it in the plane; LinuxCNC ends where the contour closes.
    assert_eq!(moves.len(), 8, "{moves:?}");
}

/// The G41/G42 entry arc followed by a corner (LinuxCNC `convert_arc_comp1`, then its corner
/// step on the entry arc's own circle). G2 from (0, 0) to (2, 2) about (2, 0), tool 1/8 in:
/// - G41 (outside), then `G1 Y4`, a concave corner: the tool path's centre (2, y0), 4 + y0² =
///   (2.125 − y0)², y0 = 0.515625 / 4.25; it ends where its circle meets the line's offset
///   x = 1.875. rs274 prints ARC_FEED(1.8750, 2.1211, 2.0000, 0.1213, -1).
/// - G42 (inside), then `G1 Y-1`: centre (2, y0), 4 + y0² = (1.875 − y0)², y0 = −0.484375 /
///   3.75, end on x = 1.875: ARC_FEED(1.8750, 1.8711, 2.0000, -0.1292, -1).
/// - G41, then `G1 Y-1`, a convex corner: the entry arc ends at (2, 2.125), the G450 arc about
///   the corner to (2.125, 2): ARC_FEED(2.0000, 2.1250, 2.0000, 0.1213, -1), ARC_FEED(2.1250,
///   2.0000, 2.0000, 2.0000, -1).
#[test]
fn entry_arc_then_a_corner() {
    let run = |side: &str, next: &str| {
        let text =
            format!("g20 f60\nt4 m6\ng0 x0 y0\n{side}\ng2 x2 y2 i2 j0\ng1 {next}\ng40\ng0 x6 y6\nm2\n");
        blocks_with(&text, &tool4()).unwrap()
    };
    let inch = |p: [f64; 3]| [p[0] / 25.4e-3, p[1] / 25.4e-3];
    let arc = |b: &Block| match b.motion {
        Motion::Arc { to, center, .. } => (inch(to), inch(center)),
        m => panic!("{m:?}"),
    };
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
    let y0: f64 = 0.515625 / 4.25;
    let want = [1.875, y0 + ((2.125 - y0).powi(2) - 0.125f64.powi(2)).sqrt()];
    let (to, c) = arc(&run("g41", "y4")[1]);
    assert!(close(to, want) && close(c, [2.0, y0]), "{to:?} {c:?}");
    let y0: f64 = -0.484375 / 3.75;
    let want = [1.875, y0 + ((1.875 - y0).powi(2) - 0.125f64.powi(2)).sqrt()];
    let (to, c) = arc(&run("g42", "y-1")[1]);
    assert!(close(to, want) && close(c, [2.0, y0]), "{to:?} {c:?}");
    let b = run("g41", "y-1");
    let (to, c) = arc(&b[1]);
    assert!(
        close(to, [2.0, 2.125]) && close(c, [2.0, 0.515625 / 4.25]),
        "{to:?} {c:?}"
    );
    let (to, c) = arc(&b[2]);
    assert!(close(to, [2.125, 2.0]) && close(c, [2.0, 2.0]), "{to:?} {c:?}");
}

/// Entry arcs LinuxCNC refuses, and the one it runs that the reader refuses (chosen otherwise):
/// an arc ending within the tool radius of its start (LinuxCNC: "Radius of cutter compensation
/// entry arc is not greater than the tool radius"); a short arc whose start lies behind the
/// tangent at its offset end — LinuxCNC's centre falls beyond the end and the tool loops round
/// (295° for G3 X0.9848 Y0.17365 I-1 from (1, 0), tool 1/8) to arrive against the contour's
/// direction, cutting outside it: refused as a gouge.
#[test]
fn entry_arcs_refused() {
    let run = |arc: &str| {
        blocks_with(
            &format!("g20 f60\nt4 m6\ng0 x1 y0\ng41\n{arc}\ng40 g0 x5\n"),
            &tool4(),
        )
    };
    let e = run("g3 x0.995004165 y0.099833417 i-1").unwrap_err();
    assert!(
        e.starts_with("t.ngc:5:1: the G41/G42 entry arc ends 2.5389 mm from its start, not farther than the tool radius 3.1750 mm"),
        "{e}"
    );
    let e = run("g3 x0.9848 y0.17365 i-1").unwrap_err();
    assert!(
        e.starts_with("t.ngc:5:1: the G41/G42 entry arc starts behind the tangent"),
        "{e}"
    );
    // A half circle from (1, 0) about (0, 0) runs to (−0.875, 0) about (0.0625, 0), the middle
    // of the radial line's chord: rs274 prints ARC_FEED(-0.8750, 0.0000, 0.0625, 0.0000, 1).
    let b = run("g3 x-1 y0 i-1").unwrap();
    let Motion::Arc { to, center, .. } = b[1].motion else {
        panic!("{b:?}")
    };
    let (x, cx) = (to[0] / 25.4e-3, center[0] / 25.4e-3);
    assert!(
        (x + 0.875).abs() < 1e-12 && (cx - 0.0625).abs() < 1e-12,
        "{x} {cx}"
    );
}

/// "G10 L2" (R: "rotation about the Z axis") with G18/G19 arcs: LinuxCNC rotates the end and
/// the centre about Z, and its canon turns the plane's axes with them, so the arc lies in a
/// vertical plane turned by R. Its planner test arc-feed_full_yz.ngc (G20, `G10 L2 P0 X-2 Y1
/// R60`, `G1 X1.5 Z.5`, `G18 G2 X.5 Z1.5 K1`, "270 deg."): rs274 prints ARC_FEED(1.5, 0.5,
/// 1.5, 1.5, -1) in program coordinates — centre X1.5 Z1.5, radius 1 in, end X.5 Z1.5. In
/// machine coordinates m = R60·(x, y) + (−2, 1): every point of the arc is at 1 in from the
/// centre (−2 + 0.75, 1 + 1.5·sin 60°, 1.5) in the plane through Z along (cos 60°, sin 60°),
/// the arc 3/2·π in long, ending at (−2 + 0.25, 1 + 0.5·sin 60°, 1.5). The same in G19
/// (arc-feed_full_xz.ngc: `G0 Y1.5 Z.5`, `G19 G2 Y.5 Z1.5 K1`) turns the YZ plane: end
/// (−2 − 0.5·sin 60°, 1 + 0.25, 1.5), a quarter circle (clockwise from −Z to −Y seen from +X).
/// A helix rises along the turned normal.
#[test]
fn g18_g19_arcs_in_a_rotated_system() {
    let inch = 25.4e-3;
    let (c, s) = (0.5, 3f64.sqrt() / 2.0);
    let to_program = |m: [f64; 3]| {
        let (x, y) = (m[0] / inch + 2.0, m[1] / inch - 1.0);
        [c * x + s * y, -s * x + c * y, m[2] / inch]
    };
    let head = "G20 G90 F1000\nG10 L2 P0 X-2 Y1 R60\nG0 X0 Y0 Z0\n";
    for (text, center, end, yz, quarters) in [
        (
            "G1 X1.5 Z.5\nG18 G2 X.5 Z1.5 K1\n",
            [1.5, 0.0, 1.5],
            [0.5, 0.0, 1.5],
            false,
            3.0,
        ),
        (
            "G0 Y1.5 Z.5\nG19 G2 Y.5 Z1.5 K1\n",
            [0.0, 1.5, 1.5],
            [0.0, 0.5, 1.5],
            true,
            1.0,
        ),
        (
            "G1 X1.5 Z.5\nG90.1 G18 G2 X.5 Z1.5 I1.5 K1.5\n",
            [1.5, 0.0, 1.5],
            [0.5, 0.0, 1.5],
            false,
            3.0,
        ),
    ] {
        let b = blocks(&format!("{head}{text}"));
        let arc = b.last().unwrap();
        let Motion::Arc { to, plane, .. } = arc.motion else {
            panic!("{b:?}")
        };
        let close = |p: [f64; 3], q: [f64; 3]| p.iter().zip(q).all(|(a, b)| (a - b).abs() < 1e-12);
        assert!(close(to_program(to), end), "{text}: end {:?}", to_program(to));
        assert!(matches!(plane, cnc_motion::geometry::Plane::Turned { yz: y, .. } if y == yz));
        let Some(cnc_motion::geometry::Source::Arc(geo)) = arc.geometry() else {
            panic!("{arc:?}")
        };
        let quarter = std::f64::consts::FRAC_PI_2 * inch;
        assert!((geo.length() - quarters * quarter).abs() < 1e-12, "{text}");
        for k in 0..=16 {
            let p = to_program(geo.eval(geo.length() * k as f64 / 16.0).p);
            let r = ((0..3).map(|i| (p[i] - center[i]).powi(2)).sum::<f64>()).sqrt();
            // On the circle, in the program's plane through the centre.
            let normal = if yz { 0 } else { 1 };
            assert!(
                (r - 1.0).abs() < 1e-9 && (p[normal] - center[normal]).abs() < 1e-9,
                "{text} {k}: {p:?}"
            );
        }
    }
    // A helix: G18 with Y rises along the program's Y, turned: end (0.5, 1, 1.5) in program.
    let b = blocks(&format!("{head}G1 X1.5 Z.5\nG18 G2 X.5 Z1.5 K1 Y1\n"));
    let Motion::Arc { to, .. } = b.last().unwrap().motion else {
        panic!("{b:?}")
    };
    let p = to_program(to);
    assert!(
        (p[0] - 0.5).abs() < 1e-12 && (p[1] - 1.0).abs() < 1e-12 && (p[2] - 1.5).abs() < 1e-12,
        "{p:?}"
    );
    // Cutter compensation takes its offsets in the machine's plane: refused in a turned one.
    let m = tool4();
    let e = blocks_with(&format!("{head}T4 M6\nG18 G41 G1 X1 Z1\nX2\n"), &m).unwrap_err();
    assert!(
        e.starts_with(
            "t.ngc:5:1: cutter compensation in G18/G19 while the coordinate system is rotated (R60)"
        ),
        "{e}"
    );
}

/// "G40" ("the move after G40 … leaves from the compensated end") as LinuxCNC runs its
/// gmoccapy_2_tools_with_cutter_radius_compensation.ngc: the first circle ends at its
/// compensated point (52.5527, 50), `G0 Z30`, then `G40` and `G0 X50 Y50`, a move with no
/// motion in the plane as programmed. LinuxCNC's `convert_cutter_compensation_off` takes the
/// programmed point for the current one, so that move brings the tool back to (50, 50); the
/// second circle (tool 1, r 1.5875, G41 again) then enters from there on an arc to (63.4125,
/// 50) about (56.70625, 50). rs274 prints STRAIGHT_TRAVERSE(52.5527, 50.0000, 30.0000),
/// STRAIGHT_TRAVERSE(50.0000, 50.0000, …), ARC_FEED(63.4125, 50.0000, 56.7063, 50.0000, 1, …);
/// LinuxCNC 2.9 ends at (51.5875, 50, 42.9794) (no G40 before M2), as here; its sampled path and
/// ours agree within 1.5 µm.
#[test]
fn g40_exit_without_motion_in_the_plane() {
    let m = Machine::from_toml(
        "[tool.1]\nradius_mm = 1.5875\nlength_mm = 12.9794\n[tool.3]\nradius_mm = 2.5527\nlength_mm = 32.3342\n",
        "m.toml",
    )
    .unwrap();
    let text = "G17 G21 G54 G61 G40 G49 G80 G90\nT3 M6\nG43\nG0 X50 Y50\nG0 Z30\nG0 Z10\nF250\nG1 Z0\n\
                G41\nG3 X70 Y50 Z-1 I10 J0\nF2000\nG3 I -20\nG3 X50 Y50 Z1 I-10 J0\nG0 Z30\nG40\nT1 M6\nG43\n\
                G0 X50 Y50\nG0 Z10\nF400\nG1 Z1\nG41\nG3 X65 Y50 Z-1 I7.5 J0\nF1000\nG3 I-15\n\
                G3 X50 Y50 Z1 I-7.5 J0\nG0 Z30\nG0 X50 Y50\nM2\n";
    let b = blocks_with(text, &m).unwrap();
    let at = |line: u32| {
        let blk = b.iter().find(|x| x.line == line).unwrap();
        end_of(blk).unwrap().map(|v| (v * 1e7).round() / 1e4)
    };
    assert_eq!(at(14), [52.5527, 50.0, 62.3342]);
    assert_eq!(at(18), [50.0, 50.0, 62.3342]);
    let entry = b.iter().find(|x| x.line == 23).unwrap();
    let Motion::Arc { to, center, .. } = entry.motion else {
        panic!("{entry:?}")
    };
    assert!((to[0] * 1e3 - 63.4125).abs() < 1e-9 && (center[0] * 1e3 - 56.70625).abs() < 1e-9);
    let end = end_of(b.iter().rev().find(|x| end_of(x).is_some()).unwrap()).unwrap();
    assert_eq!(end.map(|v| (v * 1e7).round() / 1e4), [51.5875, 50.0, 42.9794]);
}

/// A tool exactly as large as the hole (LinuxCNC "G41, G42": "The lead in move must be at least
/// as long as the tool radius"; its `convert_arc_comp2`: `arc_radius <= tool_radius` is "Tool
/// radius not less than arc radius with comp"). LinuxCNC's useful-subroutines.ngc mills a
/// 1/8 in hole with a 1/16 in end mill, `o100 call [0] [0] [.01] [.125] [.125] [.0625]`; with the
/// side-by-side machine's tool 1 (radius 1.5875 mm = 1/16 in) LinuxCNC 2.9 stops at its entry
/// move `g41 g0 x#1 …`, 1/16 in long, and so does the reader. With a longer entry the hole's
/// arc, radius equal to the tool's, is refused as LinuxCNC refuses it (checked in LinuxCNC 2.9
/// in mm: "Tool radius not less than arc radius with comp"); 1 µm larger it runs, the tool
/// centre on a circle of 1 µm about the hole's centre.
#[test]
fn tool_as_large_as_the_hole() {
    let m = Machine::from_toml("[tool.1]\nradius_mm = 1.5875\n", "m.toml").unwrap();
    let sub = "o100 sub\n#4=[0 - #4]\n#7=[#6 / 2]\n#8=[#3 - #7]\ng0 z#3\ng0 x[#1 + #6] y[#2 + [#5 / 2]]\n\
               g41 g0 x#1 y[#2 + [#5 / 2]]\no101 while [#8 GT #4]\ng3 x#1 y[#2 + [#5 / 2]] i0 j[0 - [#5 / 2]] z#8\n\
               #8=[#8 - #7]\no101 endwhile\ng40\no100 endsub\n";
    let text =
        format!("{sub}g20 g64 g17 g90\nt1 m6\nf60\no100 call [0] [0] [.01] [.125] [.125] [.0625]\nm2\n");
    let e = blocks_with(&text, &m).unwrap_err();
    assert_eq!(
        e,
        "t.ngc:7:1: the G41/G42 entry move is 1.5875 mm long, not longer than the tool radius 1.5875 mm \
         (LinuxCNC: \"Length of cutter compensation entry move is not greater than the tool radius\")"
    );
    // A longer entry (tool dia. argument 0.1 in): the arc of radius 1/16 in is refused.
    let text = format!("{sub}g20 g64 g17 g90\nt1 m6\nf60\no100 call [0] [0] [.01] [.125] [.125] [.1]\nm2\n");
    let e = blocks_with(&text, &m).unwrap_err();
    assert!(
        e.starts_with(
            "t.ngc:9:1: arc radius 1.5875 mm is equal to the tool radius 1.5875 mm on the tool's side"
        ),
        "{e}"
    );
    // The same in mm, 1 µm larger than the tool: the tool centre turns 1 µm about (0, 0).
    let text = "G21 F100\nT1 M6\nG0 X3.2 Y1.5885\nG41 G0 X0 Y1.5885\nG3 X0 Y1.5885 I0 J-1.5885 Z-1\nM2\n";
    let b = blocks_with(text, &m).unwrap();
    let Motion::Arc { to, center, .. } = b[2].motion else {
        panic!("{b:?}")
    };
    let r = (to[0] - center[0]).hypot(to[1] - center[1]);
    assert!(
        (r - 1e-6).abs() < 1e-12 && center[0].abs() < 1e-15,
        "{r} {center:?}"
    );
}

/// "M61 Set Current Tool": `M61 Q-` makes Q the tool in the spindle without a change; "the
/// tool length offset is not changed by M61, use G43 after the M61". LinuxCNC's offsets.ngc
/// loops `M61Q#<n>G43` over tools 0 … 4. With tool 3 of length 10 mm, `M61 Q3` then `G43`
/// and `G0 Z0` end at machine Z10; M61 alone leaves the offset as it was. "It is an error if
/// Q- is not 0 or greater".
#[test]
fn m61_sets_the_current_tool() {
    let m = Machine::from_toml("[tool.3]\nlength_mm = 10\n", "m.toml").unwrap();
    let run = |text: &str| blocks_with(text, &m).map(|b| b.iter().filter_map(end_of).collect::<Vec<_>>());
    let z = |text: &str| run(text).unwrap().last().unwrap()[2] * 1e3;
    assert_eq!(z("M61 Q3\nG0 Z0\nG43\nG0 Z0\n"), 10.0);
    assert_eq!(z("M61 Q3\nG0 Z0\n"), 0.0);
    assert_eq!(z("M61Q3G43\nG0 Z0\nM61 Q0 G43\nG0 Z0\n"), 0.0);
    assert_eq!(
        run("M61\n").unwrap_err(),
        "t.ngc:1:1: M61 needs Q (the tool number, 0 or greater)"
    );
    assert!(run("M61 Q-1\n")
        .unwrap_err()
        .starts_with("t.ngc:1:5: Q-1 out of range"));
}
