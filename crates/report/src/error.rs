//! The report crate's error type.

use std::path::PathBuf;

/// What can stop writing results: a file that cannot be written, a folder that is not
/// navkf's to replace, a figure that cannot be drawn.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// An I/O failure on a file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A results folder that cannot be used, said in words (it holds a user's files, it is
    /// read-only, its name is not a plain name).
    #[error("{0}")]
    Folder(String),
    /// A figure that could not be drawn.
    #[error("{0}")]
    Figure(String),
    /// Stopped on request before the work was complete.
    #[error(transparent)]
    Interrupted(#[from] crate::interrupt::Interrupted),
}
