//! The one error of the capture reader and writer: what is wrong, and where in which file.

use core::fmt;
use std::path::{Path, PathBuf};

/// Why a capture could not be read (or estimates not written), with the place of the fault:
/// displayed as `FILE:LINE:COLUMN: message` (`FILE:LINE: message` without a column,
/// `FILE: message` without a line), the form compilers use, so that editors jump to it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CaptureError {
    /// The file.
    pub path: PathBuf,
    /// The 1-based line of a text file (the 1-based row of a binary array), if one is at fault.
    pub line: Option<u64>,
    /// The 1-based column (field) at fault, if one is.
    pub column: Option<usize>,
    /// What is wrong, in words (names the column, the values and what to do).
    pub message: String,
}

impl CaptureError {
    /// An error about the whole file `path`.
    ///
    /// ```
    /// use angletrack::capture::CaptureError;
    /// let e = CaptureError::new("run.csv", "empty file").at(Some(1), None);
    /// assert_eq!(e.to_string(), "run.csv:1: empty file");
    /// ```
    pub fn new(path: impl AsRef<Path>, message: impl Into<String>) -> Self {
        Self {
            path: path.as_ref().to_path_buf(),
            line: None,
            column: None,
            message: message.into(),
        }
    }

    /// The same error placed at `line` and `column` (1-based).
    pub fn at(mut self, line: Option<u64>, column: Option<usize>) -> Self {
        self.line = line;
        self.column = column;
        self
    }

    /// An input/output error on `path`, with the operating system's words.
    pub fn io(path: impl AsRef<Path>, e: &std::io::Error) -> Self {
        Self::new(path, e.to_string())
    }
}

impl fmt::Display for CaptureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for CaptureError {}
