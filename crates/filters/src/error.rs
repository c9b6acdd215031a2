//! The filter crate's error type: every numerical failure is typed, with the step it
//! happened at, so that a diverging Monte Carlo run is counted, never a panic or a NaN.

/// What went wrong in a filter.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilterError {
    /// A matrix that must be positive definite was not (Cholesky pivot `pivot` <= 0).
    #[error(
        "step {step}: {matrix} is not positive definite (pivot {pivot} of {dim} is {value:e})"
    )]
    NotPositiveDefinite {
        /// Filter step (number of predictions made).
        step: usize,
        /// Which matrix: `P`, `P augmented`, `S`.
        matrix: &'static str,
        /// Failing pivot index.
        pivot: usize,
        /// Dimension of the matrix.
        dim: usize,
        /// Value of the failing pivot.
        value: f64,
    },
    /// The state or covariance became NaN or infinite.
    #[error("step {step}: {what} is not finite")]
    NonFinite {
        /// Filter step.
        step: usize,
        /// Which quantity.
        what: &'static str,
    },
    /// A caller passed something of the wrong size or an invalid setting.
    #[error("{0}")]
    Invalid(String),
}
