//! O-word lines (LinuxCNC G-code reference, "O Codes"): `o100 sub`, `o<name> call [1] [2]`,
//! `o101 if [#1 GT 0]`, … The label and keyword are read without evaluating anything (the
//! reader scans skipped lines for them); the bracketed arguments are evaluated only on a line
//! that is executed.

use super::params::{Expr, Params};

/// What an O-word line asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keyword {
    Sub,
    EndSub,
    Call,
    Return,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Do,
    Repeat,
    EndRepeat,
    Break,
    Continue,
    /// A bare `O1234` (a comment may follow): a program number (LinuxCNC "Fanuc-Style
    /// Numbered Programs").
    Number,
    /// A word that is no keyword: an error where the line runs, skipped otherwise (LinuxCNC's
    /// O_none).
    Unknown,
}

const KEYWORDS: [(&str, Keyword); 15] = [
    ("sub", Keyword::Sub),
    ("endsub", Keyword::EndSub),
    ("call", Keyword::Call),
    ("return", Keyword::Return),
    ("if", Keyword::If),
    ("elseif", Keyword::ElseIf),
    ("else", Keyword::Else),
    ("endif", Keyword::EndIf),
    ("while", Keyword::While),
    ("endwhile", Keyword::EndWhile),
    ("do", Keyword::Do),
    ("repeat", Keyword::Repeat),
    ("endrepeat", Keyword::EndRepeat),
    ("break", Keyword::Break),
    ("continue", Keyword::Continue),
];

impl Keyword {
    /// The keyword as written in programs.
    pub fn name(self) -> &'static str {
        KEYWORDS.iter().find(|(_, k)| *k == self).map_or("", |(n, _)| n)
    }
}

/// At most this many arguments to a call (#1 … #30).
pub const MAX_ARGS: usize = super::params::LOCAL_NUMBERED;

/// The head of an O-word line: label (`100` or `<name>`, lower case, no spaces), keyword, the
/// 1-based column of the `o` and the byte index after the keyword.
#[derive(Clone, Debug, PartialEq)]
pub struct Head {
    pub label: String,
    pub keyword: Keyword,
    pub col: u32,
    pub rest: usize,
    /// Letters after the keyword (0-based column, message): an error on a line that is run;
    /// a line being skipped is taken for its keyword, as LinuxCNC checks the rest of a line
    /// only when it is not skipping.
    pub trailing: Option<(usize, String)>,
}

impl Head {
    /// The label as written in messages: `o100`, `o<name>`.
    pub fn shown(&self) -> String {
        shown(&self.label)
    }
}

/// A label as written in messages.
pub fn shown(label: &str) -> String {
    if label.starts_with(|c: char| c.is_ascii_digit()) {
        format!("o{label}")
    } else {
        format!("o<{label}>")
    }
}

/// (0-based column, message).
type Located<T> = Result<T, (usize, String)>;

fn blank(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && matches!(b[i], b' ' | b'\t' | b'\r' | b'\n') {
        i += 1;
    }
    i
}

/// The O-word head of `line`, None if the line is not an O-word line (an optional N number
/// may come first). A computed label `o[expression]` ("Indirection") is evaluated with
/// `params`; without them (a line being skipped) it matches no label.
pub fn head(line: &str, params: Option<&Params>) -> Option<Located<Head>> {
    let b = line.as_bytes();
    let mut i = blank(b, 0);
    if matches!(b.get(i), Some(b'N' | b'n')) {
        let k = i + 1 + b[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
        i = blank(b, k);
    }
    if !matches!(b.get(i), Some(b'O' | b'o')) {
        return None;
    }
    Some(parse_head(b, i, params))
}

/// `head` of a line that is run: letters after the keyword are an error.
pub fn head_run(line: &str, params: &Params) -> Option<Located<Head>> {
    head(line, Some(params)).map(|h| {
        h.and_then(|h| match h.trailing {
            Some(t) => Err(t),
            None => Ok(h),
        })
    })
}

fn parse_head(b: &[u8], o: usize, params: Option<&Params>) -> Located<Head> {
    let mut i = blank(b, o + 1);
    let label = if b.get(i) == Some(&b'[') {
        indirect(b, &mut i, params)?
    } else if b.get(i) == Some(&b'<') {
        let end = b[i..]
            .iter()
            .position(|&c| c == b'>')
            .ok_or((o, "O-word name without '>'".to_string()))?;
        let name: String = String::from_utf8_lossy(&b[i + 1..i + end])
            .chars()
            .filter(|c| !c.is_whitespace())
            .flat_map(char::to_lowercase)
            .collect();
        if name.is_empty() {
            return Err((o, "empty O-word name".into()));
        }
        i += end + 1;
        name
    } else {
        let digits = b[i..].iter().take_while(|c| c.is_ascii_digit()).count();
        if digits == 0 || digits > 9 {
            return Err((o, "an O-word needs a number (1 to 9 digits) or a <name>".into()));
        }
        let n: u32 = std::str::from_utf8(&b[i..i + digits])
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0);
        i += digits;
        n.to_string()
    };
    i = blank(b, i);
    let start = i;
    let len = b[i..].iter().take_while(|c| c.is_ascii_alphabetic()).count();
    let word = &b[start..start + len];
    let bare = len == 0 && matches!(b.get(start), None | Some(b'(' | b';'));
    if bare {
        return Ok(Head {
            label,
            keyword: Keyword::Number,
            col: o as u32 + 1,
            rest: start,
            trailing: None,
        });
    }
    // LinuxCNC's read_o takes the first keyword the word starts with, in this order, and
    // refuses letters after it ("Unexpected character after O-word"): `callsub` is `call`
    // followed by `sub`, an error.
    let Some(&(name, keyword)) = MATCH_ORDER
        .iter()
        .find(|(k, _)| word.len() >= k.len() && word[..k.len()].eq_ignore_ascii_case(k.as_bytes()))
    else {
        let msg = format!(
            "{}: unknown O-word keyword '{}' (sub, endsub, call, return, if, elseif, else, endif, \
             while, endwhile, do, repeat, endrepeat, break, continue)",
            shown(&label),
            String::from_utf8_lossy(word)
        );
        return Ok(Head {
            label,
            keyword: Keyword::Unknown,
            col: o as u32 + 1,
            rest: start + len,
            trailing: Some((start, msg)),
        });
    };
    let trailing = (word.len() > name.len()).then(|| {
        let msg = format!(
            "{}: unexpected '{}' after '{name}' (LinuxCNC reads the keyword {name} and refuses the \
             rest: \"Unexpected character after O-word\")",
            shown(&label),
            String::from_utf8_lossy(&word[name.len()..])
        );
        (start + name.len(), msg)
    });
    Ok(Head {
        label,
        keyword,
        col: o as u32 + 1,
        rest: start + len,
        trailing,
    })
}

/// The keywords in the order LinuxCNC's `read_o` tries them as prefixes of the word.
const MATCH_ORDER: [(&str, Keyword); 15] = [
    ("sub", Keyword::Sub),
    ("endsub", Keyword::EndSub),
    ("call", Keyword::Call),
    ("do", Keyword::Do),
    ("while", Keyword::While),
    ("repeat", Keyword::Repeat),
    ("if", Keyword::If),
    ("elseif", Keyword::ElseIf),
    ("else", Keyword::Else),
    ("endif", Keyword::EndIf),
    ("break", Keyword::Break),
    ("continue", Keyword::Continue),
    ("endwhile", Keyword::EndWhile),
    ("endrepeat", Keyword::EndRepeat),
    ("return", Keyword::Return),
];

/// `o[expression]`: the label it computes (a whole number), or `[…]` when not evaluated.
fn indirect(b: &[u8], i: &mut usize, params: Option<&Params>) -> Located<String> {
    let at = *i;
    let Some(params) = params else {
        let mut depth = 0usize;
        while *i < b.len() {
            depth = match b[*i] {
                b'[' => depth + 1,
                b']' => depth.saturating_sub(1),
                _ => depth,
            };
            *i += 1;
            if depth == 0 {
                break;
            }
        }
        return Ok("[…]".into());
    };
    let mut e = Expr::new(b, at, params);
    let v = e.primary()?;
    *i = e.i;
    if v.fract() != 0.0 || !(0.0..=999_999_999.0).contains(&v) {
        return Err((
            at,
            format!("O-word number {v} out of range (a whole number 0 … 999999999)"),
        ));
    }
    Ok((v as u32).to_string())
}

/// The bracketed arguments after the keyword (`[expr] [expr] …`), evaluated with `params`;
/// comments may follow, nothing else.
pub fn args(line: &str, head: &Head, params: &Params) -> Located<Vec<f64>> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = head.rest;
    loop {
        i = blank(b, i);
        match b.get(i) {
            None | Some(b';') => break,
            Some(b'(') => match b[i..].iter().position(|&c| c == b')') {
                Some(k) => i += k + 1,
                None => return Err((i, "comment not closed: '(' without ')'".into())),
            },
            Some(b'[') => {
                if out.len() == MAX_ARGS {
                    return Err((i, format!("more than {MAX_ARGS} arguments")));
                }
                let mut e = Expr::new(b, i, params);
                out.push(e.primary()?);
                i = e.i;
            }
            Some(_) => {
                let msg = format!("{}: expected '[expression]' or the end of the line", head.shown());
                return Err((i, msg));
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heads_and_arguments() {
        let h = head("  o100 SUB", None).unwrap().unwrap();
        assert_eq!((h.label.as_str(), h.keyword, h.col), ("100", Keyword::Sub, 3));
        let h = head("O<My Sub> call [1] [2+3] (c)", None).unwrap().unwrap();
        assert_eq!((h.label.as_str(), h.keyword), ("mysub", Keyword::Call));
        let p = Params::default();
        assert_eq!(
            args("O<My Sub> call [1] [2+3] (c)", &h, &p).unwrap(),
            vec![1.0, 5.0]
        );
        assert!(head("G1 X1", None).is_none());
        let p = Params::default();
        assert_eq!(head_run("o100 jump", &p).unwrap().unwrap_err().0, 5);
        assert_eq!(
            head("o100 jump", None).unwrap().unwrap().keyword,
            Keyword::Unknown
        );
        // LinuxCNC's prefix match: `callsub` is `call`, then 'sub' is refused where it is run.
        let h = head("o<g20sub> callsub", None).unwrap().unwrap();
        assert_eq!(
            (h.keyword, h.trailing.as_ref().map(|t| t.0)),
            (Keyword::Call, Some(14))
        );
        let p = Params::default();
        assert_eq!(head_run("o<g20sub> callsub", &p).unwrap().unwrap_err().0, 14);
        let h = head("o1 if [1] X", None).unwrap().unwrap();
        assert_eq!(args("o1 if [1] X", &h, &p).unwrap_err().0, 10);
    }
}
