//! The one error type of map reading, writing and importing. Every message names the file and the
//! JSON field path, because users feed these readers hand-edited and generated files and need to
//! know exactly where to look.

use std::fmt;

/// A map or house that cannot be read, with the file and the field at fault.
#[derive(Debug, thiserror::Error)]
pub struct MapError {
    /// The file (or `demo`, or `<input>`) the error is about.
    pub file: String,
    /// JSON field path such as `rooms[3].floorPolygon`; empty when the whole file is at fault.
    pub path: String,
    pub message: String,
}

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}: {}: {}", self.file, self.path, self.message)
        }
    }
}

impl MapError {
    pub fn new(
        file: impl Into<String>,
        path: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        MapError {
            file: file.into(),
            path: path.into(),
            message: message.into(),
        }
    }
}

/// Builds errors for one file, so reader code can say `ctx.err(path, msg)`.
#[derive(Clone, Debug)]
pub struct ErrCtx {
    pub file: String,
}

impl ErrCtx {
    pub fn new(file: impl Into<String>) -> Self {
        ErrCtx { file: file.into() }
    }

    pub fn err(&self, path: impl Into<String>, message: impl Into<String>) -> MapError {
        MapError::new(self.file.clone(), path, message)
    }
}
