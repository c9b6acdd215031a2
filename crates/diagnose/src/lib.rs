//! Diagnosis: compare a model with a dataset, see where it fails, and learn which catalogued
//! effects are missing.
//!
//! The algorithm is [`rounds`]; read its documentation first. One function, [`diagnose`],
//! runs its steps in order, and each step is a module of its own that never calls back into
//! it:
//!
//! - the loop: [`rounds`], with its settings ([`options`]) and its result ([`diagnosis`]);
//! - its steps, in order: [`implausible_data`] (can the data be judged?), [`under_test`] (the
//!   model under test), then per round [`noise`] (noise check), [`candidates`] (rank
//!   candidates) and [`naming`] (name), then [`stand_ins`] (check for stand-ins) and
//!   [`verdict`];
//! - what the steps are made of: [`fit`] (one filter pass, its priors widened, a noise term's
//!   density), [`priors`] (where they start), [`summary`] and [`consistency`] (how well a fit
//!   fits), [`physical`] (what real sensors have), [`rivals`] (explanations outside the
//!   catalogue);
//! - what a user reads: [`report`] (`report.md` and the findings) and [`plots`] (figures);
//! - the diagnosis measured on simulated data: [`diagnosis_study`].

pub mod candidates;
pub mod catalogue;
pub mod consistency;
pub mod diagnosis;
pub mod diagnosis_study;
pub mod error;
pub mod fit;
pub mod implausible_data;
pub mod misfit;
pub mod naming;
pub mod noise;
pub mod options;
pub mod physical;
pub mod plots;
pub mod priors;
pub mod report;
pub mod request;
pub mod rivals;
pub mod rounds;
pub mod stand_ins;
pub mod start_attitude;
pub mod summary;
pub mod under_test;
pub mod verdict;

pub use consistency::phase_name;
pub use diagnosis::{Diagnosis, Fits, Round, RoundKind};
pub use error::DiagnoseError;
pub use fit::{Fit, FitSetup};
pub use options::Options;
pub use rounds::{diagnose, MIN_UPDATES};
pub use stand_ins::Withdrawn;
pub use summary::{summarize_fit, Coefficient, FitSummary, WHITENESS_ALPHA};
pub use verdict::Verdict;
