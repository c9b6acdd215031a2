//! Why a filter run failed, typed: one cause for counting (a Monte Carlo study tallies runs
//! by it, a diagnosis reports a fit's), and the detail in words. A filter's own error
//! ([`crate::FilterError`]) maps onto a cause; a study adds the causes a filter cannot see
//! (stopped before the end, an error beyond the study's bound).

use serde::{Deserialize, Serialize};

/// What excluded a run: the class of failure, for counting. The detail (step, matrix,
/// value) is in [`RunFailure::reason`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DivergenceCause {
    /// The filter refused its settings or its initial estimate.
    Setup,
    /// A covariance (`P`, the innovation covariance `S`, or a factor) lost positive
    /// definiteness: in a filter step, or in the NEES at a stored time.
    NotPositiveDefinite,
    /// The state, the covariance or an innovation became NaN or infinite.
    NonFinite,
    /// The run stopped before the last stored time.
    Stopped,
    /// It finished, but a coefficient's final error exceeds the study's divergence bound
    /// (`[divergence] max_error_initial_sigmas`).
    ErrorBound,
}

impl DivergenceCause {
    /// The class of a filter's error.
    pub fn of_filter_error(e: &crate::FilterError) -> Self {
        use crate::FilterError as E;
        match e {
            E::NotPositiveDefinite { .. } => DivergenceCause::NotPositiveDefinite,
            E::NonFinite { .. } => DivergenceCause::NonFinite,
            E::Invalid(_) => DivergenceCause::Setup,
        }
    }

    /// The cause in words, as in the report.
    pub fn as_str(self) -> &'static str {
        match self {
            DivergenceCause::Setup => "setup refused",
            DivergenceCause::NotPositiveDefinite => "covariance not positive definite",
            DivergenceCause::NonFinite => "non-finite value",
            DivergenceCause::Stopped => "stopped early",
            DivergenceCause::ErrorBound => "final error beyond the bound",
        }
    }
}

impl std::fmt::Display for DivergenceCause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a run was excluded: its class, and the detail in words.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunFailure {
    /// The class, for counting.
    pub cause: DivergenceCause,
    /// What happened (the filter's error with its step, or the bound exceeded).
    pub reason: String,
}

impl RunFailure {
    /// A failure of class `cause`.
    pub fn new(cause: DivergenceCause, reason: impl Into<String>) -> Self {
        RunFailure {
            cause,
            reason: reason.into(),
        }
    }

    /// A filter's error, classed by [`DivergenceCause::of_filter_error`]; `reason` says it
    /// in words with its context (the time, the measurement).
    pub fn of_filter(e: &crate::FilterError, reason: impl Into<String>) -> Self {
        Self::new(DivergenceCause::of_filter_error(e), reason)
    }
}

/// The detail, as reports quote it.
impl std::fmt::Display for RunFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.reason)
    }
}
