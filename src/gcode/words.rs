//! One line of G-code → its words (letter, number, column; `@` and `^` count as letters).
//! Comments `( )` and `;`, spaces inside numbers (as LinuxCNC allows); with `split_with`, `#` parameters and `[ ]` expressions
//! evaluated (params.rs); O-words reported with their column.

use super::params::{Expr, Key, Params, FUNCTIONS};

/// A word: upper-case letter, its value, and the 1-based column of the letter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    pub letter: u8,
    pub value: f64,
    pub col: u32,
}

/// Error at a column of the line.
#[derive(Clone, Debug, PartialEq)]
pub struct LexError {
    pub col: u32,
    pub message: String,
}

fn err(col: usize, message: impl Into<String>) -> LexError {
    LexError {
        col: col as u32 + 1,
        message: message.into(),
    }
}

/// Split a line into words, appending to `out` (cleared first). A `%` line has no words.
/// Parameters and expressions are refused here; `split_with` evaluates them.
pub fn split(line: &str, out: &mut Vec<Word>) -> Result<(), LexError> {
    split_inner(line, out, None)
}

/// Parameter settings of a line: key, value, 0-based column.
pub type Sets = Vec<(Key, f64, usize)>;

/// `split` with parameters: `#1`, `#<name>` and `[...]` values are evaluated with `params`,
/// settings `#n = value` collected in `sets` (applied by the caller after the line).
pub fn split_with(line: &str, out: &mut Vec<Word>, params: &Params, sets: &mut Sets) -> Result<(), LexError> {
    sets.clear();
    split_inner(line, out, Some((params, sets)))
}

fn split_inner(
    line: &str,
    out: &mut Vec<Word>,
    mut params: Option<(&Params, &mut Sets)>,
) -> Result<(), LexError> {
    out.clear();
    let b = line.as_bytes();
    if line.trim_start().starts_with('%') {
        return Ok(());
    }
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        match c {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            b'(' => match b[i..].iter().position(|&x| x == b')') {
                Some(k) => i += k + 1,
                None => return Err(err(i, "comment not closed: '(' without ')'")),
            },
            b';' => break,
            b'/' if out.is_empty() => {
                return Err(err(i, "unsupported block delete '/'"));
            }
            b'#' => {
                let Some((p, sets)) = params.as_mut() else {
                    return Err(err(i, "unsupported # parameter (variables are not supported)"));
                };
                i = setting(b, i, p, sets)?;
            }
            b'[' => {
                return Err(err(
                    i,
                    "unsupported expression '[' (expressions are not supported)",
                ))
            }
            b'o' | b'O' => return Err(err(i, "an O-word must begin its line (LinuxCNC \"O Codes\")")),
            // `@` and `^`: polar distance and angle (LinuxCNC "Polar Coordinates").
            c if c.is_ascii_alphabetic() || c == b'@' || c == b'^' => {
                let col = i;
                i += 1;
                let k = i + b[i..].iter().take_while(|&&x| x == b' ' || x == b'\t').count();
                let letter = c.to_ascii_uppercase();
                if let Some((p, _)) = params.as_ref().filter(|_| is_expression(b, k)) {
                    let mut e = Expr::new(b, k, p);
                    let value = e
                        .primary()
                        .map_err(|(at, m)| err(at, format!("{}: {m}", letter as char)))?;
                    i = e.i;
                    let col = col as u32 + 1;
                    out.push(Word { letter, value, col });
                    continue;
                }
                match b.get(k) {
                    Some(b'#') => {
                        return Err(err(k, "unsupported # parameter (variables are not supported)"))
                    }
                    Some(b'[') => {
                        return Err(err(
                            k,
                            "unsupported expression '[' (expressions are not supported)",
                        ))
                    }
                    _ => {}
                }
                let (value, next) = number(b, i).map_err(|m| err(col, format!("{}: {m}", c as char)))?;
                i = next;
                out.push(Word {
                    letter: c.to_ascii_uppercase(),
                    value,
                    col: col as u32 + 1,
                });
            }
            _ => return Err(err(i, format!("unexpected character '{}'", printable(line, i)))),
        }
    }
    Ok(())
}

/// A parameter setting `#key = value` starting at `i` (the `#`); the index after it.
fn setting(b: &[u8], i: usize, params: &Params, sets: &mut Sets) -> Result<usize, LexError> {
    let mut e = Expr::new(b, i + 1, params);
    let key = e.key().map_err(|(c, m)| err(c, m))?;
    if e.peek_byte() != Some(b'=') {
        return Err(err(e.i, "expected '=' after the parameter (a parameter setting)"));
    }
    e.i += 1;
    let v = e.primary().map_err(|(c, m)| err(c, m))?;
    sets.push((key, v, i));
    Ok(e.i)
}

/// A value that needs the evaluator: `#`, `[`, a function name, or a sign before them.
fn is_expression(b: &[u8], k: usize) -> bool {
    let mut k = k;
    while k < b.len() && matches!(b[k], b' ' | b'\t' | b'-' | b'+') {
        k += 1;
    }
    match b.get(k) {
        Some(b'#') | Some(b'[') => true,
        Some(c) if c.is_ascii_alphabetic() => FUNCTIONS
            .iter()
            .any(|f| b.len() >= k + f.len() && b[k..k + f.len()].eq_ignore_ascii_case(f.as_bytes())),
        _ => false,
    }
}

fn printable(line: &str, i: usize) -> String {
    line[i..]
        .chars()
        .next()
        .map_or_else(String::new, |c| c.to_string())
}

/// A real number starting at `i` (spaces allowed anywhere inside, as LinuxCNC does):
/// optional sign, digits, optional point and digits; at least one digit.
pub(crate) fn number(b: &[u8], mut i: usize) -> Result<(f64, usize), String> {
    let mut text = String::with_capacity(16);
    let skip = |i: &mut usize| {
        while *i < b.len() && (b[*i] == b' ' || b[*i] == b'\t') {
            *i += 1;
        }
    };
    skip(&mut i);
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        text.push(b[i] as char);
        i += 1;
        skip(&mut i);
    }
    let mut digits = 0;
    let mut point = false;
    while i < b.len() {
        match b[i] {
            c @ b'0'..=b'9' => {
                text.push(c as char);
                digits += 1;
            }
            b'.' if !point => {
                text.push('.');
                point = true;
            }
            b' ' | b'\t' => {
                // A space inside a number is skipped only if the number goes on after it.
                let mut k = i;
                skip(&mut k);
                if k < b.len() && (b[k].is_ascii_digit() || (b[k] == b'.' && !point)) {
                    i = k;
                    continue;
                }
                break;
            }
            _ => break,
        }
        i += 1;
    }
    if digits == 0 {
        return Err("a number is missing".into());
    }
    let value = text
        .parse::<f64>()
        .map_err(|e| format!("bad number '{text}': {e}"))?;
    if !value.is_finite() {
        let shown: String = text.chars().take(16).collect();
        return Err(format!(
            "number {shown}… ({} digits) out of range (not a finite number)",
            digits
        ));
    }
    Ok((value, i))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(line: &str) -> Vec<(char, f64, u32)> {
        let mut out = Vec::new();
        split(line, &mut out).unwrap();
        out.iter().map(|w| (w.letter as char, w.value, w.col)).collect()
    }

    #[test]
    fn numbers_comments_and_columns() {
        assert_eq!(
            words("N10 g1 X1. Y.5 Z-0.5 (comment) F+2 ; rest"),
            vec![
                ('N', 10.0, 1),
                ('G', 1.0, 5),
                ('X', 1.0, 8),
                ('Y', 0.5, 12),
                ('Z', -0.5, 16),
                ('F', 2.0, 32)
            ]
        );
        assert_eq!(words("X 1 . 5 Y2"), vec![('X', 1.5, 1), ('Y', 2.0, 9)]);
        assert_eq!(
            words("G90.1 G64 P0.01"),
            vec![('G', 90.1, 1), ('G', 64.0, 7), ('P', 0.01, 11)]
        );
        assert!(words("%").is_empty());
    }

    #[test]
    fn errors_name_the_column() {
        let mut out = Vec::new();
        let e = split("G1 X#1", &mut out).unwrap_err();
        assert_eq!(e.col, 5);
        let e = split("G1 X", &mut out).unwrap_err();
        assert_eq!((e.col, e.message.as_str()), (4, "X: a number is missing"));
        let e = split("G1 (open", &mut out).unwrap_err();
        assert_eq!(e.col, 4);
        let e = split("O100 sub", &mut out).unwrap_err();
        assert_eq!(e.col, 1);
    }
}
