//! Numbered and named parameters and expressions (LinuxCNC G-code reference, "Parameters",
//! "Expressions", "Binary Operators", "Functions").
#![allow(unused_crate_dependencies)]

use cnc_motion::gcode::{validate, Block, Motion, Reader};
use std::sync::Arc;

fn xs(text: &str) -> Vec<f64> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().unwrap_or_else(|e| panic!("{e}")) {
        if let Block {
            motion: Motion::Linear { to },
            ..
        } = b
        {
            out.push((to[0] * 1e9).round() / 1e6);
        }
    }
    out
}

fn error(text: &str) -> String {
    validate(Arc::from(text), "t.ngc").unwrap_err().to_string()
}

/// "Expressions": the documentation's example `[1 + acos[0] - [#3 ** [4.0/2]]]` with #3 = 2 is
/// 1 + 90 − 4 = 87; precedence `**` > `* / MOD` > `+ -` > comparisons > logic, left to right.
#[test]
fn expressions_and_functions() {
    let x = xs("#3 = 2\nG1 F100 X[1 + acos[0] - [#3 ** [4.0/2]]]\nX[2 + 3 * 4]\nX[2 ** 3 ** 2]\nX[7 MOD 3]\n\
                X[1 LT 2 AND 3 GT 2]\nX[1 EQ 2 OR 0]\nX ATAN[1]/[1]\nX FIX[-1.5]\nX FUP[1.2]\nX ROUND[2.5]\nX-#3\n\
                X SQRT[16]\nX[ABS[-3] + SIN[90] + COS[0] + EXP[0] + LN[1] + TAN[45]]\n");
    assert_eq!(
        x,
        vec![87.0, 14.0, 64.0, 1.0, 1.0, 0.0, 45.0, -2.0, 2.0, 3.0, -2.0, 4.0, 7.0]
    );
}

/// "Parameters": `#n = value` and `#<name> = value` (names case-insensitive, spaces ignored);
/// settings take effect after the line, so a value read on the same line is the old one.
#[test]
fn numbered_and_named_parameters() {
    let x = xs(
        "#3 = 15\n#3 = 6 G1 X#3 F100\nX#3\n#<Tool Dia> = 2.5\nX#<tooldia>\n#1 = 3 #2 = #1\nX#2\nX##1\n\
                X[EXISTS[#<tooldia>] + EXISTS[#<nope>]]\n",
    );
    // #2 takes the old #1 (0); ##1 is #3 (6).
    assert_eq!(x, vec![15.0, 6.0, 2.5, 0.0, 6.0, 1.0]);
    // ##1: the parameter whose number is in #1 (#3 = 6).
    let x = xs("#1 = 3\n#3 = 6\nG1 F100 X##1\n");
    assert_eq!(x, vec![6.0]);
}

/// Errors stay located at the column of the problem.
#[test]
fn parameter_errors_are_located() {
    assert_eq!(error("G1 F100 X[1/0]\n"), "t.ngc:1:12: X: division by zero");
    assert_eq!(
        error("G1 F100 X#<nope>\n"),
        "t.ngc:1:10: X: parameter #<nope> is not defined"
    );
    assert!(error("#5603 = 1\n").starts_with("t.ngc:1:2: parameter #5603 out of range"));
    assert_eq!(
        error("#1 G1\n"),
        "t.ngc:1:4: expected '=' after the parameter (a parameter setting)"
    );
    assert_eq!(error("G1 F100 X[1 + 2\n"), "t.ngc:1:16: X: expected ']'");
    assert_eq!(
        error("G1 F100 X SQRT[-1]\n"),
        "t.ngc:1:11: X: SQRT of -1 is not a finite number"
    );
    let deep = format!("G1 F100 X{}1{}\n", "[".repeat(100), "]".repeat(100));
    assert!(error(&deep).contains("nested deeper than 64"));
}
