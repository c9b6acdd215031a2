//! Monte Carlo studies of the filters on the platform model: seeded runs in parallel,
//! streaming tallies, summaries, figures and reports; sweeps of a study over one setting; the
//! test planner; and the accuracy guard CI runs.
//!
//! What every kind of study shares to tell its results (statistics, the figure kit, results
//! folders) is in `navkf-report`; the diagnosis and its error-rate study are in
//! `navkf-diagnose`.

pub mod config;
pub mod error;
mod family;
pub mod guard;
pub mod merge;
pub mod monte_carlo;
pub mod output;
pub mod partial;
pub mod plan;
pub mod plan_output;
pub mod plots;
pub mod report;
pub mod simulation;
pub mod summary;
pub mod sweep;
pub mod tally;

pub use config::StudyConfig;
pub use error::StudyError;
pub use monte_carlo::Study;
pub use tally::Tally;
