//! Issue 20, the side-by-side run: programs LinuxCNC 2.9 runs (its sample programs in
//! /usr/share/linuxcnc/ncfiles and its planner tests) that the reader refused. Each test follows
//! the section of LinuxCNC's documentation ("O Codes", "G-code", "Cutter Compensation") or, where
//! it is silent, what LinuxCNC's interpreter does (named), and asserts the end position LinuxCNC
//! reaches (hand-computed in the comments) or the located error.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::gcode::{Block, Motion, Reader};
use std::sync::Arc;

fn blocks_with(text: &str, machine: &Machine) -> Result<Vec<Block>, String> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]).with_machine(machine);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().map_err(|e| e.to_string())? {
        out.push(b);
    }
    Ok(out)
}

fn blocks(text: &str) -> Vec<Block> {
    blocks_with(text, &Machine::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> String {
    blocks_with(text, &Machine::default()).unwrap_err()
}

fn end_of(b: &Block) -> Option<[f64; 3]> {
    match b.motion {
        Motion::Rapid { to } | Motion::Linear { to } | Motion::Arc { to, .. } => Some(to),
        _ => None,
    }
}

/// End points of the moves in mm, rounded to 1e-9.
fn ends(text: &str) -> Vec<[f64; 3]> {
    blocks(text)
        .iter()
        .filter_map(end_of)
        .map(|p| p.map(|v| (v * 1e12).round() / 1e9))
        .collect()
}

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
    // In a branch not taken the line is skipped, as LinuxCNC checks the rest only when it runs.
    assert_eq!(
        ends("o1 if [0]\nO<g20sub> callsub\no1 endif\nG0 X1\n"),
        vec![[1.0, 0.0, 0.0]]
    );
}
