//! Where a Mitsuba element came from (file, line, column), and the errors and warnings that say so.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A position in a scene file: 1-based line and column (in characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceLoc {
    pub file: Arc<PathBuf>,
    pub line: usize,
    pub column: usize,
}

impl SourceLoc {
    pub fn new(file: &Arc<PathBuf>, line: usize, column: usize) -> Self {
        Self {
            file: file.clone(),
            line,
            column,
        }
    }

    pub fn path(&self) -> &Path {
        &self.file
    }
}

impl fmt::Display for SourceLoc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)
    }
}

/// The scene cannot be read: where, and why (with the offending text).
#[derive(Clone, Debug, PartialEq)]
pub struct MitsubaError {
    pub loc: SourceLoc,
    pub message: String,
}

impl MitsubaError {
    pub fn new(loc: &SourceLoc, message: impl Into<String>) -> Self {
        Self {
            loc: loc.clone(),
            message: message.into(),
        }
    }
}

impl fmt::Display for MitsubaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: error: {}", self.loc, self.message)
    }
}

impl std::error::Error for MitsubaError {}

/// Something skipped or read differently from Mitsuba; loading goes on.
#[derive(Clone, Debug, PartialEq)]
pub struct MitsubaWarning {
    pub loc: SourceLoc,
    pub message: String,
}

impl fmt::Display for MitsubaWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: warning: {}", self.loc, self.message)
    }
}
