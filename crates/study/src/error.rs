//! The study crate's error type.

use std::path::PathBuf;

/// What can stop a study (a diverged run does not: it is counted).
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// A malformed study file.
    #[error("{}: {message}", path.display())]
    Config {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the key.
        message: String,
    },
    /// The model, trajectory or simulator refused the settings.
    #[error(transparent)]
    Dynamics(#[from] navkf_dynamics::DynamicsError),
    /// A filter refused its settings.
    #[error(transparent)]
    Filter(#[from] navkf_filters::FilterError),
    /// Results could not be written, or the run was stopped on request.
    #[error(transparent)]
    Report(#[from] navkf_report::ReportError),
    /// An I/O failure on a file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// Anything else, said in words (e.g. shards that do not fit together).
    #[error("{0}")]
    Other(String),
}
