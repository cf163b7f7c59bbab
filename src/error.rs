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
    pub fn new(file: &str, line: u32, col: u32, message: impl Into<String>) -> Self {
        ProgramError {
            file: file.to_string(),
            line,
            col,
            message: message.into(),
        }
    }
}

impl fmt::Display for ProgramError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: {}", self.file, self.line, self.col, self.message)
    }
}

impl std::error::Error for ProgramError {}
