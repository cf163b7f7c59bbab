//! Where the reader's lines come from: a text in memory (the FMU's `program` parameter, tests) or
//! a file read line by line through a buffer, so memory does not grow with the program's length.
//! Either way the reader keeps only a byte offset; a cloned or restored reader reopens the file
//! and seeks there.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::PathBuf;
use std::sync::Arc;

/// Longest line accepted (bytes, newline included): a file without newlines (`/dev/zero`) fails
/// here instead of filling the memory.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// A G-code program: text in memory, a file streamed line by line, or a file read whole (the
/// FMU's `programFile`: its text, and its path for the subroutine files beside it).
#[derive(Clone, Debug)]
pub enum ProgramSource {
    Text(Arc<str>),
    File(PathBuf),
    FileText(Arc<str>, PathBuf),
}

impl ProgramSource {
    /// The text, for a program held in memory.
    pub fn text(&self) -> Option<&str> {
        match self {
            ProgramSource::Text(t) | ProgramSource::FileText(t, _) => Some(t),
            ProgramSource::File(_) => None,
        }
    }

    /// The program file's path (None for a text given as such).
    pub fn path(&self) -> Option<&std::path::Path> {
        match self {
            ProgramSource::Text(_) => None,
            ProgramSource::File(p) | ProgramSource::FileText(_, p) => Some(p),
        }
    }
}

impl Default for ProgramSource {
    fn default() -> Self {
        ProgramSource::Text(Arc::from(""))
    }
}

impl From<Arc<str>> for ProgramSource {
    fn from(text: Arc<str>) -> Self {
        ProgramSource::Text(text)
    }
}

impl From<&str> for ProgramSource {
    fn from(text: &str) -> Self {
        ProgramSource::Text(Arc::from(text))
    }
}

/// A source with its open file (if any). Cloning drops the handle: the clone reopens the file at
/// its own offset when it reads.
#[derive(Debug, Default)]
pub struct Lines {
    pub source: ProgramSource,
    handle: Option<BufReader<File>>,
    /// Byte offset the open file is at (an O-word jump reads elsewhere: seek).
    at: usize,
}

impl Clone for Lines {
    fn clone(&self) -> Self {
        Lines {
            source: self.source.clone(),
            handle: None,
            at: 0,
        }
    }
}

/// Why a line could not be read.
#[derive(Debug)]
pub enum LineError {
    Io(std::io::Error),
    TooLong,
}

impl Lines {
    pub fn new(source: ProgramSource) -> Lines {
        Lines {
            source,
            handle: None,
            at: 0,
        }
    }

    /// Forget the open file (after an error, so that a retry starts again at the offset).
    pub fn reset(&mut self) {
        self.handle = None;
    }

    /// The line starting at byte `offset` into `buf` (cleared first), newline included; an empty
    /// buffer at the end of the program.
    pub fn read_line(&mut self, offset: usize, buf: &mut Vec<u8>) -> Result<(), LineError> {
        buf.clear();
        match &self.source {
            ProgramSource::Text(text) | ProgramSource::FileText(text, _) => {
                let rest = text.as_bytes().get(offset..).unwrap_or_default();
                let end = rest
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(rest.len(), |i| i + 1);
                if end > MAX_LINE_BYTES {
                    return Err(LineError::TooLong);
                }
                buf.extend_from_slice(&rest[..end]);
                Ok(())
            }
            ProgramSource::File(path) => {
                if self.handle.is_none() {
                    let mut file = File::open(path).map_err(LineError::Io)?;
                    file.seek(SeekFrom::Start(offset as u64)).map_err(LineError::Io)?;
                    self.handle = Some(BufReader::new(file));
                    self.at = offset;
                }
                let Some(handle) = self.handle.as_mut() else {
                    return Ok(());
                };
                if self.at != offset {
                    // Relative: a jump within the buffer (a short loop) keeps it.
                    let delta = offset as i64 - self.at as i64;
                    handle.seek_relative(delta).map_err(LineError::Io)?;
                }
                let limit = MAX_LINE_BYTES as u64 + 1;
                handle
                    .by_ref()
                    .take(limit)
                    .read_until(b'\n', buf)
                    .map_err(LineError::Io)?;
                if buf.len() > MAX_LINE_BYTES {
                    self.handle = None;
                    return Err(LineError::TooLong);
                }
                self.at = offset + buf.len();
                Ok(())
            }
        }
    }
}

/// Largest program file the FMU loads into memory (`programFile`; the CLI streams any size).
pub const MAX_PROGRAM_FILE_BYTES: u64 = 64 * 1024 * 1024;

/// A program file read whole, for the FMU: a regular file of at most MAX_PROGRAM_FILE_BYTES,
/// UTF-8 (a BOM is dropped). `name` is used in messages, invalid UTF-8 is located `name:line:col`.
pub fn read_program_file(path: &std::path::Path, name: &str) -> Result<String, String> {
    read_whole(path, name).map_err(crate::error::clip)
}

/// `read_program_file` before its message is clipped (a path may be megabytes long).
fn read_whole(path: &std::path::Path, name: &str) -> Result<String, String> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| format!("{shown}: {e}"))?;
    if !meta.is_file() {
        return Err(format!("{shown}: not a regular file"));
    }
    let too_big =
        || format!("{shown}: program file out of range (larger than {MAX_PROGRAM_FILE_BYTES} bytes)");
    if meta.len() > MAX_PROGRAM_FILE_BYTES {
        return Err(too_big());
    }
    let mut bytes = Vec::new();
    File::open(path)
        .and_then(|f| f.take(MAX_PROGRAM_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| format!("{shown}: {e}"))?;
    if bytes.len() as u64 > MAX_PROGRAM_FILE_BYTES {
        return Err(too_big());
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        let col = good.len() - good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1) + 1;
        format!("{name}:{line}:{col}: invalid UTF-8 (a program is ASCII or UTF-8 text)")
    })?;
    Ok(text)
}
