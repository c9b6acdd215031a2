//! Monte Carlo studies of the filters on the platform model: seeded runs in parallel,
//! streaming tallies, summaries, plots and reports; the diagnosis of model misfit, and the
//! study that measures the diagnosis' error rates.

pub mod config;
pub mod diagnose;
pub mod diagnosis_study;
pub mod error;
pub mod filters;
pub mod guard;
pub mod interrupt;
mod json_nan;
pub mod monte_carlo;
pub mod output;
pub mod plan;
pub mod plots;
pub mod report;
pub mod results_dir;
pub mod shard_check;
pub mod stats;
pub mod summary;
pub mod sweep;
pub mod tally;

pub use config::StudyConfig;
pub use error::StudyError;
pub use monte_carlo::Study;
pub use tally::Tally;
