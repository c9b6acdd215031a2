//! The diagnose crate's error type.

use std::path::PathBuf;

/// What can stop a diagnosis or a diagnosis study (bad data is caught when reading the
/// dataset; a filter that diverges on a candidate model is an outcome, not an error).
#[derive(Debug, thiserror::Error)]
pub enum DiagnoseError {
    /// The model could not be assembled.
    #[error(transparent)]
    Dynamics(#[from] navkf_dynamics::DynamicsError),
    /// The filter refused its settings.
    #[error(transparent)]
    Filter(#[from] navkf_filters::FilterError),
    /// The dataset cannot start a filter.
    #[error("{0}")]
    Data(String),
    /// A malformed diagnosis-study file.
    #[error("{}: {message}", path.display())]
    Config {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the key.
        message: String,
    },
    /// A diagnosis study's content that cannot be simulated as stated.
    #[error("{0}")]
    Content(String),
    /// Results could not be written, or the run was stopped on request.
    #[error(transparent)]
    Report(#[from] navkf_report::ReportError),
}

impl From<navkf_report::Interrupted> for DiagnoseError {
    fn from(stop: navkf_report::Interrupted) -> Self {
        DiagnoseError::Report(stop.into())
    }
}

/// Stops a diagnosis asked to stop (Ctrl-C: [`navkf_report::interrupt`]) between its fits,
/// with nothing decided: a diagnosis is whole or not given.
pub(crate) fn stop_if_requested() -> Result<(), DiagnoseError> {
    if navkf_report::interrupt::requested() {
        return Err(DiagnoseError::Report(
            navkf_report::ReportError::Interrupted(navkf_report::Interrupted {
                done: 0,
                total: 1,
                what: "diagnoses",
            }),
        ));
    }
    Ok(())
}
