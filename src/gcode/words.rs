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
                let letter = c.to_ascii_uppercase();
                // A digit or point after the letter (and its sign) starts a number: no
                // parameter or expression.
                let signed = matches!(b.get(i + 1), Some(b'-' | b'+'));
                let first = i + 1 + usize::from(signed);
                let plain = b.get(first).is_some_and(|&x| x.is_ascii_digit() || x == b'.');
                let found = match plain {
                    true => None,
                    false => not_plain(b, i + 1, letter, params.as_ref().map(|(p, _)| *p))?,
                };
                let (value, next) = match found {
                    Some(found) => found,
                    None => number(b, i + 1).map_err(|m| err(i, format!("{}: {m}", c as char)))?,
                };
                out.push(Word {
                    letter,
                    value,
                    col: i as u32 + 1,
                });
                i = next;
            }
            _ => return Err(err(i, format!("unexpected character '{}'", printable(line, i)))),
        }
    }
    Ok(())
}

/// The value of `letter` from `i` where it is no plain number: an expression's (with `params`),
/// an error for `#` or `[` without them; None where `number` reads it.
fn not_plain(
    b: &[u8],
    i: usize,
    letter: u8,
    params: Option<&Params>,
) -> Result<Option<(f64, usize)>, LexError> {
    let k = i + b[i..].iter().take_while(|&&x| x == b' ' || x == b'\t').count();
    if let Some(p) = params.filter(|_| is_expression(b, k)) {
        let mut e = Expr::new(b, k, p);
        let value = e
            .primary()
            .map_err(|(at, m)| err(at, format!("{}: {m}", letter as char)))?;
        return Ok(Some((value, e.i)));
    }
    match b.get(k) {
        Some(b'#') => Err(err(k, "unsupported # parameter (variables are not supported)")),
        Some(b'[') => Err(err(
            k,
            "unsupported expression '[' (expressions are not supported)",
        )),
        _ => Ok(None),
    }
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

/// Powers of ten that f64 holds exactly (10^0 … 10^22).
const EXACT_POWERS: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18,
    1e19, 1e20, 1e21, 1e22,
];
/// Digits at most of a number read by `plain_number`: its digits as an integer stay below 2^53.
const PLAIN_DIGITS: usize = 15;

/// A number written plainly at `i` (a sign, digits with at most one point, no space inside, at
/// most `PLAIN_DIGITS` digits), as m / 10^k: m and 10^k are exact, so the division's one rounding
/// gives the correctly rounded value, which `str::parse` gives too. None: `number` reads it.
fn plain_number(b: &[u8], i: usize) -> Option<(f64, usize)> {
    let (negative, start) = match b.get(i) {
        Some(b'-') => (true, i + 1),
        Some(b'+') => (false, i + 1),
        _ => (false, i),
    };
    let (m, whole_end) = digits_from(b, start, 0);
    let point = b.get(whole_end) == Some(&b'.');
    let (m, end) = if point {
        digits_from(b, whole_end + 1, m)
    } else {
        (m, whole_end)
    };
    let decimals = if point { end - whole_end - 1 } else { 0 };
    let digits = whole_end - start + decimals;
    if matches!(b.get(end), Some(b' ' | b'\t')) {
        // A number that goes on after a space is `number`'s.
        let next = b[end..].iter().find(|&&x| x != b' ' && x != b'\t');
        if next.is_some_and(|&x| x.is_ascii_digit() || (x == b'.' && !point)) {
            return None;
        }
    }
    if digits == 0 || digits > PLAIN_DIGITS {
        return None;
    }
    let v = m as f64 / EXACT_POWERS[decimals];
    Some((if negative { -v } else { v }, end))
}

/// The digits from `k` appended to `m` (wrapping past 19 digits, which `plain_number` refuses
/// anyway), and the index after them.
fn digits_from(b: &[u8], mut k: usize, mut m: u64) -> (u64, usize) {
    while let Some(&c) = b.get(k).filter(|c| c.is_ascii_digit()) {
        m = m.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
        k += 1;
    }
    (m, k)
}

/// A real number starting at `i` (spaces allowed anywhere inside, as LinuxCNC does):
/// optional sign, digits, optional point and digits; at least one digit.
#[inline]
pub(crate) fn number(b: &[u8], i: usize) -> Result<(f64, usize), String> {
    plain_number(b, i).map_or_else(|| spelled_number(b, i), Ok)
}

/// `number` from its text, gathered without the spaces, by `str::parse`.
fn spelled_number(b: &[u8], mut i: usize) -> Result<(f64, usize), String> {
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

    /// The plain numbers read without `str::parse` are its values bit for bit, end where it
    /// ends, and leave the rest (spaces inside, long or malformed numbers) to it: 20 000
    /// random numbers of 0–18 digits, signs, points, spaces and letters after them.
    #[test]
    fn plain_numbers_are_parsed_values() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = move |n: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % n
        };
        let (mut plain, mut general) = (0, 0);
        for _ in 0..20_000 {
            let mut t = String::new();
            match next(4) {
                0 => t.push('-'),
                1 => t.push('+'),
                _ => {}
            }
            let digits = next(19);
            let point = next(digits + 2);
            for d in 0..digits {
                if d == point {
                    t.push('.');
                }
                t.push(char::from(b'0' + next(10) as u8));
                if next(40) == 0 {
                    t.push(' ');
                }
            }
            t.push_str([" Y1", "X", "", " ", ";"][next(5) as usize]);
            let b = t.as_bytes();
            match (plain_number(b, 0), spelled_number(b, 0)) {
                (Some((v, end)), Ok((w, i))) => {
                    assert_eq!((v.to_bits(), end), (w.to_bits(), i), "{t:?}");
                    plain += 1;
                }
                (None, _) => general += 1,
                (Some(_), Err(e)) => panic!("{t:?}: read plainly, refused spelled: {e}"),
            }
        }
        assert!(
            plain > 5000 && general > 1000,
            "{plain} plain, {general} left to parse"
        );
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
