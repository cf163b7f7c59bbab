//! Where the reader's lines come from: the program and the subroutine files it calls
//! (LinuxCNC "O Codes", "Calling Files": `o<name> call` of a sub the program does not define
//! loads `<name>.ngc`, lower case, which holds `o<name> sub … o<name> endsub`). Each source is
//! streamed as the program is (a byte offset and line per place, `Place::src` naming the
//! source), so a call into a file jumps there and back as a call within the program does.
//! Files are looked for in the program file's directory, then in the machine file's
//! `subroutine_path` (LinuxCNC's PROGRAM_PREFIX and SUBROUTINE_PATH); a program given as text
//! has no directory of its own.

use super::flow::{Place, MAX_SUBS};
use super::Reader;
use crate::error::ProgramError;
use crate::gcode::oword::{self, Head, Keyword};
use crate::gcode::source::{LineError, Lines, ProgramSource, MAX_LINE_BYTES};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A subroutine file the program called: its label, where it was found and its name in
/// messages (the path as found).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SubFile {
    label: String,
    path: PathBuf,
    name: String,
    /// Opened when read (a restored or cloned reader reopens it at its offset).
    #[serde(skip)]
    lines: Option<Lines>,
}

/// An O-word line found by a scan: its place, the line after it, its head and text.
pub(super) struct Found {
    pub here: Place,
    pub next: Place,
    pub head: Head,
    pub text: String,
}

/// A label that names a file: LinuxCNC's "lowercase letters, numbers, dash, and underscore
/// only" (labels are lower case already), nothing that leaves the directory.
fn file_label(label: &str) -> bool {
    !label.is_empty()
        && label
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-' || b == b'_')
}

impl Reader {
    /// The directories searched for `<name>.ngc`: the program file's, then `subroutine_path`.
    pub(super) fn subroutine_dirs(&self) -> Vec<PathBuf> {
        let own = self.lines.source.path().map(|p| match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        });
        own.into_iter()
            .chain(self.nc.subroutine_path.iter().cloned())
            .collect()
    }

    /// The file `<label>.ngc` in the first directory that has it.
    fn locate(&self, label: &str) -> Option<PathBuf> {
        if !file_label(label) {
            return None;
        }
        let name = format!("{label}.ngc");
        self.subroutine_dirs()
            .into_iter()
            .map(|d| d.join(&name))
            .find(|p| p.is_file())
    }

    /// The name of source `src` in messages.
    pub(super) fn file_of(&self, src: u32) -> &str {
        match src.checked_sub(1).and_then(|k| self.subfiles.get(k as usize)) {
            Some(f) => &f.name,
            None => &self.file,
        }
    }

    /// An error at `line`:`col` of source `src`.
    pub(super) fn error_in(&self, src: u32, line: u32, col: u32, message: impl Into<String>) -> ProgramError {
        ProgramError::new(self.file_of(src), line, col, message)
    }

    fn lines_of(&mut self, src: u32) -> &mut Lines {
        match src.checked_sub(1).map(|k| k as usize) {
            Some(k) if k < self.subfiles.len() => {
                let f = &mut self.subfiles[k];
                let path = &f.path;
                f.lines
                    .get_or_insert_with(|| Lines::new(ProgramSource::File(path.clone())))
            }
            _ => &mut self.lines,
        }
    }

    /// Close source `src` (after an error, or when the cursor leaves it: at most the program and
    /// one file are open).
    pub(super) fn close(&mut self, src: u32) {
        self.lines_of(src).reset();
    }

    /// The line at `at` into `buf` (empty at the end of its source), a located error if it
    /// cannot be read.
    pub(super) fn read_at(&mut self, at: Place, buf: &mut Vec<u8>) -> Result<(), ProgramError> {
        self.lines_of(at.src).read_line(at.offset, buf).map_err(|e| {
            let message = match e {
                LineError::Io(e) => format!("cannot read the program: {e}"),
                LineError::TooLong => format!("line out of range (longer than {MAX_LINE_BYTES} bytes)"),
            };
            self.error_in(at.src, at.line, 1, message)
        })
    }

    /// A subroutine not yet met: its file (LinuxCNC looks for the file before reading on in
    /// the program), else its `sub` line anywhere in the program; its `endsub` must follow.
    pub(super) fn find_sub(&mut self, line: u32, head: &Head) -> Result<Place, ProgramError> {
        if self.flow.sub_count() >= MAX_SUBS {
            return Err(self.error(line, head.col, format!("more than {MAX_SUBS} subroutines")));
        }
        let found = match self.locate(&head.label) {
            Some(path) => self.open_sub_file(line, head, path)?,
            None => {
                let start = Place::default();
                let Some(found) = self.scan(start, &head.label, &[Keyword::Sub])? else {
                    let msg = format!(
                        "{} call: the program has no {} sub{}",
                        head.shown(),
                        head.shown(),
                        self.searched(&head.label)
                    );
                    return Err(self.error(line, head.col, msg));
                };
                found
            }
        };
        // A sub without its endsub would run into the lines after it.
        self.find(
            found.here.line,
            found.next,
            &found.head,
            &[Keyword::EndSub],
            "endsub",
        )?;
        self.flow.add_sub(&head.label, found.next);
        Ok(found.next)
    }

    /// Where `<label>.ngc` was looked for, for messages.
    fn searched(&self, label: &str) -> String {
        let dirs = self.subroutine_dirs();
        if !file_label(label) {
            return String::new();
        }
        if dirs.is_empty() {
            return format!(
                " (a program given as text has no directory to find {label}.ngc in: machine key subroutine_path)"
            );
        }
        let shown: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        let shown = crate::error::clip(shown.join(", "));
        format!(", and no {label}.ngc is in {shown} (machine key subroutine_path)")
    }

    /// Add the subroutine file `path` as a source and find its `sub` line.
    fn open_sub_file(&mut self, line: u32, head: &Head, path: PathBuf) -> Result<Found, ProgramError> {
        let name = path.display().to_string();
        self.subfiles.push(SubFile {
            label: head.label.clone(),
            path,
            name: crate::error::clip(name),
            lines: None,
        });
        let src = self.subfiles.len() as u32;
        let start = Place {
            src,
            ..Place::default()
        };
        match self.scan(start, &head.label, &[Keyword::Sub]) {
            Ok(Some(found)) => {
                self.close(src);
                Ok(found)
            }
            Ok(None) => {
                let msg = format!(
                    "{} call: {} has no {} sub (LinuxCNC \"Calling Files\")",
                    head.shown(),
                    self.file_of(src),
                    head.shown()
                );
                self.subfiles.pop();
                Err(self.error(line, head.col, msg))
            }
            Err(e) => {
                self.subfiles.pop();
                Err(e)
            }
        }
    }

    /// Read forward from `from` in its source, without executing, to the O-word line `label`
    /// with one of `keys`; None at the end of the source (or at the program's closing `%`).
    pub(super) fn scan(
        &mut self,
        from: Place,
        label: &str,
        keys: &[Keyword],
    ) -> Result<Option<Found>, ProgramError> {
        let mut at = from;
        let mut buf = Vec::new();
        loop {
            self.read_at(at, &mut buf)?;
            if buf.is_empty() {
                return Ok(None);
            }
            let next = Place {
                src: at.src,
                offset: at.offset + buf.len(),
                line: at.line.saturating_add(1),
            };
            let text = String::from_utf8_lossy(&buf);
            let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
            if at.src == 0 && text.trim() == "%" && Some(at.line) != self.opening_percent() {
                // A closing `%` ends the program (LinuxCNC "File Requirements").
                return Ok(None);
            }
            // Block delete: the line is skipped (switch on) or read without its '/'.
            let slash = text.trim_start().strip_prefix('/');
            let deleted = self.nc.block_delete && slash.is_some();
            let shift = slash.map_or(0, |rest| text.len() - rest.len());
            let text = slash.unwrap_or(text);
            if let Some(h) = oword::head(text, None).filter(|_| !deleted) {
                let h = h.map_err(|(c, m)| self.error_in(at.src, at.line, (shift + c) as u32 + 1, m))?;
                if h.label == label && keys.contains(&h.keyword) {
                    let text = text.to_string();
                    return Ok(Some(Found {
                        here: at,
                        next,
                        head: h,
                        text,
                    }));
                }
            }
            at = next;
        }
    }

    /// A restored state's subroutine files: each the file its label finds now (a state cannot
    /// point the reader anywhere else), at most MAX_SUBS.
    pub(super) fn check_subfiles(&self) -> Result<(), String> {
        crate::valid::at_most("subroutine files", self.subfiles.len() as u64, MAX_SUBS as u64)?;
        for f in &self.subfiles {
            if self.locate(&f.label).as_ref() != Some(&f.path) {
                return Err(format!(
                    "subroutine file {}: not where o<{}> call finds it",
                    f.name, f.label
                ));
            }
        }
        Ok(())
    }

    /// Number of subroutine files: a place's `src` is at most this.
    pub(super) fn subfile_count(&self) -> usize {
        self.subfiles.len()
    }
}
