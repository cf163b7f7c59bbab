//! Errors that name the place: `FILE:LINE:COL: what is wrong`.

use std::fmt;

/// An error in a program (or machine file) at a given place. Lines and columns count from 1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramError {
    pub file: String,
    pub line: u32,
    pub col: u32,
    pub message: String,
}

impl ProgramError {
    /// The message is `clip`ped: a value quoted whole could be megabytes long.
    pub fn new(file: &str, line: u32, col: u32, message: impl Into<String>) -> Self {
        ProgramError {
            file: clip(file.to_string()),
            line,
            col,
            message: clip(message.into()),
        }
    }
}

impl fmt::Display for ProgramError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: {}", self.file, self.line, self.col, self.message)
    }
}

impl std::error::Error for ProgramError {}

/// Longest run between backticks or double quotes kept whole in a message (characters).
pub const MAX_QUOTED_CHARS: usize = 80;
/// Longest message kept whole (characters): its head and tail are kept around an ellipsis.
pub const MAX_MESSAGE_CHARS: usize = 2000;

/// `message` with every quoted run (`…` or "…") longer than MAX_QUOTED_CHARS cut to its first
/// characters and an ellipsis with the length, and the whole cut to MAX_MESSAGE_CHARS.
pub fn clip(message: String) -> String {
    if message.len() <= MAX_QUOTED_CHARS {
        return message;
    }
    let mut out = String::with_capacity(MAX_MESSAGE_CHARS.min(message.len()));
    let mut rest = message.as_str();
    while let Some(open) = rest.find(['`', '"']) {
        let quote = rest[open..].chars().next().unwrap_or('`');
        out.push_str(&rest[..=open]);
        rest = &rest[open + 1..];
        let Some(close) = rest.find(quote) else {
            break;
        };
        let inner = &rest[..close];
        let n = inner.chars().count();
        if n > MAX_QUOTED_CHARS {
            let head: String = inner.chars().take(MAX_QUOTED_CHARS / 2).collect();
            out.push_str(&format!("{head}… ({n} characters)"));
        } else {
            out.push_str(inner);
        }
        out.push(quote);
        rest = &rest[close + 1..];
    }
    out.push_str(rest);
    let n = out.chars().count();
    if n <= MAX_MESSAGE_CHARS {
        return out;
    }
    let head: String = out.chars().take(MAX_MESSAGE_CHARS / 2).collect();
    let tail: String = out.chars().skip(n - MAX_MESSAGE_CHARS / 4).collect();
    format!(
        "{head} … ({} characters cut) … {tail}",
        n - head.chars().count() - tail.chars().count()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_values_are_cut_with_an_ellipsis() {
        let long = "x".repeat(10_000_000);
        let m = clip(format!(
            "unknown variant `{long}`, expected one of `scurve7`, `quintic`"
        ));
        assert!(
            m.starts_with("unknown variant `xxxx") && m.len() < 200,
            "{}",
            &m[..200.min(m.len())]
        );
        assert!(
            m.contains("… (10000000 characters)`, expected one of `scurve7`, `quintic`"),
            "{m}"
        );
        let m = clip(format!("{long}: No such file or directory"));
        assert!(m.len() < MAX_MESSAGE_CHARS + 100 && m.ends_with(": No such file or directory"));
        assert!(m.contains("characters cut"));
        let short = "profile = `scurve9` unknown".to_string();
        assert_eq!(clip(short.clone()), short);
    }
}
