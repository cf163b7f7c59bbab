//! O-word control flow (LinuxCNC G-code reference, "O Codes"): the documentation's examples
//! ("Subroutines", "O- Call Example", "Looping", "Do While Example", "Conditional", "Repeat",
//! "Subroutine return values", "Indirection") run with the moves their text implies; the errors
//! of section "Errors" are located at `file:line:col`; loops are bounded.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::gcode::{Block, Motion, ProgramSource, Reader};
use std::sync::Arc;

/// End points (mm, rounded to 1e-6) of the moves (G0/G1) of a program.
fn moves_with(text: &str, machine: &Machine) -> Result<Vec<[f64; 3]>, String> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]).with_machine(machine);
    collect(&mut r)
}

fn collect(r: &mut Reader) -> Result<Vec<[f64; 3]>, String> {
    let mut out = Vec::new();
    while let Some(b) = r.next_block().map_err(|e| e.to_string())? {
        if let Block {
            motion: Motion::Linear { to } | Motion::Rapid { to },
            ..
        } = b
        {
            out.push(to.map(|v| (v * 1e9).round() / 1e6));
        }
    }
    Ok(out)
}

fn moves(text: &str) -> Vec<[f64; 3]> {
    moves_with(text, &Machine::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn xs(text: &str) -> Vec<f64> {
    moves(text).iter().map(|p| p[0]).collect()
}

fn error(text: &str) -> String {
    moves_with(text, &Machine::default()).unwrap_err()
}

/// "Looping", While Endwhile Example: the sawtooth, ten teeth: 20 moves, tooth k rising to
/// Y = k/10 at X1, ending at (1, 0.9).
#[test]
fn while_endwhile_draws_the_sawtooth() {
    let m = moves(
        "(draw a sawtooth shape)\nG0 X1 Y0 (move to start position)\n#1 = 0 (assign parameter #1 the value of 0)\n\
         F25 (set a feed rate)\no101 while [#1 LT 10]\n  G1 X0\n  G1 Y[#1/10] X1\n  #1 = [#1+1] (increment the test counter)\n\
         o101 endwhile\nM2 (end program)\n",
    );
    assert_eq!(m.len(), 1 + 20);
    let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9);
    for k in 0..10 {
        let before = k.max(1) as f64 / 10.0 - 0.1;
        assert!(close(m[1 + 2 * k], [0.0, before, 0.0]), "{k}: {:?}", m[1 + 2 * k]);
        assert!(
            close(m[2 + 2 * k], [1.0, k as f64 / 10.0, 0.0]),
            "{k}: {:?}",
            m[2 + 2 * k]
        );
    }
    assert_eq!(m[20], [1.0, 0.9, 0.0]);
}

/// "Looping", Do While Example with `continue` ("skips to the next evaluation of the while
/// condition"): passes with #1 = 0 and 1 reach the move, the pass with #1 = 2 sets 3 and
/// continues to `while [3 LT 3]`, which ends the loop.
#[test]
fn do_while_with_continue() {
    let x = xs(
        "#1 = 0 (assign parameter #1 the value of 0)\nF100\no100 do\n  (debug, parameter 1 = #1)\n  o110 if [#1 EQ 2]\n\
         #1 = 3 (assign the value of 3 to parameter #1)\n    (msg, #1 has been assigned the value of 3)\n\
         o100 continue (skip to start of loop)\n  o110 endif\n  G1 X#1\n  #1 = [#1 + 1] (increment the test counter)\n\
         o100 while [#1 LT 3]\nG1 X[10 + #1]\nM2\n",
    );
    assert_eq!(x, vec![0.0, 1.0, 13.0]);
}

/// "Subroutines", "O- Return Example", "O- Call Example": arguments are #1, #2, #3; `return`
/// leaves at once; #1 … #30 are the caller's again afterwards, #N+1 … #30 are the caller's
/// inside the call.
#[test]
fn call_with_arguments_return_and_locals() {
    let x = xs("#1 = 4\n#3 = 8\nF100\no100 sub\n  o110 if [#2 GT 5]\n    o100 return\n  o110 endif\n  G1 X#1 Y#3\n\
                o100 endsub\no100 call [100] [2] [325]\no100 call [7] [9] [1]\no100 call [50] [1]\nG1 X#1 Y#3\nM2\n");
    // The second call returns before its move; the third sees the caller's #3 = 8.
    assert_eq!(x, vec![100.0, 50.0, 4.0]);
    let m = moves("#3 = 8\nF100\no100 sub\nG1 X#1 Y#3\no100 endsub\no100 call [1]\nM2\n");
    assert_eq!(m, vec![[1.0, 8.0, 0.0]]);
}

/// "Subroutine return values": `return [#2 * 5]` / `endsub [3 * 4]` set `#<_value>` and
/// `#<_value_returned>` = 1; both are cleared at the next call.
#[test]
fn return_values() {
    let x = xs(
        "o123 sub\no124 if [#2 GT 0]\no123 return [#2 * 5]\no124 endif\no123 endsub [3 * 4]\n\
                o123 call [0] [2]\nG1 F100 X#<_value> Y#<_value_returned>\no123 call [0] [0]\nG1 X#<_value>\n\
                o<none> sub\no<none> endsub\no<none> call\nG1 X[#<_value> + 100 * #<_value_returned>]\nM2\n",
    );
    assert_eq!(x, vec![10.0, 12.0, 0.0]);
}

/// Named parameters without `_` are local to their call level; `_` ones are global.
#[test]
fn named_locals_and_globals() {
    let x = xs(
        "#<a> = 1\no<set> sub\n#<a> = 5\n#<_g> = [#<a> + 1]\nG1 X#<a>\no<set> endsub\nF100\n\
                o<set> call\nG1 X[#<a> * 100 + #<_g>]\nM2\n",
    );
    assert_eq!(x, vec![5.0, 106.0]);
    assert!(
        error("o<s> sub\nG1 F100 X#<a>\no<s> endsub\n#<a> = 1\no<s> call\n")
            .starts_with("t.ngc:2:10: X: parameter #<a> is not defined")
    );
}

/// "Conditional": if / elseif / else / endif, the first true branch only.
#[test]
fn if_elseif_else() {
    for (p2, want) in [(7.0, 100.0), (1.0, 200.0), (3.0, 150.0), (2.0, 150.0)] {
        let text = format!(
            "#2 = {p2}\nG1 F100 X0\no102 if [#2 GT 5]\n  X100\no102 elseif [#2 LT 2]\n  X200\no102 elseif [#2 LT 2]\n  X300\n\
             o102 else\n  X150\no102 endif\nY1\nM2\n"
        );
        assert_eq!(xs(&text), vec![0.0, want, want], "#2 = {p2}");
    }
    // No else, false: nothing; nested ifs with their own numbers.
    let x = xs("G1 F100 X1\no1 if [0]\nX2\no1 endif\no2 if [1]\no3 if [1]\nX3\no3 else\nX4\no3 endif\no2 endif\nM2\n");
    assert_eq!(x, vec![1.0, 3.0]);
}

/// "Repeat": five diagonal moves in G91 from the present position end at (5, 5); nested repeat
/// loops and break.
#[test]
fn repeat_nested_and_break() {
    let m = moves("G91 (Incremental mode)\no103 repeat [5]\nG0 X1 Y1 (diagonal move to next position)\no103 endrepeat\nG90\nM2\n");
    assert_eq!(m.len(), 5);
    assert_eq!(m[4], [5.0, 5.0, 0.0]);
    let m =
        moves("G91 F100\no1 repeat [3]\no2 repeat [4]\nG1 X1\no2 endrepeat\nG1 X-4 Y1\no1 endrepeat\nM2\n");
    assert_eq!(m.len(), 15);
    assert_eq!(m[14], [0.0, 3.0, 0.0]);
    let x = xs("#1 = 0\nF100\no1 while [1]\n#1 = [#1 + 1]\no2 if [#1 GT 3]\no1 break\no2 endif\nG1 X#1\no1 endwhile\nG1 X9\nM2\n");
    assert_eq!(x, vec![1.0, 2.0, 3.0, 9.0]);
    assert!(moves("o1 repeat [0]\nG0 X1\no1 endrepeat\nM2\n").is_empty());
}

/// Subroutines defined after the call, recursion, and the computed label of "Indirection".
#[test]
fn recursion_forward_definition_and_indirection() {
    // Recursion (LinuxCNC: "may call themselves recursively"): depth 5 gives 5 moves.
    let x = xs(
        "F100\no<down> call [5]\nM2\no<down> sub\no1 if [#1 GT 0]\nG1 X#1\no<down> call [#1 - 1]\no1 endif\n\
                o<down> endsub\n",
    );
    assert_eq!(x, vec![5.0, 4.0, 3.0, 2.0, 1.0]);
    let x = xs("#101 = 98\no100 sub\nG1 F100 X7\no100 endsub\no[#101+2] call\nM2\n");
    assert_eq!(x, vec![7.0]);
}

/// A program number heading the program (LinuxCNC "Fanuc-Style Numbered Programs": `o1 (Example
/// 1)`) is accepted and has no effect.
#[test]
fn program_number_at_the_head() {
    assert_eq!(xs("%\nO0001 (PART 1)\nG1 F100 X1\nM30\n%\n"), vec![1.0]);
}

/// Block delete on O-word lines: with the switch on a `/o…` line is skipped, with it off it runs.
#[test]
fn block_delete_on_o_word_lines() {
    let text = "F100\no1 if [0]\nG1 X1\n/o1 else\nG1 X2\no1 endif\nG1 X3\n";
    assert_eq!(xs(text), vec![3.0]);
    let off = Machine::from_toml("block_delete = false\n", "m.toml").unwrap();
    let x: Vec<f64> = moves_with(text, &off).unwrap().iter().map(|p| p[0]).collect();
    assert_eq!(x, vec![2.0, 3.0]);
}

/// A file source is streamed and seeked (the loop re-reads its body from the file): same moves
/// as the text.
#[test]
fn loops_and_calls_from_a_file() {
    let text =
        "F100\no1 sub\nG1 X[#1 * 2]\no1 endsub\n#2 = 0\no2 while [#2 LT 50]\no1 call [#2]\n#2 = [#2 + 1]\n\
                o2 endwhile\nM2\n";
    let path = std::env::temp_dir().join(format!("oword_{}.ngc", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let mut r = Reader::new(ProgramSource::File(path.clone()), "t.ngc", [0.0; 3]);
    let from_file = collect(&mut r).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(from_file, moves(text));
    assert_eq!(from_file.len(), 50);
    assert_eq!(from_file[49], [98.0, 0.0, 0.0]);
}

/// The loop bound: `max_loop_iterations` jumps back, then a located error at the jumping line.
#[test]
fn loops_are_bounded() {
    let machine = Machine::from_toml("max_loop_iterations = 1000\n", "m.toml").unwrap();
    let e = moves_with("o1 while [1]\nG0 X1\no1 endwhile\n", &machine).unwrap_err();
    assert_eq!(
        e,
        "t.ngc:3:1: more than 1000 loop iterations (machine key max_loop_iterations)"
    );
    // 1000 passes are within the bound (999 jumps back).
    assert_eq!(
        moves_with("o1 repeat [1000]\nG0 X1\no1 endrepeat\n", &machine)
            .unwrap()
            .len(),
        1000
    );
    let e = moves_with("o1 repeat [1001]\nG0 X1\no1 endrepeat\n", &machine).unwrap_err();
    assert!(
        e.starts_with("t.ngc:1:1: o1 repeat [1001]: count out of range"),
        "{e}"
    );
    let e = Machine::from_toml("max_loop_iterations = 0\n", "m.toml").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("m.toml:1:23: max_loop_iterations = 0 out of range"),
        "{e}"
    );
    // Endless recursion stops at LinuxCNC's nesting level 10.
    let e = error("o1 sub\no1 call\no1 endsub\no1 call\n");
    assert_eq!(e, "t.ngc:2:1: o1 call: calls nested deeper than 10");
}

/// "Errors": each located at the O-word.
#[test]
fn errors_are_located() {
    for (text, want) in [
        ("o100 endsub\n", "t.ngc:1:1: o100 endsub outside a call of o100 (no o100 call is running)"),
        ("G0 X1\n  o1 endwhile\n", "t.ngc:2:3: o1 endwhile without a matching o1 while"),
        ("o1 while [0]\nG0 X1\n", "t.ngc:1:1: o1 while without o1 endwhile"),
        ("o1 while [1]\nG0 X1\n", "t.ngc:1:1: o1 while is not closed before the end of the program"),
        ("o1 if [1]\no2 endif\no1 endif\n", "t.ngc:2:1: o2 endif without a matching o2 if (open: o1 if of line 1)"),
        ("o1 else\n", "t.ngc:1:1: o1 else without a matching o1 if"),
        ("o1 if [0]\nG0 X1\n", "t.ngc:1:1: o1 if without o1 endif"),
        ("o1 repeat [2]\no2 break\no1 endrepeat\n", "t.ngc:2:1: o2 break outside a loop o2 (while, do, repeat)"),
        ("o1 sub\no1 endsub\no1 sub\no1 endsub\n", "t.ngc:3:1: o1 sub defined twice (first at line 1)"),
        (
            "o<nope> call\n",
            "t.ngc:1:1: o<nope> call: the program has no o<nope> sub (a program given as text has no directory to find \
             nope.ngc in: machine key subroutine_path)",
        ),
        ("o1 sub\nG0 X1\n", "t.ngc:1:1: o1 sub without o1 endsub"),
        ("o1 if\no1 endif\n", "t.ngc:1:1: o1 if needs one [expression]"),
        ("o1 if [1/0]\no1 endif\n", "t.ngc:1:9: division by zero"),
        ("o1 goto\n", "t.ngc:1:4: o1: unknown O-word keyword 'goto' (sub, endsub, call, return, if, elseif, else, endif, while, endwhile, do, repeat, endrepeat, break, continue)"),
        ("o1 if [1] G0 X1\no1 endif\n", "t.ngc:1:11: o1: expected '[expression]' or the end of the line"),
        ("G0 X1 o1 if [1]\n", "t.ngc:1:7: an O-word must begin its line (LinuxCNC \"O Codes\")"),
        ("o sub\n", "t.ngc:1:1: an O-word needs a number (1 to 9 digits) or a <name>"),
        (
            "G0 X1\nO100\nG0 X2\nM99\n",
            "t.ngc:2:1: unsupported Fanuc-style subprogram o100 (… M99); write o100 sub … o100 endsub",
        ),
    ] {
        assert_eq!(error(text), want, "{text}");
    }
}

/// A saved engine state in the middle of a loop inside a subroutine call restores to the same
/// motion (the open constructs, the call stack and its saved locals are part of the state;
/// FMI 2.0 fmi2GetFMUstate).
#[test]
fn engine_state_round_trip_inside_a_loop_and_a_call() {
    let program =
        "G21 F3000\no<tooth> sub\n#<n> = 0\no2 repeat [3]\nG1 X0\nG1 Y[#1 + #<n>] X1\n#<n> = [#<n> + 0.1]\n\
                   o2 endrepeat\no<tooth> endsub\n#<k> = 0\no1 while [#<k> LT 4]\no<tooth> call [#<k>]\n\
                   #<k> = [#<k> + 1]\no1 endwhile\nM2\n";
    let m = Machine::default();
    let new = || cnc_motion::engine::Engine::new(program, "p", &m).unwrap();
    let mut a = new();
    a.advance(0.7).unwrap();
    let state = a.save_state();
    let mut b = new();
    b.restore_state(&state).unwrap();
    while !a.finished() {
        a.advance(0.01).unwrap();
        b.advance(0.01).unwrap();
        assert_eq!(a.tick().p, b.tick().p);
    }
    assert!(b.finished());
    let end = b.tick().p;
    assert!(
        (end[0] - 1e-3).abs() < 1e-12 && (end[1] - 3.2e-3).abs() < 1e-12,
        "{end:?}"
    );
}
