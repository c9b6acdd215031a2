//! The Monte Carlo engine: hundreds of seeded runs, each simulating the truth and running
//! every filter on the same data, folded into [`Tally`] blocks in a fixed order.
//!
//! Each run also carries a lower reference for the errors: the covariance recursion of the
//! EKF with the truth model, its state reset to the true state before each step, so that
//! every Jacobian is evaluated on the true path (the Riccati recursion of the posterior
//! Cramer-Rao bound for additive Gaussian noise, with the expectation over the truth taken
//! by averaging over runs). No filter can be consistently below it; a filter close to it is
//! efficient.

mod bound;
mod example;
mod run;
mod schedule;
mod setup;

pub use example::{ExampleFilter, ExampleRun};
pub use run::{FilterRun, NisTotals, RunRecord, TracePoint};

use crate::config::StudyConfig;
use navkf_dynamics::{FamilyModel, TruthSimulation};
use navkf_filters::FilterSpec;
use std::sync::Arc;

/// A prepared study: models, simulator and filter settings, shared by all runs.
pub struct Study {
    /// The study file.
    pub config: StudyConfig,
    /// The truth simulator (the family's).
    pub sim: Box<dyn TruthSimulation>,
    /// The filters' model.
    pub filter_model: Arc<dyn FamilyModel>,
    /// Filter state index -> truth state index (by name), `None` if the truth lacks it.
    pub to_truth: Vec<Option<usize>>,
    /// Initial one-sigma of every filter state.
    pub initial_sigma: Vec<f64>,
    /// Names of the stored times' states (the filter model's).
    pub names: Vec<String>,
    /// Stored times, s.
    pub times: Vec<f64>,
    /// What each compared filter is built from, in the study's order.
    filters: Vec<FilterSetup>,
}

/// One compared filter as specified, with its model (the filters' model in the spec's
/// attitude equations).
struct FilterSetup {
    spec: FilterSpec,
    model: Arc<dyn FamilyModel>,
}
