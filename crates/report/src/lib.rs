//! What every kind of study shares to tell its results, whatever it studies: the statistics
//! (chi-square bounds and verdicts), the figure kit, the results folder (staged, marked,
//! committed whole, never deleting a user's file), atomic writes, names that become paths,
//! the stop on request (Ctrl-C), and the provenance written beside every result.
//!
//! It knows nothing of models or filters: `navkf-study` and `navkf-diagnose` build on it.

pub mod atomic_write;
pub mod error;
pub mod executor;
pub mod figure;
pub mod interrupt;
pub mod json_nan;
pub mod markdown;
pub mod names;
pub mod progress;
pub mod provenance;
pub mod results_dir;
pub mod setting_names;
pub mod stats;
pub mod study_kind;

pub use atomic_write::write_atomic;
pub use error::ReportError;
pub use interrupt::Interrupted;
pub use results_dir::marker::FolderKind;
pub use results_dir::{ResultsDir, ShardFolder, MARKER};
pub use setting_names::SettingNames;
pub use study_kind::StudyKind;
