//! The dynamics crate's error type.

use std::path::PathBuf;

/// Everything that can go wrong in the dynamics crate. Dataset errors name the file, the
/// line (1-based, counting the header as line 1), the column and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum DynamicsError {
    /// An effect name that is not in the registry, or an effect that conflicts with another.
    #[error("effect: {0}")]
    Effect(String),
    /// A malformed configuration value (trajectory, simulator).
    #[error("configuration: {key}: {message}")]
    Config {
        /// The key or setting at fault.
        key: String,
        /// What was expected.
        message: String,
    },
    /// A malformed cell or row in a dataset file.
    #[error("{}:{line}: column `{column}`: {message}", path.display())]
    Data {
        /// The file.
        path: PathBuf,
        /// 1-based line number (the header is line 1).
        line: usize,
        /// Column name (or `-` when the whole row is at fault).
        column: String,
        /// What was found and what was expected.
        message: String,
    },
    /// A malformed file as a whole (missing column, not a regular file, too large).
    #[error("{}: {message}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What was found and what was expected.
        message: String,
    },
    /// A TOML file the parser refused (bad syntax, an unknown key, a value of the wrong
    /// type), located; the excerpt is a short cut of the line with a caret under the column
    /// ([`crate::input_file::toml_error`]), never the line whole.
    #[error("{}:{line}:{column}: {message}\n{excerpt}", path.display())]
    Toml {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column, in characters.
        column: usize,
        /// The parser's message.
        message: String,
        /// The line, cut around the column, and a caret under it.
        excerpt: String,
    },
    /// An I/O failure, with the file it concerns.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}
